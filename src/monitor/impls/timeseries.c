/*
   The time series monitor: timeseries.csv, a row every -fs_series_interval steps (its option, read in the solver's
   options block; the energy budget's rows follow it) and at the last step (time, dt,
   energies, mass, momentum, extremes, dissipated energies, the case's columns, the loads per wall, the structure's
   columns). The row's quantities come from the solver (FSSolverSeriesLocal(), FSSolverSeriesValues()); its sums are
   reduced with the other rows' (FSMonitorRows()).
*/
#include "monitor/monitorimpl.h"
#include "sys/fssys.h"

typedef struct {
  PetscInt  interval; /* -fs_series_interval */
  PetscInt  step;     /* the step of the row being made */
  PetscInt  ncols;
  PetscReal vals[FS_SERIES_MAX_COLUMNS];
} FSMonitor_TimeSeries;

/*
   FSMonitorSeriesIntervalRead - -fs_series_interval, the steps between the rows of timeseries.csv and energy.csv, in
   the options block items: listed by -help (the time series monitor's), else read from the database without a line
   of -help and checked as FSOptionsInt() checks (the energy budget's, whose rows are timeseries.csv's).
*/
PetscErrorCode FSMonitorSeriesIntervalRead(FSMonitor m, PetscOptionItems *items, PetscBool listed, PetscInt *interval)
{
  PetscFunctionBegin;
  if (listed) {
    PetscCall(FSOptionsInt(items, "-fs_series_interval",
                           "Steps between the rows of timeseries.csv and energy.csv (the last step's is always "
                           "written): a row's sums ride on the step's own reduction",
                           "FSSolverMonitor", interval, NULL, 1, PETSC_MAX_INT));
  } else {
    PetscCall(FSOptionsCheckPetscInt(PetscObjectComm((PetscObject)m), "-fs_series_interval", 1, PETSC_MAX_INT));
    PetscCall(PetscOptionsGetInt(items->options, items->prefix, "-fs_series_interval", interval, NULL));
  }
  PetscFunctionReturn(0);
}

/* FSMonitorSeriesDue - whether a row is due: every interval steps from the start, and at the last step */
PetscErrorCode FSMonitorSeriesDue(FSSolver s, PetscInt interval, PetscBool *due)
{
  FSSolverOutputSettings o;
  PetscReal              t;
  PetscInt               step;
  PetscBool              end;

  PetscFunctionBegin;
  PetscCall(FSSolverGetOutputSettings(s, &o));
  PetscCall(FSSolverGetTime(s, &t, &step));
  PetscCall(FSSolverAtEnd(s, &end)); /* the last step's row is written whatever the interval */
  *due = (PetscBool)((step - o.step0) % interval == 0 || end);
  PetscFunctionReturn(0);
}

static PetscErrorCode FSMonitorSetFromOptions_TimeSeries(FSMonitor m, PetscOptionItems *PetscOptionsObject)
{
  FSMonitor_TimeSeries *ts = (FSMonitor_TimeSeries *)m->data;

  PetscFunctionBegin;
  PetscCall(FSMonitorSeriesIntervalRead(m, PetscOptionsObject, PETSC_TRUE, &ts->interval));
  PetscFunctionReturn(0);
}

static PetscErrorCode FSMonitorBegin_TimeSeries(FSMonitor m, FSSolver s)
{
  FSMonitor_TimeSeries  *ts = (FSMonitor_TimeSeries *)m->data;
  FSSolverOutputSettings o;
  const char            *names[FS_SERIES_MAX_COLUMNS];
  char(*buf)[FS_SERIES_NAME_LEN], path[PETSC_MAX_PATH_LEN];
  PetscReal t;
  PetscInt  step;

  PetscFunctionBegin;
  PetscCall(FSSolverGetOutputSettings(s, &o));
  PetscCall(FSSolverGetTime(s, &t, &step));
  PetscCall(PetscMalloc1(FS_SERIES_MAX_COLUMNS, &buf));
  PetscCall(FSSolverSeriesColumns(s, &ts->ncols, names, buf));
  PetscCall(PetscSNPrintf(path, sizeof(path), "%s/timeseries.csv", o.outdir));
  PetscCall(
      FSTimeSeriesCreate(PetscObjectComm((PetscObject)m), path, ts->ncols, names, o.restart ? step : -1, &m->file));
  PetscCall(PetscFree(buf));
  /* a row's write status rides on the next step's reduction (FSMonitorGetWriteStatus()), not on a broadcast of its
     own */
  PetscCall(FSTimeSeriesSetDeferred(m->file, PETSC_TRUE));
  PetscFunctionReturn(0);
}

static PetscErrorCode FSMonitorRowSize_TimeSeries(FSMonitor m, FSSolver s, PetscBool *due, PetscInt *nsum,
                                                  PetscInt *nmax)
{
  PetscFunctionBegin;
  PetscCall(FSMonitorSeriesDue(s, ((FSMonitor_TimeSeries *)m->data)->interval, due));
  PetscCall(FSSolverSeriesSize(s, nsum));
  *nmax = 1; /* the largest speed */
  PetscFunctionReturn(0);
}

static PetscErrorCode FSMonitorRowLocal_TimeSeries(FSMonitor m, FSSolver s, PetscReal sum[], PetscReal max[])
{
  PetscFunctionBegin;
  (void)m;
  PetscCall(FSSolverSeriesLocal(s, sum, &max[0]));
  PetscFunctionReturn(0);
}

static PetscErrorCode FSMonitorRowValues_TimeSeries(FSMonitor m, FSSolver s, const PetscReal sum[],
                                                    const PetscReal max[])
{
  FSMonitor_TimeSeries *ts = (FSMonitor_TimeSeries *)m->data;
  PetscReal             t;

  PetscFunctionBegin;
  PetscCall(FSSolverGetTime(s, &t, &ts->step));
  PetscCall(FSSolverSeriesValues(s, sum, max[0], ts->vals));
  PetscFunctionReturn(0);
}

static PetscErrorCode FSMonitorRowWrite_TimeSeries(FSMonitor m, FSSolver s)
{
  FSMonitor_TimeSeries *ts = (FSMonitor_TimeSeries *)m->data;

  PetscFunctionBegin;
  (void)s;
  PetscCall(FSTimeSeriesAppend(m->file, ts->step, ts->vals));
  PetscFunctionReturn(0);
}

static PetscErrorCode FSMonitorView_TimeSeries(FSMonitor m, PetscViewer viewer)
{
  FSMonitor_TimeSeries *ts = (FSMonitor_TimeSeries *)m->data;

  PetscFunctionBegin;
  PetscCall(PetscViewerASCIIPrintf(viewer, "timeseries.csv, %" PetscInt_FMT " columns\n", ts->ncols));
  PetscFunctionReturn(0);
}

static PetscErrorCode FSMonitorDestroy_TimeSeries(FSMonitor m)
{
  PetscFunctionBegin;
  PetscCall(FSTimeSeriesDestroy(&m->file));
  PetscCall(PetscFree(m->data));
  PetscFunctionReturn(0);
}

/* FSMonitorCreate_TimeSeries - the time series monitor (FSMONITORTIMESERIES): timeseries.csv. */
PetscErrorCode FSMonitorCreate_TimeSeries(FSMonitor m)
{
  FSMonitor_TimeSeries *ts;

  PetscFunctionBegin;
  PetscCall(PetscNew(&ts));
  ts->interval           = 1;
  m->data                = ts;
  m->ops->setfromoptions = FSMonitorSetFromOptions_TimeSeries;
  m->ops->begin          = FSMonitorBegin_TimeSeries;
  m->ops->rowsize        = FSMonitorRowSize_TimeSeries;
  m->ops->rowlocal       = FSMonitorRowLocal_TimeSeries;
  m->ops->rowvalues      = FSMonitorRowValues_TimeSeries;
  m->ops->rowwrite       = FSMonitorRowWrite_TimeSeries;
  m->ops->view           = FSMonitorView_TimeSeries;
  m->ops->destroy        = FSMonitorDestroy_TimeSeries;
  PetscFunctionReturn(0);
}
