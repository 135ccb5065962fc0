/*
   The quantities of a row of timeseries.csv (the time series monitor, src/monitor/impls/timeseries.c, owns the file):
   its columns, this rank's sums (kinetic energy, mass, momentum, the walls' loads of the last right-hand side) and
   largest speed, and the row from their reductions over the ranks.
*/
#include "solver/solverimpl.h"

#define FS_MAX_WALL_COLUMNS  16 /* walls whose loads go into the time series */
#define FS_MAX_FLUID_COLUMNS (32 + FS_CASE_MAX_COLUMNS + FS_MAX_TERMS)
#define FS_MAX_COLUMNS       (FS_MAX_FLUID_COLUMNS + FS_STRUCTURE_MAX_COLUMNS + 6 * FS_MAX_WALL_COLUMNS)
#define FS_SERIES_NDIAG      5 /* the diagnostics' sums: kinetic energy, mass, momentum (3) */

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

/*
   FSSolverGetOutputSettings - the run's output settings that the built-in monitors follow.

   Not collective
*/
PetscErrorCode FSSolverGetOutputSettings(FSSolver s, FSSolverOutputSettings *o)
{
  PetscFunctionBegin;
  o->outdir     = s->opt.outdir;
  o->restart    = (PetscBool)(s->opt.restart[0] != 0);
  o->step0      = s->mon.step0;
  o->t0         = s->mon.t0;
  o->wall_start = s->mon.wall_start;
  PetscFunctionReturn(0);
}

/*
   FSSolverSeriesColumns - the names of timeseries.csv's columns: time, dt, dt_limit, the diagnostics, the dissipated
   energies, the case's columns, the loads of each wall (at most 16 walls), the structure's columns.

   Not collective

   Output Parameters:
+  n     - the number of columns (at most FS_SERIES_MAX_COLUMNS)
.  names - the names, pointing to constants or into buf
-  buf   - FS_SERIES_MAX_COLUMNS names' room for the names made here
*/
PetscErrorCode FSSolverSeriesColumns(FSSolver s, PetscInt *n, const char *names[], char buf[][FS_SERIES_NAME_LEN])
{
  PetscInt           k = 0, b = 0;
  static const char *mom[] = {"momentum_x", "momentum_y", "momentum_z"};

  PetscFunctionBegin;
  PetscCheck(FS_MAX_COLUMNS <= FS_SERIES_MAX_COLUMNS, PETSC_COMM_SELF, PETSC_ERR_PLIB,
             "FS_SERIES_MAX_COLUMNS %d is less than the time series' %d columns", FS_SERIES_MAX_COLUMNS,
             (int)FS_MAX_COLUMNS);
  names[k++] = "time";
  names[k++] = "dt";
  names[k++] = "dt_limit"; /* what set the step: FSDtLimit, its names in summary.json's dt_limit_steps order */
  names[k++] = "kinetic_energy";
  names[k++] = "mass";
  for (PetscInt d = 0; d < s->opt.dim; d++) names[k++] = mom[d];
  names[k++] = "max_velocity";
  names[k++] = "max_density_variation";
  for (PetscInt g = 0; g < s->terms.nterms; g++)
    if (s->terms.term[g]->has_power) {
      PetscCall(PetscSNPrintf(buf[b], FS_SERIES_NAME_LEN, "dissipated_%s", s->terms.term[g]->name));
      names[k++] = buf[b++];
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
        PetscCall(PetscSNPrintf(buf[b], FS_SERIES_NAME_LEN, "wall_%s_%s", wname[w], np == 6 ? part3[c] : part2[c]));
        names[k++] = buf[b++];
      }
  }
  {
    PetscInt nc;
    PetscCall(FSSolverStructureColumns(s, &nc, &names[k]));
    k += nc;
  }
  *n = k;
  PetscFunctionReturn(0);
}

/* FSSolverSeriesSize - the sums of a row (FSSolverSeriesLocal()): the diagnostics, then the walls' loads. Not
   collective */
PetscErrorCode FSSolverSeriesSize(FSSolver s, PetscInt *nsum)
{
  PetscInt nwalls = 0;

  PetscFunctionBegin;
  if (s->boundary) {
    const PetscReal *wloc;
    PetscCall(FSBoundaryGetLoadsLocal(s->boundary, &nwalls, &wloc));
  }
  *nsum = FS_SERIES_NDIAG + FS_WALL_LOAD_STRIDE * nwalls;
  PetscFunctionReturn(0);
}

/*
   FSSolverSeriesLocal - this rank's sums of a row (FSSolverSeriesSize() of them): the diagnostics and the walls' loads
   of the last right-hand side, and its largest |u|^2.

   Not collective
*/
PetscErrorCode FSSolverSeriesLocal(FSSolver s, PetscReal sum[], PetscReal *v2max)
{
  const PetscReal *wloc   = NULL;
  PetscInt         nwalls = 0;

  PetscFunctionBegin;
  if (s->boundary) PetscCall(FSBoundaryGetLoadsLocal(s->boundary, &nwalls, &wloc));
  PetscCall(FSSolverDiagnosticsLocal(s, sum, v2max));
  if (nwalls) PetscCall(PetscArraycpy(sum + FS_SERIES_NDIAG, wloc, FS_WALL_LOAD_STRIDE * nwalls));
  PetscFunctionReturn(0);
}

/*
   FSSolverSeriesValues - a row of timeseries.csv from the sums of FSSolverSeriesLocal() summed over the ranks and the
   largest |u|^2 over them.

   Not collective (the case's and the structure's columns may be: called on every rank)
*/
PetscErrorCode FSSolverSeriesValues(FSSolver s, const PetscReal sum[], PetscReal v2max, PetscReal vals[])
{
  const PetscReal *wsum = sum + FS_SERIES_NDIAG;
  PetscInt         k = 0, step, nwalls = 0;
  PetscMPIInt      rank;
  PetscReal        t, dt;

  PetscFunctionBegin;
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
  PetscFunctionReturn(0);
}
