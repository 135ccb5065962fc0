/*
   The energy budget monitor: energy.csv, a row with each row of timeseries.csv (the seed's energy terms, the work
   of each force, the residual). The budget's quantities come from the solver (src/solver/energy.c); the row's sums
   are reduced with timeseries.csv's (FSMonitorRows()), and its check of the structure's energy, made before any row of
   the step is written, stops the run before either row.
*/
#include "monitor/monitorimpl.h"

typedef struct {
  PetscInt     interval; /* -fs_series_interval, as timeseries.csv's */
  FSTankMotion mo;       /* the tank's motion FSSolverEnergyLocal() gave with this rank's sums */
  PetscInt     step;
  PetscInt     ncols;
  PetscReal    vals[FS_ENERGY_MAX_COLUMNS];
} FSMonitor_Energy;

static PetscErrorCode FSMonitorBegin_Energy(FSMonitor m, FSSolver s)
{
  FSMonitor_Energy      *en = (FSMonitor_Energy *)m->data;
  FSSolverOutputSettings o;
  const char            *names[FS_ENERGY_MAX_COLUMNS];
  char                   path[PETSC_MAX_PATH_LEN];
  PetscReal              t;
  PetscInt               step;

  PetscFunctionBegin;
  PetscCall(FSSolverGetOutputSettings(s, &o));
  PetscCall(FSSolverGetTime(s, &t, &step));
  PetscCall(FSSolverEnergyColumns(s, &en->ncols, names));
  PetscCall(PetscSNPrintf(path, sizeof(path), "%s/energy.csv", o.outdir));
  PetscCall(
      FSTimeSeriesCreate(PetscObjectComm((PetscObject)m), path, en->ncols, names, o.restart ? step : -1, &m->file));
  PetscCall(FSTimeSeriesSetDeferred(m->file, PETSC_TRUE)); /* its write status as timeseries.csv's */
  PetscFunctionReturn(0);
}

/* -fs_series_interval, the time series monitor's option (listed by -help with it), read unlisted */
static PetscErrorCode FSMonitorSetFromOptions_Energy(FSMonitor m, PetscOptionItems *PetscOptionsObject)
{
  FSMonitor_Energy *en = (FSMonitor_Energy *)m->data;

  PetscFunctionBegin;
  PetscCall(FSMonitorSeriesIntervalRead(m, PetscOptionsObject, PETSC_FALSE, &en->interval));
  PetscFunctionReturn(0);
}

/* a row with each of timeseries.csv's: every -fs_series_interval steps from the start, and at the last step */
static PetscErrorCode FSMonitorRowSize_Energy(FSMonitor m, FSSolver s, PetscBool *due, PetscInt *nsum, PetscInt *nmax)
{
  PetscFunctionBegin;
  PetscCall(FSMonitorSeriesDue(s, ((FSMonitor_Energy *)m->data)->interval, due));
  *nsum = FS_ENERGY_NSUMS;
  *nmax = 0;
  PetscFunctionReturn(0);
}

static PetscErrorCode FSMonitorRowLocal_Energy(FSMonitor m, FSSolver s, PetscReal sum[], PetscReal max[])
{
  FSMonitor_Energy *en = (FSMonitor_Energy *)m->data;

  PetscFunctionBegin;
  (void)max;
  PetscCall(FSSolverEnergyLocal(s, sum, &en->mo));
  PetscFunctionReturn(0);
}

static PetscErrorCode FSMonitorRowValues_Energy(FSMonitor m, FSSolver s, const PetscReal sum[], const PetscReal max[])
{
  FSMonitor_Energy *en = (FSMonitor_Energy *)m->data;
  PetscReal         t;

  PetscFunctionBegin;
  (void)max;
  PetscCall(FSSolverGetTime(s, &t, &en->step));
  PetscCall(FSSolverEnergySummed(s, sum, &en->mo, en->vals));
  PetscFunctionReturn(0);
}

static PetscErrorCode FSMonitorRowWrite_Energy(FSMonitor m, FSSolver s)
{
  FSMonitor_Energy *en = (FSMonitor_Energy *)m->data;

  PetscFunctionBegin;
  (void)s;
  PetscCall(FSTimeSeriesAppend(m->file, en->step, en->vals));
  PetscFunctionReturn(0);
}

static PetscErrorCode FSMonitorView_Energy(FSMonitor m, PetscViewer viewer)
{
  FSMonitor_Energy *en = (FSMonitor_Energy *)m->data;

  PetscFunctionBegin;
  PetscCall(PetscViewerASCIIPrintf(viewer, "energy.csv, %" PetscInt_FMT " columns\n", en->ncols));
  PetscFunctionReturn(0);
}

static PetscErrorCode FSMonitorDestroy_Energy(FSMonitor m)
{
  PetscFunctionBegin;
  PetscCall(FSTimeSeriesDestroy(&m->file));
  PetscCall(PetscFree(m->data));
  PetscFunctionReturn(0);
}

/* FSMonitorCreate_Energy - the energy budget monitor (FSMONITORENERGY): energy.csv. */
PetscErrorCode FSMonitorCreate_Energy(FSMonitor m)
{
  FSMonitor_Energy *en;

  PetscFunctionBegin;
  PetscCall(PetscNew(&en));
  en->interval           = 1;
  m->data                = en;
  m->ops->setfromoptions = FSMonitorSetFromOptions_Energy;
  m->ops->begin          = FSMonitorBegin_Energy;
  m->ops->rowsize        = FSMonitorRowSize_Energy;
  m->ops->rowlocal       = FSMonitorRowLocal_Energy;
  m->ops->rowvalues      = FSMonitorRowValues_Energy;
  m->ops->rowwrite       = FSMonitorRowWrite_Energy;
  m->ops->view           = FSMonitorView_Energy;
  m->ops->destroy        = FSMonitorDestroy_Energy;
  PetscFunctionReturn(0);
}
