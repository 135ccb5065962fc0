/*
   The snapshots monitor: the particles (snapshot_*.h5, indexed by particles.xdmf) at the start of a new run, at every
   multiple of -fs_output_interval (its option, read in the solver's options block: FSMonitorSetFromOptionItems())
   and at the end. The fields are the solver's (FSSolverFillField()); the monitor owns the writer and when it
   writes.
*/
#include "monitor/monitorimpl.h"
#include "sys/fssys.h"

typedef struct {
  FSSnapshotWriter writer;
  PetscReal        interval; /* -fs_output_interval (0: the first and the last only) */
  PetscReal        next;     /* the time of the next snapshot */
  PetscReal        last;     /* the time of the last snapshot (PETSC_MIN_REAL: none yet) */
  PetscBool        restart;  /* a restart: no snapshot at its start (the run it continues wrote it) */
} FSMonitor_Snapshots;

/* the first multiple of the output interval after t (one within 1e-9 of the interval is t's), computed rather than
   counted up to, so that no interval loops however small it is against t; none without an interval */
static PetscReal FSNextOutputTime(PetscReal t, PetscReal interval)
{
  return interval > 0 ? (PetscFloorReal(t / interval + 1e-9) + 1) * interval : PETSC_MAX_REAL;
}

/* the snapshot's fields, in the files' order (docs/running.md, "Output") */
static const char *const FSSnapshotFields[] = {
    "position", "velocity", "density", "pressure", "strain_rate", "turbulent_viscosity", "rank", "id"};
#define FS_SNAP_N ((PetscInt)PETSC_STATIC_ARRAY_LENGTH(FSSnapshotFields))

/* a snapshot field of the owned particles into values, when the writer writes it (one field at a time) */
static PetscErrorCode FSMonitorSnapshotFill(void *ctx, PetscInt f, PetscReal values[])
{
  PetscFunctionBegin;
  PetscCall(FSSolverFillField((FSSolver)ctx, FSSnapshotFields[f], NULL, values));
  PetscFunctionReturn(0);
}

/*
   FSMonitorSnapshotWrite - writes the particles (position, velocity, density, pressure, strain_rate ||D||,
   turbulent_viscosity, rank, id) to the next snapshot file, and updates the XDMF index. The derived fields come from
   a fresh evaluation of the right-hand side at the current state, made first on every rank. Each field is made when
   the writer writes it, into one buffer (3 reals a particle, not 12).

   Collective
*/
static PetscErrorCode FSMonitorSnapshotWrite(FSMonitor m, FSSolver s, PetscReal t)
{
  FSMonitor_Snapshots *sn = (FSMonitor_Snapshots *)m->data;
  FSOutputField        fields[FS_SNAP_N];
  PetscInt             step, dim, n;
  PetscInt64           nglobal;

  PetscFunctionBegin;
  PetscCall(FSSolverWriteStatusCheck(s)); /* a failed csv row is reported before another file is written */
  PetscCall(PetscLogEventBegin(FS_Output, 0, 0, 0, 0));
  PetscCall(FSSolverGetTime(s, &t, &step));
  PetscCall(FSSolverGetDimension(s, &dim));
  PetscCall(FSSolverGetLocalSize(s, &n));
  PetscCall(FSSolverGetGlobalSize(s, &nglobal));
  PetscCall(FSSolverStructureSnapshot(s));    /* the structure's own output (e.g. the deflected shape) */
  if (nglobal > 0) {                          /* a dry structure: no particle file */
    PetscCall(FSSolverEvaluateAtState(s, t)); /* before the fields: the derived fields evaluate at it */
    for (PetscInt f = 0; f < FS_SNAP_N; f++)
      fields[f] = (FSOutputField){
          .name = FSSnapshotFields[f], .bs = f < 2 ? dim : 1, .fill = FSMonitorSnapshotFill, .ctx = s};
    PetscCall(FSSnapshotWriterWrite(sn->writer, t, step, dim, n, FS_SNAP_N, fields));
  }
  sn->last = t;
  PetscCall(PetscLogEventEnd(FS_Output, 0, 0, 0, 0));
  PetscFunctionReturn(0);
}

static PetscErrorCode FSMonitorSetFromOptions_Snapshots(FSMonitor m, PetscOptionItems *PetscOptionsObject)
{
  FSMonitor_Snapshots *sn = (FSMonitor_Snapshots *)m->data;

  PetscFunctionBegin;
  PetscCall(FSOptionsReal(PetscOptionsObject, "-fs_output_interval",
                          "Simulated time between particle snapshots (0: first and last only)", "FSSolverWriteSnapshot",
                          &sn->interval, NULL, 0, PETSC_INFINITY, FS_RANGE_CLOSED));
  PetscFunctionReturn(0);
}

/* the snapshots' times are multiples of the interval: more than 1e12 of them, the run's time cannot tell apart */
static PetscErrorCode FSMonitorSetUp_Snapshots(FSMonitor m, FSSolver s)
{
  FSMonitor_Snapshots *sn = (FSMonitor_Snapshots *)m->data;
  TS                   ts;
  PetscReal            tmax;

  PetscFunctionBegin;
  PetscCall(FSSolverGetTS(s, &ts));
  PetscCall(TSGetMaxTime(ts, &tmax));
  PetscCheck(sn->interval == 0 || sn->interval >= 1e-12 * PetscAbsReal(tmax), PetscObjectComm((PetscObject)m),
             PETSC_ERR_ARG_OUTOFRANGE,
             "-fs_output_interval %g is too small for the run's time: expected 0 (the first and last snapshots only) "
             "or at least 1e-12 of the final time -ts_max_time %g, that is %g",
             (double)sn->interval, (double)tmax, (double)(1e-12 * PetscAbsReal(tmax)));
  PetscFunctionReturn(0);
}

static PetscErrorCode FSMonitorBegin_Snapshots(FSMonitor m, FSSolver s)
{
  FSMonitor_Snapshots   *sn = (FSMonitor_Snapshots *)m->data;
  FSSolverOutputSettings o;
  PetscReal              t;
  PetscInt               step;

  PetscFunctionBegin;
  PetscCall(FSSolverGetOutputSettings(s, &o));
  PetscCall(FSSolverGetTime(s, &t, &step));
  sn->restart = o.restart;
  sn->next    = FSNextOutputTime(t, sn->interval); /* multiples of the interval, also after a restart */
  sn->last    = PETSC_MIN_REAL;
  PetscCall(FSSnapshotWriterCreate(PetscObjectComm((PetscObject)m), o.outdir, o.restart ? t : -1.0, &sn->writer));
  PetscFunctionReturn(0);
}

static PetscErrorCode FSMonitorStep_Snapshots(FSMonitor m, FSSolver s, PetscInt step, PetscReal t, PetscBool first)
{
  FSMonitor_Snapshots *sn = (FSMonitor_Snapshots *)m->data;

  PetscFunctionBegin;
  (void)step;
  if (first) { /* the state a new run starts from */
    if (!sn->restart) PetscCall(FSMonitorSnapshotWrite(m, s, t));
    PetscFunctionReturn(0);
  }
  if (sn->interval > 0 && t >= sn->next - 1e-9 * sn->interval) {
    PetscCall(FSMonitorSnapshotWrite(m, s, t));
    sn->next = FSNextOutputTime(t, sn->interval);
  }
  PetscFunctionReturn(0);
}

/* the last state, unless a snapshot was written at its time */
static PetscErrorCode FSMonitorEnd_Snapshots(FSMonitor m, FSSolver s)
{
  FSMonitor_Snapshots *sn = (FSMonitor_Snapshots *)m->data;
  PetscReal            t;
  PetscInt             step;

  PetscFunctionBegin;
  PetscCall(FSSolverGetTime(s, &t, &step));
  if (sn->last < t) PetscCall(FSMonitorSnapshotWrite(m, s, t));
  PetscFunctionReturn(0);
}

static PetscErrorCode FSMonitorView_Snapshots(FSMonitor m, PetscViewer viewer)
{
  FSMonitor_Snapshots *sn = (FSMonitor_Snapshots *)m->data;

  PetscFunctionBegin;
  if (sn->interval > 0)
    PetscCall(PetscViewerASCIIPrintf(viewer, "particle snapshots every %g s, the first and the last\n",
                                     (double)sn->interval));
  else PetscCall(PetscViewerASCIIPrintf(viewer, "particle snapshots: the first and the last\n"));
  PetscFunctionReturn(0);
}

static PetscErrorCode FSMonitorDestroy_Snapshots(FSMonitor m)
{
  FSMonitor_Snapshots *sn = (FSMonitor_Snapshots *)m->data;

  PetscFunctionBegin;
  PetscCall(FSSnapshotWriterDestroy(&sn->writer));
  PetscCall(PetscFree(m->data));
  PetscFunctionReturn(0);
}

/* FSMonitorCreate_Snapshots - the snapshots monitor (FSMONITORSNAPSHOTS): snapshot_*.h5 and particles.xdmf. */
PetscErrorCode FSMonitorCreate_Snapshots(FSMonitor m)
{
  FSMonitor_Snapshots *sn;

  PetscFunctionBegin;
  PetscCall(PetscNew(&sn));
  m->data                = sn;
  m->ops->setfromoptions = FSMonitorSetFromOptions_Snapshots;
  m->ops->setup          = FSMonitorSetUp_Snapshots;
  m->ops->begin          = FSMonitorBegin_Snapshots;
  m->ops->step           = FSMonitorStep_Snapshots;
  m->ops->end            = FSMonitorEnd_Snapshots;
  m->ops->view           = FSMonitorView_Snapshots;
  m->ops->destroy        = FSMonitorDestroy_Snapshots;
  PetscFunctionReturn(0);
}
