/*
   The probes monitor: probes.csv, a row every -fs_probe_interval steps of the probes' and wave gauges' values
   (-fs_probes). The sampling and the sensors' time response are the solver's (src/solver/probes.c,
   FSSolverProbesRecord()); the row's sums are reduced there, in one reduction of their own.
*/
#include "monitor/monitorimpl.h"

typedef struct {
  PetscInt   interval, ncols; /* -fs_probe_interval, the columns after "time" */
  PetscReal *row;             /* 1 + ncols */
} FSMonitor_Probes;

static PetscErrorCode FSMonitorBegin_Probes(FSMonitor m, FSSolver s)
{
  FSMonitor_Probes      *pr = (FSMonitor_Probes *)m->data;
  FSSolverOutputSettings o;
  const char           **cols;
  char                   path[PETSC_MAX_PATH_LEN];
  PetscReal              t;
  PetscInt               step;

  PetscFunctionBegin;
  PetscCall(FSSolverGetOutputSettings(s, &o));
  PetscCall(FSSolverGetTime(s, &t, &step));
  PetscCall(FSSolverProbesColumns(s, &pr->interval, &pr->ncols, NULL));
  if (!pr->ncols) PetscFunctionReturn(0); /* no -fs_probes: no file */
  PetscCall(PetscMalloc1(pr->ncols + 1, &cols));
  PetscCall(PetscMalloc1(pr->ncols + 1, &pr->row));
  cols[0] = "time";
  PetscCall(FSSolverProbesColumns(s, &pr->interval, &pr->ncols, cols + 1));
  PetscCall(PetscSNPrintf(path, sizeof(path), "%s/probes.csv", o.outdir));
  PetscCall(
      FSTimeSeriesCreate(PetscObjectComm((PetscObject)m), path, pr->ncols + 1, cols, o.restart ? step : -1, &m->file));
  PetscCall(FSTimeSeriesSetDeferred(m->file, PETSC_TRUE)); /* its write status as timeseries.csv's */
  PetscCall(PetscFree(cols));
  PetscFunctionReturn(0);
}

/* every -fs_probe_interval steps (counted from step 0), the first row included */
static PetscErrorCode FSMonitorStep_Probes(FSMonitor m, FSSolver s, PetscInt step, PetscReal t, PetscBool first)
{
  FSMonitor_Probes *pr = (FSMonitor_Probes *)m->data;
  const PetscReal  *values;

  PetscFunctionBegin;
  (void)t;
  (void)first;
  if (!m->file || step % pr->interval) PetscFunctionReturn(0);
  PetscCall(FSSolverProbesRecord(s, &pr->row[0], &values));
  PetscCall(PetscArraycpy(pr->row + 1, values, pr->ncols));
  PetscCall(FSTimeSeriesAppend(m->file, step, pr->row));
  m->unchecked = PETSC_TRUE;
  PetscFunctionReturn(0);
}

static PetscErrorCode FSMonitorView_Probes(FSMonitor m, PetscViewer viewer)
{
  FSMonitor_Probes *pr = (FSMonitor_Probes *)m->data;

  PetscFunctionBegin;
  PetscCall(PetscViewerASCIIPrintf(viewer, "probes.csv, %" PetscInt_FMT " columns, every %" PetscInt_FMT " steps\n",
                                   pr->ncols + 1, pr->interval));
  PetscFunctionReturn(0);
}

static PetscErrorCode FSMonitorDestroy_Probes(FSMonitor m)
{
  FSMonitor_Probes *pr = (FSMonitor_Probes *)m->data;

  PetscFunctionBegin;
  PetscCall(FSTimeSeriesDestroy(&m->file));
  PetscCall(PetscFree(pr->row));
  PetscCall(PetscFree(m->data));
  PetscFunctionReturn(0);
}

/* FSMonitorCreate_Probes - the probes monitor (FSMONITORPROBES): probes.csv. */
PetscErrorCode FSMonitorCreate_Probes(FSMonitor m)
{
  FSMonitor_Probes *pr;

  PetscFunctionBegin;
  PetscCall(PetscNew(&pr));
  m->data         = pr;
  m->ops->begin   = FSMonitorBegin_Probes;
  m->ops->step    = FSMonitorStep_Probes;
  m->ops->view    = FSMonitorView_Probes;
  m->ops->destroy = FSMonitorDestroy_Probes;
  PetscFunctionReturn(0);
}
