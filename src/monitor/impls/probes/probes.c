/*
   The probes monitor: the probes and wave gauges of -fs_probes (probeset.c: the file parsed and checked, the samples,
   the sensors' time response, sensor.c) and probes.csv, a row of their values every -fs_probe_interval steps (its
   options, read in the solver's options block). The solver makes this monitor with its options and its set-up sets
   it up (the probe file's errors are set-up's), FSSolverGetProbes() reads it (FSMonitorProbesGetValues()), and the
   run's output attaches it, when the file has items, with the other built-in monitors. A sample's sums are reduced
   in one reduction of their own.
*/
#include "monitor/impls/probes/probesimpl.h"

typedef struct {
  FSProbeSet set;
  PetscReal *row; /* time, then the set's nvalues */
} FSMonitor_Probes;

static PetscErrorCode FSMonitorSetFromOptions_Probes(FSMonitor m, PetscOptionItems *PetscOptionsObject)
{
  FSProbeSet *ps = &((FSMonitor_Probes *)m->data)->set;

  PetscFunctionBegin;
  PetscCall(PetscOptionsString(
      "-fs_probes",
      "File of pressure probes and wave gauges (\"probe NAME x y [z] [diameter D] [cutoff HZ] [order 1|2] "
      "[rate HZ]\", "
      "\"gauge NAME x0 y0 [z0] x1 y1 [z1]\"): their values into <output_dir>/probes.csv",
      "FSSolverGetProbes", ps->file, ps->file, sizeof(ps->file), NULL));
  PetscCall(FSOptionsInt(PetscOptionsObject, "-fs_probe_interval", "Steps between the samples of the probes and gauges",
                         "FSSolverGetProbes", &ps->interval, NULL, 1, PETSC_MAX_INT));
  PetscFunctionReturn(0);
}

static PetscErrorCode FSMonitorSetUp_Probes(FSMonitor m, FSSolver s)
{
  FSMonitor_Probes *pr = (FSMonitor_Probes *)m->data;

  PetscFunctionBegin;
  PetscCall(FSProbeSetSetUp(&pr->set, s));
  PetscFunctionReturn(0);
}

static PetscErrorCode FSMonitorBegin_Probes(FSMonitor m, FSSolver s)
{
  FSMonitor_Probes      *pr = (FSMonitor_Probes *)m->data;
  const FSProbeSet      *ps = &pr->set;
  FSSolverOutputSettings o;
  const char           **cols;
  char                   path[PETSC_MAX_PATH_LEN];
  PetscInt               step;

  PetscFunctionBegin;
  if (!ps->n) PetscFunctionReturn(0); /* no -fs_probes, or a file without items: no file */
  PetscCall(FSSolverGetOutputSettings(s, &o));
  PetscCall(FSSolverGetTime(s, NULL, &step));
  PetscCall(PetscMalloc1(ps->nvalues + 1, &cols));
  PetscCall(PetscMalloc1(ps->nvalues + 1, &pr->row));
  cols[0] = "time";
  for (PetscInt c = 0; c < ps->nvalues; c++) cols[1 + c] = ps->colname[c];
  PetscCall(PetscSNPrintf(path, sizeof(path), "%s/probes.csv", o.outdir));
  PetscCall(FSTimeSeriesCreate(PetscObjectComm((PetscObject)m), path, ps->nvalues + 1, cols, o.restart ? step : -1,
                               &m->file));
  PetscCall(FSTimeSeriesSetDeferred(m->file, PETSC_TRUE)); /* its write status as timeseries.csv's */
  PetscCall(PetscFree(cols));
  PetscFunctionReturn(0);
}

/* every -fs_probe_interval steps (counted from step 0), the first row included */
static PetscErrorCode FSMonitorStep_Probes(FSMonitor m, FSSolver s, PetscInt step, PetscReal t, PetscBool first)
{
  FSMonitor_Probes *pr = (FSMonitor_Probes *)m->data;
  FSProbeSet       *ps = &pr->set;

  PetscFunctionBegin;
  (void)t;
  (void)first;
  if (!m->file || step % ps->interval) PetscFunctionReturn(0);
  PetscCall(FSProbeSetRecord(ps, s));
  pr->row[0] = ps->time;
  PetscCall(PetscArraycpy(pr->row + 1, ps->values, ps->nvalues));
  PetscCall(FSTimeSeriesAppend(m->file, step, pr->row));
  m->unchecked = PETSC_TRUE;
  PetscFunctionReturn(0);
}

static PetscErrorCode FSMonitorView_Probes(FSMonitor m, PetscViewer viewer)
{
  FSMonitor_Probes *pr = (FSMonitor_Probes *)m->data;

  PetscFunctionBegin;
  PetscCall(PetscViewerASCIIPrintf(viewer, "probes.csv, %" PetscInt_FMT " columns, every %" PetscInt_FMT " steps\n",
                                   (pr->set.n ? pr->set.nvalues : 0) + 1, pr->set.interval));
  PetscFunctionReturn(0);
}

static PetscErrorCode FSMonitorDestroy_Probes(FSMonitor m)
{
  FSMonitor_Probes *pr = (FSMonitor_Probes *)m->data;

  PetscFunctionBegin;
  PetscCall(FSTimeSeriesDestroy(&m->file));
  PetscCall(FSProbeSetDestroy(&pr->set));
  PetscCall(PetscFree(pr->row));
  PetscCall(PetscFree(m->data));
  PetscFunctionReturn(0);
}

/*
   FSMonitorProbesGetValues - the values of a probes monitor's probes and wave gauges at the solver's current state.

   Collective (when values are asked for)

   Input Parameters:
+  m - the probes monitor (FSMONITORPROBES), set up
-  s - the solver it was set up with

   Output Parameters:
+  n       - the number of probes and gauges, in the order of the file
.  names   - their names (an array of n pointers, or NULL); owned by the monitor
.  offsets - (an array of n+1, or NULL) item k's values are values[offsets[k] .. offsets[k+1])
-  values  - (an array of at most FS_PROBE_MAX_VALUES n reals, or NULL) the values, as the columns of probes.csv

   Notes:
   The values are those sampled at this step by probes.csv's row, or sampled now (one evaluation of the right-hand
   side). FSSolverGetProbes() calls this for the solver's own probes monitor.

.seealso: FSSolverGetProbes()
*/
PetscErrorCode FSMonitorProbesGetValues(FSMonitor m, FSSolver s, PetscInt *n, const char *names[], PetscInt offsets[],
                                        PetscReal values[])
{
  FSMonitor_Probes *pr;
  FSProbeSet       *ps;
  PetscBool         same;
  PetscReal         t;
  PetscInt          step;

  PetscFunctionBegin;
  PetscValidHeaderSpecific(m, FSMONITOR_CLASSID, 1);
  PetscCall(PetscObjectTypeCompare((PetscObject)m, FSMONITORPROBES, &same));
  PetscCheck(same && m->setupcalled, PetscObjectComm((PetscObject)m), PETSC_ERR_ARG_WRONGSTATE,
             "FSMonitorProbesGetValues(): the monitor is not a probes monitor (%s) set up",
             ((PetscObject)m)->type_name ? ((PetscObject)m)->type_name : "no type");
  pr = (FSMonitor_Probes *)m->data;
  ps = &pr->set;
  if (n) *n = ps->n;
  for (PetscInt k = 0; names && k < ps->n; k++) names[k] = ps->names[k];
  for (PetscInt k = 0; offsets && k <= ps->n; k++) offsets[k] = ps->offset[k];
  if (!values || !ps->n) PetscFunctionReturn(0);
  PetscCall(FSSolverGetTime(s, &t, &step));
  if (ps->step != step || ps->time != t) PetscCall(FSProbeSetSample(ps, s));
  PetscCall(PetscArraycpy(values, ps->values, ps->nvalues));
  PetscFunctionReturn(0);
}

/* FSMonitorCreate_Probes - the probes monitor (FSMONITORPROBES): -fs_probes, probes.csv. */
PetscErrorCode FSMonitorCreate_Probes(FSMonitor m)
{
  FSMonitor_Probes *pr;

  PetscFunctionBegin;
  PetscCall(PetscNew(&pr));
  pr->set.interval       = 1;
  m->data                = pr;
  m->ops->setfromoptions = FSMonitorSetFromOptions_Probes;
  m->ops->setup          = FSMonitorSetUp_Probes;
  m->ops->begin          = FSMonitorBegin_Probes;
  m->ops->step           = FSMonitorStep_Probes;
  m->ops->view           = FSMonitorView_Probes;
  m->ops->destroy        = FSMonitorDestroy_Probes;
  PetscFunctionReturn(0);
}
