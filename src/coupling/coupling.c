/*
   The coupling of the liquid and the structure (seed sections II.C-II.D): the liquid is solved in the
   tank's frame, where the walls are at rest; the structure's rigid motion of the tank enters the
   liquid as inertial accelerations, and the liquid's loads on the walls (the integral of the wall
   pressure and the wall shear, seed Eq. 29) drive the structure. Both happen inside every right-hand
   side, so the one TS advances the coupled system with the integrator's own order:

     1. the structure's state y at this stage (rank 0, broadcast) gives the tank's rotation theta;
     2. the liquid's loads at this stage (they depend on the particles only): minus the force and moment
        all terms but gravity put on the particles (by default; Newton's third law, so the coupled system
        conserves momentum and energy), or the wall-pressure integral; taken about the tank's reference point, turned into the global axes, scaled by
        the tank's width (the liquid is 2-D: loads per unit width), and their value for the liquid
        at rest in the undeflected tank is subtracted (the structure's deflections are measured from
        its static equilibrium under gravity, liquid included);
     3. the structure's rate dy/dt under those loads gives the tank's acceleration A, angular rate
        omega and angular acceleration alpha at this stage;
     4. every particle gets, in the tank frame with r = x - x_ref,
          a = R(-theta) g - g - R(-theta) A - alpha e_z x r - 2 omega e_z x u + omega^2 r
        (the gravity term adds g itself), whose power sum_i m_i u_i . a is the work of the tank on
        the liquid, P_ext.
   Explicit and stable while the liquid is light against the structure (here a few per cent of the
   moving mass): the loads at a stage use the liquid's state, not its acceleration, so the liquid's
   added mass is carried by the loads one stage late. A liquid as heavy as the structure would need
   the added mass moved to the structure's side (or an implicit coupling).

   Options Database Keys:
+  -fs_coupling <bool>               - couple the liquid and the structure (default: when both exist)
.  -fs_coupling_loads <reaction|walls> - the loads the structure receives: the reaction of the terms' forces on the liquid (default), or the wall-pressure integral
.  -fs_tank_width <w>                - the tank's width across the 2-D plane (0.1 m): loads per unit width times w
-  -fs_tank_reference <x,y>          - the tank's point on the beam, in the tank's frame (default: the middle of the floor)
*/
#include "solver/solverimpl.h"

/* the tank frame's body acceleration field (gravity and the frame's inertia but Coriolis) of a motion */
static void FrameField(FSSolver s, const FSTankMotion *mo, FSFrameField *ff)
{
  const PetscReal c = PetscCosReal(mo->angle), sn = PetscSinReal(mo->angle);
  const PetscReal gx = s->gravity[0] - mo->acc[0], gy = s->gravity[1] - mo->acc[1];

  ff->b[0]   = c * gx + sn * gy;
  ff->b[1]   = -sn * gx + c * gy;
  ff->omega  = mo->rate;
  ff->alpha  = mo->angacc;
  ff->ref[0] = s->tank_ref[0];
  ff->ref[1] = s->tank_ref[1];
}

/*
   FSSolverCouplingSetUp - decides whether the liquid and the structure are coupled, reads the
   coupling options and computes the loads of the liquid at rest (weight and its moment about the
   reference point), which the structure does not see. After the walls and particles, before the
   structure's set-up (its payload may depend on the liquid's mass).

   Collective
*/
PetscErrorCode FSSolverCouplingSetUp(FSSolver s)
{
  MPI_Comm     comm = PetscObjectComm((PetscObject)s);
  PetscBool    want = PETSC_TRUE, set;
  PetscReal    ref[2], loc[3] = {0, 0, 0}, glob[3];
  PetscInt     nref = 2, n, lt = 0;
  const char  *loadtypes[] = {"reaction", "walls"};
  PetscReal   *x, *m, lo[3], hi[3];

  PetscFunctionBegin;
  s->coupled = PETSC_FALSE;
  PetscCall(PetscMemzero(&s->body, sizeof(s->body))); /* without a coupling the frame's body acceleration is g */
  s->body.b[0] = s->gravity[0];
  s->body.b[1] = s->gravity[1];
  if (!s->structure || !s->boundary || !s->nglobal_particles) PetscFunctionReturn(0);
  PetscCall(FSBoundaryGetBoundingBox(s->boundary, lo, hi));
  ref[0]         = 0.5 * (lo[0] + hi[0]);
  ref[1]         = lo[1];
  s->tank_width  = 0.1;
  PetscOptionsBegin(comm, NULL, "Coupling of the liquid and the structure", "FS");
  PetscCall(PetscOptionsBool("-fs_coupling", "Couple the liquid and the structure (loads to the structure, tank motion to the liquid)", "FSSolverCouplingSetUp", want, &want, NULL));
  PetscCall(PetscOptionsEList("-fs_coupling_loads", "The liquid's loads the structure receives: reaction (minus the force and moment of all terms but gravity on the particles: Newton's third law) or walls (the integral of the wall pressure and shear)", "FSSolverCouplingSetUp", loadtypes, 2, loadtypes[s->loads_from_walls ? 1 : 0], &lt, NULL));
  s->loads_from_walls = lt == 1 ? PETSC_TRUE : PETSC_FALSE;
  PetscCall(PetscOptionsReal("-fs_tank_width", "Width of the tank across the 2-D plane: the liquid's loads per unit width times this", "FSSolverCouplingSetUp", s->tank_width, &s->tank_width, NULL));
  PetscCall(PetscOptionsRealArray("-fs_tank_reference", "The tank's point on the beam, in the tank's frame (default: the middle of the floor)", "FSSolverCouplingSetUp", ref, &nref, &set));
  PetscOptionsEnd();
  PetscCheck(!set || nref == 2, comm, PETSC_ERR_ARG_SIZ, "-fs_tank_reference takes two values x,y; got %" PetscInt_FMT, nref);
  PetscCheck(s->tank_width > 0, comm, PETSC_ERR_ARG_OUTOFRANGE, "-fs_tank_width %g must be positive", (double)s->tank_width);
  if (!want) PetscFunctionReturn(0);
  s->coupled     = PETSC_TRUE;
  s->tank_ref[0] = ref[0];
  s->tank_ref[1] = ref[1];
  /* the liquid at rest: its weight and the weight's moment about the reference point, per unit width */
  PetscCall(DMSwarmGetLocalSize(s->swarm, &n));
  PetscCall(DMSwarmGetField(s->swarm, FS_FIELD_POSITION, NULL, NULL, (void **)&x));
  PetscCall(DMSwarmGetField(s->swarm, FS_FIELD_MASS, NULL, NULL, (void **)&m));
  for (PetscInt p = 0; p < n; p++) {
    loc[0] += m[p];
    loc[1] += m[p] * (x[2 * p] - ref[0]);
    loc[2] += m[p] * (x[2 * p + 1] - ref[1]);
  }
  PetscCall(DMSwarmRestoreField(s->swarm, FS_FIELD_MASS, NULL, NULL, (void **)&m));
  PetscCall(DMSwarmRestoreField(s->swarm, FS_FIELD_POSITION, NULL, NULL, (void **)&x));
  PetscCallMPI(MPI_Allreduce(loc, glob, 3, MPIU_REAL, MPI_SUM, comm));
  s->liquid_mass          = glob[0] * s->tank_width;
  s->static_loads.force[0] = glob[0] * s->gravity[0] * s->tank_width;
  s->static_loads.force[1] = glob[0] * s->gravity[1] * s->tank_width;
  s->static_loads.moment[2] = (glob[1] * s->gravity[1] - glob[2] * s->gravity[0]) * s->tank_width;
  PetscFunctionReturn(0);
}

/*
   FSSolverGetLiquidMass - the mass of the liquid the structure carries: the 2-D liquid's mass times
   the tank's width (-fs_tank_width) when the liquid and the structure are coupled, else 0. Known after
   the particles are created, in FSSolverSetUp() before the structure's set-up (a structure's
   payload may depend on it, as -fs_beam_payload_mass does).

   Not collective

.seealso: FSSolverSetUp(), FSStructureGetSolver()
*/
PetscErrorCode FSSolverGetLiquidMass(FSSolver s, PetscReal *mass)
{
  PetscFunctionBegin;
  *mass = s->liquid_mass;
  PetscFunctionReturn(0);
}

/*
   FSSolverCouplingPredict - at the start of a right-hand side: the structure's state of this stage on
   every rank, and the tank's motion it gives with the liquid at rest (its dynamic loads left out),
   the body acceleration field s->body of the tank's frame it gives, and the tank's angle (it depends
   on the state alone). The walls extrapolate the pressure hydrostatically with that field: it depends on this stage's state alone, so runs stay
   reproducible (restarts, output intervals), and it misses only the liquid's share of the tank's
   acceleration.

   Collective
*/
PetscErrorCode FSSolverCouplingPredict(FSSolver s, const PetscReal *u)
{
  FSStructure st   = s->structure;
  MPI_Comm    comm = PetscObjectComm((PetscObject)s);
  PetscMPIInt  rank;
  FSLoads      none;
  FSTankMotion predicted;

  PetscFunctionBegin;
  PetscCallMPI(MPI_Comm_rank(comm, &rank));
  PetscCall(FSSolverStructureBroadcastState(s, u));
  PetscCall(PetscMemzero(&none, sizeof(none)));
  {
    PetscErrorCode ierr = 0;
    if (!rank) {
      ierr = (*st->ops.rhs)(st, s->rhs_time, s->sy, &none, s->sydot);
      if (!ierr) ierr = (*st->ops.motion)(st, s->sy, s->sydot, &predicted);
    }
    PetscCall(FSSolverStructureResultRank0(s, ierr, "right-hand side or motion", FS_MOTION_NREAL, (PetscReal *)&predicted));
  }
  s->angle = predicted.angle;
  FrameField(s, &predicted, &s->body);
  PetscFunctionReturn(0);
}

/*
   FSSolverCouplingRates - the structure's part of a right-hand side when coupled (steps 1-3 above,
   after FSSolverCouplingPredict): the loads of this stage to the structure, its rate into f (rank 0),
   and the tank's motion at this stage on every rank (s->motion).

   Collective
*/
PetscErrorCode FSSolverCouplingRates(FSSolver s, PetscReal *f)
{
  FSStructure st   = s->structure;
  MPI_Comm    comm = PetscObjectComm((PetscObject)s);
  PetscReal   F[2] = {0, 0}, M = 0;
  const PetscReal c = PetscCosReal(s->angle), sn = PetscSinReal(s->angle);
  PetscMPIInt rank;

  PetscFunctionBegin;
  PetscCallMPI(MPI_Comm_rank(comm, &rank));
  /* the liquid's loads at this stage, about the reference point, in the global axes */
  if (s->loads_from_walls) {
    const PetscReal *L;
    PetscReal        lp[3];
    PetscInt         nwalls;
    PetscCall(FSBoundaryGetLoads(s->boundary, &nwalls, NULL, &L));
    PetscCall(FSBoundaryGetLoadPoint(s->boundary, lp));
    for (PetscInt w = 0; w < nwalls; w++) {
      F[0] += L[6 * w];
      F[1] += L[6 * w + 1];
      M += L[6 * w + 5];
    }
    M += (lp[0] - s->tank_ref[0]) * F[1] - (lp[1] - s->tank_ref[1]) * F[0];
  } else {
    F[0] = -s->reaction[0];
    F[1] = -s->reaction[1];
    M    = -s->reaction[2];
  }
  s->tank_load[0] = F[0]; /* in the tank's frame, per unit width, about the reference point: for the energy budget */
  s->tank_load[1] = F[1];
  s->tank_load[2] = M;
  PetscCall(PetscMemzero(&s->loads, sizeof(s->loads)));
  s->loads.force[0]  = (c * F[0] - sn * F[1]) * s->tank_width - s->static_loads.force[0];
  s->loads.force[1]  = (sn * F[0] + c * F[1]) * s->tank_width - s->static_loads.force[1];
  s->loads.moment[2] = M * s->tank_width - s->static_loads.moment[2];
  /* the structure's rate under them (its state is on every rank since the prediction), and the tank's motion */
  {
    PetscErrorCode ierr; /* rank 0's: checked with the motion's broadcast, one collective for both */
    PetscCall(FSSolverStructureRates(s, PETSC_FALSE, NULL, f, &ierr));
    if (!rank && !ierr) ierr = (*st->ops.motion)(st, s->sy, s->sydot, &s->motion);
    PetscCall(FSSolverStructureResultRank0(s, ierr, "right-hand side or motion", FS_MOTION_NREAL, (PetscReal *)&s->motion));
  }
  PetscFunctionReturn(0);
}

/*
   FSSolverCouplingReaction - after the terms, before the inertial accelerations and the relaxation:
   the force (2) and moment about the reference point (1) that all terms but gravity put on the
   particles, sum_i m_i (f_i - g) and sum_i r_i x m_i (f_i - g), per unit width in the tank's frame:
   this rank's share in local[], the sum over the ranks in s->reaction. Internal forces cancel (up to
   the renormalization near walls, which the walls take): it is the walls' force on the liquid, whose
   reaction the structure receives with -fs_coupling_loads reaction, so that the coupled system keeps
   Newton's third law and the energy the loads give the structure is what the liquid loses.

   Collective
*/
PetscErrorCode FSSolverCouplingReaction(FSSolver s, const PetscReal *f, PetscReal local[3])
{
  const PetscInt S = s->stride, US = s->ustride, n = s->nowned;

  PetscFunctionBegin;
  local[0] = local[1] = local[2] = 0;
  for (PetscInt i = 0; i < n; i++) {
    const PetscReal *ri = &s->rec[i * S];
    const PetscReal  rx = ri[0] - s->tank_ref[0], ry = ri[1] - s->tank_ref[1];
    const PetscReal  fx = ri[5] * (f[i * US + 2] - s->gravity[0]), fy = ri[5] * (f[i * US + 3] - s->gravity[1]);
    local[0] += fx;
    local[1] += fy;
    local[2] += rx * fy - ry * fx;
  }
  PetscCallMPI(MPI_Allreduce(local, s->reaction, 3, MPIU_REAL, MPI_SUM, PetscObjectComm((PetscObject)s)));
  PetscFunctionReturn(0);
}

/*
   FSSolverCouplingInertia - step 4: the inertial accelerations of the tank's frame added to the
   owned particles' rates f; returns their power sum_i m_i u_i . a on this rank (P_ext).
*/
PetscErrorCode FSSolverCouplingInertia(FSSolver s, PetscReal *f, PetscReal *power)
{
  const PetscInt S = s->stride, US = s->ustride, n = s->nowned;
  FSFrameField   ff;
  PetscReal      pw = 0;

  PetscFunctionBegin;
  FrameField(s, &s->motion, &ff);
  ff.b[0] -= s->gravity[0]; /* the gravity term adds g itself */
  ff.b[1] -= s->gravity[1];
  for (PetscInt i = 0; i < n; i++) {
    const PetscReal *ri = &s->rec[i * S];
    const PetscReal  ux = ri[2], uy = ri[3];
    PetscReal        a[2];
    FSFrameFieldEval(&ff, ri, a);
    const PetscReal ax = a[0] + 2 * ff.omega * uy, ay = a[1] - 2 * ff.omega * ux; /* with Coriolis */
    f[i * US + 2] += ax;
    f[i * US + 3] += ay;
    pw += ri[5] * (ux * ax + uy * ay);
  }
  *power = pw;
  PetscFunctionReturn(0);
}
