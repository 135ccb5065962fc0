/*
   The coupling of the liquid and the structure (seed sections II.C-II.D): the liquid is solved in the
   tank's frame, where the walls are at rest; the structure's rigid motion of the tank enters the
   liquid as inertial accelerations, and the liquid's loads on the walls (the integral of the wall
   pressure and the wall shear, seed Eq. 29) drive the structure. Both happen inside every right-hand
   side, so the one TS advances the coupled system with the integrator's own order:

     1. the structure's state y at this stage (rank 0, broadcast) gives the tank's rotation theta;
     2. the liquid's loads at this stage (they depend on the particles only): minus the force and moment
        all terms but gravity put on the particles (by default; Newton's third law, so the coupled system
        conserves momentum and energy), or the wall-pressure integral; taken about the tank's reference point, turned
into the global axes, scaled by the tank's width (the liquid is 2-D: loads per unit width), and their value for the
liquid at rest in the undeflected tank is subtracted (the structure's deflections are measured from its static
equilibrium under gravity, liquid included);
     3. the structure's rate dy/dt under those loads gives the tank's acceleration A, angular rate
        omega and angular acceleration alpha at this stage;
     4. every particle gets, in the tank frame with r = x - x_ref,
          a = R(-theta) g - g - R(-theta) A - alpha e_z x r - 2 omega e_z x u + omega^2 r
        (the gravity term adds g itself), whose power sum_i m_i u_i . a is the work of the tank on
        the liquid, P_ext.
   FSCoupling holds the frame and the loads; the solver evaluates the structure (src/solver/structure.c)
   and hands the coupling the motions it gives. Explicit and stable while the liquid is light against the structure
(here a few per cent of the moving mass): the loads at a stage use the liquid's state, not its acceleration, so the
liquid's added mass is carried by the loads one stage late. A liquid as heavy as the structure would need the added mass
moved to the structure's side (or an implicit coupling).

   Options Database Keys:
+  -fs_coupling <bool>               - couple the liquid and the structure (default: when both exist)
.  -fs_coupling_loads <reaction|walls> - the loads the structure receives: the reaction of the terms' forces on the
liquid (default), or the wall-pressure integral .  -fs_tank_width <w>                - the tank's width across the 2-D
plane (0.1 m): loads per unit width times w
-  -fs_tank_reference <x,y>          - the tank's point on the beam, in the tank's frame (default: the middle of the
floor)
*/
#include "couplingimpl.h"
#include "sys/fssys.h"

/* the tank frame's body acceleration field (gravity and the frame's inertia but Coriolis) of a motion */
static void FrameField(FSCoupling c, const FSTankMotion *mo, FSFrameField *ff)
{
  const PetscReal cs = PetscCosReal(mo->angle), sn = PetscSinReal(mo->angle);
  const PetscReal gx = c->gravity[0] - mo->acc[0], gy = c->gravity[1] - mo->acc[1];

  ff->rotated = mo->rotated != 0 ? PETSC_TRUE : PETSC_FALSE;
  ff->ref_z   = c->tank_ref[2];
  if (ff->rotated) { /* b = Q^T (g - A); the angular velocity and acceleration in the tank's axes */
    const PetscReal *Q = mo->Q, G[3] = {gx, gy, c->gravity[2] - mo->acc[2]};
    for (PetscInt d = 0; d < 3; d++) {
      ff->b[d]  = Q[d] * G[0] + Q[3 + d] * G[1] + Q[6 + d] * G[2];
      ff->w[d]  = mo->w[d];
      ff->dw[d] = mo->dw[d];
    }
    ff->omega = ff->alpha = 0;
    ff->ref[0]            = c->tank_ref[0];
    ff->ref[1]            = c->tank_ref[1];
    return;
  }
  for (PetscInt d = 0; d < 3; d++) ff->w[d] = ff->dw[d] = 0;
  ff->b[0]   = cs * gx + sn * gy;
  ff->b[1]   = -sn * gx + cs * gy;
  ff->b[2]   = c->gravity[2] - mo->acc[2];
  ff->omega  = mo->rate;
  ff->alpha  = mo->angacc;
  ff->ref[0] = c->tank_ref[0];
  ff->ref[1] = c->tank_ref[1];
}

/* FSCouplingCreate - a coupling, off until FSCouplingSetUp() decides. Collective. */
PetscErrorCode FSCouplingCreate(MPI_Comm comm, FSCoupling *coupling)
{
  FSCoupling c;

  PetscFunctionBegin;
  PetscCall(PetscNew(&c));
  c->comm       = comm;
  c->tank_width = 0.1;
  *coupling     = c;
  PetscFunctionReturn(0);
}

/* the coupling's options (FSCouplingSetUp, FSCouplingHelp): whether to couple, the loads, the width, the reference
 * point */
static PetscErrorCode CouplingOptions(FSCoupling c, PetscOptionItems *PetscOptionsObject, PetscBool *want,
                                      PetscReal ref[3], PetscInt *nref, PetscBool *set)
{
  const char *loadtypes[] = {"reaction", "walls"};
  PetscInt    lt          = c->loads_from_walls ? 1 : 0;

  PetscFunctionBegin;
  PetscCall(PetscOptionsBool("-fs_coupling",
                             "Couple the liquid and the structure (loads to the structure, tank motion to the liquid)",
                             "FSCouplingSetUp", *want, want, NULL));
  PetscCall(PetscOptionsEList(
      "-fs_coupling_loads",
      "The liquid's loads the structure receives: reaction (minus the force and moment of all terms but gravity on the "
      "particles: Newton's third law) or walls (the integral of the wall pressure and shear)",
      "FSCouplingSetUp", loadtypes, 2, loadtypes[c->loads_from_walls ? 1 : 0], &lt, NULL));
  c->loads_from_walls = lt == 1 ? PETSC_TRUE : PETSC_FALSE;
  PetscCall(FSOptionsReal(PetscOptionsObject, "-fs_tank_width",
                          "Width of the tank across the 2-D plane: the liquid's loads per unit width times this",
                          "FSCouplingSetUp", &c->tank_width, NULL, 0, PETSC_INFINITY, FS_RANGE_OPEN_LOWER));
  PetscCall(FSOptionsRealArray(PetscOptionsObject, "-fs_tank_reference",
                               "The tank's point on the beam, in the tank's frame, x,y (3-D: x,y[,z]; the centre of a "
                               "prescribed rotation; default: the middle of the floor)",
                               "FSCouplingSetUp", ref, nref, set, PETSC_NINFINITY, PETSC_INFINITY, FS_RANGE_CLOSED));
  PetscFunctionReturn(0);
}

/*
   FSCouplingSetUp - decides whether the liquid and the structure are coupled, reads the coupling
   options and computes the loads of the liquid at rest (weight and its moment about the reference
   point), which the structure does not see. possible: there is a structure, walls and liquid; b: the
   walls (the default reference point is the middle of their floor); x, m: this rank's n particles'
   positions (dim each) and masses. After the walls and particles, before the structure's set-up (its
   payload may depend on the liquid's mass). In 3-D the liquid's loads are the tank's (no width factor)
   and the reference point's z is the middle of the walls' width.

   Collective
*/
PetscErrorCode FSCouplingSetUp(FSCoupling c, PetscBool possible, PetscInt dim, const PetscReal gravity[], FSBoundary b,
                               PetscInt n, const PetscReal x[], const PetscReal m[])
{
  MPI_Comm  comm = c->comm;
  PetscBool want = PETSC_TRUE, set;
  PetscReal ref[3], loc[4] = {0, 0, 0, 0}, glob[4], lo[3], hi[3];
  PetscInt  nref = 3;

  PetscFunctionBegin;
  c->coupled = PETSC_FALSE;
  c->dim     = dim;
  for (PetscInt d = 0; d < 3; d++) c->gravity[d] = gravity[d];
  PetscCall(PetscMemzero(&c->body, sizeof(c->body))); /* without a coupling the frame's body acceleration is g */
  c->body.b[0] = gravity[0];
  c->body.b[1] = gravity[1];
  c->body.b[2] = gravity[2];
  if (!possible) PetscFunctionReturn(0);
  PetscCall(FSBoundaryGetBoundingBox(b, lo, hi));
  ref[0] = 0.5 * (lo[0] + hi[0]);
  ref[1] = lo[1];
  ref[2] = dim == 3 ? 0.5 * (lo[2] + hi[2]) : 0;
  PetscOptionsBegin(comm, NULL, "Coupling of the liquid and the structure", "FS");
  PetscCall(CouplingOptions(c, PetscOptionsObject, &want, ref, &nref, &set));
  PetscOptionsEnd();
  PetscCheck(!set || nref == 2 || (nref == 3 && dim == 3), comm, PETSC_ERR_ARG_SIZ,
             "-fs_tank_reference takes two values x,y%s; got %" PetscInt_FMT, dim == 3 ? " (3-D: or x,y,z)" : "", nref);
  if (set && nref == 2) ref[2] = dim == 3 ? 0.5 * (lo[2] + hi[2]) : 0;
  for (PetscInt d = 0; set && d < nref;
       d++) { /* on the beam next to the tank: within the walls' box grown by its size */
    const PetscReal size = hi[d] - lo[d];
    PetscCheck(ref[d] >= lo[d] - size && ref[d] <= hi[d] + size, comm, PETSC_ERR_ARG_OUTOFRANGE,
               "-fs_tank_reference %g,%g%s: its %c must lie in [%g, %g] (the walls' extent grown by its size on each "
               "side)",
               (double)ref[0], (double)ref[1], nref == 3 ? ",z" : "", "xyz"[d], (double)(lo[d] - size),
               (double)(hi[d] + size));
  }
  PetscCheck(c->tank_width > 0, comm, PETSC_ERR_ARG_OUTOFRANGE, "-fs_tank_width %g must be positive",
             (double)c->tank_width);
  if (!want) PetscFunctionReturn(0);
  c->coupled     = PETSC_TRUE;
  c->tank_ref[0] = ref[0];
  c->tank_ref[1] = ref[1];
  c->tank_ref[2] = ref[2];
  if (dim == 3) c->tank_width = 1; /* the liquid's loads are the whole tank's */
  /* the liquid at rest: its weight and the weight's moment about the reference point, per unit width */
  for (PetscInt p = 0; p < n; p++) {
    loc[0] += m[p];
    loc[1] += m[p] * (x[dim * p] - ref[0]);
    loc[2] += m[p] * (x[dim * p + 1] - ref[1]);
    if (dim == 3) loc[3] += m[p] * (x[dim * p + 2] - c->tank_ref[2]);
  }
  PetscCallMPI(MPI_Allreduce(loc, glob, dim == 3 ? 4 : 3, MPIU_REAL, MPI_SUM, comm));
  c->liquid_mass            = glob[0] * c->tank_width;
  c->static_loads.force[0]  = glob[0] * c->gravity[0] * c->tank_width;
  c->static_loads.force[1]  = glob[0] * c->gravity[1] * c->tank_width;
  c->static_loads.moment[2] = (glob[1] * c->gravity[1] - glob[2] * c->gravity[0]) * c->tank_width;
  if (dim == 3) { /* the weight's out-of-plane components: sum m r x g */
    c->static_loads.force[2]  = glob[0] * c->gravity[2];
    c->static_loads.moment[0] = glob[2] * c->gravity[2] - glob[3] * c->gravity[1];
    c->static_loads.moment[1] = glob[3] * c->gravity[0] - glob[1] * c->gravity[2];
  }
  PetscFunctionReturn(0);
}

/*
   FSCouplingHelp - with -help, lists the coupling's options (a run reads them at set-up, only when a
   structure carries a tank of liquid), on a scratch coupling.

   Collective
*/
PetscErrorCode FSCouplingHelp(MPI_Comm comm)
{
  FSCoupling c      = NULL;
  PetscBool  want   = PETSC_TRUE, set;
  PetscReal  ref[3] = {0, 0, 0};
  PetscInt   nref   = 3;

  PetscFunctionBegin;
  PetscCall(FSCouplingCreate(comm, &c));
  PetscOptionsBegin(comm, NULL, "Coupling of the liquid and the structure (with a structure and a tank)", "FS");
  PetscCall(FSOptionsSurveyBlock(PetscOptionsObject));
  PetscCall(FSOptionsSurveyOwner("coupling", NULL));
  PetscCall(CouplingOptions(c, PetscOptionsObject, &want, ref, &nref, &set));
  PetscCall(FSOptionsSurveyOwner(NULL, NULL));
  PetscOptionsEnd();
  PetscCall(FSCouplingDestroy(&c));
  PetscFunctionReturn(0);
}

/* FSCouplingGetActive - whether the liquid and the structure are coupled. Not collective. */
PetscErrorCode FSCouplingGetActive(FSCoupling c, PetscBool *active)
{
  PetscFunctionBegin;
  *active = c->coupled;
  PetscFunctionReturn(0);
}

/* FSCouplingGetLiquidMass - the whole tank's liquid mass (the 2-D mass times the width), 0 uncoupled. */
PetscErrorCode FSCouplingGetLiquidMass(FSCoupling c, PetscReal *mass)
{
  PetscFunctionBegin;
  *mass = c->liquid_mass;
  PetscFunctionReturn(0);
}

/* FSCouplingGetWidth - the factor from the liquid's 2-D energies and loads to the tank's: the tank's
   width when coupled in 2-D, else 1. */
PetscErrorCode FSCouplingGetWidth(FSCoupling c, PetscReal *w)
{
  PetscFunctionBegin;
  *w = c->coupled ? c->tank_width : 1.0;
  PetscFunctionReturn(0);
}

/* FSCouplingGetBody - the body acceleration field of the tank's frame at this stage (gravity uncoupled). */
PetscErrorCode FSCouplingGetBody(FSCoupling c, const FSFrameField **body)
{
  PetscFunctionBegin;
  *body = &c->body;
  PetscFunctionReturn(0);
}

/*
   FSCouplingSetPredictedMotion - at the start of a right-hand side, the tank's motion the structure's
   state of this stage gives with the liquid at rest (its dynamic loads left out): the body acceleration
   field of the tank's frame (FSCouplingGetBody) and the tank's angle (it depends on the state alone).
   The walls extrapolate the pressure hydrostatically with that field: it depends on this stage's
   state alone, so runs stay reproducible (restarts, output intervals), and it misses only the liquid's
   share of the tank's acceleration.
*/
PetscErrorCode FSCouplingSetPredictedMotion(FSCoupling c, const FSTankMotion *predicted)
{
  PetscFunctionBegin;
  c->angle     = predicted->angle;
  c->predicted = *predicted;
  FrameField(c, predicted, &c->body);
  PetscFunctionReturn(0);
}

/*
   FSCouplingReaction - after the terms, before the inertial accelerations and the relaxation: the
   force (2) and moment about the reference point (1) that all terms but gravity put on the particles,
   sum_i m_i (f_i - g) and sum_i r_i x m_i (f_i - g), per unit width in the tank's frame (in 3-D the
   whole tank's, the out-of-plane components F_z, M_x, M_y kept apart for the output), from the n
   owned particles' records rec (stride) and rates f (ustride): this rank's share in local[], the sum
   over the ranks kept for FSCouplingComputeLoads() and FSCouplingPower(). Internal forces cancel (up
   to the renormalization near walls, which the walls take): it is the walls' force on the liquid, whose
   reaction the structure receives with -fs_coupling_loads reaction, so that the coupled system keeps
   Newton's third law and the energy the loads give the structure is what the liquid loses.
   extra[0..nextra): other sums of this rank's that ride on the same MPI_Allreduce (the right-hand side's
   powers), replaced by their sums over the ranks: a coupled stage takes one collective.

   Collective
*/
/* the sums of FSCouplingReaction for a compile-time dimension D: in-plane F_x, F_y, M_z, then (3-D) F_z, M_x, M_y */
FS_ALWAYS_INLINE void ReactionSums(PetscInt D, FSCoupling c, PetscInt n, PetscInt S, const PetscReal rec[], PetscInt US,
                                   const PetscReal f[], PetscReal all[6])
{
  for (PetscInt i = 0; i < n; i++) {
    const PetscReal *ri = &rec[i * S], mi = ri[2 * D + 1];
    const PetscReal  rx = ri[0] - c->tank_ref[0], ry = ri[1] - c->tank_ref[1];
    const PetscReal  fx = mi * (f[i * US + D] - c->gravity[0]), fy = mi * (f[i * US + D + 1] - c->gravity[1]);
    all[0] += fx;
    all[1] += fy;
    all[2] += rx * fy - ry * fx;
    if (D == 3) {
      const PetscReal rz = ri[2] - c->tank_ref[2], fz = mi * (f[i * US + D + 2] - c->gravity[2]);
      all[3] += fz;
      all[4] += ry * fz - rz * fy;
      all[5] += rz * fx - rx * fz;
    }
  }
}

PetscErrorCode FSCouplingReaction(FSCoupling c, PetscInt n, PetscInt S, const PetscReal rec[], PetscInt US,
                                  const PetscReal f[], PetscReal local[3], PetscInt nextra, PetscReal extra[])
{
  PetscReal      all[6 + FS_COUPLING_MAX_EXTRA] = {0, 0, 0, 0, 0, 0};
  const PetscInt nr                             = c->dim == 3 ? 6 : 3;

  PetscFunctionBegin;
  PetscCheck(nextra >= 0 && nextra <= FS_COUPLING_MAX_EXTRA, c->comm, PETSC_ERR_PLIB,
             "FSCouplingReaction: %" PetscInt_FMT " extra sums, at most %d", nextra, FS_COUPLING_MAX_EXTRA);
  if (c->dim == 2) ReactionSums(2, c, n, S, rec, US, f, all);
  else ReactionSums(3, c, n, S, rec, US, f, all);
  for (PetscInt k = 0; k < 3; k++) local[k] = all[k];
  for (PetscInt k = 0; k < nextra; k++) all[nr + k] = extra[k];
  PetscCallMPI(MPI_Allreduce(MPI_IN_PLACE, all, (PetscMPIInt)(nr + nextra), MPIU_REAL, MPI_SUM, c->comm));
  for (PetscInt k = 0; k < 3; k++) {
    c->reaction[k]     = all[k];
    c->reaction_out[k] = c->dim == 3 ? all[3 + k] : 0;
  }
  for (PetscInt k = 0; k < nextra; k++) extra[k] = all[nr + k];
  PetscFunctionReturn(0);
}

/* FSCouplingGetReaction - the reaction (in-plane F_x, F_y, M_z) of the last FSCouplingReaction(), summed over the
   ranks. Not collective */
PetscErrorCode FSCouplingGetReaction(FSCoupling c, PetscReal reaction[3])
{
  PetscFunctionBegin;
  for (PetscInt k = 0; k < 3; k++) reaction[k] = c->reaction[k];
  PetscFunctionReturn(0);
}

/*
   FSCouplingComputeLoads - the liquid's loads at this stage for the structure (step 2 above): about the
   reference point, in the global axes for the tank's angle at this stage, times the tank's width, less the static
   loads. From the reaction (FSCouplingReaction) or, with -fs_coupling_loads walls, from the walls'
   loads b (collective then).
*/
PetscErrorCode FSCouplingComputeLoads(FSCoupling c, FSBoundary b, FSLoads *loads)
{
  PetscReal       F[2] = {0, 0}, M = 0, out[3] = {0, 0, 0}; /* out: 3-D F_z, M_x, M_y in the tank's frame */
  const PetscReal cs = PetscCosReal(c->angle), sn = PetscSinReal(c->angle);

  PetscFunctionBegin;
  if (c->loads_from_walls) {
    const PetscReal *L;
    PetscReal        lp[3], r[3];
    PetscInt         nwalls;
    PetscCall(FSBoundaryGetLoads(b, &nwalls, &L));
    PetscCall(FSBoundaryGetLoadPoint(b, lp));
    for (PetscInt w = 0; w < nwalls; w++) {
      F[0] += L[FS_WALL_LOAD_STRIDE * w];
      F[1] += L[FS_WALL_LOAD_STRIDE * w + 1];
      M += L[FS_WALL_LOAD_STRIDE * w + 5];
      out[0] += L[FS_WALL_LOAD_STRIDE * w + 2];
      out[1] += L[FS_WALL_LOAD_STRIDE * w + 3];
      out[2] += L[FS_WALL_LOAD_STRIDE * w + 4];
    }
    M += (lp[0] - c->tank_ref[0]) * F[1] - (lp[1] - c->tank_ref[1]) * F[0];
    for (PetscInt d = 0; d < 3; d++) r[d] = lp[d] - c->tank_ref[d]; /* the moments moved to the reference point */
    out[1] += r[1] * out[0] - r[2] * F[1];
    out[2] += r[2] * F[0] - r[0] * out[0];
  } else {
    F[0] = -c->reaction[0];
    F[1] = -c->reaction[1];
    M    = -c->reaction[2];
    for (PetscInt k = 0; k < 3; k++) out[k] = -c->reaction_out[k];
  }
  c->tank_load[0] = F[0]; /* in the tank's frame, per unit width, about the reference point: for the energy budget */
  c->tank_load[1] = F[1];
  c->tank_load[2] = M;
  for (PetscInt k = 0; k < 3; k++) c->tank_load_out[k] = out[k];
  PetscCall(PetscMemzero(loads, sizeof(*loads)));
  if (c->predicted.rotated != 0) { /* 3-D, turned about any axis: Q (F, out_F) and Q (out_M, M) */
    const PetscReal *Q = c->predicted.Q, Ft[3] = {F[0], F[1], out[0]}, Mt[3] = {out[1], out[2], M};
    for (PetscInt i = 0; i < 3; i++) {
      loads->force[i]  = Q[3 * i] * Ft[0] + Q[3 * i + 1] * Ft[1] + Q[3 * i + 2] * Ft[2] - c->static_loads.force[i];
      loads->moment[i] = Q[3 * i] * Mt[0] + Q[3 * i + 1] * Mt[1] + Q[3 * i + 2] * Mt[2] - c->static_loads.moment[i];
    }
    PetscFunctionReturn(0);
  }
  loads->force[0]  = (cs * F[0] - sn * F[1]) * c->tank_width - c->static_loads.force[0];
  loads->force[1]  = (sn * F[0] + cs * F[1]) * c->tank_width - c->static_loads.force[1];
  loads->moment[2] = M * c->tank_width - c->static_loads.moment[2];
  if (c->dim == 3) { /* the components the beam does not carry, turned about z into the global axes */
    loads->force[2]  = out[0] - c->static_loads.force[2];
    loads->moment[0] = cs * out[1] - sn * out[2] - c->static_loads.moment[0];
    loads->moment[1] = sn * out[1] + cs * out[2] - c->static_loads.moment[1];
  }
  PetscFunctionReturn(0);
}

/* FSCouplingSetMotion - the tank's motion at this stage (step 3 above, from the structure's rate). */
PetscErrorCode FSCouplingSetMotion(FSCoupling c, const FSTankMotion *motion)
{
  PetscFunctionBegin;
  c->motion = *motion;
  PetscFunctionReturn(0);
}

/*
   FSCouplingInertia - step 4: the inertial accelerations of the tank's frame for the motion of this
   stage added to the n owned particles' rates f (ustride; records rec with stride); returns their power
   sum_i m_i u_i . a on this rank (P_ext).
*/
PetscErrorCode FSCouplingInertia(FSCoupling c, PetscInt n, PetscInt S, const PetscReal rec[], PetscInt US,
                                 PetscReal f[], PetscReal *power)
{
  const PetscInt dim = c->dim;
  FSFrameField   ff;
  PetscReal      pw = 0;

  PetscFunctionBegin;
  FrameField(c, &c->motion, &ff);
  if (ff.rotated) { /* 3-D, turned about any axis: b - g - dw x r - w x (w x r) - 2 w x u */
    const PetscReal *w = ff.w;
    for (PetscInt i = 0; i < n; i++) {
      const PetscReal *ri = &rec[i * S], *u = &ri[3];
      PetscReal        a[3];
      FSFrameFieldEval3(&ff, ri, a);
      a[0] -= c->gravity[0] + 2 * (w[1] * u[2] - w[2] * u[1]);
      a[1] -= c->gravity[1] + 2 * (w[2] * u[0] - w[0] * u[2]);
      a[2] -= c->gravity[2] + 2 * (w[0] * u[1] - w[1] * u[0]);
      for (PetscInt d = 0; d < 3; d++) {
        f[i * US + 3 + d] += a[d];
        pw += ri[7] * u[d] * a[d];
      }
    }
    *power = pw;
    PetscFunctionReturn(0);
  }
  ff.b[0] -= c->gravity[0]; /* the gravity term adds g itself */
  ff.b[1] -= c->gravity[1];
  for (PetscInt i = 0; i < n; i++) { /* in 3-D the frame turns about z: along z only the tank's acceleration */
    const PetscReal *ri = &rec[i * S];
    const PetscReal  ux = ri[dim], uy = ri[dim + 1];
    PetscReal        a[2];
    FSFrameFieldEval(&ff, ri, a);
    const PetscReal ax = a[0] + 2 * ff.omega * uy, ay = a[1] - 2 * ff.omega * ux; /* with Coriolis */
    f[i * US + dim] += ax;
    f[i * US + dim + 1] += ay;
    pw += ri[2 * dim + 1] * (ux * ax + uy * ay);
  }
  if (dim == 3 && c->motion.acc[2] != 0) { /* a prescribed motion along z (a structure's is zero) */
    const PetscReal az = -c->motion.acc[2];
    for (PetscInt i = 0; i < n; i++) {
      f[i * US + dim + 2] += az;
      pw += rec[i * S + 2 * dim + 1] * rec[i * S + dim + 2] * az;
    }
  }
  *power = pw;
  PetscFunctionReturn(0);
}

/*
   FSCouplingInertiaSums - this rank's sums of the n owned particles that FSCouplingInertia()'s power is made of,
   for the sums over the ranks to ride on the reaction's MPI_Allreduce before the tank's motion of the stage is
   known: sums[d] = sum_i m_i u_d, sums[3 + 3 d + k] = sum_i m_i u_d r_k (r = x - the reference point, the tank's
   frame). The inertial acceleration is affine in r (a(r) = a(0) + J r) and the Coriolis part does no work, so
   P_ext = a(0) . sums[0..3) + sum_dk J_dk sums[3 + 3 d + k] (FSCouplingInertiaPower), the same power up to
   round-off. Not collective
*/
void FSCouplingInertiaSums(FSCoupling c, PetscInt n, PetscInt S, const PetscReal rec[],
                           PetscReal sums[FS_COUPLING_NINERTIA_SUMS])
{
  const PetscInt  dim    = c->dim;
  const PetscReal ref[3] = {c->tank_ref[0], c->tank_ref[1], c->tank_ref[2]};

  for (PetscInt k = 0; k < FS_COUPLING_NINERTIA_SUMS; k++) sums[k] = 0;
  for (PetscInt i = 0; i < n; i++) {
    const PetscReal *ri = &rec[i * S], m = ri[2 * dim + 1];
    for (PetscInt d = 0; d < dim; d++) {
      const PetscReal mu = m * ri[dim + d];
      sums[d] += mu;
      for (PetscInt k = 0; k < dim; k++) sums[3 + 3 * d + k] += mu * (ri[k] - ref[k]);
    }
  }
}

/* the inertial acceleration FSCouplingInertia() adds at r from the reference point, without the Coriolis part */
static void InertiaAcceleration(FSCoupling c, const FSFrameField *ff, const PetscReal r[3], PetscReal a[3])
{
  const PetscReal x[3] = {c->tank_ref[0] + r[0], c->tank_ref[1] + r[1], c->tank_ref[2] + r[2]};

  a[2] = 0;
  if (ff->rotated) {
    FSFrameFieldEval3(ff, x, a);
    for (PetscInt d = 0; d < 3; d++) a[d] -= c->gravity[d];
    return;
  }
  FSFrameFieldEval(ff, x, a);
  a[0] -= c->gravity[0];
  a[1] -= c->gravity[1];
  if (c->dim == 3) a[2] = -c->motion.acc[2];
}

/*
   FSCouplingInertiaPower - the power sum_i m_i u_i . a_i of the inertial accelerations of this stage's motion
   (FSCouplingInertia()'s) from FSCouplingInertiaSums()'s sums, summed over the ranks. Not collective
*/
PetscErrorCode FSCouplingInertiaPower(FSCoupling c, const PetscReal sums[FS_COUPLING_NINERTIA_SUMS], PetscReal *power)
{
  const PetscInt  dim     = c->dim;
  const PetscReal zero[3] = {0, 0, 0};
  FSFrameField    ff;
  PetscReal       a0[3], p = 0;

  PetscFunctionBegin;
  FrameField(c, &c->motion, &ff);
  InertiaAcceleration(c, &ff, zero, a0);
  for (PetscInt d = 0; d < dim; d++) p += a0[d] * sums[d];
  for (PetscInt k = 0; k < dim; k++) { /* column k of J: a(e_k) - a(0) */
    PetscReal e[3] = {0, 0, 0}, ak[3];
    e[k]           = 1;
    InertiaAcceleration(c, &ff, e, ak);
    for (PetscInt d = 0; d < dim; d++) p += (ak[d] - a0[d]) * sums[3 + 3 * d + k];
  }
  *power = p;
  PetscFunctionReturn(0);
}

/* the power w [F . R(-theta) V_ref + omega F_M] of the in-plane force F[0..1] and moment F[2] on the liquid moving
   with the tank's rigid motion (F in the tank's frame); turned about any axis (3-D), F . Q^T V_ref + w . M with the
   out-of-plane components out[] = F_z, M_x, M_y */
static PetscReal RigidPower(const FSCoupling c, const PetscReal F[3], const PetscReal out[3])
{
  const FSTankMotion *mo = &c->motion;
  const PetscReal     cs = PetscCosReal(mo->angle), sn = PetscSinReal(mo->angle);
  const PetscReal     vx = cs * mo->vel[0] + sn * mo->vel[1], vy = -sn * mo->vel[0] + cs * mo->vel[1];

  if (mo->rotated != 0) {
    const PetscReal *Q = mo->Q, *V = mo->vel, Ft[3] = {F[0], F[1], out[0]}, Mt[3] = {out[1], out[2], F[2]};
    PetscReal        p = 0;
    for (PetscInt d = 0; d < 3; d++) p += Ft[d] * (Q[d] * V[0] + Q[3 + d] * V[1] + Q[6 + d] * V[2]) + mo->w[d] * Mt[d];
    return p; /* 3-D: no width factor */
  }
  return c->tank_width * (F[0] * vx + F[1] * vy + mo->rate * F[2]);
}

/*
   FSCouplingPower - the power of the difference between the loads the structure receives and the
   reaction R of the walls' forces on the liquid (the sum over the ranks of FSCouplingReaction's local
   shares): w [(R + L) . R(-theta) V_ref + omega (R_M + L_M)], the energy the coupling creates.
*/
PetscErrorCode FSCouplingPower(FSCoupling c, const PetscReal R[3], PetscReal *power)
{
  const PetscReal *L      = c->tank_load;
  const PetscReal  F[3]   = {R[0] + L[0], R[1] + L[1], R[2] + L[2]};
  const PetscReal  out[3] = {c->reaction_out[0] + c->tank_load_out[0], c->reaction_out[1] + c->tank_load_out[1],
                             c->reaction_out[2] + c->tank_load_out[2]};

  PetscFunctionBegin;
  *power = RigidPower(c, F, out);
  PetscFunctionReturn(0);
}

/*
   FSCouplingMotionPower - the power a prescribed motion of the tank puts into the liquid: the walls'
   forces on the liquid (the reaction R, as for FSCouplingPower) times the walls' rigid velocity,
   w [R . R(-theta) V_ref + omega R_M], and in 3-D the force across the plane times the velocity along
   z. Its time integral is the work of the motion (work_motion), which changes the liquid's energy in the
   absolute frame.
*/
PetscErrorCode FSCouplingMotionPower(FSCoupling c, const PetscReal R[3], PetscReal *power)
{
  PetscFunctionBegin;
  *power = RigidPower(c, R, c->reaction_out);
  if (c->dim == 3 && c->motion.rotated == 0) *power += c->reaction_out[0] * c->motion.vel[2];
  PetscFunctionReturn(0);
}

/* FSCouplingAbsoluteEnergy - a particle's kinetic and potential energy in the absolute frame (coupled),
   its tank-frame position x and velocity v carried by the tank's motion mo (c, sn: cos and sin of its
   angle); in 3-D the frame turns about z, so z and v_z carry over. */
void FSCouplingAbsoluteEnergy(FSCoupling cp, const FSTankMotion *mo, PetscReal c, PetscReal sn, const PetscReal x[],
                              const PetscReal v[], PetscReal m, PetscReal *kin, PetscReal *pot)
{
  const PetscReal rx = x[0] - cp->tank_ref[0], ry = x[1] - cp->tank_ref[1];
  const PetscReal wx = v[0] - mo->rate * ry, wy = v[1] + mo->rate * rx; /* u + omega e_z x r */

  if (mo->rotated != 0) { /* 3-D, turned about any axis: V = V_ref + Q (u + w x r), X = x_ref + D + Q r */
    const PetscReal *Q = mo->Q, *w = mo->w, r[3] = {rx, ry, x[2] - cp->tank_ref[2]};
    const PetscReal  W[3] = {v[0] + w[1] * r[2] - w[2] * r[1], v[1] + w[2] * r[0] - w[0] * r[2],
                             v[2] + w[0] * r[1] - w[1] * r[0]};
    *kin = *pot = 0;
    for (PetscInt i = 0; i < 3; i++) {
      const PetscReal Vi = mo->vel[i] + Q[3 * i] * W[0] + Q[3 * i + 1] * W[1] + Q[3 * i + 2] * W[2];
      const PetscReal Xi = cp->tank_ref[i] + mo->disp[i] + Q[3 * i] * r[0] + Q[3 * i + 1] * r[1] + Q[3 * i + 2] * r[2];
      *kin += 0.5 * m * Vi * Vi;
      *pot -= m * cp->gravity[i] * Xi;
    }
    return;
  }
  const PetscReal Vx = mo->vel[0] + c * wx - sn * wy, Vy = mo->vel[1] + sn * wx + c * wy;
  const PetscReal Xx = cp->tank_ref[0] + mo->disp[0] + c * rx - sn * ry,
                  Xy = cp->tank_ref[1] + mo->disp[1] + sn * rx + c * ry;
  *kin               = 0.5 * m * (Vx * Vx + Vy * Vy);
  *pot               = -m * (cp->gravity[0] * Xx + cp->gravity[1] * Xy);
  if (cp->dim == 3) { /* plus the tank's translation along z (zero but for a prescribed motion) */
    const PetscReal Vz = mo->vel[2] + v[2];
    *kin += 0.5 * m * Vz * Vz;
    *pot -= m * cp->gravity[2] * (x[2] + mo->disp[2]);
  }
}

/* FSCouplingStaticLoadsWork - the potential of the liquid's static loads at the tank's motion mo:
   L_s . (d, theta) (0 uncoupled). */
PetscErrorCode FSCouplingStaticLoadsWork(FSCoupling c, const FSTankMotion *mo, PetscReal *w)
{
  PetscFunctionBegin;
  *w = c->coupled ? c->static_loads.force[0] * mo->disp[0] + c->static_loads.force[1] * mo->disp[1] +
                        c->static_loads.moment[2] * mo->angle
                  : 0;
  PetscFunctionReturn(0);
}

PetscErrorCode FSCouplingDestroy(FSCoupling *c)
{
  PetscFunctionBegin;
  PetscCall(PetscFree(*c));
  PetscFunctionReturn(0);
}
