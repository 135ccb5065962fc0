/*
   FSMonitor: what a run reports after its steps, as an object with an ops table (monitorimpl.h) and a registry of
   implementations, as PETSc's TS monitors: the built-in ones (time series, energy budget, probes, snapshots,
   checkpoints, at-rest check, progress line, summary) are registered and attached to the solver (FSSolverMonitorAdd())
   the way a user's are. This file dispatches to the implementation, batches the rows' reductions (FSMonitorRows()) and
   keeps the write status of a monitor's csv file.
*/
#include "monitor/monitorimpl.h"
#include "sys/fssys.h"

PetscClassId FSMONITOR_CLASSID;

static FSRegistry FSMonitors; /* src/sys/registry.c */

PETSC_EXTERN PetscErrorCode FSMonitorCreate_TimeSeries(FSMonitor);
PETSC_EXTERN PetscErrorCode FSMonitorCreate_Energy(FSMonitor);
PETSC_EXTERN PetscErrorCode FSMonitorCreate_Probes(FSMonitor);
PETSC_EXTERN PetscErrorCode FSMonitorCreate_Snapshots(FSMonitor);
PETSC_EXTERN PetscErrorCode FSMonitorCreate_Checkpoints(FSMonitor);
PETSC_EXTERN PetscErrorCode FSMonitorCreate_RestCheck(FSMonitor);
PETSC_EXTERN PetscErrorCode FSMonitorCreate_Progress(FSMonitor);
PETSC_EXTERN PetscErrorCode FSMonitorCreate_Summary(FSMonitor);

/*
   FSMonitorRegister - adds a monitor type to the registry.

   Not collective

   Input Parameters:
+  name        - the name given to FSMonitorSetType() or -<prefix>monitor_type
.  description - one line
-  create      - fills the monitor's ops and data (FSMonitorCreate_<Name>)

.seealso: FSMonitorSetType(), FSSolverMonitorAdd()
*/
PetscErrorCode FSMonitorRegister(const char name[], const char description[], FSMonitorCreateFn create)
{
  PetscFunctionBegin;
  PetscCall(FSRegistryAdd(&FSMonitors, name, description, (void (*)(void))create));
  PetscFunctionReturn(0);
}

/* FSMonitorRegisterAll - registers the built-in monitors and the class (idempotent). */
PetscErrorCode FSMonitorRegisterAll(void)
{
  static PetscBool done = PETSC_FALSE;

  PetscFunctionBegin;
  if (done) PetscFunctionReturn(0);
  done = PETSC_TRUE;
  PetscCall(PetscClassIdRegister("FSMonitor", &FSMONITOR_CLASSID));
  PetscCall(FSMonitorRegister(FSMONITORTIMESERIES,
                              "timeseries.csv: energies, mass, momentum, loads per wall, the structure's motion "
                              "(-fs_series_interval)",
                              FSMonitorCreate_TimeSeries));
  PetscCall(FSMonitorRegister(FSMONITORENERGY,
                              "energy.csv: the energy budget with its residual, rows as timeseries.csv's",
                              FSMonitorCreate_Energy));
  PetscCall(FSMonitorRegister(FSMONITORPROBES, "probes.csv: pressure probes and wave gauges (-fs_probes)",
                              FSMonitorCreate_Probes));
  PetscCall(FSMonitorRegister(FSMONITORSNAPSHOTS, "particle snapshots and particles.xdmf (-fs_output_interval)",
                              FSMonitorCreate_Snapshots));
  PetscCall(FSMonitorRegister(FSMONITORCHECKPOINTS, "checkpoints to restart from (-fs_checkpoint_interval)",
                              FSMonitorCreate_Checkpoints));
  PetscCall(FSMonitorRegister(FSMONITORRESTCHECK,
                              "the at-rest check: a liquid at rest that moves, a time step that collapses "
                              "(-fs_rest_check_time)",
                              FSMonitorCreate_RestCheck));
  PetscCall(FSMonitorRegister(FSMONITORPROGRESS, "the progress line on the terminal (-fs_progress)",
                              FSMonitorCreate_Progress));
  PetscCall(FSMonitorRegister(FSMONITORSUMMARY, "summary.json at the end of the run", FSMonitorCreate_Summary));
  PetscFunctionReturn(0);
}

/* FSMonitorListView - prints every registered monitor type with its description. */
PetscErrorCode FSMonitorListView(PetscViewer viewer)
{
  PetscFunctionBegin;
  PetscCall(FSMonitorRegisterAll());
  PetscCall(FSRegistryView(&FSMonitors, viewer, "monitors", "attach with FSSolverMonitorAdd()"));
  PetscFunctionReturn(0);
}

/*
   FSMonitorCreate - creates a monitor without a type.

   Collective

   Input Parameter:
.  comm - the solver's communicator

   Output Parameter:
.  mon - the monitor

.seealso: FSMonitorSetType(), FSSolverMonitorAdd(), FSMonitorDestroy()
*/
PetscErrorCode FSMonitorCreate(MPI_Comm comm, FSMonitor *mon)
{
  FSMonitor m;

  PetscFunctionBegin;
  PetscCall(FSMonitorRegisterAll());
  PetscCall(
      PetscHeaderCreate(m, FSMONITOR_CLASSID, "FSMonitor", "run monitor", "FS", comm, FSMonitorDestroy, FSMonitorView));
  *mon = m;
  PetscFunctionReturn(0);
}

/*
   FSMonitorSetType - chooses the monitor's type by its registered name (destroying what an earlier type held).

   Collective

   Input Parameters:
+  mon  - the monitor, not yet set up
-  type - FSMONITORTIMESERIES, FSMONITORENERGY, FSMONITORPROBES, FSMONITORSNAPSHOTS, FSMONITORCHECKPOINTS,
          FSMONITORRESTCHECK, FSMONITORPROGRESS, FSMONITORSUMMARY or a type of FSMonitorRegister()

.seealso: FSMonitorRegister()
*/
PetscErrorCode FSMonitorSetType(FSMonitor m, const char type[])
{
  FSMonitorCreateFn create;
  PetscBool         same;

  PetscFunctionBegin;
  PetscValidHeaderSpecific(m, FSMONITOR_CLASSID, 1);
  PetscCall(PetscObjectTypeCompare((PetscObject)m, type, &same));
  if (same) PetscFunctionReturn(0);
  PetscCheck(!m->setupcalled, PetscObjectComm((PetscObject)m), PETSC_ERR_ARG_WRONGSTATE,
             "FSMonitorSetType(\"%s\"): the monitor is set up already; set its type before FSMonitorSetUp()", type);
  PetscCall(FSRegistryFind(&FSMonitors, type, (void (**)(void)) & create));
  if (!create) {
    char known[1024];
    PetscCall(FSRegistryNames(&FSMonitors, known, sizeof(known)));
    SETERRQ(PetscObjectComm((PetscObject)m), PETSC_ERR_ARG_UNKNOWN_TYPE,
            "Unknown monitor type \"%s\": the registered types are%s", type, known);
  }
  if (m->ops->destroy) PetscCall((*m->ops->destroy)(m));
  PetscCall(PetscMemzero(m->ops, sizeof(*m->ops)));
  m->data = NULL;
  PetscCall(PetscObjectChangeTypeName((PetscObject)m, type));
  PetscCall((*create)(m));
  PetscFunctionReturn(0);
}

/*
   FSMonitorSetOps - the operations of the monitor's type, for the create routine of a type registered with
   FSMonitorRegister() outside the library (a plug-in, a program): what each does is in include/flexslosh.h and
   docs/architecture.md ("The monitor object").

   Not collective

   Input Parameters:
+  mon - the monitor, in its type's create routine
-  ops - the operations (copied; any may be NULL)

.seealso: FSMonitorRegister(), FSMonitorSetContext()
*/
PetscErrorCode FSMonitorSetOps(FSMonitor m, const FSMonitorOps *ops)
{
  PetscFunctionBegin;
  PetscValidHeaderSpecific(m, FSMONITOR_CLASSID, 1);
  *m->ops = *ops;
  PetscFunctionReturn(0);
}

/* FSMonitorSetContext - the data of the monitor's type (its destroy op frees it). Not collective */
PetscErrorCode FSMonitorSetContext(FSMonitor m, void *ctx)
{
  PetscFunctionBegin;
  PetscValidHeaderSpecific(m, FSMONITOR_CLASSID, 1);
  m->data = ctx;
  PetscFunctionReturn(0);
}

/* FSMonitorGetContext - the data of the monitor's type (ctx: the address of a pointer). Not collective */
PetscErrorCode FSMonitorGetContext(FSMonitor m, void *ctx)
{
  PetscFunctionBegin;
  PetscValidHeaderSpecific(m, FSMONITOR_CLASSID, 1);
  *(void **)ctx = m->data;
  PetscFunctionReturn(0);
}

/* FSMonitorGetType - the monitor's type name (NULL before FSMonitorSetType()). Not collective */
PetscErrorCode FSMonitorGetType(FSMonitor m, const char *type[])
{
  PetscFunctionBegin;
  PetscValidHeaderSpecific(m, FSMONITOR_CLASSID, 1);
  *type = ((PetscObject)m)->type_name;
  PetscFunctionReturn(0);
}

/*
   FSMonitorSetOptionsPrefix - the prefix of the monitor's options (those of FSMonitorSetFromOptions()).

   Logically collective
*/
PetscErrorCode FSMonitorSetOptionsPrefix(FSMonitor m, const char prefix[])
{
  PetscFunctionBegin;
  PetscValidHeaderSpecific(m, FSMONITOR_CLASSID, 1);
  PetscCall(PetscObjectSetOptionsPrefix((PetscObject)m, prefix));
  PetscFunctionReturn(0);
}

/*
   FSMonitorSetFromOptions - the monitor's options under its prefix: its type when none is set, and its type's own.

   Collective

   Options Database Key:
.  -<prefix>monitor_type <type> - a registered monitor type (FSMonitorListView())

   Notes:
   The solver reads the options of its built-in monitors (-fs_series_interval, -fs_probes, -fs_probe_interval,
   -fs_output_interval, -fs_checkpoint_interval, -fs_rest_check_*, -fs_progress, -fs_progress_interval) inside its own
options block (FSMonitorSetFromOptionItems()), so that -help lists them with the run's; it does not call this for them.
A user's monitor takes a prefix outside fs_: the check of unused -fs_ options (FSSolverCheckOptions()) knows the options
of the built-in objects only.

.seealso: FSMonitorSetFromOptionItems()
*/
PetscErrorCode FSMonitorSetFromOptions(FSMonitor m)
{
  char      type[256] = "";
  PetscBool set;

  PetscFunctionBegin;
  PetscValidHeaderSpecific(m, FSMONITOR_CLASSID, 1);
  PetscCall(FSMonitorRegisterAll());
  PetscObjectOptionsBegin((PetscObject)m);
  PetscCall(PetscOptionsString("-monitor_type", "The monitor's type", "FSMonitorSetType",
                               ((PetscObject)m)->type_name ? ((PetscObject)m)->type_name : "", type, sizeof(type),
                               &set));
  if (set && type[0]) PetscCall(FSMonitorSetType(m, type));
  if (m->ops->setfromoptions) PetscCall((*m->ops->setfromoptions)(m, PetscOptionsObject));
  PetscOptionsEnd();
  PetscFunctionReturn(0);
}

/*
   FSMonitorSetFromOptionItems - the options of the monitor's type, read inside an options block its caller opened
   (as TSAdaptSetFromOptions() inside TSSetFromOptions()): FSSolverSetFromOptions() reads its built-in monitors'
   options this way, so that -help lists them in the run's block, each where it always was.

   Collective

   Input Parameters:
+  mon   - the monitor, with its type set
-  items - the caller's options block (PetscOptionsObject)

.seealso: FSMonitorSetFromOptions()
*/
PetscErrorCode FSMonitorSetFromOptionItems(FSMonitor m, PetscOptionItems *items)
{
  PetscFunctionBegin;
  PetscValidHeaderSpecific(m, FSMONITOR_CLASSID, 1);
  if (m->ops->setfromoptions) PetscCall((*m->ops->setfromoptions)(m, items));
  PetscFunctionReturn(0);
}

/*
   FSMonitorSetUp - makes the monitor ready for the solver's run (called by FSSolverMonitorAdd() when the solver is
   set up, else by the solver's set-up).

   Collective
*/
PetscErrorCode FSMonitorSetUp(FSMonitor m, FSSolver s)
{
  PetscFunctionBegin;
  PetscValidHeaderSpecific(m, FSMONITOR_CLASSID, 1);
  if (m->setupcalled) PetscFunctionReturn(0);
  PetscCheck(((PetscObject)m)->type_name, PetscObjectComm((PetscObject)m), PETSC_ERR_ARG_WRONGSTATE,
             "FSMonitorSetUp(): the monitor has no type; call FSMonitorSetType() first");
  if (m->ops->setup) PetscCall((*m->ops->setup)(m, s));
  m->setupcalled = PETSC_TRUE;
  PetscFunctionReturn(0);
}

/*
   FSMonitorBegin - the start of the run's output: the monitor opens its files (on a restart, cut after the restart's
   step). Its first FSMonitorStep() (and row, FSMonitorRows()) follows, for the state the run starts from.

   Collective
*/
PetscErrorCode FSMonitorBegin(FSMonitor m, FSSolver s)
{
  PetscFunctionBegin;
  PetscValidHeaderSpecific(m, FSMONITOR_CLASSID, 1);
  if (m->begun) PetscFunctionReturn(0);
  PetscCall(FSMonitorSetUp(m, s));
  if (m->ops->begin) PetscCall((*m->ops->begin)(m, s));
  m->begun = PETSC_TRUE;
  m->first = PETSC_TRUE;
  PetscFunctionReturn(0);
}

/*
   FSMonitorRowBatchReset - leaves the batch empty, no rows due (a step that stopped between FSMonitorRowsBegin() and
   FSMonitorRowsEnd() leaves it so); its arrays are kept for the next step. Not collective
*/
PetscErrorCode FSMonitorRowBatchReset(FSMonitorRowBatch *b)
{
  PetscFunctionBegin;
  b->n = b->nsum = b->nmax = 0;
  b->active                = PETSC_FALSE;
  PetscFunctionReturn(0);
}

/*
   FSMonitorRowBatchDestroy - frees the batch's arrays and leaves it empty. Not collective
*/
PetscErrorCode FSMonitorRowBatchDestroy(FSMonitorRowBatch *b)
{
  PetscFunctionBegin;
  PetscCall(PetscFree(b->sum));
  PetscCall(PetscFree2(b->off, b->due));
  PetscCall(PetscMemzero(b, sizeof(*b)));
  PetscFunctionReturn(0);
}

/*
   FSMonitorRowsBegin - the first half of FSMonitorRows(): which of the monitors have a row due at this step, and
   this rank's sums and maxima of those rows in b (b->sum[0..b->nsum), b->max[0..b->nmax), in the monitors' order),
   for the caller to reduce (FSSolverReduceSumMax(), or with other values in one reduction as the step does) before
   FSMonitorRowsEnd().

   Not collective (a monitor's rowlocal may be)
*/
PetscErrorCode FSMonitorRowsBegin(PetscInt n, const FSMonitor mons[], FSSolver s, FSMonitorRowBatch *b)
{
  PetscFunctionBegin;
  PetscCall(FSMonitorRowBatchReset(b));
  b->n      = n;
  b->active = PETSC_TRUE;
  if (!n) PetscFunctionReturn(0);
  if (n > b->nmon) { /* room for the monitors, kept from step to step */
    PetscCall(PetscFree2(b->off, b->due));
    PetscCall(PetscMalloc2(2 * n + 2, &b->off, n, &b->due));
    b->nmon = n;
  }
  for (PetscInt k = 0; k < n; k++) { /* the sums of the rows due, in the monitors' order, then their maxima */
    PetscInt ns = 0, nm = 0;
    b->due[k] = PETSC_FALSE;
    if (mons[k]->begun && mons[k]->ops->rowsize) PetscCall((*mons[k]->ops->rowsize)(mons[k], s, &b->due[k], &ns, &nm));
    b->off[2 * k]     = b->nsum;
    b->off[2 * k + 1] = b->nmax;
    if (!b->due[k]) continue;
    b->nsum += ns;
    b->nmax += nm;
  }
  b->off[2 * n]     = b->nsum;
  b->off[2 * n + 1] = b->nmax;
  if (b->nsum + b->nmax + 1 > b->nval) {
    PetscCall(PetscFree(b->sum));
    PetscCall(PetscMalloc1(b->nsum + b->nmax + 1, &b->sum));
    b->nval = b->nsum + b->nmax + 1;
  }
  b->max = b->sum + b->nsum;
  for (PetscInt k = 0; k < n; k++)
    if (b->due[k]) PetscCall((*mons[k]->ops->rowlocal)(mons[k], s, b->sum + b->off[2 * k], b->max + b->off[2 * k + 1]));
  PetscFunctionReturn(0);
}

/*
   FSMonitorRowsEnd - the second half of FSMonitorRows(), once b's sums and maxima are reduced over the ranks: each
   monitor makes its row (where a check may stop the run before any row is written), then the rows are written in the
   monitors' order, a row only while the rows before it were written (rank 0's deferred write status,
   FSMonitorGetWriteStatus()); b is emptied.

   Not collective (a monitor's rowvalues may be)
*/
PetscErrorCode FSMonitorRowsEnd(PetscInt n, const FSMonitor mons[], FSSolver s, FSMonitorRowBatch *b)
{
  PetscFunctionBegin;
  PetscCheck(b->active && b->n == n, PETSC_COMM_SELF, PETSC_ERR_ARG_WRONGSTATE,
             "FSMonitorRowsEnd: no FSMonitorRowsBegin() for these %" PetscInt_FMT " monitors", n);
  for (PetscInt k = 0; k < n; k++)
    if (b->due[k])
      PetscCall((*mons[k]->ops->rowvalues)(mons[k], s, b->sum + b->off[2 * k], b->max + b->off[2 * k + 1]));
  for (PetscInt k = 0, failed = 0; k < n; k++) {
    if (!b->due[k]) continue;
    if (!failed) PetscCall((*mons[k]->ops->rowwrite)(mons[k], s));
    mons[k]->unchecked = PETSC_TRUE;
    if (mons[k]->file) { /* rank 0: a later row only where this one was written */
      PetscBool unchecked;
      PetscInt  status;
      PetscCall(FSMonitorGetWriteStatus(mons[k], &status, &unchecked));
      if (status) failed = 1;
    }
  }
  PetscCall(FSMonitorRowBatchReset(b));
  PetscFunctionReturn(0);
}

/*
   FSMonitorRows - the rows due at this step of the monitors with rows (the time series, the energy budget): each
   gives this rank's sums and maxima, one reduction (FSSolverReduceSumMax()) takes them all, then each makes its row
   (where a check may stop the run before any row is written) and the rows are written in the monitors' order, a row
   only while the rows before it were written (rank 0's deferred write status, FSMonitorGetWriteStatus()).
   FSMonitorRowsBegin() and FSMonitorRowsEnd() are its two halves, for a caller whose reduction the rows' ride on
   (FSSolverStep: the step's own).

   Collective

   Input Parameters:
+  n    - the number of monitors
.  mons - the monitors (those without rows are skipped)
-  s    - the solver
*/
PetscErrorCode FSMonitorRows(PetscInt n, const FSMonitor mons[], FSSolver s)
{
  FSMonitorRowBatch b;

  PetscFunctionBegin;
  PetscCall(PetscMemzero(&b, sizeof(b)));
  PetscCall(FSMonitorRowsBegin(n, mons, s, &b));
  if (b.nsum + b.nmax > 0) PetscCall(FSSolverReduceSumMax(s, b.nsum, b.sum, b.nmax, b.max)); /* the rows' one */
  PetscCall(FSMonitorRowsEnd(n, mons, s, &b));
  PetscCall(FSMonitorRowBatchDestroy(&b));
  PetscFunctionReturn(0);
}

/*
   FSMonitorStep - the monitor after a step (and once after FSMonitorBegin(), for the state the run starts from):
   what it writes at this step, at its own interval.

   Collective
*/
PetscErrorCode FSMonitorStep(FSMonitor m, FSSolver s)
{
  PetscReal t;
  PetscInt  step;

  PetscFunctionBegin;
  PetscValidHeaderSpecific(m, FSMONITOR_CLASSID, 1);
  PetscCheck(m->begun, PetscObjectComm((PetscObject)m), PETSC_ERR_ARG_WRONGSTATE,
             "FSMonitorStep(): call FSMonitorBegin() first");
  PetscCall(FSSolverGetTime(s, &t, &step));
  if (m->ops->step) PetscCall((*m->ops->step)(m, s, step, t, m->first));
  m->first = PETSC_FALSE;
  PetscFunctionReturn(0);
}

/* FSMonitorEnd - the end of the run: what the monitor writes last. Collective */
PetscErrorCode FSMonitorEnd(FSMonitor m, FSSolver s)
{
  PetscFunctionBegin;
  PetscValidHeaderSpecific(m, FSMONITOR_CLASSID, 1);
  if (m->begun && m->ops->end) PetscCall((*m->ops->end)(m, s));
  PetscFunctionReturn(0);
}

/*
   FSMonitorGetWriteStatus - the first failed write of the monitor's csv file (its rows are written by rank 0, their
   failure carried to the other ranks by the run's next collective, FSMonitorRaiseWriteStatus()).

   Not collective

   Output Parameters:
+  status    - 0 when none (always on the ranks but 0), else 1 + 2 errno + (1 when the row was left torn)
-  unchecked - whether rows were written since the status was last raised

.seealso: FSMonitorRaiseWriteStatus()
*/
PetscErrorCode FSMonitorGetWriteStatus(FSMonitor m, PetscInt *status, PetscBool *unchecked)
{
  int       err = 0;
  PetscBool torn;

  PetscFunctionBegin;
  *status    = 0;
  *unchecked = m->unchecked;
  if (!m->file) PetscFunctionReturn(0);
  PetscCall(FSTimeSeriesGetFailure(m->file, &err, &torn));
  if (err) *status = 1 + 2 * err + (torn ? 1 : 0);
  PetscFunctionReturn(0);
}

/*
   FSMonitorRaiseWriteStatus - raises the failed write that status (FSMonitorGetWriteStatus(), carried to every rank)
   names, on every rank; with 0 nothing. Rows written before are now checked.

   Not collective (called on every rank with the same status)
*/
PetscErrorCode FSMonitorRaiseWriteStatus(FSMonitor m, PetscInt status)
{
  PetscFunctionBegin;
  m->unchecked = PETSC_FALSE;
  if (!status) PetscFunctionReturn(0);
  PetscCheck(m->file, PetscObjectComm((PetscObject)m), PETSC_ERR_PLIB,
             "Write status %" PetscInt_FMT " of a monitor without a file", status);
  PetscCall(FSTimeSeriesRaiseFailure(m->file, (int)((status - 1) / 2), (PetscBool)((status - 1) % 2)));
  PetscFunctionReturn(0);
}

/* FSMonitorView - the monitor's type and what it writes. Collective */
PetscErrorCode FSMonitorView(FSMonitor m, PetscViewer viewer)
{
  PetscBool ascii;

  PetscFunctionBegin;
  PetscValidHeaderSpecific(m, FSMONITOR_CLASSID, 1);
  if (!viewer) PetscCall(PetscViewerASCIIGetStdout(PetscObjectComm((PetscObject)m), &viewer));
  PetscCall(PetscObjectTypeCompare((PetscObject)viewer, PETSCVIEWERASCII, &ascii));
  if (!ascii) PetscFunctionReturn(0);
  PetscCall(PetscObjectPrintClassNamePrefixType((PetscObject)m, viewer));
  if (m->ops->view) {
    PetscCall(PetscViewerASCIIPushTab(viewer));
    PetscCall((*m->ops->view)(m, viewer));
    PetscCall(PetscViewerASCIIPopTab(viewer));
  }
  PetscFunctionReturn(0);
}

/* FSMonitorDestroy - closes the monitor's files and frees it. Collective */
PetscErrorCode FSMonitorDestroy(FSMonitor *mon)
{
  PetscFunctionBegin;
  if (!*mon) PetscFunctionReturn(0);
  PetscValidHeaderSpecific(*mon, FSMONITOR_CLASSID, 1);
  if (--((PetscObject)(*mon))->refct > 0) {
    *mon = NULL;
    PetscFunctionReturn(0);
  }
  if ((*mon)->ops->destroy) PetscCall((*(*mon)->ops->destroy)(*mon));
  PetscCall(PetscHeaderDestroy(mon));
  PetscFunctionReturn(0);
}
