/*
   The solver's monitors: the list of FSMonitor objects (src/monitor/; the built-in ones, time series, energy budget,
   probes, snapshots, checkpoints, at-rest check, progress line and summary, made with their options by the solver and
   attached as a user's are) and plain callbacks (FSSolverMonitorSet()), called after every step; the deferred write
   status of their csv rows; the output directory.
*/
#include <errno.h>
#include <sys/stat.h>
#include "solver/solverimpl.h"

/*
   FSSolverWriteStatus - rank 0's first failed write of a monitor's csv file (timeseries.csv, energy.csv, probes.csv)
   not yet raised, as one real for a maximum over the ranks that a collective of the run carries (the step's
   reduction, FSSolverWriteStatusCheck()): 0 when none (always on the other ranks), else 1 + the monitor's place in the
   list + FS_MAX_MONITORS (its status - 1) (FSMonitorGetWriteStatus()).

   Not collective
*/
PetscReal FSSolverWriteStatus(FSSolver s)
{
  for (PetscInt k = 0; k < s->mon.nlist; k++) {
    PetscInt  status = 0;
    PetscBool unchecked;
    if (FSMonitorGetWriteStatus(s->mon.list[k], &status, &unchecked)) return 0; /* not a failed write */
    if (status) return (PetscReal)(1 + k + FS_MAX_MONITORS * (status - 1));
  }
  return 0;
}

/*
   FSSolverWriteStatusRaise - raises the failed write that status (FSSolverWriteStatus(), carried to every rank)
   names, on every rank; nothing when it is 0. Rows since the status was taken are now checked.

   Not collective (called on every rank with the same status)
*/
PetscErrorCode FSSolverWriteStatusRaise(FSSolver s, PetscReal status)
{
  const PetscInt code = (PetscInt)status;

  PetscFunctionBegin;
  for (PetscInt k = 0; k < s->mon.nlist; k++) PetscCall(FSMonitorRaiseWriteStatus(s->mon.list[k], 0));
  if (!code) PetscFunctionReturn(0);
  PetscCheck((code - 1) % FS_MAX_MONITORS < s->mon.nlist, PetscObjectComm((PetscObject)s), PETSC_ERR_PLIB,
             "Write status %" PetscInt_FMT " names no monitor", code);
  PetscCall(FSMonitorRaiseWriteStatus(s->mon.list[(code - 1) % FS_MAX_MONITORS], 1 + (code - 1) / FS_MAX_MONITORS));
  PetscFunctionReturn(0);
}

/*
   FSSolverWriteStatusCheck - when rows were written since the write status was last carried to the ranks, one
   broadcast of it, and its failure raised on every rank: at the end of the run and before a snapshot or checkpoint
   (so that a failed row is reported before another file is written).

   Collective
*/
PetscErrorCode FSSolverWriteStatusCheck(FSSolver s)
{
  PetscReal status;
  PetscBool unchecked = PETSC_FALSE;

  PetscFunctionBegin;
  for (PetscInt k = 0; k < s->mon.nlist; k++) {
    PetscInt  st;
    PetscBool u;
    PetscCall(FSMonitorGetWriteStatus(s->mon.list[k], &st, &u));
    unchecked = (PetscBool)(unchecked || u);
  }
  if (!unchecked) PetscFunctionReturn(0);
  status = FSSolverWriteStatus(s);
  PetscCallMPI(MPI_Bcast(&status, 1, MPIU_REAL, 0, PetscObjectComm((PetscObject)s)));
  PetscCall(FSSolverWriteStatusRaise(s, status));
  PetscFunctionReturn(0);
}

/*
   FSSolverMonitorAdd - attaches a monitor to the solver: after every step (and once before the first) it writes what
   it reports, after the monitors attached before it. The solver keeps a reference; FSSolverDestroy() and
   FSSolverMonitorCancel() give it back.

   Logically collective

   Input Parameters:
+  s   - the solver
-  mon - the monitor, with its type set (FSMonitorSetType())

   Notes:
   The run's own output is made of built-in monitors (FSMONITORTIMESERIES, FSMONITORENERGY, FSMONITORPROBES,
   FSMONITORSNAPSHOTS, FSMONITORCHECKPOINTS, FSMONITORRESTCHECK, FSMONITORPROGRESS, FSMONITORSUMMARY), which the
   solver attaches first when the run's output begins (with -fs_output 0 the at-rest check and the progress line
   only). A monitor attached after the run began
begins at once; its first call is after the next step. At most 16 monitors.

.seealso: FSSolverMonitorSet(), FSSolverMonitorCancel(), FSMonitorCreate(), FSMonitorRegister()
*/
PetscErrorCode FSSolverMonitorAdd(FSSolver s, FSMonitor mon)
{
  PetscFunctionBegin;
  PetscValidHeaderSpecific(s, FSSOLVER_CLASSID, 1);
  PetscCheck(s->mon.nlist < FS_MAX_MONITORS, PetscObjectComm((PetscObject)s), PETSC_ERR_ARG_OUTOFRANGE,
             "FSSolverMonitorAdd(): the solver holds %d monitors already, the most it can", FS_MAX_MONITORS);
  PetscCall(PetscObjectReference((PetscObject)mon));
  s->mon.list[s->mon.nlist++] = mon;
  if (s->mon.monitoring) PetscCall(FSMonitorBegin(mon, s));
  PetscFunctionReturn(0);
}

/*
   FSSolverMonitorSet - adds a plain monitor, as TSMonitorSet(): a function called after every step (and once before
   the first) with the step number and the time, after the monitor objects (FSSolverMonitorAdd()).

   Logically collective

   Input Parameters:
+  s       - the solver
.  fn      - the function: PetscErrorCode fn(FSSolver s, PetscInt step, PetscReal t, void *ctx)
.  ctx     - its context (may be NULL)
-  destroy - frees the context when the solver is destroyed or the monitors cancelled (may be NULL)

   Notes:
   The function may read the run through the public API (FSSolverGetField(), FSSolverGetEnergy(),
   FSSolverGetWallLoads(), FSSolverGetProbes(), ...), collectively where those are. At most 16.

.seealso: FSSolverMonitorAdd(), FSSolverMonitorCancel()
*/
PetscErrorCode FSSolverMonitorSet(FSSolver s, FSSolverMonitorFn fn, void *ctx, PetscErrorCode (*destroy)(void **))
{
  PetscFunctionBegin;
  PetscValidHeaderSpecific(s, FSSOLVER_CLASSID, 1);
  PetscCheck(s->mon.nfn < FS_MAX_MONITORS, PetscObjectComm((PetscObject)s), PETSC_ERR_ARG_OUTOFRANGE,
             "FSSolverMonitorSet(): the solver holds %d monitor functions already, the most it can", FS_MAX_MONITORS);
  s->mon.fn[s->mon.nfn]        = fn;
  s->mon.fnctx[s->mon.nfn]     = ctx;
  s->mon.fndestroy[s->mon.nfn] = destroy;
  s->mon.nfn++;
  PetscFunctionReturn(0);
}

/*
   FSSolverMonitorCancel - removes the monitors a user attached (FSSolverMonitorAdd(), FSSolverMonitorSet()), freeing
   their contexts; the run's own (the built-in monitors) stay.

   Logically collective

.seealso: FSSolverMonitorAdd(), FSSolverMonitorSet()
*/
PetscErrorCode FSSolverMonitorCancel(FSSolver s)
{
  PetscFunctionBegin;
  PetscValidHeaderSpecific(s, FSSOLVER_CLASSID, 1);
  for (PetscInt k = s->mon.nbuiltin; k < s->mon.nlist; k++) PetscCall(FSMonitorDestroy(&s->mon.list[k]));
  s->mon.nlist = s->mon.nbuiltin;
  for (PetscInt k = 0; k < s->mon.nfn; k++)
    if (s->mon.fndestroy[k]) PetscCall((*s->mon.fndestroy[k])(&s->mon.fnctx[k]));
  s->mon.nfn = 0;
  PetscFunctionReturn(0);
}

/*
   FSSolverGetProbes - the values of the probes and wave gauges (-fs_probes) at the current state.

   Collective

   Input Parameter:
.  s - the solver, set up

   Output Parameters:
+  n       - the number of probes and gauges, in the order of the file (0 without -fs_probes)
.  names   - their names (an array of n pointers, or NULL); owned by the solver
.  offsets - (an array of n+1, or NULL) item k's values are values[offsets[k] .. offsets[k+1]): a probe's
             pressure then its velocity (dim values), then with a cut-off or a rate its filtered pressure (the
             reading of the last sample of probes.csv), a gauge's elevation
-  values  - (an array of at most FS_PROBE_MAX_VALUES n reals, or NULL) the values, as the columns of
             probes.csv

   Notes:
   The values are those of the current state: sampled at this step by the run's output, or computed now
   (one evaluation of the right-hand side). Pass NULL for names, offsets and values to get n only. The probes are
   the solver's probes monitor's, which the set-up sets up (FSMonitorProbesGetValues()).

.seealso: FSSolverStep(), FSMonitorProbesGetValues(), docs/running.md, "Probes and wave gauges"
*/
PetscErrorCode FSSolverGetProbes(FSSolver s, PetscInt *n, const char *names[], PetscInt offsets[], PetscReal values[])
{
  PetscFunctionBegin;
  PetscValidHeaderSpecific(s, FSSOLVER_CLASSID, 1);
  PetscCheck(s->setupcalled, PetscObjectComm((PetscObject)s), PETSC_ERR_ARG_WRONGSTATE,
             "FSSolverGetProbes(): call FSSolverSetUp() first");
  PetscCall(FSMonitorProbesGetValues(s->mon.probes, s, n, names, offsets, values));
  PetscFunctionReturn(0);
}

/*
   FSSolverWriteCheckpoint - writes <output_dir>/checkpoint_<step>.h5 with the whole state (FSMonitorCheckpointsWrite(),
   through the solver's checkpoints monitor, which the run attaches with -fs_checkpoint_interval). A run
   started with -fs_restart on that file continues exactly as the uninterrupted run.

   Collective

   Notes:
   The run writes one every -fs_checkpoint_interval steps (its checkpoints monitor); a driver may write one
   at any step of a run whose output is open (after its first step), as the Python package does when
   a run is interrupted (KeyboardInterrupt).

.seealso: FSMonitorCheckpointsWrite(), docs/running.md
*/
PetscErrorCode FSSolverWriteCheckpoint(FSSolver s)
{
  PetscFunctionBegin;
  PetscValidHeaderSpecific(s, FSSOLVER_CLASSID, 1);
  PetscCheck(s->mon.monitoring, PetscObjectComm((PetscObject)s), PETSC_ERR_ARG_WRONGSTATE,
             "FSSolverWriteCheckpoint(): the run's output is not open: take a step first");
  PetscCall(FSMonitorCheckpointsWrite(s->mon.checkpoints, s)); /* attached or not (no -fs_checkpoint_interval) */
  PetscFunctionReturn(0);
}

/*
   FSSolverGetMonitors - the monitor objects attached to the solver, the built-in ones first.

   Not collective

   Output Parameters:
+  n    - their number
-  mons - the monitors (owned by the solver)
*/
PetscErrorCode FSSolverGetMonitors(FSSolver s, PetscInt *n, const FSMonitor *mons[])
{
  PetscFunctionBegin;
  PetscValidHeaderSpecific(s, FSSOLVER_CLASSID, 1);
  if (n) *n = s->mon.nlist;
  if (mons) *mons = s->mon.list;
  PetscFunctionReturn(0);
}

/*
   FSSolverBuiltinMonitorsCreate - the built-in monitors (time series, energy budget, probes, snapshots, checkpoints,
   at-rest check, progress line, summary), made once, without their options: FSSolverSetFromOptions() has each read its
   own inside the solver's options block (FSMonitorSetFromOptionItems()), so that -help lists them where it always did.

   Collective
*/
PetscErrorCode FSSolverBuiltinMonitorsCreate(FSSolver s)
{
  FSMonitor  *mons[]  = {&s->mon.series,      &s->mon.energy,    &s->mon.probes,   &s->mon.snapshots,
                         &s->mon.checkpoints, &s->mon.restcheck, &s->mon.progress, &s->mon.summary};
  const char *types[] = {FSMONITORTIMESERIES,  FSMONITORENERGY,    FSMONITORPROBES,   FSMONITORSNAPSHOTS,
                         FSMONITORCHECKPOINTS, FSMONITORRESTCHECK, FSMONITORPROGRESS, FSMONITORSUMMARY};

  PetscFunctionBegin;
  for (size_t k = 0; k < PETSC_STATIC_ARRAY_LENGTH(mons); k++) {
    if (*mons[k]) continue;
    PetscCall(FSMonitorCreate(PetscObjectComm((PetscObject)s), mons[k]));
    PetscCall(FSMonitorSetType(*mons[k], types[k]));
  }
  PetscFunctionReturn(0);
}

/* FSSolverBuiltinMonitorsSetUp - sets up the built-in monitors (the solver's set-up: the probe file read and checked,
   the snapshots' interval against the final time). Collective */
PetscErrorCode FSSolverBuiltinMonitorsSetUp(FSSolver s)
{
  PetscFunctionBegin;
  PetscCall(FSSolverBuiltinMonitorsCreate(s));
  {
    FSMonitor mons[] = {s->mon.series,      s->mon.energy,    s->mon.probes,   s->mon.snapshots,
                        s->mon.checkpoints, s->mon.restcheck, s->mon.progress, s->mon.summary};
    for (size_t k = 0; k < PETSC_STATIC_ARRAY_LENGTH(mons); k++) PetscCall(FSMonitorSetUp(mons[k], s));
  }
  PetscFunctionReturn(0);
}

/* FSSolverBuiltinMonitorsDestroy - gives back the solver's references to its built-in monitors. Collective */
PetscErrorCode FSSolverBuiltinMonitorsDestroy(FSSolver s)
{
  PetscFunctionBegin;
  PetscCall(FSMonitorDestroy(&s->mon.series));
  PetscCall(FSMonitorDestroy(&s->mon.energy));
  PetscCall(FSMonitorDestroy(&s->mon.probes));
  PetscCall(FSMonitorDestroy(&s->mon.snapshots));
  PetscCall(FSMonitorDestroy(&s->mon.checkpoints));
  PetscCall(FSMonitorDestroy(&s->mon.restcheck));
  PetscCall(FSMonitorDestroy(&s->mon.progress));
  PetscCall(FSMonitorDestroy(&s->mon.summary));
  PetscFunctionReturn(0);
}

/* the run's built-in monitors, put first in the list (before those a user attached before the run): with the output
   (-fs_output) the time series, the energy budget, the probes with a file of items, the snapshots, the checkpoints
   with an interval; the at-rest check and the progress line; with the output the summary, last, so that it counts what
   the others' ends cost */
static PetscErrorCode FSSolverAddBuiltinMonitors(FSSolver s)
{
  FSMonitor add[8];
  PetscInt  n = 0, nuser = s->mon.nlist, nprobes = 0, ckinterval = 0;
  FSMonitor user[FS_MAX_MONITORS];

  PetscFunctionBegin;
  PetscCall(FSSolverBuiltinMonitorsSetUp(s)); /* done by the set-up already: nothing new */
  PetscCall(FSMonitorProbesGetValues(s->mon.probes, s, &nprobes, NULL, NULL, NULL));
  PetscCall(FSMonitorCheckpointsGetInterval(s->mon.checkpoints, &ckinterval));
  if (s->opt.write_output) {
    add[n++] = s->mon.series;
    add[n++] = s->mon.energy;
    if (nprobes) add[n++] = s->mon.probes; /* a file without items: none */
    add[n++] = s->mon.snapshots;
    if (ckinterval > 0) add[n++] = s->mon.checkpoints;
  }
  add[n++] = s->mon.restcheck;
  add[n++] = s->mon.progress;
  if (s->opt.write_output) add[n++] = s->mon.summary;
  PetscCheck(nuser + n <= FS_MAX_MONITORS, PetscObjectComm((PetscObject)s), PETSC_ERR_ARG_OUTOFRANGE,
             "The run's %" PetscInt_FMT " output monitors and the %" PetscInt_FMT
             " a user attached are more than the %d a solver holds",
             n, nuser, FS_MAX_MONITORS);
  for (PetscInt k = 0; k < nuser; k++) user[k] = s->mon.list[k];
  s->mon.nlist = 0;
  for (PetscInt k = 0; k < n; k++) {
    PetscCall(PetscObjectReference((PetscObject)add[k]));
    s->mon.list[s->mon.nlist++] = add[k];
  }
  for (PetscInt k = 0; k < nuser; k++) s->mon.list[s->mon.nlist++] = user[k];
  s->mon.nbuiltin = n;
  PetscFunctionReturn(0);
}

/* the monitors and the plain callbacks at this step (the rows, then each monitor in order, then the callbacks) */
static PetscErrorCode FSSolverMonitorsStep(FSSolver s)
{
  PetscReal t;
  PetscInt  step;

  PetscFunctionBegin;
  PetscCall(TSGetTime(s->ts, &t));
  PetscCall(TSGetStepNumber(s->ts, &step));
  if (s->mon.rows.active) /* their sums rode on the step's reduction (FSSolverStepReduce) */
    PetscCall(FSMonitorRowsEnd(s->mon.nlist, s->mon.list, s, &s->mon.rows));
  else PetscCall(FSMonitorRows(s->mon.nlist, s->mon.list, s)); /* timeseries.csv and energy.csv: one reduction */
  for (PetscInt k = 0; k < s->mon.nlist; k++) PetscCall(FSMonitorStep(s->mon.list[k], s));
  for (PetscInt k = 0; k < s->mon.nfn; k++) PetscCall((*s->mon.fn[k])(s, step, t, s->mon.fnctx[k]));
  PetscFunctionReturn(0);
}

/*
   FSSolverOutputDirChoose - without -fs_output_dir, makes the run's own directory: output/<name>-<time stamp> as
   FSSolverSetFromOptions() named it, or with -2, -3, ... added when it exists (a run started in the same second),
   made by rank 0 with mkdir(), which fails on an existing directory, so that two runs never share one; says where.
   Nothing to do with -fs_output_dir, or once made.

   Collective
*/
PetscErrorCode FSSolverOutputDirChoose(FSSolver s)
{
  MPI_Comm    comm = PetscObjectComm((PetscObject)s);
  PetscMPIInt rank;
  int         err = 0;
  char        dir[PETSC_MAX_PATH_LEN];

  PetscFunctionBegin;
  if (!s->opt.outdir_auto || s->opt.outdir_taken) PetscFunctionReturn(0);
  PetscCallMPI(MPI_Comm_rank(comm, &rank));
  PetscCall(PetscStrncpy(dir, s->opt.outdir, sizeof(dir)));
  if (!rank) {
    char *slash = strrchr(dir, '/');
    if (slash) { /* the parent, output/ */
      *slash = 0;
      if (mkdir(dir, S_IRWXU | S_IRWXG | S_IRWXO) && errno != EEXIST) err = errno;
      *slash = '/';
    }
    for (int k = 2; !err && mkdir(dir, S_IRWXU | S_IRWXG | S_IRWXO); k++) {
      if (errno != EEXIST || k > 1000) err = errno;
      else PetscCall(PetscSNPrintf(dir, sizeof(dir), "%s-%d", s->opt.outdir, k));
    }
  }
  PetscCallMPI(MPI_Bcast(&err, 1, MPI_INT, 0, comm));
  PetscCheck(
      !err, comm, PETSC_ERR_FILE_OPEN,
      "Cannot make the output directory \"%s\" (the default, new for each run; -fs_output_dir gives another): %s", dir,
      strerror(err));
  PetscCallMPI(MPI_Bcast(dir, sizeof(dir), MPI_CHAR, 0, comm));
  PetscCall(PetscStrncpy(s->opt.outdir, dir, sizeof(s->opt.outdir)));
  s->opt.outdir_taken = PETSC_TRUE;
  PetscCall(PetscPrintf(comm, "Output directory: %s (new for this run; -fs_output_dir DIR writes to DIR)\n", dir));
  PetscFunctionReturn(0);
}

/*
   FSSolverOpenOutputDir - the output directory, once: made, checked writable on every rank (FSMakeDirectory()),
   locked for this run (FSOutputDirLock(): another run writing there is an error naming it), and for a new run (not a
   restart, which continues what the directory holds) cleared of what an earlier run wrote there (FSOutputDirClear()),
   so that it holds this run's results only. The lock is given back by FSSolverDestroy().

   Collective
*/
PetscErrorCode FSSolverOpenOutputDir(FSSolver s)
{
  MPI_Comm comm = PetscObjectComm((PetscObject)s);

  PetscFunctionBegin;
  if (s->mon.lock) PetscFunctionReturn(0);
  PetscCall(FSSolverOutputDirChoose(s));
  PetscCall(FSMakeDirectory(comm, s->opt.outdir, "-fs_output_dir"));
  PetscCall(FSOutputDirLock(comm, s->opt.outdir, "-fs_output_dir", &s->mon.lock));
  if (!s->opt.restart[0]) PetscCall(FSOutputDirClear(comm, s->opt.outdir));
  PetscFunctionReturn(0);
}

/*
   FSSolverMonitorBegin - opens the output (directory, walls.h5 + walls.xdmf, the built-in monitors: time series,
   energy budget, probes, snapshots, checkpoints) and records the initial state with every monitor. Called by
   FSSolverSolve, or by the first FSSolverStep before its step.
*/
PetscErrorCode FSSolverMonitorBegin(FSSolver s)
{
  PetscInt  step;
  PetscReal t;

  PetscFunctionBegin;
  if (s->mon.monitoring) PetscFunctionReturn(0);
  PetscCall(FSSolverSetUp(s));
  s->mon.monitoring = PETSC_TRUE;
  PetscCall(PetscTime(&s->mon.wall_start));
  PetscCall(TSGetTime(s->ts, &t));
  PetscCall(TSGetStepNumber(s->ts, &step));
  s->mon.step0          = step;
  s->mon.t0             = t;
  s->mon.particle_steps = 0;
  s->mon.steps_taken    = 0;
  s->mon.nrebuilds      = 0;
  s->mon.nrebalances    = 0;
  s->mon.pair_visits    = 0;
  PetscCall(FSParallelStatsBegin(s));
  if (!s->opt.restart[0])
    PetscCall(FSSolverEnergyInitial(s)); /* the energy budget's initial values (a restart has them in its state) */
  if (s->opt.write_output) {
    PetscCall(FSSolverCheckState(s)); /* before the output is touched: a restart refused leaves it as it was */
    PetscCall(FSSolverOpenOutputDir(s));
    /* the walls beside the snapshots, for ParaView and the movie (the geometry view has written them) */
    if (s->boundary && !s->opt.geometry_view)
      PetscCall(FSBoundaryWriteGeometry(s->boundary, s->opt.outdir, PETSC_FALSE));
  }
  PetscCall(FSSolverAddBuiltinMonitors(s));
  for (PetscInt k = 0; k < s->mon.nlist; k++) PetscCall(FSMonitorBegin(s->mon.list[k], s)); /* files opened */
  PetscCall(FSSolverMonitorsStep(s)); /* the state the run starts from (on a restart, the files were cut before it) */
  PetscFunctionReturn(0);
}

/* FSSolverMonitor - called after every step: the monitors (time series and energy budget every -fs_series_interval
   steps and at the last step, probes, snapshots, checkpoints, the at-rest check, the progress line, the user's). */
PetscErrorCode FSSolverMonitor(FSSolver s)
{
  PetscBool end;

  PetscFunctionBegin;
  if (!s->mon.monitoring) PetscCall(FSSolverMonitorBegin(s));
  PetscCall(FSSolverAtEnd(s, &end));
  PetscCall(FSSolverMonitorsStep(s));
  if (end) PetscCall(FSSolverWriteStatusCheck(s)); /* the last rows' write status: no step's reduction carries it */
  PetscFunctionReturn(0);
}

/* FSSolverMonitorEnd - the monitors' end (the last snapshot, the run's summary.json). */
PetscErrorCode FSSolverMonitorEnd(FSSolver s)
{
  PetscFunctionBegin;
  if (!s->mon.monitoring) PetscFunctionReturn(0);
  PetscCall(FSSolverWriteStatusCheck(s)); /* the last rows' write status, when no step carried it */
  for (PetscInt k = 0; k < s->mon.nlist; k++) PetscCall(FSMonitorEnd(s->mon.list[k], s));
  PetscFunctionReturn(0);
}
