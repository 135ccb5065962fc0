/*
   The summary monitor: <output_dir>/summary.json at the end of the run (what ran, how long, how fast, with which
   options). The content is the solver's (FSSolverSummaryWrite(), src/solver/output.c); the monitor owns the file
   and when it is written: after the monitors attached before it have ended, the last snapshot's evaluation counted.
*/
#include "monitor/monitorimpl.h"

static PetscErrorCode FSMonitorEnd_Summary(FSMonitor m, FSSolver s)
{
  FSSolverOutputSettings o;
  FSJSON                 js;
  char                   path[PETSC_MAX_PATH_LEN];

  PetscFunctionBegin;
  PetscCall(FSSolverGetOutputSettings(s, &o));
  PetscCall(PetscSNPrintf(path, sizeof(path), "%s/summary.json", o.outdir));
  PetscCall(FSJSONCreate(PetscObjectComm((PetscObject)m), path, &js));
  PetscCall(FSSolverSummaryWrite(s, js));
  PetscCall(FSJSONDestroy(&js));
  PetscFunctionReturn(0);
}

static PetscErrorCode FSMonitorView_Summary(FSMonitor m, PetscViewer viewer)
{
  PetscFunctionBegin;
  (void)m;
  PetscCall(PetscViewerASCIIPrintf(viewer, "summary.json at the end of the run\n"));
  PetscFunctionReturn(0);
}

/* FSMonitorCreate_Summary - the summary monitor (FSMONITORSUMMARY): summary.json. */
PetscErrorCode FSMonitorCreate_Summary(FSMonitor m)
{
  PetscFunctionBegin;
  m->ops->end  = FSMonitorEnd_Summary;
  m->ops->view = FSMonitorView_Summary;
  PetscFunctionReturn(0);
}
