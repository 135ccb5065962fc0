/*
   Monitors: the per-step time series (energy, mass, momentum, extremes, dissipated energies), the
   energy budget (energy.csv, src/coupling/energy.c),
   particle snapshots at the output interval, checkpoints, the progress line and the summary.
*/
#include <errno.h>
#include <sys/stat.h>
#include "solver/solverimpl.h"

#define FS_MAX_WALL_COLUMNS  16 /* walls whose loads go into the time series */
#define FS_MAX_FLUID_COLUMNS (32 + FS_CASE_MAX_COLUMNS + FS_MAX_TERMS)
#define FS_MAX_COLUMNS       (FS_MAX_FLUID_COLUMNS + FS_STRUCTURE_MAX_COLUMNS + 6 * FS_MAX_WALL_COLUMNS)

/* This rank's sums for the row's diagnostics: kinetic energy, mass, momentum (3), and its largest |u|^2. */
static PetscErrorCode FSSolverDiagnosticsLocal(FSSolver s, PetscReal loc[5], PetscReal *v2max)
{
  const PetscInt     dim = s->opt.dim, US = s->state.ustride, S = s->pw.stride;
  const PetscScalar *u;
  PetscReal          vmax = 0;

  PetscFunctionBegin;
  for (PetscInt k = 0; k < 5; k++) loc[k] = 0;
  PetscCall(VecGetArrayRead(s->state.U, &u));
  for (PetscInt p = 0; p < s->pw.nowned; p++) {
    const PetscReal m  = s->pw.rec[p * S + 2 * dim + 1];
    PetscReal       v2 = 0;
    for (PetscInt d = 0; d < dim; d++) {
      const PetscReal v = u[p * US + dim + d];
      v2 += v * v;
      loc[2 + d] += m * v;
    }
    loc[0] += 0.5 * m * v2;
    loc[1] += m;
    vmax = PetscMax(vmax, v2);
  }
  PetscCall(VecRestoreArrayRead(s->state.U, &u));
  *v2max = vmax;
  PetscFunctionReturn(0);
}

/* the csv files whose write status is deferred (FSTimeSeriesSetDeferred()), in the order of FSSolverWriteStatus() */
static void FSSolverDeferredFiles(FSSolver s, FSTimeSeries f[3])
{
  f[0] = s->mon.series;
  f[1] = s->mon.energyseries;
  f[2] = s->mon.probes.series;
}

/*
   FSSolverWriteStatus - rank 0's first failed write of timeseries.csv, energy.csv or probes.csv not yet raised, as one
   real for a maximum over the ranks that a collective of the run carries (the step's reduction,
   FSSolverWriteStatusCheck()): 0 when none (always on the other ranks), else 4 (2 errno + torn) + 1 + the file.

   Not collective
*/
PetscReal FSSolverWriteStatus(FSSolver s)
{
  FSTimeSeries f[3];

  FSSolverDeferredFiles(s, f);
  for (int k = 0; k < 3; k++) {
    int       err = 0;
    PetscBool torn;
    if (f[k] && !FSTimeSeriesGetFailure(f[k], &err, &torn) && err)
      return (PetscReal)(4 * (2 * err + (torn ? 1 : 0)) + 1 + k);
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
  const int    code = (int)status;
  FSTimeSeries f[3];

  PetscFunctionBegin;
  s->mon.rows_unchecked = PETSC_FALSE;
  if (!code) PetscFunctionReturn(0);
  FSSolverDeferredFiles(s, f);
  PetscCheck(f[(code - 1) % 4], PetscObjectComm((PetscObject)s), PETSC_ERR_PLIB, "Write status %d names no file", code);
  PetscCall(FSTimeSeriesRaiseFailure(f[(code - 1) % 4], (code - 1) / 8, (PetscBool)(((code - 1) / 4) % 2)));
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

  PetscFunctionBegin;
  if (!s->mon.rows_unchecked) PetscFunctionReturn(0);
  status = FSSolverWriteStatus(s);
  PetscCallMPI(MPI_Bcast(&status, 1, MPIU_REAL, 0, PetscObjectComm((PetscObject)s)));
  PetscCall(FSSolverWriteStatusRaise(s, status));
  PetscFunctionReturn(0);
}

/*
   A row of timeseries.csv and energy.csv: a local pass fills one buffer with this rank's sums (the diagnostics, the
   walls' loads of the last right-hand side, the liquid's energies) and its largest speed, one reduction
   (FSSolverReduceSumMax) sums them over the ranks, then the rows are made and written by rank 0, their write status
   left for the next step's reduction (FSSolverWriteStatus()).

   Collective
*/
static PetscErrorCode FSSolverAppendSeries(FSSolver s)
{
  PetscReal        vals[FS_MAX_COLUMNS], evals[FS_ENERGY_MAX_COLUMNS], buf[64], *sum = buf, v2max, t, dt;
  const PetscReal *wloc = NULL, *esum = NULL, *wsum = NULL;
  PetscInt         k = 0, step, nwalls = 0, nsum = 5;
  PetscMPIInt      rank;
  FSTankMotion     mo;

  PetscFunctionBegin;
  if (!s->mon.series) PetscFunctionReturn(0);
  if (s->boundary) PetscCall(FSBoundaryGetLoadsLocal(s->boundary, &nwalls, &wloc));
  nsum += FS_WALL_LOAD_STRIDE * nwalls + (s->mon.energyseries ? FS_ENERGY_NSUMS : 0);
  if (nsum > (PetscInt)PETSC_STATIC_ARRAY_LENGTH(buf)) PetscCall(PetscMalloc1(nsum, &sum));
  PetscCall(FSSolverDiagnosticsLocal(s, sum, &v2max));
  if (nwalls) PetscCall(PetscArraycpy(sum + 5, wloc, FS_WALL_LOAD_STRIDE * nwalls));
  if (s->mon.energyseries) PetscCall(FSSolverEnergyLocal(s, sum + 5 + FS_WALL_LOAD_STRIDE * nwalls, &mo));
  PetscCall(FSSolverReduceSumMax(s, nsum, sum, 1, &v2max)); /* the row's one reduction */
  wsum = sum + 5;
  esum = wsum + FS_WALL_LOAD_STRIDE * nwalls;

  PetscCallMPI(MPI_Comm_rank(PetscObjectComm((PetscObject)s), &rank));
  PetscCall(TSGetTime(s->ts, &t));
  PetscCall(TSGetStepNumber(s->ts, &step));
  if (step > s->mon.step0) { /* the step just taken (TS's own time step is its proposal for the next one) */
    PetscReal tprev;
    PetscCall(TSGetPrevTime(s->ts, &tprev));
    dt = t - tprev;
  } else PetscCall(TSGetTimeStep(s->ts, &dt));
  vals[k++] = t;
  vals[k++] = dt;
  vals[k++] = (PetscReal)s->state.dt_limit;
  vals[k++] = sum[0];
  vals[k++] = sum[1];
  for (PetscInt d = 0; d < s->opt.dim; d++) vals[k++] = sum[2 + d];
  vals[k++] = PetscSqrtReal(v2max);
  vals[k++] = s->state.max_variation;
  if (!rank && s->state.ndiss) { /* the dissipated energies */
    const PetscScalar *u;
    PetscCall(VecGetArrayRead(s->state.U, &u));
    for (PetscInt g = s->state.gdiss; g < s->state.gdiss + s->state.ndiss; g++)
      vals[k++] = u[s->pw.nowned * s->state.ustride + g];
    PetscCall(VecRestoreArrayRead(s->state.U, &u));
  } else k += s->state.ndiss;
  if (s->caseops.columns) {
    PetscCall((*s->caseops.columns)(s, t, &vals[k]));
    k += s->caseops.ncolumns;
  }
  if (s->boundary) { /* the liquid's loads on each wall, from the step's last right-hand side */
    const PetscReal *L;
    PetscCall(FSBoundaryGetWallLoadsSummed(s->boundary, wsum, &nwalls, &L)); /* each moment about its wall's point */
    for (PetscInt w = 0; w < PetscMin(nwalls, FS_MAX_WALL_COLUMNS); w++) {
      const PetscReal *Lw = &L[FS_WALL_LOAD_STRIDE * w];
      if (s->opt.dim == 3) { /* force and moment vectors */
        for (PetscInt c = 0; c < FS_WALL_LOAD_STRIDE; c++) vals[k++] = Lw[c];
      } else { /* the in-plane force and the moment about z */
        vals[k++] = Lw[FS_WALL_LOAD_FORCE];
        vals[k++] = Lw[FS_WALL_LOAD_FORCE + 1];
        vals[k++] = Lw[FS_WALL_LOAD_MOMENT + 2];
      }
    }
  }
  if (s->structure) { /* the structure's motion, loads and the model's own columns */
    const char *names[FS_MAX_COLUMNS];
    PetscInt    nc;
    PetscCall(FSSolverStructureColumns(s, &nc, names));
    PetscCall(FSSolverStructureValues(s, &vals[k]));
    k += nc;
  }
  /* energy.csv's row, the energy budget (src/solver/energy.c), first: its check of the structure's energy stops the
     run before either row of the step is written */
  if (s->mon.energyseries) PetscCall(FSSolverEnergySummed(s, esum, &mo, evals));
  if (sum != buf) PetscCall(PetscFree(sum));
  PetscCall(FSTimeSeriesAppend(s->mon.series, step, vals));
  /* rank 0: energy.csv's row only where timeseries.csv's was written, as when a failed row stopped the run at once */
  if (s->mon.energyseries && !FSSolverWriteStatus(s)) PetscCall(FSTimeSeriesAppend(s->mon.energyseries, step, evals));
  s->mon.rows_unchecked = PETSC_TRUE;
  PetscFunctionReturn(0);
}

/* the first multiple of the output interval after t (one within 1e-9 of the interval is t's), computed rather than
   counted up to, so that no interval loops however small it is against t; none without an interval */
static PetscReal FSNextOutputTime(PetscReal t, PetscReal interval)
{
  return interval > 0 ? (PetscFloorReal(t / interval + 1e-9) + 1) * interval : PETSC_MAX_REAL;
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
   FSSolverMonitorBegin - opens the output (directory, walls.h5 + walls.xdmf, time series, snapshots) and records the
   initial state. Called by FSSolverSolve, or by the first FSSolverStep before its step.
*/
PetscErrorCode FSSolverMonitorBegin(FSSolver s)
{
  MPI_Comm           comm = PetscObjectComm((PetscObject)s);
  const char        *names[FS_MAX_COLUMNS];
  char               namebuf[FS_MAX_TERMS][80], wallbuf[6 * FS_MAX_WALL_COLUMNS][80], path[PETSC_MAX_PATH_LEN];
  PetscInt           k = 0, step;
  PetscReal          t;
  static const char *mom[] = {"momentum_x", "momentum_y", "momentum_z"};

  PetscFunctionBegin;
  if (s->mon.monitoring) PetscFunctionReturn(0);
  PetscCall(FSSolverSetUp(s));
  s->mon.monitoring = PETSC_TRUE;
  PetscCall(PetscTime(&s->mon.wall_start));
  s->mon.wall_last_progress = s->mon.wall_start;
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
  PetscCall(FSSolverRestCheckBegin(s)); /* a liquid at rest too shallow in particles: warned here */
  /* snapshots at multiples of the interval, also after a restart */
  s->mon.next_output        = FSNextOutputTime(t, s->opt.output_interval);
  s->mon.last_snapshot_time = PETSC_MIN_REAL; /* no snapshot yet */
  if (!s->opt.restart[0])
    PetscCall(FSSolverEnergyInitial(s)); /* the energy budget's initial values (a restart has them in its state) */
  if (!s->opt.write_output) PetscFunctionReturn(0);
  PetscCall(FSSolverCheckState(s)); /* before the output is touched: a restart refused leaves it as it was */
  PetscCall(FSSolverOpenOutputDir(s));
  /* the walls beside the snapshots, for ParaView and the movie (the geometry view has written them) */
  if (s->boundary && !s->opt.geometry_view) PetscCall(FSBoundaryWriteGeometry(s->boundary, s->opt.outdir, PETSC_FALSE));
  names[k++] = "time";
  names[k++] = "dt";
  names[k++] = "dt_limit"; /* what set the step: FSDtLimit, its names in summary.json's dt_limit_steps order */
  names[k++] = "kinetic_energy";
  names[k++] = "mass";
  for (PetscInt d = 0; d < s->opt.dim; d++) names[k++] = mom[d];
  names[k++] = "max_velocity";
  names[k++] = "max_density_variation";
  for (PetscInt g = 0, q = 0; g < s->terms.nterms; g++)
    if (s->terms.term[g]->has_power) {
      PetscCall(PetscSNPrintf(namebuf[q], sizeof(namebuf[q]), "dissipated_%s", s->terms.term[g]->name));
      names[k++] = namebuf[q++];
    }
  if (s->caseops.columns)
    for (PetscInt c = 0; c < s->caseops.ncolumns; c++) names[k++] = s->caseops.column_names[c];
  if (s->boundary) {
    static const char *part2[] = {"force_x", "force_y", "moment"};
    static const char *part3[] = {"force_x", "force_y", "force_z", "moment_x", "moment_y", "moment_z"};
    const PetscInt     np      = s->opt.dim == 3 ? 6 : 3;
    const char *const *wname;
    PetscInt           nwalls;
    PetscCall(FSBoundaryGetWallNames(s->boundary, &nwalls, &wname));
    for (PetscInt w = 0; w < PetscMin(nwalls, FS_MAX_WALL_COLUMNS); w++)
      for (PetscInt c = 0; c < np; c++) {
        PetscCall(PetscSNPrintf(wallbuf[np * w + c], sizeof(wallbuf[0]), "wall_%s_%s", wname[w],
                                np == 6 ? part3[c] : part2[c]));
        names[k++] = wallbuf[np * w + c];
      }
  }
  {
    PetscInt nc;
    PetscCall(FSSolverStructureColumns(s, &nc, &names[k]));
    k += nc;
  }
  PetscCall(PetscSNPrintf(path, sizeof(path), "%s/timeseries.csv", s->opt.outdir));
  PetscCall(FSTimeSeriesCreate(comm, path, k, names, s->opt.restart[0] ? step : -1, &s->mon.series));
  PetscCall(FSSolverEnergyColumns(s, &k, names));
  PetscCall(PetscSNPrintf(path, sizeof(path), "%s/energy.csv", s->opt.outdir));
  PetscCall(FSTimeSeriesCreate(comm, path, k, names, s->opt.restart[0] ? step : -1, &s->mon.energyseries));
  /* a row's write status rides on the next step's reduction (FSSolverWriteStatus()), not on a broadcast of its own */
  PetscCall(FSTimeSeriesSetDeferred(s->mon.series, PETSC_TRUE));
  PetscCall(FSTimeSeriesSetDeferred(s->mon.energyseries, PETSC_TRUE));
  PetscCall(FSSnapshotWriterCreate(comm, s->opt.outdir, s->opt.restart[0] ? t : -1.0, &s->mon.snapshots));
  PetscCall(FSSolverAppendSeries(s)); /* on restart, the series was cut just before this row */
  PetscCall(FSSolverProbesBegin(s));  /* probes.csv, as the series */
  if (!s->opt.restart[0]) PetscCall(FSSolverWriteSnapshot(s));
  PetscFunctionReturn(0);
}

/* FSSolverMonitor - called after every step: time series (every -fs_series_interval steps and at the last step),
   snapshots, checkpoints, progress. */
PetscErrorCode FSSolverMonitor(FSSolver s)
{
  PetscReal      t, tmax, dt;
  PetscInt       step;
  PetscBool      end;
  PetscLogDouble now;

  PetscFunctionBegin;
  if (!s->mon.monitoring) PetscCall(FSSolverMonitorBegin(s));
  PetscCall(TSGetTime(s->ts, &t));
  PetscCall(TSGetStepNumber(s->ts, &step));
  PetscCall(FSSolverAtEnd(s, &end)); /* the last step's row is written whatever the interval */
  if ((step - s->mon.step0) % s->opt.series_interval == 0 || end) PetscCall(FSSolverAppendSeries(s));
  PetscCall(FSSolverProbesMonitor(s));
  PetscCall(FSSolverRestCheck(s)); /* the first steps: a liquid at rest that moves, a step that collapses */
  if (s->opt.write_output && s->opt.output_interval > 0 && t >= s->mon.next_output - 1e-9 * s->opt.output_interval) {
    PetscCall(FSSolverWriteSnapshot(s));
    s->mon.next_output = FSNextOutputTime(t, s->opt.output_interval);
  }
  if (s->opt.write_output && s->opt.checkpoint_interval > 0 && step % s->opt.checkpoint_interval == 0)
    PetscCall(FSSolverWriteCheckpoint(s));
  PetscCall(PetscTime(&now));
  if (s->opt.progress && now - s->mon.wall_last_progress >= s->opt.progress_interval) {
    PetscReal frac, eta;
    PetscCall(TSGetMaxTime(s->ts, &tmax));
    PetscCall(TSGetTimeStep(s->ts, &dt));
    frac = tmax > s->mon.t0 ? (t - s->mon.t0) / (tmax - s->mon.t0) : 1;
    eta  = frac > 0 ? (now - s->mon.wall_start) * (1 - frac) / frac : 0;
    PetscCall(PetscPrintf(PetscObjectComm((PetscObject)s),
                          "step %6" PetscInt_FMT "  t = %-11.5g dt = %-10.4g %5.1f%%  elapsed %7.1f s  left ~%7.1f s\n",
                          step, (double)t, (double)dt, (double)(100 * frac), now - s->mon.wall_start, (double)eta));
    s->mon.wall_last_progress = now;
  }
  if (end) PetscCall(FSSolverWriteStatusCheck(s)); /* the last rows' write status: no step's reduction carries it */
  PetscFunctionReturn(0);
}

/* FSSolverMonitorEnd - the last snapshot and the run's summary.json. */
PetscErrorCode FSSolverMonitorEnd(FSSolver s)
{
  PetscReal t;

  PetscFunctionBegin;
  if (!s->mon.monitoring) PetscFunctionReturn(0);
  PetscCall(TSGetTime(s->ts, &t));
  PetscCall(FSSolverWriteStatusCheck(s)); /* the last rows' write status, when no step carried it */
  if (s->opt.write_output && s->mon.last_snapshot_time < t)
    PetscCall(FSSolverWriteSnapshot(s)); /* unless one was written at t */
  if (s->opt.write_output) PetscCall(FSSolverWriteSummary(s));
  PetscFunctionReturn(0);
}
