/*
   The checkpoints monitor: a checkpoint (checkpoint_<step>.h5, FSMonitorCheckpointsWrite()) at every step that is a
   multiple of -fs_checkpoint_interval (its option, read in the solver's options block), none at the start. The
   solver gives the content (FSSolverGetCheckpoint()); FSSolverWriteCheckpoint() writes one through this monitor at
   any step of a run whose output is open. The restart loader stays with the solver's set-up (src/solver/output.c).
*/
#include "monitor/monitorimpl.h"
#include "sys/fssys.h"

typedef struct {
  PetscInt interval; /* -fs_checkpoint_interval (0: none) */
} FSMonitor_Checkpoints;

static PetscErrorCode FSMonitorSetFromOptions_Checkpoints(FSMonitor m, PetscOptionItems *PetscOptionsObject)
{
  FSMonitor_Checkpoints *ck = (FSMonitor_Checkpoints *)m->data;

  PetscFunctionBegin;
  PetscCall(FSOptionsInt(PetscOptionsObject, "-fs_checkpoint_interval", "Steps between checkpoints (0: none)",
                         "FSSolverWriteCheckpoint", &ck->interval, NULL, 0, PETSC_MAX_INT));
  PetscFunctionReturn(0);
}

/*
   FSMonitorCheckpointsGetInterval - the steps between a checkpoints monitor's checkpoints (-fs_checkpoint_interval;
   0: none, the run does not attach it).

   Not collective

.seealso: FSMonitorCheckpointsWrite()
*/
PetscErrorCode FSMonitorCheckpointsGetInterval(FSMonitor m, PetscInt *interval)
{
  PetscBool same;

  PetscFunctionBegin;
  PetscValidHeaderSpecific(m, FSMONITOR_CLASSID, 1);
  PetscCall(PetscObjectTypeCompare((PetscObject)m, FSMONITORCHECKPOINTS, &same));
  PetscCheck(same, PetscObjectComm((PetscObject)m), PETSC_ERR_ARG_WRONGSTATE,
             "FSMonitorCheckpointsGetInterval(): the monitor is not a checkpoints monitor (%s)",
             ((PetscObject)m)->type_name ? ((PetscObject)m)->type_name : "no type");
  *interval = ((FSMonitor_Checkpoints *)m->data)->interval;
  PetscFunctionReturn(0);
}

static PetscErrorCode FSMonitorStep_Checkpoints(FSMonitor m, FSSolver s, PetscInt step, PetscReal t, PetscBool first)
{
  FSMonitor_Checkpoints *ck = (FSMonitor_Checkpoints *)m->data;

  PetscFunctionBegin;
  (void)t;
  if (!first && ck->interval > 0 && step % ck->interval == 0) PetscCall(FSMonitorCheckpointsWrite(m, s));
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

/*
   FSMonitorCheckpointsWrite - writes <output_dir>/checkpoint_<step>.h5 with the solver's whole state at this step
   (FSSolverGetCheckpoint() lists what): a run started with -fs_restart on that file continues exactly as the
   uninterrupted run.

   Collective

   Input Parameters:
+  m - a checkpoints monitor (FSMONITORCHECKPOINTS)
-  s - the solver, its output open

   Notes:
   A failed csv row of the run's monitors is reported before the checkpoint is written (FSSolverWriteStatusCheck()).

.seealso: FSSolverWriteCheckpoint()
*/
PetscErrorCode FSMonitorCheckpointsWrite(FSMonitor m, FSSolver s)
{
  FSSolverOutputSettings o;
  FSSolverCheckpoint    *c;
  PetscBool              same;
  char                   path[PETSC_MAX_PATH_LEN];

  PetscFunctionBegin;
  PetscValidHeaderSpecific(m, FSMONITOR_CLASSID, 1);
  PetscCall(PetscObjectTypeCompare((PetscObject)m, FSMONITORCHECKPOINTS, &same));
  PetscCheck(same, PetscObjectComm((PetscObject)m), PETSC_ERR_ARG_WRONGSTATE,
             "FSMonitorCheckpointsWrite(): the monitor is not a checkpoints monitor (%s)",
             ((PetscObject)m)->type_name ? ((PetscObject)m)->type_name : "no type");
  PetscCall(FSSolverWriteStatusCheck(s)); /* a failed csv row is reported before the checkpoint is written */
  PetscCall(PetscLogEventBegin(FS_Output, 0, 0, 0, 0));
  PetscCall(FSSolverGetOutputSettings(s, &o));
  PetscCall(PetscNew(&c)); /* the layout's room is large for a stack */
  PetscCall(FSSolverGetCheckpoint(s, c));
  PetscCall(PetscSNPrintf(path, sizeof(path), "%s/checkpoint_%06" PetscInt_FMT ".h5", o.outdir, c->hdr.step));
  PetscCall(FSCheckpointWrite(PetscObjectComm((PetscObject)s), path, &c->hdr, c->n, FS_CHECKPOINT_NFIELDS, c->fields));
  PetscCall(FSSolverRestoreCheckpoint(s, c));
  PetscCall(PetscFree(c));
  PetscCall(PetscLogEventEnd(FS_Output, 0, 0, 0, 0));
  PetscFunctionReturn(0);
}

/* FSMonitorCreate_Checkpoints - the checkpoints monitor (FSMONITORCHECKPOINTS): checkpoint_*.h5. */
PetscErrorCode FSMonitorCreate_Checkpoints(FSMonitor m)
{
  FSMonitor_Checkpoints *ck;

  PetscFunctionBegin;
  PetscCall(PetscNew(&ck));
  m->data                = ck;
  m->ops->setfromoptions = FSMonitorSetFromOptions_Checkpoints;
  m->ops->step           = FSMonitorStep_Checkpoints;
  m->ops->view           = FSMonitorView_Checkpoints;
  m->ops->destroy        = FSMonitorDestroy_Checkpoints;
  PetscFunctionReturn(0);
}
