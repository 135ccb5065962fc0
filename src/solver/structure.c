/*
   The structure inside the solver: its DOFs y are the first block of the state's global DOFs (after the
   particles), advanced by the same TS as the liquid. Every rank needs y at each stage (the tank's position and
   rotation for the fictitious forces). A structure written in C holds its DOFs on every rank and runs there: each
   rank computes dy/dt, the tank's motion and the energies from the same y and the same loads (reduced over the
   ranks), so that every rank holds the same values and no broadcast is needed. A rank0 structure (the callbacks'
   models: a Python structure) runs on rank 0 alone, which broadcasts y, the motion and its status (one broadcast
   per call) to the others. The loads are FSSolverSetLoads()'s (zero until the coupling).
*/
#include "solver/solverimpl.h"

/* FSSolverGetStructure - the run's structure (NULL with -fs_structure none). */
PetscErrorCode FSSolverGetStructure(FSSolver s, FSStructure *st)
{
  PetscFunctionBegin;
  *st = s->structure;
  PetscFunctionReturn(0);
}

/* FSSolverSetDefaultStructure - lets a case choose the default of -fs_structure (from its setfromoptions). */
PetscErrorCode FSSolverSetDefaultStructure(FSSolver s, const char name[])
{
  PetscFunctionBegin;
  PetscCall(PetscStrncpy(s->opt.structname, name, sizeof(s->opt.structname)));
  PetscFunctionReturn(0);
}

/*
   FSSolverSetLoads - the liquid's loads on the tank for the next right-hand sides (the coupling
   calls it; the structure sees zero loads until then). Loads are read where the structure runs: on every
   rank, which must give the same loads (the coupling's come from a reduction over the ranks), or on rank 0
   for a rank0 structure.
*/
PetscErrorCode FSSolverSetLoads(FSSolver s, const FSLoads *loads)
{
  PetscFunctionBegin;
  s->loads = *loads;
  PetscFunctionReturn(0);
}

/*
   FSSolverSetUpGlobalBlocks - lays out the global DOFs of the state: the structure's, then one
   dissipated energy per term with a power, then the energy block (FS_ENERGY_*). Called from
   FSSolverSetUp once the structure is set up.
*/
PetscErrorCode FSSolverSetUpGlobalBlocks(FSSolver s)
{
  PetscInt ndiss = 0;

  PetscFunctionBegin;
  for (PetscInt t = 0; t < s->terms.nterms; t++)
    if (s->terms.term[t]->has_power) ndiss++;
  s->state.ngblocks = 0;
  s->state.gstruct  = 0;
  PetscCall(PetscStrncpy(s->state.gblock[s->state.ngblocks].name, "structure", sizeof(s->state.gblock[0].name)));
  s->state.gblock[s->state.ngblocks].offset = 0;
  s->state.gblock[s->state.ngblocks++].n    = s->structure ? s->structure->ndof : 0;
  s->state.gdiss                            = s->state.gblock[0].n;
  s->state.nrepl = s->structure && !s->structure->rank0 ? s->structure->ndof : 0; /* on every rank */
  s->state.ndiss = ndiss;
  PetscCall(
      PetscStrncpy(s->state.gblock[s->state.ngblocks].name, "dissipated_energy", sizeof(s->state.gblock[0].name)));
  s->state.gblock[s->state.ngblocks].offset = s->state.gdiss;
  s->state.gblock[s->state.ngblocks++].n    = ndiss;
  s->state.genergy                          = s->state.gdiss + ndiss;
  PetscCall(PetscStrncpy(s->state.gblock[s->state.ngblocks].name, "energy_budget", sizeof(s->state.gblock[0].name)));
  s->state.gblock[s->state.ngblocks].offset = s->state.genergy;
  s->state.gblock[s->state.ngblocks++].n    = FS_ENERGY_NDOF;
  s->state.nglobaldofs                      = s->state.genergy + FS_ENERGY_NDOF;
  /* the checkpoint header keeps the global DOFs and four more values (FSSolverWriteCheckpoint) */
  PetscCheck(s->state.nglobaldofs + 4 <= FS_MAX_GLOBAL, PetscObjectComm((PetscObject)s), PETSC_ERR_ARG_OUTOFRANGE,
             "The state has %" PetscInt_FMT " global DOFs (structure %" PetscInt_FMT
             ", dissipated energies %" PetscInt_FMT ", energy budget %d), more than %d: use fewer structure modes",
             s->state.nglobaldofs, s->state.gdiss, ndiss, (int)FS_ENERGY_NDOF, FS_MAX_GLOBAL - 4);
  PetscFunctionReturn(0);
}

/*
   FSSolverGlobalDofName - what global DOF g of the state holds, in words, for the messages of the state's
   checks: "the structure msd's DOF 0 (of 2)", "the dissipated energy of term delta (dissipated_delta)",
   "the energy block's work_struct_damping".

   Not collective

   Input Parameters:
+  s   - the solver, set up
.  g   - the global DOF (0 .. s->state.nglobaldofs - 1)
-  len - the size of name

   Output Parameter:
.  name - the text

.seealso: FSSolverSetUpGlobalBlocks(), FSSolverCheckState()
*/
PetscErrorCode FSSolverGlobalDofName(FSSolver s, PetscInt g, char name[], size_t len)
{
  static const char *energy[] = {"work_ext",          "work_relax",  "work_struct_damping",
                                 "work_coupling",     "work_motion", "work_bounce",
                                 "work_bounce_total", "E_liquid(0)", "E_total(0)"};

  PetscFunctionBegin;
  PetscCheck(PETSC_STATIC_ARRAY_LENGTH(energy) == FS_ENERGY_NDOF, PETSC_COMM_SELF, PETSC_ERR_PLIB,
             "The energy block's names do not match FS_ENERGY_NDOF");
  if (g >= s->state.gstruct && g < s->state.gdiss)
    PetscCall(PetscSNPrintf(name, len, "the structure %s's DOF %" PetscInt_FMT " (of %" PetscInt_FMT ")",
                            s->structure->name, g - s->state.gstruct, s->state.gdiss - s->state.gstruct));
  else if (g >= s->state.gdiss && g < s->state.gdiss + s->state.ndiss) {
    PetscInt q = g - s->state.gdiss, t = 0; /* the q-th term with a power */
    for (; t < s->terms.nterms; t++)
      if (s->terms.term[t]->has_power && q-- == 0) break;
    PetscCall(PetscSNPrintf(name, len, "the dissipated energy of term %s (dissipated_%s)", s->terms.term[t]->name,
                            s->terms.term[t]->name));
  } else if (g >= s->state.genergy && g < s->state.genergy + FS_ENERGY_NDOF)
    PetscCall(PetscSNPrintf(name, len, "the energy block's %s", energy[g - s->state.genergy]));
  else PetscCall(PetscSNPrintf(name, len, "global DOF %" PetscInt_FMT, g));
  PetscFunctionReturn(0);
}

/*
   FSSolverStructureResultRank0 - a structure routine ran on rank 0 alone, returned ierr there and
   computed buf[0..n) (n <= FS_RANK0_MAX): one broadcast gives every rank buf and the error code, so
   that a failure (a Python structure's exception, a failed solve) stops the run everywhere instead of
   leaving the other ranks waiting in the next collective. n = 0 broadcasts the code alone. For a
   structure that runs on every rank (not rank0) each rank has computed buf and ierr itself: no
   broadcast, ierr returned as it is.

   Collective for a rank0 structure
*/
PetscErrorCode FSSolverStructureResultRank0(FSSolver s, PetscErrorCode ierr, const char what[], PetscInt n,
                                            PetscReal buf[])
{
  MPI_Comm    comm = PetscObjectComm((PetscObject)s);
  PetscMPIInt size, rank;
  PetscReal   pack[FS_RANK0_MAX + 1];
  char        msg[512] = "";
  int         code;

  PetscFunctionBegin;
  PetscCallMPI(MPI_Comm_size(comm, &size));
  /* the error as raised, its message first; a structure that runs on every rank has its result and status there */
  if (size == 1 || !s->structure->rank0) PetscFunctionReturn(ierr);
  PetscCheck(n <= FS_RANK0_MAX, comm, PETSC_ERR_PLIB,
             "FSSolverStructureResultRank0: %" PetscInt_FMT " values, at most %d", n, FS_RANK0_MAX);
  PetscCallMPI(MPI_Comm_rank(comm, &rank));
  pack[0] = (PetscReal)ierr;
  if (!rank)
    for (PetscInt k = 0; k < n; k++) pack[k + 1] = buf[k];
  PetscCallMPI(MPI_Bcast(pack, (PetscMPIInt)(n + 1), MPIU_REAL, 0, comm));
  code = (int)pack[0];
  if (!code) {
    for (PetscInt k = 0; k < n; k++) buf[k] = pack[k + 1];
    PetscFunctionReturn(0);
  }
  if (!rank) {
    const char *text = NULL;
    (void)PetscErrorMessage(ierr, NULL, (char **)&text);
    if (text) (void)PetscStrncpy(msg, text, sizeof(msg));
  }
  PetscCallMPI(MPI_Bcast(msg, (PetscMPIInt)sizeof(msg), MPI_CHAR, 0, comm));
  if (!rank) PetscFunctionReturn(ierr); /* rank 0 keeps the error as raised */
  SETERRQ(comm, (PetscErrorCode)code, "Structure %s: its %s failed on rank 0, where the structure lives: %s",
          s->structure->name, what, msg);
}

/* FSSolverStructureBroadcastState - the structure's state from the packed state u into s->sy on every rank: each
 * rank's own copy, or rank 0's broadcast for a rank0 structure. Collective for a rank0 structure. */
PetscErrorCode FSSolverStructureBroadcastState(FSSolver s, const PetscReal *u)
{
  PetscMPIInt rank, size;

  PetscFunctionBegin;
  PetscCallMPI(MPI_Comm_rank(PetscObjectComm((PetscObject)s), &rank));
  PetscCallMPI(MPI_Comm_size(PetscObjectComm((PetscObject)s), &size));
  if (FSSolverStructureHere(s))
    PetscCall(PetscArraycpy(s->sy, u + s->pw.nowned * s->state.ustride + s->state.gstruct, s->structure->ndof));
  if (size > 1 && s->structure->rank0)
    PetscCallMPI(MPI_Bcast(s->sy, (PetscMPIInt)s->structure->ndof, MPIU_REAL, 0, PetscObjectComm((PetscObject)s)));
  PetscFunctionReturn(0);
}

/*
   FSSolverStructureRates - the structure's part of a right-hand side: the structure's state from the packed state
   u (its global DOFs) into s->sy on every rank (FSSolverStructureBroadcastState), then dy/dt at s->state.rhs_time
   with the current loads into f (every rank; rank 0 alone for a rank0 structure).

   Collective
   With broadcast PETSC_FALSE s->sy already holds this stage's state on every rank (the coupling
   broadcast it) and u is not read. The flag is explicit: u itself cannot say it, since a rank that
   owns no entries of the state gets a NULL array from VecGetArrayRead().
   With rank0err NULL a failure of the structure's routine on rank 0 is raised on every rank here
   (one broadcast of the error code); else rank 0's code is returned in *rank0err (0 elsewhere) for a
   caller that broadcasts a result of its own next, to check it there (FSSolverStructureResultRank0)
   without a broadcast of its own.
*/
PetscErrorCode FSSolverStructureRates(FSSolver s, PetscBool broadcast, const PetscReal *u, PetscReal *f,
                                      PetscErrorCode *rank0err)
{
  FSStructure    st  = s->structure;
  const PetscInt off = s->pw.nowned * s->state.ustride + s->state.gstruct;

  PetscFunctionBegin;
  if (rank0err) *rank0err = 0;
  if (!st || !st->ndof) PetscFunctionReturn(0);
  PetscCall(PetscLogEventBegin(FS_Structure, 0, 0, 0, 0));
  if (broadcast) PetscCall(FSSolverStructureBroadcastState(s, u));
  {
    PetscErrorCode ierr = 0;
    if (FSSolverStructureHere(s)) {
      ierr = (*st->ops.rhs)(st, s->state.rhs_time, s->sy, &s->loads, s->sydot);
      if (!ierr && f) ierr = PetscArraycpy(f + off, s->sydot, st->ndof);
    }
    if (rank0err) *rank0err = ierr;
    else PetscCall(FSSolverStructureResultRank0(s, ierr, "right-hand side", 0, NULL));
  }
  PetscCall(PetscLogEventEnd(FS_Structure, 0, 0, 0, 0));
  PetscFunctionReturn(0);
}

/* The structure's state (every rank) and rate (rank 0) at the current state of the TS, the rate with
   the current loads; rank0err as in FSSolverStructureRates (NULL: a failure is raised here). */
static PetscErrorCode FSSolverStructureCurrent(FSSolver s, PetscErrorCode *rank0err)
{
  const PetscScalar *u;
  PetscReal          t;

  PetscFunctionBegin;
  PetscCall(TSGetTime(s->ts, &t));
  PetscCall(VecGetArrayRead(s->state.U, &u));
  s->state.rhs_time = t;
  PetscCall(FSSolverStructureRates(s, PETSC_TRUE, u, NULL, rank0err));
  PetscCall(VecRestoreArrayRead(s->state.U, &u));
  PetscFunctionReturn(0);
}

/*
   FSSolverGetTankMotion - the tank's motion at the current state (displacement, velocity and
   acceleration of its reference point, rotation angle, rate and angular acceleration), the same on
   every rank (computed there, or on rank 0 and broadcast for a rank0 structure). Zero without a structure; a structure
   without DOFs (a prescribed motion) gives its motion at the current time.

   Collective
*/
PetscErrorCode FSSolverGetTankMotion(FSSolver s, FSTankMotion *m)
{
  PetscErrorCode ierr;

  PetscFunctionBegin;
  PetscCall(PetscMemzero(m, sizeof(*m)));
  PetscCall(FSSolverSetUp(s)); /* the state exists from the set-up on */
  if (!s->structure) PetscFunctionReturn(0);
  PetscCall(FSSolverStructureCurrent(s, &ierr));
  if (FSSolverStructureHere(s) && !ierr)
    ierr = (*s->structure->ops.motion)(s->structure, s->state.rhs_time, s->sy, s->sydot, m);
  PetscCall(FSSolverStructureResultRank0(s, ierr, "right-hand side or motion", FS_MOTION_NREAL, (PetscReal *)m));
  PetscFunctionReturn(0);
}

/*
   FSSolverGetStructureState - the structure's state at the current TS state, on every rank.
   n (out) is the number of DOFs; y may be NULL to ask for n only.

   Collective
*/
PetscErrorCode FSSolverGetStructureState(FSSolver s, PetscInt *n, PetscReal y[])
{
  PetscFunctionBegin;
  *n = s->structure ? s->structure->ndof : 0;
  if (!*n || !y) PetscFunctionReturn(0);
  PetscCall(FSSolverSetUp(s));
  PetscCall(FSSolverStructureCurrent(s, NULL));
  PetscCall(PetscArraycpy(y, s->sy, *n));
  PetscFunctionReturn(0);
}

/*
   FSSolverStructureDt - the time step of a run without particles: the -ts_dt given, else
   -fs_structure_cfl times the shortest period the structure resolves.
*/
PetscErrorCode FSSolverStructureDt(FSSolver s, PetscReal *dt)
{
  PetscBool set;
  PetscReal user;

  PetscFunctionBegin;
  PetscCall(PetscOptionsGetReal(NULL, NULL, "-ts_dt", &user, &set));
  if (set) {
    PetscCheck(user > 0, PetscObjectComm((PetscObject)s), PETSC_ERR_ARG_OUTOFRANGE, "-ts_dt %g must be positive",
               (double)user);
    *dt = user;
  } else {
    PetscCheck(
        s->structure && s->structure->min_period > 0, PetscObjectComm((PetscObject)s), PETSC_ERR_ARG_WRONGSTATE,
        "A run without particles takes its time step from the structure, but structure %s gives no period: set -ts_dt",
        s->structure ? s->structure->name : "none");
    *dt = s->opt.structure_cfl * s->structure->min_period;
  }
  s->state.dt_stable = *dt;
  PetscFunctionReturn(0);
}

/*
   FSSolverStructureDtAdvice - at set-up, a warning when the structure's shortest period sets the time step of a run
   with liquid: -fs_structure_cfl times it is shorter than the liquid's acoustic step -fs_cfl h/(c0 + |u|max). It
   names the mode (for a model that lists its modes, e.g. modal), its frequency, both steps and their ratio (the
   factor on the number of steps), and what to do: keep the modes the liquid's step resolves (-fs_modal_modes K),
   or raise -fs_structure_cfl (docs/structures.md: what RK4 loses of a mode's amplitude at each fraction).

   Collective (rank 0 prints)
*/
PetscErrorCode FSSolverStructureDtAdvice(FSSolver s)
{
  FSStructure st = s->structure;
  PetscReal   dts, dtl, cfl;
  PetscInt    keep      = 0;
  char        mode[128] = "", advice[256] = "", text[1024];

  PetscFunctionBegin;
  if (!st || !(st->min_period > 0) || s->pw.nglobal_particles == 0) PetscFunctionReturn(0);
  dts = s->opt.structure_cfl * st->min_period;
  dtl = s->opt.cfl * s->opt.h / (s->opt.c0 + s->state.umax);
  if (dts >= dtl) PetscFunctionReturn(0);
  cfl = dtl / st->min_period;
  if (st->nmodes > 1) {
    for (PetscInt i = 0; i < st->nmodes && i < FS_STRUCTURE_MAX_MODES; i++)
      if (s->opt.structure_cfl * st->period[i] >= dtl) keep = i + 1;
    PetscCall(
        PetscSNPrintf(mode, sizeof(mode), " (mode %" PetscInt_FMT " of %" PetscInt_FMT ")", st->nmodes, st->nmodes));
    if (keep)
      PetscCall(PetscSNPrintf(advice, sizeof(advice),
                              "keep the %" PetscInt_FMT " mode%s the liquid's step resolves "
                              "(-fs_modal_modes %" PetscInt_FMT ", the highest kept at %.4g Hz), or ",
                              keep, keep > 1 ? "s" : "", keep, (double)(1 / st->period[keep - 1])));
  }
  /* C's own %g: PETSc's prints 1 as "1." */
  (void)snprintf(
      text, sizeof(text),
      "Warning: the structure %s's shortest period sets the time step: %.4g Hz%s, period %.4g s; "
      "-fs_structure_cfl %g of it is %.3g s, %.3g times shorter than the liquid's acoustic step %.3g s "
      "(-fs_cfl %g h/(c0 + |u|max) at the start), so the run takes up to %.3g times the steps. To save them, "
      "%sraise -fs_structure_cfl to %.2g (stable with RK4 up to about 0.45; at 0.05 RK4 loses about 1e-4 of "
      "the mode's amplitude a period: docs/structures.md)",
      st->name, (double)(1 / st->min_period), mode, (double)st->min_period, (double)s->opt.structure_cfl, (double)dts,
      (double)(dtl / dts), (double)dtl, (double)s->opt.cfl, (double)(dtl / dts), advice, (double)cfl);
  PetscCall(PetscPrintf(PetscObjectComm((PetscObject)s), "%s\n", text));
  PetscFunctionReturn(0);
}

/*
   FSSolverStructureColumns - names of the structure's time-series columns: the tank's motion,
   the applied loads, then the model's own columns. Without a structure, none.
*/
PetscErrorCode FSSolverStructureColumns(FSSolver s, PetscInt *n, const char *names[])
{
  static const char *motion[] = {"tip_displacement", "tip_velocity",       "tip_acceleration",
                                 "tank_rotation",    "tank_rotation_rate", "tank_angular_acceleration"};
  static const char *load2[]  = {"load_force_x", "load_force_y", "load_moment_z"};
  static const char *load3[]  = {"load_force_x",  "load_force_y",  "load_force_z",
                                 "load_moment_x", "load_moment_y", "load_moment_z"};
  FSStructure        st       = s->structure;
  PetscInt           k        = 0;

  PetscFunctionBegin;
  *n = 0;
  if (!st) PetscFunctionReturn(0);
  for (PetscInt c = 0; c < 6; c++) names[k++] = motion[c];
  if (s->opt.dim == 2)
    for (PetscInt c = 0; c < 3; c++) names[k++] = load2[c];
  else
    for (PetscInt c = 0; c < 6; c++) names[k++] = load3[c];
  for (PetscInt c = 0; c < st->ncolumns; c++) names[k++] = st->column[c];
  *n = k;
  PetscFunctionReturn(0);
}

/* FSSolverStructureValues - the values of those columns at the current state (valid on rank 0; on every rank but
   for a rank0 structure). Collective for a rank0 structure. */
PetscErrorCode FSSolverStructureValues(FSSolver s, PetscReal vals[])
{
  FSStructure  st = s->structure;
  FSTankMotion m;
  PetscInt     k = 0;
  PetscReal    t;

  PetscFunctionBegin;
  if (!st) PetscFunctionReturn(0);
  PetscCall(FSSolverStructureCurrent(s, NULL));
  if (!FSSolverStructureHere(s)) PetscFunctionReturn(0);
  PetscCall(TSGetTime(s->ts, &t));
  PetscCall(PetscMemzero(&m, sizeof(m)));
  PetscCall((*st->ops.motion)(st, t, s->sy, s->sydot, &m));
  vals[k++] = m.disp[1];
  vals[k++] = m.vel[1];
  vals[k++] = m.acc[1];
  vals[k++] = m.angle;
  vals[k++] = m.rate;
  vals[k++] = m.angacc;
  if (s->opt.dim == 2) {
    vals[k++] = s->loads.force[0];
    vals[k++] = s->loads.force[1];
    vals[k++] = s->loads.moment[2];
  } else {
    for (PetscInt d = 0; d < 3; d++) vals[k++] = s->loads.force[d];
    for (PetscInt d = 0; d < 3; d++) vals[k++] = s->loads.moment[d];
  }
  if (st->ncolumns) PetscCall((*st->ops.columns)(st, t, s->sy, s->sydot, &vals[k]));
  PetscFunctionReturn(0);
}

/* FSSolverStructureSnapshot - the model's output at a snapshot time (e.g. the deflected shape). Collective. */
PetscErrorCode FSSolverStructureSnapshot(FSSolver s)
{
  PetscMPIInt rank;
  PetscReal   t;
  PetscInt    step;

  PetscFunctionBegin;
  if (!s->structure || !s->structure->ops.snapshot) PetscFunctionReturn(0);
  PetscCallMPI(MPI_Comm_rank(PetscObjectComm((PetscObject)s), &rank));
  PetscCall(FSSolverStructureCurrent(s, NULL));
  PetscCall(TSGetTime(s->ts, &t));
  PetscCall(TSGetStepNumber(s->ts, &step));
  if (!rank) PetscCall((*s->structure->ops.snapshot)(s->structure, s->opt.outdir, t, step, s->sy));
  PetscFunctionReturn(0);
}

/* FSSolverStructureSummary - the "structure" object of summary.json. Collective. */
PetscErrorCode FSSolverStructureSummary(FSSolver s, FSJSON js)
{
  FSStructure st = s->structure;

  PetscFunctionBegin;
  PetscCall(FSJSONBeginObject(js, "structure"));
  PetscCall(FSJSONWriteString(js, "model", st ? st->name : "none"));
  if (st) {
    PetscCall(FSJSONWriteInt(js, "ndof", st->ndof));
    PetscCall(FSJSONWriteReal(js, "min_period", st->min_period));
    if (st->ndof) {
      PetscCall(FSSolverStructureCurrent(s, NULL));
      PetscCall(FSJSONWriteRealArray(js, "final_state", st->ndof, s->sy));
    }
    if (st->ops.summary) PetscCall((*st->ops.summary)(st, js));
  }
  PetscCall(FSJSONEndObject(js));
  PetscFunctionReturn(0);
}

/*
   FSSolverCouplingPredict - at the start of a right-hand side when coupled: the structure's state of
   this stage on every rank, and the tank's motion it gives with the liquid at rest (its dynamic loads
   left out), which sets the tank frame's body acceleration and angle of this stage
   (FSCouplingSetPredictedMotion). Every rank computes it from its own copy of the state; for a rank0 structure
   rank 0 computes the motion and broadcasts it with the state and its status: one collective.

   Collective for a rank0 structure
*/
PetscErrorCode FSSolverCouplingPredict(FSSolver s, const PetscReal *u)
{
  FSStructure    st = s->structure;
  const PetscInt nm = FS_MOTION_NREAL, nd = st->ndof;
  FSLoads        none;
  FSTankMotion   predicted;
  PetscReal      buf[FS_RANK0_MAX];
  PetscErrorCode ierr = 0;

  PetscFunctionBegin;
  PetscCheck(nm + nd <= FS_RANK0_MAX, PETSC_COMM_SELF, PETSC_ERR_PLIB, "%" PetscInt_FMT " structure DOFs", nd);
  PetscCall(PetscMemzero(&none, sizeof(none)));
  PetscCall(PetscMemzero(&predicted, sizeof(predicted)));
  if (FSSolverStructureHere(s)) {
    PetscCall(PetscArraycpy(s->sy, u + s->pw.nowned * s->state.ustride + s->state.gstruct, nd));
    ierr = (*st->ops.rhs)(st, s->state.rhs_time, s->sy, &none, s->sydot);
    if (!ierr) ierr = (*st->ops.motion)(st, s->state.rhs_time, s->sy, s->sydot, &predicted);
    PetscCall(PetscArraycpy(buf, (PetscReal *)&predicted, nm));
    PetscCall(PetscArraycpy(buf + nm, s->sy, nd));
  }
  PetscCall(FSSolverStructureResultRank0(s, ierr, "right-hand side or motion", nm + nd, buf));
  PetscCall(PetscArraycpy((PetscReal *)&predicted, buf, nm));
  PetscCall(PetscArraycpy(s->sy, buf + nm, nd));
  PetscCall(FSCouplingSetPredictedMotion(s->coupling, &predicted));
  PetscFunctionReturn(0);
}

/*
   FSSolverCouplingRates - the structure's part of a right-hand side when coupled (after
   FSSolverCouplingPredict and the terms): the liquid's loads of this stage to the structure
   (FSCouplingComputeLoads, from the reaction reduced over the ranks), its rate into f, the tank's motion at this
   stage to the coupling, and the structure's energies for the energy budget (s->state.structure_energy;
   FSSolverPowerRates books them), each rank from its own copy of the state. For a rank0 structure rank 0 computes
   them, and the status of its three calls rides on the motion's broadcast: one collective.

   Collective for a rank0 structure
*/
PetscErrorCode FSSolverCouplingRates(FSSolver s, PetscReal *f)
{
  FSStructure    st = s->structure;
  FSTankMotion   motion;
  PetscErrorCode ierr; /* this rank's (0 where the structure does not run) */

  PetscFunctionBegin;
  PetscCall(FSCouplingComputeLoads(s->coupling, s->boundary, &s->loads));
  /* the structure's rate under them (its state is on every rank since the prediction), and the tank's motion */
  PetscCall(FSSolverStructureRates(s, PETSC_FALSE, NULL, f, &ierr));
  PetscCall(PetscMemzero(&motion, sizeof(motion))); /* a model that fills part of it leaves no rotation */
  if (FSSolverStructureHere(s) && !ierr) ierr = (*st->ops.motion)(st, s->state.rhs_time, s->sy, s->sydot, &motion);
  PetscCall(PetscArrayzero(s->state.structure_energy, 3));
  if (FSSolverStructureHere(s) && !ierr && st->ndof && st->ops.energy)
    ierr = (*st->ops.energy)(st, s->sy, s->state.structure_energy);
  PetscCall(FSSolverStructureResultRank0(s, ierr, "right-hand side, motion or energy", FS_MOTION_NREAL,
                                         (PetscReal *)&motion));
  PetscCall(FSCouplingSetMotion(s->coupling, &motion));
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
  PetscCall(FSCouplingGetLiquidMass(s->coupling, mass));
  PetscFunctionReturn(0);
}
