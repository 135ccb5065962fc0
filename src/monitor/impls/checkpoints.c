/*
   The checkpoints monitor: a checkpoint (FSSolverWriteCheckpoint(), checkpoint_<step>.h5) at every step that is a
   multiple of -fs_checkpoint_interval, none at the start.
*/
#include "monitor/monitorimpl.h"

typedef struct {
  PetscInt interval; /* -fs_checkpoint_interval (0: none) */
} FSMonitor_Checkpoints;

static PetscErrorCode FSMonitorBegin_Checkpoints(FSMonitor m, FSSolver s)
{
  FSMonitor_Checkpoints *ck = (FSMonitor_Checkpoints *)m->data;
  FSSolverOutputSettings o;

  PetscFunctionBegin;
  PetscCall(FSSolverGetOutputSettings(s, &o));
  ck->interval = o.checkpoint_interval;
  PetscFunctionReturn(0);
}

static PetscErrorCode FSMonitorStep_Checkpoints(FSMonitor m, FSSolver s, PetscInt step, PetscReal t, PetscBool first)
{
  FSMonitor_Checkpoints *ck = (FSMonitor_Checkpoints *)m->data;

  PetscFunctionBegin;
  (void)t;
  if (!first && ck->interval > 0 && step % ck->interval == 0) PetscCall(FSSolverWriteCheckpoint(s));
  PetscFunctionReturn(0);
}

static PetscErrorCode FSMonitorView_Checkpoints(FSMonitor m, PetscViewer viewer)
{
  FSMonitor_Checkpoints *ck = (FSMonitor_Checkpoints *)m->data;

  PetscFunctionBegin;
  PetscCall(PetscViewerASCIIPrintf(viewer, "checkpoints every %" PetscInt_FMT " steps\n", ck->interval));
  PetscFunctionReturn(0);
}

static PetscErrorCode FSMonitorDestroy_Checkpoints(FSMonitor m)
{
  PetscFunctionBegin;
  PetscCall(PetscFree(m->data));
  PetscFunctionReturn(0);
}

/* FSMonitorCreate_Checkpoints - the checkpoints monitor (FSMONITORCHECKPOINTS): checkpoint_*.h5. */
PetscErrorCode FSMonitorCreate_Checkpoints(FSMonitor m)
{
  FSMonitor_Checkpoints *ck;

  PetscFunctionBegin;
  PetscCall(PetscNew(&ck));
  m->data         = ck;
  m->ops->begin   = FSMonitorBegin_Checkpoints;
  m->ops->step    = FSMonitorStep_Checkpoints;
  m->ops->view    = FSMonitorView_Checkpoints;
  m->ops->destroy = FSMonitorDestroy_Checkpoints;
  PetscFunctionReturn(0);
}
