/*
   The solver's side of the output: which fields go into snapshots and checkpoints, restarting
   from a checkpoint, and the run summary's content (the monitors in src/monitor/ write the files). The file formats
   live in src/io/.
*/
#include "solver/solverimpl.h"
#include <sys/resource.h>
#include <petscbt.h>

/*
   FSSolverEvaluateAtState - a fresh evaluation of the right-hand side at the current state U and time t,
   for the outputs (not counted in the run's statistics): the particles' volumes, pressures, first-pass
   fields, the wall pressure and the body field are then those of the state. Done once per state: the
   probes, a snapshot and the Python front's fields at the same step share it (a step, or the
   integrator's own evaluations, make the next call evaluate again).

   Collective
*/
PetscErrorCode FSSolverEvaluateAtState(FSSolver s, PetscReal t)
{
  const PetscScalar *u;
  PetscScalar       *f;
  Vec                F;
  PetscBool          staged;

  PetscFunctionBegin;
  if (s->state.evaluated && s->state.rhs_time == t) PetscFunctionReturn(0);
  /* the rates are not kept: into a stage vector of the integrator that the next step overwrites; else (an
     integrator without a free stage, or before the first step: the stages do not exist yet) into Fout, made once
     and kept with the state's layout for an integrator that never has a free stage, and dropped at once by one
     that will have it (rk4lean, rk: the outputs before the first step; kept, it would add a state-sized vector
     to the run's peak memory) */
  PetscCall(FSSolverGetFreeStage(s, &F, &staged));
  if (F) PetscCall(VecDestroy(&s->state.Fout));
  else {
    if (!s->state.Fout) PetscCall(VecDuplicate(s->state.U, &s->state.Fout));
    F = s->state.Fout;
  }
  s->state.rhs_time = t;
  PetscCall(VecGetArrayRead(s->state.U, &u));
  PetscCall(VecGetArray(F, &f));
  PetscCall(FSSolverEvaluateRates(s, u, f, PETSC_FALSE));
  PetscCall(VecRestoreArray(F, &f));
  PetscCall(VecRestoreArrayRead(s->state.U, &u));
  if (F == s->state.Fout && staged) PetscCall(VecDestroy(&s->state.Fout));
  s->state.evaluated = PETSC_TRUE;
  PetscFunctionReturn(0);
}

/*
   FSSolverDerivedFields - the fields of the owned particles that the state does not hold, from a fresh
   evaluation of the right-hand side at the current state (not counted in the run's statistics): the
   pressure p (the equation of state, as the right-hand side evaluates it), the strain rate ||D|| (0
   when no term needs it) and the turbulent viscosity (from the first term that provides the field
   "turbulent_viscosity", else 0). Any of the arrays (nowned values each) may be NULL.

   Collective
*/
static PetscErrorCode FSSolverDerivedFields(FSSolver s, PetscReal p[], PetscReal nD[], PetscReal nut[])
{
  const PetscInt n = s->pw.nowned, A = s->pw.auxstride;
  PetscReal      t;
  PetscBool      has = PETSC_FALSE;
  FSParticles    P;

  PetscFunctionBegin;
  PetscCall(TSGetTime(s->ts, &t));
  PetscCall(FSSolverEvaluateAtState(s, t));
  for (PetscInt k = 0; k < n; k++) {
    if (p) p[k] = s->pw.pressure[k];
    if (nD) nD[k] = s->terms.needs ? s->pw.aux[k * A + s->opt.dim] : 0;
    if (nut) nut[k] = 0;
  }
  if (!nut) PetscFunctionReturn(0);
  PetscCall(FSSolverGetParticles(s, &P));
  for (PetscInt t = 0; t < s->terms.nterms && !has; t++) {
    FSTerm term = s->terms.term[t];
    if (term->ops.field) PetscCall((*term->ops.field)(term, "turbulent_viscosity", &P, nut, &has));
  }
  PetscFunctionReturn(0);
}

/* the particles' ids as reals, when a snapshot or a checkpoint writes them */
static PetscErrorCode FSSolverFillIds(void *ctx, PetscInt f, PetscReal values[])
{
  const FSSolverIds *c = (const FSSolverIds *)ctx;

  PetscFunctionBegin;
  (void)f;
  for (PetscInt k = 0; k < c->n; k++) values[k] = c->pid[k];
  PetscFunctionReturn(0);
}

static const char *FSFieldNames[] = {
    "position", "velocity", "density", "mass", "pressure", "strain_rate", "turbulent_viscosity", "id", "rank"};

/*
   FSSolverFillField - one per-particle field of this rank's owned particles at the current state into values, in the
   swarm's local order (FSSolverGetField() without the copy's allocation: the snapshots monitor fills its writer's
   buffer with it, src/monitor/impls/snapshots.c).

   Collective (the derived fields evaluate a right-hand side; the others are local)

   Input Parameters:
+  s      - the solver, set up
.  name   - a field of FSSolverGetField()
-  values - room for the owned particles' values (bs each), or NULL for bs only

   Output Parameter:
.  bs - the values per particle (may be NULL)
*/
PetscErrorCode FSSolverFillField(FSSolver s, const char name[], PetscInt *bs, PetscReal values[])
{
  const PetscInt dim = s->opt.dim, US = s->state.ustride, S = s->pw.stride, np = s->pw.nowned;
  PetscInt       k = 0, b = 1, off = -1;
  PetscReal     *v    = values;
  MPI_Comm       comm = PetscObjectComm((PetscObject)s);

  PetscFunctionBegin;
  PetscCheck(s->setupcalled, comm, PETSC_ERR_ARG_WRONGSTATE, "FSSolverGetField(): call FSSolverSetUp() first");
  while (k < (PetscInt)PETSC_STATIC_ARRAY_LENGTH(FSFieldNames) && strcmp(name, FSFieldNames[k])) k++;
  PetscCheck(k < (PetscInt)PETSC_STATIC_ARRAY_LENGTH(FSFieldNames), comm, PETSC_ERR_ARG_UNKNOWN_TYPE,
             "Unknown particle field \"%s\": expected position, velocity, density, mass, pressure, strain_rate, "
             "turbulent_viscosity, id or rank",
             name);
  if (k < 2) b = dim;
  if (bs) *bs = b;
  if (!v) PetscFunctionReturn(0);
  if (k <= 2) off = k * dim; /* the packed state: position, velocity, density */
  if (off >= 0) {
    const PetscScalar *u;
    PetscCall(VecGetArrayRead(s->state.U, &u));
    for (PetscInt i = 0; i < np; i++)
      for (PetscInt d = 0; d < b; d++) v[i * b + d] = u[i * US + off + d];
    if (k == 0) /* inside the periodic domain: between rebuilds a particle may have crossed a periodic side */
      for (PetscInt i = 0; i < np; i++) FSSolverWrapPeriodic(s, &v[i * dim]);
    PetscCall(VecRestoreArrayRead(s->state.U, &u));
  } else if (k == 3) { /* the mass, from the particle records */
    for (PetscInt i = 0; i < np; i++) v[i] = s->pw.rec[i * S + 2 * dim + 1];
  } else if (k <= 6) {
    PetscCall(FSSolverDerivedFields(s, k == 4 ? v : NULL, k == 5 ? v : NULL, k == 6 ? v : NULL));
  } else if (k == 7) {
    FSSolverIds ids = {.n = np};
    PetscCall(DMSwarmGetField(s->swarm, FS_FIELD_ID, NULL, NULL, (void **)&ids.pid));
    PetscCall(FSSolverFillIds(&ids, 0, v));
    PetscCall(DMSwarmRestoreField(s->swarm, FS_FIELD_ID, NULL, NULL, (void **)&ids.pid));
  } else {
    PetscMPIInt rank;
    PetscCallMPI(MPI_Comm_rank(comm, &rank));
    for (PetscInt i = 0; i < np; i++) v[i] = rank;
  }
  PetscFunctionReturn(0);
}

/*
   FSSolverGetField - a copy of one per-particle field of this rank's owned particles at the current
   state, in the swarm's local order (the particles' ids are the field "id"; the order changes at
   every step).

   Collective (the derived fields evaluate a right-hand side; the others are local)

   Input Parameters:
+  s    - the solver, set up
-  name - position, velocity (dim values per particle), density, mass, pressure, strain_rate (||D||),
          turbulent_viscosity, id or rank (1 value)

   Output Parameters:
+  n      - the number of owned particles (may be NULL)
.  bs     - the values per particle (may be NULL)
-  values - n*bs values; give them back with FSSolverRestoreField()

   Notes:
   pressure, strain_rate and turbulent_viscosity come from a fresh evaluation of the right-hand side
   at the current state, as in the snapshots; it also refreshes what the last right-hand side left
   (the wall loads of FSSolverGetWallLoads()). id and rank are returned as reals, as in the snapshots.

.seealso: FSSolverRestoreField(), FSSolverGetSwarm(), FSSolverFillField()
*/
PetscErrorCode FSSolverGetField(FSSolver s, const char name[], PetscInt *n, PetscInt *bs, const PetscReal *values[])
{
  PetscInt   b;
  PetscReal *v;

  PetscFunctionBegin;
  PetscCall(FSSolverFillField(s, name, &b, NULL));
  PetscCall(PetscMalloc1(s->pw.nowned * b + 1, &v));
  PetscCall(FSSolverFillField(s, name, NULL, v));
  if (n) *n = s->pw.nowned;
  if (bs) *bs = b;
  *values = v;
  PetscFunctionReturn(0);
}

/*
   FSSolverRestoreField - gives back the values of FSSolverGetField().

   Not collective

.seealso: FSSolverGetField()
*/
PetscErrorCode FSSolverRestoreField(FSSolver s, const char name[], PetscInt *n, PetscInt *bs, const PetscReal *values[])
{
  PetscFunctionBegin;
  (void)s;
  (void)name;
  PetscCall(PetscFree(*values));
  if (n) *n = 0;
  if (bs) *bs = 0;
  PetscFunctionReturn(0);
}

/*
   FSSolverGetCheckpoint - a checkpoint's content at the current state, for the checkpoints monitor
   (src/monitor/impls/checkpoints.c, FSMonitorCheckpointsWrite()), which writes it: the whole state, the particles
   (position, velocity, density, mass, id, and the positions at the last build of the lists, from which a restart
   rebuilds the same lists), time, step, dt and the global DOFs (the structure's state, the dissipated energies), then
   the viscosity bound of the next step with its source, the limit that set the last step, and the number of
   structure DOFs (to refuse a restart with another structure), the record of the run's set-up
   (FSSolverSetUpRecord()) and the domain's split. The particle fields are the swarm's, lent until
   FSSolverRestoreCheckpoint().

   Collective
*/
PetscErrorCode FSSolverGetCheckpoint(FSSolver s, FSSolverCheckpoint *c)
{
  const PetscInt      dim = s->opt.dim;
  FSCheckpointHeader *hdr = &c->hdr;
  PetscReal          *x, *v, *rho, *m, *xb;
  PetscMPIInt         rank;

  PetscFunctionBegin;
  PetscCallMPI(MPI_Comm_rank(PetscObjectComm((PetscObject)s), &rank));
  PetscCall(PetscMemzero(hdr, sizeof(*hdr)));
  PetscCall(TSGetTime(s->ts, &hdr->time));
  PetscCall(TSGetStepNumber(s->ts, &hdr->step));
  PetscCall(TSGetTimeStep(s->ts, &hdr->dt));
  /* the global DOFs, the viscosity bound of the next step and its source, the limit that set the last step,
     the structure's DOF count */
  hdr->nglobal = s->state.nglobaldofs + 4;
  if (!rank && s->state.nglobaldofs) {
    const PetscScalar *u;
    PetscInt           nl;
    PetscCall(VecGetLocalSize(s->state.U, &nl));
    PetscCall(VecGetArrayRead(s->state.U, &u));
    for (PetscInt g = 0; g < s->state.nglobaldofs; g++) hdr->global[g] = u[nl - s->state.nglobaldofs + g];
    PetscCall(VecRestoreArrayRead(s->state.U, &u));
  }
  PetscCallMPI(
      MPI_Bcast(hdr->global, (PetscMPIInt)s->state.nglobaldofs, MPIU_REAL, 0, PetscObjectComm((PetscObject)s)));
  {
    PetscReal nu;
    PetscInt  source;
    PetscCall(FSSolverViscosityBound(s, &nu, &source));
    hdr->global[s->state.nglobaldofs]     = nu;
    hdr->global[s->state.nglobaldofs + 1] = (PetscReal)source;
    hdr->global[s->state.nglobaldofs + 2] = (PetscReal)s->state.dt_limit;
    hdr->global[s->state.nglobaldofs + 3] = (PetscReal)(s->state.gdiss - s->state.gstruct);
  }
  PetscCall(DMSwarmGetField(s->swarm, FS_FIELD_POSITION, NULL, NULL, (void **)&x));
  PetscCall(DMSwarmGetField(s->swarm, FS_FIELD_VELOCITY, NULL, NULL, (void **)&v));
  PetscCall(DMSwarmGetField(s->swarm, FS_FIELD_DENSITY, NULL, NULL, (void **)&rho));
  PetscCall(DMSwarmGetField(s->swarm, FS_FIELD_MASS, NULL, NULL, (void **)&m));
  PetscCall(DMSwarmGetField(s->swarm, FS_FIELD_ID, NULL, NULL, (void **)&c->ids.pid));
  PetscCall(DMSwarmGetField(s->swarm, FS_FIELD_BUILD, NULL, NULL, (void **)&xb));
  c->n         = s->pw.nowned;
  c->ids.n     = c->n;
  c->fields[0] = (FSOutputField){.name = FS_FIELD_POSITION, .bs = dim, .data = x};
  c->fields[1] = (FSOutputField){.name = FS_FIELD_VELOCITY, .bs = dim, .data = v};
  c->fields[2] = (FSOutputField){.name = FS_FIELD_DENSITY, .bs = 1, .data = rho};
  c->fields[3] = (FSOutputField){.name = FS_FIELD_MASS, .bs = 1, .data = m};
  c->fields[4] = (FSOutputField){.name = FS_FIELD_ID, .bs = 1, .fill = FSSolverFillIds, .ctx = &c->ids};
  c->fields[5] = (FSOutputField){.name = FS_FIELD_BUILD, .bs = dim, .data = xb};
  hdr->setup   = s->mon.setup;
  /* the split of the domain (the cuts move with -fs_rebalance_threshold) and the step it was last balanced at */
  hdr->nlayout = 1 + FSDecompLayoutSize(&s->pw.decomp);
  PetscCheck(hdr->nlayout <= FS_LAYOUT_MAX, PETSC_COMM_SELF, PETSC_ERR_PLIB, "%" PetscInt_FMT " layout values",
             hdr->nlayout);
  c->layout[0] = (PetscReal)s->pw.balance_step;
  PetscCall(FSDecompGetLayout(&s->pw.decomp, c->layout + 1));
  hdr->layout = c->layout;
  PetscFunctionReturn(0);
}

/* FSSolverRestoreCheckpoint - gives back the particle fields FSSolverGetCheckpoint() lent. */
PetscErrorCode FSSolverRestoreCheckpoint(FSSolver s, FSSolverCheckpoint *c)
{
  PetscFunctionBegin;
  PetscCall(DMSwarmRestoreField(s->swarm, FS_FIELD_BUILD, NULL, NULL, (void **)&c->fields[5].data));
  PetscCall(DMSwarmRestoreField(s->swarm, FS_FIELD_ID, NULL, NULL, (void **)&c->ids.pid));
  PetscCall(DMSwarmRestoreField(s->swarm, FS_FIELD_MASS, NULL, NULL, (void **)&c->fields[3].data));
  PetscCall(DMSwarmRestoreField(s->swarm, FS_FIELD_DENSITY, NULL, NULL, (void **)&c->fields[2].data));
  PetscCall(DMSwarmRestoreField(s->swarm, FS_FIELD_VELOCITY, NULL, NULL, (void **)&c->fields[1].data));
  PetscCall(DMSwarmRestoreField(s->swarm, FS_FIELD_POSITION, NULL, NULL, (void **)&c->fields[0].data));
  PetscFunctionReturn(0);
}

/*
   FSSolverCheckIds - the ids read from a checkpoint of N particles (n on this rank, each already an integer in [0, N))
   are each of 0..N-1 once: every id goes to the rank that keeps its share of 0..N-1, which marks it; an id seen twice
   is an error naming the checkpoint and the id. Collective.
*/
static PetscErrorCode FSSolverCheckIds(FSSolver s, PetscInt64 N, PetscInt n, const PetscInt id[])
{
  MPI_Comm     comm = PetscObjectComm((PetscObject)s);
  const char  *path = s->opt.restart;
  PetscMPIInt  size, rank;
  PetscInt64   twice = -1, gtwice;
  PetscMPIInt *scount, *sdispl, *rcount, *rdispl;
  PetscInt    *sbuf, *rbuf, *fill;
  PetscInt     nrecv;
  PetscBT      seen;

  PetscFunctionBegin;
  if (N == 0) PetscFunctionReturn(0);
  PetscCallMPI(MPI_Comm_size(comm, &size));
  PetscCallMPI(MPI_Comm_rank(comm, &rank));
  /* rank r keeps the ids i with floor(i size / N) == r: from ceil(r N / size) on */
#define FS_ID_OWNER(i) ((PetscMPIInt)(((PetscInt64)(i)*size) / N))
#define FS_ID_FIRST(r) ((PetscInt)(((PetscInt64)(r)*N + size - 1) / size))
  PetscCall(PetscCalloc4(size, &scount, size + 1, &sdispl, size, &rcount, size + 1, &rdispl));
  PetscCall(PetscMalloc2(n + 1, &sbuf, size, &fill));
  for (PetscInt k = 0; k < n; k++) scount[FS_ID_OWNER(id[k])]++;
  for (PetscMPIInt r = 0; r < size; r++) sdispl[r + 1] = sdispl[r] + scount[r];
  for (PetscMPIInt r = 0; r < size; r++) fill[r] = sdispl[r];
  for (PetscInt k = 0; k < n; k++) sbuf[fill[FS_ID_OWNER(id[k])]++] = id[k];
  PetscCallMPI(MPI_Alltoall(scount, 1, MPI_INT, rcount, 1, MPI_INT, comm));
  for (PetscMPIInt r = 0; r < size; r++) rdispl[r + 1] = rdispl[r] + rcount[r];
  nrecv = rdispl[size];
  PetscCall(PetscMalloc1(nrecv + 1, &rbuf));
  PetscCallMPI(MPI_Alltoallv(sbuf, scount, sdispl, MPIU_INT, rbuf, rcount, rdispl, MPIU_INT, comm));
  {
    const PetscInt first = FS_ID_FIRST(rank), count = FS_ID_FIRST(rank + 1) - first;
    PetscCall(PetscBTCreate(count, &seen));
    for (PetscInt k = 0; k < nrecv && twice < 0; k++)
      if (PetscBTLookupSet(seen, rbuf[k] - first)) twice = rbuf[k];
    PetscCall(PetscBTDestroy(&seen));
  }
#undef FS_ID_OWNER
#undef FS_ID_FIRST
  PetscCall(PetscFree(rbuf));
  PetscCall(PetscFree2(sbuf, fill));
  PetscCall(PetscFree4(scount, sdispl, rcount, rdispl));
  PetscCallMPI(MPI_Allreduce(&twice, &gtwice, 1, MPIU_INT64, MPI_MAX, comm));
  PetscCheck(gtwice < 0, comm, PETSC_ERR_FILE_UNEXPECTED,
             "Checkpoint \"%s\": /particles/id holds the id %" PetscInt64_FMT
             " more than once: expected each of 0 to %" PetscInt64_FMT " once",
             path, gtwice, N - 1);
  PetscFunctionReturn(0);
}

/*
   FSSolverCheckLayout - the writers' split of the domain read from a checkpoint (layout[0] the step it was balanced at,
   then the split's values, FSDecompGetLayout()) before FSDecompSetLayout() takes it: the step an integer in [0, the
   checkpoint's step], and along each direction the cuts increasing from the domain's start to its end, as this run's
   decomposition has them (the same number of ranks per direction; FSDecompSetLayout() ignores another split).
*/
static PetscErrorCode FSSolverCheckLayout(FSSolver s, PetscInt step, PetscInt nl, const PetscReal layout[])
{
  MPI_Comm        comm = PetscObjectComm((PetscObject)s);
  const FSDecomp *dd   = &s->pw.decomp;
  PetscInt        k    = 4;

  PetscFunctionBegin;
  PetscCheck(layout[0] >= 0 && layout[0] <= step && layout[0] == PetscFloorReal(layout[0]), comm,
             PETSC_ERR_FILE_UNEXPECTED,
             "Checkpoint \"%s\": /layout/domain[0], the step the ranks' cuts were balanced at, is %g: expected an "
             "integer in [0, %" PetscInt_FMT "] (the checkpoint's step)",
             s->opt.restart, (double)layout[0], step);
  if (nl - 1 != FSDecompLayoutSize(dd)) PetscFunctionReturn(0);
  for (PetscInt d = 0; d < 3; d++)
    if (layout[1 + d] != (PetscReal)dd->np[d]) PetscFunctionReturn(0);
  for (PetscInt d = 0; d < 3; d++) {
    const PetscReal *cut = &layout[k], lo = dd->cut[d][0], hi = dd->cut[d][dd->np[d]];
    const PetscReal  tol = 1e-12 * PetscMax(1, PetscAbsReal(hi - lo));
    PetscBool        ok  = (PetscBool)(PetscAbsReal(cut[0] - lo) <= tol && PetscAbsReal(cut[dd->np[d]] - hi) <= tol);
    for (PetscMPIInt i = 0; i < dd->np[d] && ok; i++) ok = (PetscBool)(cut[i + 1] > cut[i]);
    PetscCheck(ok, comm, PETSC_ERR_FILE_UNEXPECTED,
               "Checkpoint \"%s\": /layout/domain[%" PetscInt_FMT "..%" PetscInt_FMT
               "], the ranks' cuts along direction %" PetscInt_FMT ", are not increasing from %g to %g: expected the "
               "cuts of a split of this run's domain",
               s->opt.restart, k, k + dd->np[d], d, (double)lo, (double)hi);
    k += dd->np[d] + 1;
  }
  PetscFunctionReturn(0);
}

/*
   FSSolverLoadCheckpoint - replaces the case's particles by those of the checkpoint given to
   -fs_restart and remembers its time, step, dt and global DOFs for the TS, once the checkpoint's
   set-up is found to be this run's (FSSolverCheckSetUp()). Every value is checked before it is used
   (FSCheckpointReadField() and the others check types, counts, checksums and that values are finite; here
   what they mean to this run): positions inside the domain along its walled directions, masses and densities
   positive, the ids each of 0..N-1 once, the global values' time-step bound, its source and the last step's
   limit in range, the ranks' cuts a split of the domain; then the particles as any start
   (FSSolverCheckStart()). An error names the checkpoint and what is wrong, before the output is touched.
*/
PetscErrorCode FSSolverLoadCheckpoint(FSSolver s)
{
  MPI_Comm           comm = PetscObjectComm((PetscObject)s);
  const PetscInt     dim  = s->opt.dim;
  const char        *path = s->opt.restart;
  FSCheckpointHeader hdr;
  PetscInt           nglob, n, ng = s->state.nglobaldofs, source, limit;
  PetscMPIInt        nranks;
  PetscReal         *x, *v, *rho, *m, *id, *xb;
  PetscInt          *pid;
  PetscBool          hasbuild;
  PetscReal          lo[3], hi[3], zero[1] = {0}, idlo[1] = {0}, idhi[1];
  char               inside[256], idrange[64];
  FSCheckpointRange  rpos, rpositive, rid;

  PetscFunctionBegin;
  PetscCall(FSCheckpointReadHeader(comm, path, &hdr, &nglob, &nranks));
  if (hdr.version < 3)
    PetscCall(PetscPrintf(comm,
                          "Warning: checkpoint %s (format version %" PetscInt_FMT
                          ") has no checksums: a damaged value is caught only where it is out of range\n",
                          path, hdr.version));
  { /* the same set-up, but for the changes allowed */
    char *record;
    PetscCall(FSCheckpointReadSetUp(comm, path, &record));
    PetscCall(FSSolverCheckSetUp(s, record));
    PetscCall(PetscFree(record));
  }
  PetscCheck(hdr.nglobal == ng + 4 && hdr.global[hdr.nglobal - 1] == (PetscReal)(s->state.gdiss - s->state.gstruct),
             comm, PETSC_ERR_FILE_UNEXPECTED,
             "Checkpoint %s holds %" PetscInt_FMT
             " global values (%g of them structure DOFs) but this run needs %" PetscInt_FMT " (%" PetscInt_FMT
             "): restart with the same -fs_terms and -fs_structure (and its modes) as the run that wrote it",
             path, hdr.nglobal, hdr.nglobal > 0 ? (double)hdr.global[hdr.nglobal - 1] : 0.0, ng + 4,
             s->state.gdiss - s->state.gstruct);
  /* the viscosity bound of the first step, its source (0: the laminar viscosity, t + 1: term t) and the limit that
     set the last step (FSDtLimit) */
  PetscCheck(hdr.global[ng] >= 0, comm, PETSC_ERR_FILE_UNEXPECTED,
             "Checkpoint \"%s\": /header/global[%" PetscInt_FMT "], the viscosity bound of the time step, is %g: "
             "expected a number >= 0",
             path, ng, (double)hdr.global[ng]);
  PetscCheck(hdr.global[ng + 1] >= 0 && hdr.global[ng + 1] <= s->terms.nterms &&
                 hdr.global[ng + 1] == PetscFloorReal(hdr.global[ng + 1]),
             comm, PETSC_ERR_FILE_UNEXPECTED,
             "Checkpoint \"%s\": /header/global[%" PetscInt_FMT "], the source of the time step's viscosity bound, is "
             "%g but this run has %" PetscInt_FMT " terms: expected an integer in [0, %" PetscInt_FMT
             "]; restart with the same -fs_terms",
             path, ng + 1, (double)hdr.global[ng + 1], s->terms.nterms, s->terms.nterms);
  PetscCheck(hdr.global[ng + 2] >= 0 && hdr.global[ng + 2] < FS_DT_TERM + s->terms.nterms &&
                 hdr.global[ng + 2] == PetscFloorReal(hdr.global[ng + 2]),
             comm, PETSC_ERR_FILE_UNEXPECTED,
             "Checkpoint \"%s\": /header/global[%" PetscInt_FMT "], the limit that set the last step, is %g: expected "
             "an integer in [0, %" PetscInt_FMT "] (timeseries.csv's dt_limit)",
             path, ng + 2, (double)hdr.global[ng + 2], (PetscInt)FS_DT_TERM + s->terms.nterms - 1);
  source = (PetscInt)hdr.global[ng + 1];
  limit  = (PetscInt)hdr.global[ng + 2];

  /* what the particles' values may be */
  for (PetscInt d = 0; d < 3; d++) {
    const PetscBool walled = (PetscBool)(d < dim && !s->pw.periodic[d]);
    lo[d]                  = walled ? s->pw.lo[d] : PETSC_NINFINITY;
    hi[d]                  = walled ? s->pw.hi[d] : PETSC_INFINITY;
  }
  if (dim == 3)
    PetscCall(PetscSNPrintf(inside, sizeof(inside), "a coordinate inside the domain [%g, %g] x [%g, %g] x [%g, %g]",
                            (double)s->pw.lo[0], (double)s->pw.hi[0], (double)s->pw.lo[1], (double)s->pw.hi[1],
                            (double)s->pw.lo[2], (double)s->pw.hi[2]));
  else
    PetscCall(PetscSNPrintf(inside, sizeof(inside), "a coordinate inside the domain [%g, %g] x [%g, %g]",
                            (double)s->pw.lo[0], (double)s->pw.hi[0], (double)s->pw.lo[1], (double)s->pw.hi[1]));
  idhi[0] = (PetscReal)(nglob - 1);
  PetscCall(PetscSNPrintf(idrange, sizeof(idrange), "an integer in [0, %" PetscInt_FMT "]", nglob - 1));
  rpos      = (FSCheckpointRange){.lo = lo, .hi = hi, .expect = inside};
  rpositive = (FSCheckpointRange){.lo = zero, .open = PETSC_TRUE, .expect = "a positive number"};
  rid       = (FSCheckpointRange){.lo = idlo, .hi = idhi, .integer = PETSC_TRUE, .expect = idrange};

  PetscCall(FSCheckpointGetLocalSize(comm, path, &n));
  PetscCall(DMSwarmSetLocalSizes(s->swarm, n, 1024));
  PetscCall(PetscMalloc1(n + 1, &id));
  PetscCall(DMSwarmGetField(s->swarm, FS_FIELD_POSITION, NULL, NULL, (void **)&x));
  PetscCall(DMSwarmGetField(s->swarm, FS_FIELD_VELOCITY, NULL, NULL, (void **)&v));
  PetscCall(DMSwarmGetField(s->swarm, FS_FIELD_DENSITY, NULL, NULL, (void **)&rho));
  PetscCall(DMSwarmGetField(s->swarm, FS_FIELD_MASS, NULL, NULL, (void **)&m));
  PetscCall(DMSwarmGetField(s->swarm, FS_FIELD_ID, NULL, NULL, (void **)&pid));
  PetscCall(FSCheckpointReadField(comm, path, FS_FIELD_POSITION, dim, n, &rpos, x));
  PetscCall(FSCheckpointReadField(comm, path, FS_FIELD_VELOCITY, dim, n, NULL, v));
  PetscCall(FSCheckpointReadField(comm, path, FS_FIELD_DENSITY, 1, n, &rpositive, rho));
  PetscCall(FSCheckpointReadField(comm, path, FS_FIELD_MASS, 1, n, &rpositive, m));
  PetscCall(FSCheckpointReadField(comm, path, FS_FIELD_ID, 1, n, &rid, id));
  for (PetscInt k = 0; k < n; k++) pid[k] = (PetscInt)id[k];
  PetscCall(PetscFree(id));
  PetscCall(FSSolverCheckIds(s, nglob, n, pid));
  /* the positions of the last build (a checkpoint older than them: the lists are built at the positions) */
  PetscCall(FSCheckpointHasField(comm, path, FS_FIELD_BUILD, &hasbuild));
  PetscCall(DMSwarmGetField(s->swarm, FS_FIELD_BUILD, NULL, NULL, (void **)&xb));
  if (hasbuild) PetscCall(FSCheckpointReadField(comm, path, FS_FIELD_BUILD, dim, n, &rpos, xb));
  else PetscCall(PetscArraycpy(xb, x, n * dim));
  PetscCall(DMSwarmRestoreField(s->swarm, FS_FIELD_BUILD, NULL, NULL, (void **)&xb));
  PetscCall(DMSwarmRestoreField(s->swarm, FS_FIELD_ID, NULL, NULL, (void **)&pid));
  PetscCall(DMSwarmRestoreField(s->swarm, FS_FIELD_MASS, NULL, NULL, (void **)&m));
  PetscCall(DMSwarmRestoreField(s->swarm, FS_FIELD_DENSITY, NULL, NULL, (void **)&rho));
  PetscCall(DMSwarmRestoreField(s->swarm, FS_FIELD_VELOCITY, NULL, NULL, (void **)&v));
  PetscCall(DMSwarmRestoreField(s->swarm, FS_FIELD_POSITION, NULL, NULL, (void **)&x));
  s->pw.nglobal_particles = nglob;
  s->state.restart_hdr    = hdr;
  s->pw.balance_step      = hdr.step;
  if (nranks == s->pw.decomp.size) { /* as many ranks: the writers' cuts, so that the run goes on as theirs */
    PetscReal layout[FS_LAYOUT_MAX];
    PetscInt  nl;
    PetscBool taken = PETSC_FALSE;
    PetscCall(FSCheckpointReadLayout(comm, path, FS_LAYOUT_MAX, layout, &nl));
    if (nl > 1) PetscCall(FSSolverCheckLayout(s, hdr.step, nl, layout));
    if (nl > 1) PetscCall(FSDecompSetLayout(&s->pw.decomp, nl - 1, layout + 1, &taken));
    if (taken) s->pw.balance_step = (PetscInt)layout[0];
  }
  for (PetscInt g = 0; g < ng; g++) s->state.global0[g] = hdr.global[g];
  PetscCall(PetscArrayzero(s->state.nu_src, FS_MAX_TERMS + 1));
  s->state.nu_src[source] = hdr.global[ng];
  s->state.dt_limit       = limit;
  PetscCall(FSSolverCheckStart(s));
  PetscFunctionReturn(0);
}

/*
   FSSolverSummaryWrite - summary.json's content into js (the summary monitor's file): what ran, how long (since the
   monitors began), how fast, with which options.

   Collective
*/
PetscErrorCode FSSolverSummaryWrite(FSSolver s, FSJSON js)
{
  MPI_Comm       comm = PetscObjectComm((PetscObject)s);
  char          *opts;
  PetscLogDouble now, wall;
  PetscReal      t, dt, mem, memsum;
  PetscInt       step;
  PetscMPIInt    size;
  struct rusage  ru;
  PetscInt64     pv = s->mon.pair_visits;

  PetscFunctionBegin;
  PetscCallMPI(MPI_Comm_size(comm, &size));
  PetscCall(PetscTime(&now));
  wall = now - s->mon.wall_start;
  PetscCall(TSGetTime(s->ts, &t));
  PetscCall(TSGetTimeStep(s->ts, &dt));
  PetscCall(TSGetStepNumber(s->ts, &step));
  PetscCallMPI(MPI_Allreduce(MPI_IN_PLACE, &pv, 1, MPIU_INT64, MPI_SUM, comm));
  getrusage(RUSAGE_SELF, &ru);
  mem = (PetscReal)ru.ru_maxrss * 1024.0;
  PetscCallMPI(MPI_Allreduce(&mem, &memsum, 1, MPIU_REAL, MPI_SUM, comm));
  PetscCall(FSJSONWriteString(js, "program", "flexslosh " FLEXSLOSH_VERSION));
  PetscCall(FSJSONWriteString(js, "case", s->opt.casename));
  PetscCall(FSJSONWriteInt(js, "dim", s->opt.dim));
  PetscCall(FSJSONWriteInt(js, "ranks", size));
  PetscCall(FSJSONWriteInt(js, "particles", s->pw.nglobal_particles));
  PetscCall(FSJSONWriteInt(js, "steps", step - s->mon.step0));
  PetscCall(FSJSONWriteInt(js, "final_step", step));
  PetscCall(FSJSONWriteReal(js, "start_time", s->mon.t0));
  PetscCall(FSJSONWriteReal(js, "final_time", t));
  PetscCall(FSJSONWriteReal(js, "last_dt", dt));
  PetscCall(FSJSONWriteReal(js, "dx", s->opt.dx));
  PetscCall(FSJSONWriteReal(js, "h", s->opt.h));
  if (s->liquid[0] > 0) { /* the liquid's exact volume and mass, and how far the lattice's mass was from it */
    PetscCall(FSJSONWriteReal(js, "liquid_volume", s->liquid[0]));
    PetscCall(FSJSONWriteReal(js, "liquid_mass", s->liquid[1]));
    PetscCall(FSJSONWriteReal(js, "lattice_mass_ratio", s->liquid[2] / s->liquid[1]));
  }
  PetscCall(FSJSONWriteReal(js, "wall_time", wall));
  PetscCall(FSJSONWriteReal(js, "particle_steps_per_second", wall > 0 ? (PetscReal)s->mon.particle_steps / wall : 0));
  PetscCall(FSJSONWriteInt(js, "rhs_evaluations", s->mon.nrhs));
  PetscCall(FSJSONWriteInt(js, "pair_visits", pv));
  PetscCall(FSJSONWriteReal(js, "pair_visits_per_second", wall > 0 ? (PetscReal)pv / wall : 0));
  PetscCall(FSJSONWriteReal(js, "peak_memory_bytes", memsum));
  PetscCall(
      FSJSONWriteReal(js, "peak_memory_bytes_per_particle", memsum / (PetscReal)PetscMax(s->pw.nglobal_particles, 1)));
  PetscCall(FSSolverWriteMemory(s, js, memsum));
  PetscCall(FSJSONWriteInt(js, "migrations", s->mon.nmigrations));
  PetscCall(FSJSONWriteInt(js, "neighbour_rebuilds", s->mon.nrebuilds));
  PetscCall(FSJSONWriteInt(js, "rebalances", s->mon.nrebalances));
  if (s->state.split_stages) { /* the split terms' RKL2 stages (FSSolverSplitStep) */
    PetscCall(FSJSONBeginObject(js, "split_stages"));
    PetscCall(FSJSONWriteInt(js, "total", s->state.split_stages));
    PetscCall(FSJSONWriteInt(js, "max", s->state.split_max_stages));
    PetscCall(FSJSONEndObject(js));
  }
  PetscCall(FSJSONBeginObject(js, "dt_limit_steps")); /* how many steps each time-step limit set */
  for (PetscInt l = 0; l < FS_DT_TERM + s->terms.nterms; l++) {
    const char *name;
    PetscCall(FSSolverDtLimitName(s, l, &name));
    PetscCall(FSJSONWriteInt(js, name, s->state.dt_limit_steps[l]));
  }
  PetscCall(FSJSONEndObject(js));
  if (s->boundary) PetscCall(FSBoundarySummary(s->boundary, js));
  PetscCall(FSSolverStructureSummary(s, js));
  PetscCall(FSParallelStatsSummary(s, js));
  PetscCall(FSJSONBeginObject(js, "terms"));
  for (PetscInt k = 0; k < s->terms.nterms; k++) PetscCall(FSJSONWriteBool(js, s->terms.term[k]->name, PETSC_TRUE));
  PetscCall(FSJSONEndObject(js));
  PetscCall(PetscOptionsGetAll(NULL, &opts));
  PetscCall(FSJSONWriteString(js, "options", opts));
  PetscCall(PetscFree(opts));
  PetscFunctionReturn(0);
}

/*
   FSSolverGetWallLoads - the liquid's load on each wall from the last right-hand side evaluation (the
   values of the wall_<name>_* columns of timeseries.csv), summed over the ranks, on every rank.

   Collective (not collective when loads is NULL)

   Input Parameter:
.  s - the solver

   Output Parameters:
+  nwalls - the number of walls (0 in a case without walls)
.  names  - the walls' names (an array of nwalls pointers into the solver, or NULL)
-  loads  - per wall: the force (3) and the moment (3) about -fs_walls_load_point (or the wall's own point,
            -fs_walls_moment_walls and -fs_walls_moment_points), 6 nwalls values
            that stay valid until the next right-hand side (NULL without walls), or NULL

   Notes:
   After a step the last right-hand side is the integrator's last stage; FSSolverGetField() for a
   derived field evaluates one at the current state.

.seealso: FSSolverGetField(), FSSolverSetUp()
*/
PetscErrorCode FSSolverGetWallLoads(FSSolver s, PetscInt *nwalls, const char *names[], const PetscReal *loads[])
{
  const char *const *wname;

  PetscFunctionBegin;
  *nwalls = 0;
  if (loads) *loads = NULL;
  if (!s->boundary) PetscFunctionReturn(0);
  PetscCall(FSBoundaryGetWallNames(s->boundary, nwalls, &wname));
  if (names)
    for (PetscInt w = 0; w < *nwalls; w++) names[w] = wname[w];
  if (loads) PetscCall(FSBoundaryGetWallLoads(s->boundary, nwalls, loads));
  PetscFunctionReturn(0);
}

/*
   FSSolverSetLiquidAtRest - says that the case starts its liquid at rest in equilibrium under gravity (a tank
   filled to a level), and how deep it is, so that the at-rest check (the restcheck monitor) watches it when nothing
   forces it.

   Logically collective

   Input Parameters:
+  s       - the solver, from the case's setup
.  at_rest - whether the liquid starts at rest
-  depth   - the liquid's depth, from the lowest point of the container to the free surface

   Options Database Keys:
+  -fs_rest_check_time T  - the simulated time watched from the start (0.5 s; 0: no check)
.  -fs_rest_check_speed F - warn when the largest speed exceeds F sqrt(g H), H the liquid's depth (0.25)
-  -fs_rest_check_dt F    - warn when the time step's limit falls below F of the start's (0.25)

.seealso: FSSolverSetUp()
*/
PetscErrorCode FSSolverSetLiquidAtRest(FSSolver s, PetscBool at_rest, PetscReal depth)
{
  PetscFunctionBegin;
  PetscValidHeaderSpecific(s, FSSOLVER_CLASSID, 1);
  s->mon.at_rest    = at_rest;
  s->mon.rest_depth = depth;
  PetscFunctionReturn(0);
}

/*
   FSSolverGetRestView - what the at-rest check watches (src/monitor/impls/restcheck.c): the liquid the case started
   at rest, the particles' step limit from the state at the start of the last step and what set it.

   Not collective
*/
PetscErrorCode FSSolverGetRestView(FSSolver s, FSSolverRestView *v)
{
  PetscReal g = 0;

  PetscFunctionBegin;
  for (PetscInt d = 0; d < s->opt.dim; d++) g += s->opt.gravity[d] * s->opt.gravity[d];
  v->dim           = s->opt.dim;
  v->dx            = s->opt.dx;
  v->c0            = s->opt.c0;
  v->g             = PetscSqrtReal(g);
  v->at_rest       = s->mon.at_rest;
  v->depth         = s->mon.rest_depth;
  v->structure     = (PetscBool)(s->structure != NULL);
  v->nglobal       = s->pw.nglobal_particles;
  v->dt_stable     = s->state.dt_stable;
  v->dt_limit_term = (PetscBool)(s->state.dt_limit >= FS_DT_TERM);
  PetscCall(FSSolverDtLimitName(s, s->state.dt_limit, &v->dt_limit));
  PetscFunctionReturn(0);
}

/* FSSolverMaxSpeed2 - the largest squared speed of the particles in the state, over the ranks. Collective */
PetscErrorCode FSSolverMaxSpeed2(FSSolver s, PetscReal *v2)
{
  PetscFunctionBegin;
  PetscCall(FSSolverOwnedMaxSpeed2(s, v2));
  PetscCallMPI(MPI_Allreduce(MPI_IN_PLACE, v2, 1, MPIU_REAL, MPI_MAX, PetscObjectComm((PetscObject)s)));
  PetscFunctionReturn(0);
}

/*
   FSSolverGetParticleView - what the probes sample (src/monitor/impls/probes/): this rank's owned particles as the
   last evaluation left them (FSSolverEvaluateAtState() first for the current state), the kernel, the walls, the
   coupling and the domain. The pointers are the solver's, valid until its next step or evaluation.

   Not collective
*/
PetscErrorCode FSSolverGetParticleView(FSSolver s, FSSolverParticleView *v)
{
  PetscFunctionBegin;
  v->dim                 = s->opt.dim;
  v->stride              = s->pw.stride;
  v->nowned              = s->pw.nowned;
  v->nglobal             = s->pw.nglobal_particles;
  v->rec                 = s->pw.rec;
  v->vol                 = s->pw.vol;
  v->pressure            = s->pw.pressure;
  v->kernel              = &s->pw.kernel;
  v->boundary            = s->boundary;
  v->coupling            = s->coupling;
  v->dx                  = s->opt.dx;
  v->background_pressure = s->opt.background_pressure;
  for (PetscInt d = 0; d < 3; d++) {
    v->lo[d] = s->pw.lo[d];
    v->hi[d] = s->pw.hi[d];
  }
  PetscFunctionReturn(0);
}
