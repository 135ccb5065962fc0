/*
   The progress monitor: a line on the terminal (step, time, step size, the share of the run done, the wall time
   taken and left) at most every -fs_progress_interval seconds of wall time, after a step, with -fs_progress (its
   options, read in the solver's options block). The run attaches it whether or not it writes files.
*/
#include "monitor/monitorimpl.h"

typedef struct {
  PetscBool      on;       /* -fs_progress */
  PetscReal      interval; /* -fs_progress_interval: seconds of wall time between two lines */
  PetscLogDouble last;     /* the wall time of the last line (the run's start before the first) */
} FSMonitor_Progress;

static PetscErrorCode FSMonitorSetFromOptions_Progress(FSMonitor m, PetscOptionItems *PetscOptionsObject)
{
  FSMonitor_Progress *pg = (FSMonitor_Progress *)m->data;

  PetscFunctionBegin;
  PetscCall(PetscOptionsBool("-fs_progress", "Print a progress line on the terminal", "FSSolverMonitor", pg->on,
                             &pg->on, NULL));
  PetscCall(FSOptionsReal(PetscOptionsObject, "-fs_progress_interval", "Seconds between progress lines",
                          "FSSolverMonitor", &pg->interval, NULL, 0, PETSC_INFINITY, FS_RANGE_CLOSED));
  PetscFunctionReturn(0);
}

static PetscErrorCode FSMonitorBegin_Progress(FSMonitor m, FSSolver s)
{
  FSMonitor_Progress    *pg = (FSMonitor_Progress *)m->data;
  FSSolverOutputSettings o;

  PetscFunctionBegin;
  PetscCall(FSSolverGetOutputSettings(s, &o));
  pg->last = o.wall_start;
  PetscFunctionReturn(0);
}

/* after a step (not for the state the run starts from): the line, when the interval has passed since the last */
static PetscErrorCode FSMonitorStep_Progress(FSMonitor m, FSSolver s, PetscInt step, PetscReal t, PetscBool first)
{
  FSMonitor_Progress    *pg = (FSMonitor_Progress *)m->data;
  FSSolverOutputSettings o;
  PetscLogDouble         now;
  PetscReal              tmax, dt, frac, eta;
  TS                     ts;

  PetscFunctionBegin;
  if (first || !pg->on) PetscFunctionReturn(0);
  PetscCall(PetscTime(&now));
  if (now - pg->last < pg->interval) PetscFunctionReturn(0);
  PetscCall(FSSolverGetOutputSettings(s, &o));
  PetscCall(FSSolverGetTS(s, &ts));
  PetscCall(TSGetMaxTime(ts, &tmax));
  PetscCall(TSGetTimeStep(ts, &dt));
  frac = tmax > o.t0 ? (t - o.t0) / (tmax - o.t0) : 1;
  eta  = frac > 0 ? (now - o.wall_start) * (1 - frac) / frac : 0;
  PetscCall(PetscPrintf(PetscObjectComm((PetscObject)m),
                        "step %6" PetscInt_FMT "  t = %-11.5g dt = %-10.4g %5.1f%%  elapsed %7.1f s  left ~%7.1f s\n",
                        step, (double)t, (double)dt, (double)(100 * frac), now - o.wall_start, (double)eta));
  pg->last = now;
  PetscFunctionReturn(0);
}

static PetscErrorCode FSMonitorView_Progress(FSMonitor m, PetscViewer viewer)
{
  FSMonitor_Progress *pg = (FSMonitor_Progress *)m->data;

  PetscFunctionBegin;
  if (pg->on) PetscCall(PetscViewerASCIIPrintf(viewer, "a progress line every %g s\n", (double)pg->interval));
  else PetscCall(PetscViewerASCIIPrintf(viewer, "no progress line (-fs_progress 0)\n"));
  PetscFunctionReturn(0);
}

static PetscErrorCode FSMonitorDestroy_Progress(FSMonitor m)
{
  PetscFunctionBegin;
  PetscCall(PetscFree(m->data));
  PetscFunctionReturn(0);
}

/* FSMonitorCreate_Progress - the progress monitor (FSMONITORPROGRESS): the progress line on the terminal. */
PetscErrorCode FSMonitorCreate_Progress(FSMonitor m)
{
  FSMonitor_Progress *pg;

  PetscFunctionBegin;
  PetscCall(PetscNew(&pg));
  pg->on                 = PETSC_TRUE;
  pg->interval           = 5.0;
  m->data                = pg;
  m->ops->setfromoptions = FSMonitorSetFromOptions_Progress;
  m->ops->begin          = FSMonitorBegin_Progress;
  m->ops->step           = FSMonitorStep_Progress;
  m->ops->view           = FSMonitorView_Progress;
  m->ops->destroy        = FSMonitorDestroy_Progress;
  PetscFunctionReturn(0);
}
