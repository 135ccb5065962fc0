/*
   Unit test of the monitors (src/monitor/), through the public API only, as a user's program: a plain monitor function
   (FSSolverMonitorSet(), the way a user's monitor plugs in) called once before the first step and after every step,
   with the state timeseries.csv's rows are made from (its kinetic energy from the fields equals the file's column); a
   monitor type of its own registered with FSMonitorRegister() and attached with FSSolverMonitorAdd() before the run,
   after the built-in ones, whose row's sum (the particles' mass) is reduced with the built-in rows' and equals the
   fields'; FSSolverMonitorCancel() and the contexts' destroy; an unknown type's error.

   Usage: mpirun -n <1..3> test_monitor     Prints "test_monitor: OK" and returns 0 on success.
*/
#include <flexslosh.h>
#include "../tempdir.h"

#define TCHECK(comm, cond, ...) PetscCheck(cond, comm, PETSC_ERR_PLIB, "test_monitor: " __VA_ARGS__)
#define NSTEPS                  6

/* ---------------------------------------------------------------- a plain monitor: the kinetic energy */

typedef struct {
  PetscInt  calls, step[NSTEPS + 2];
  PetscReal t[NSTEPS + 2], kin[NSTEPS + 2];
  PetscInt *destroyed; /* counts the destroys, outside the context */
} KinCtx;

/* the liquid's kinetic energy from the fields, summed over the ranks */
static PetscErrorCode KineticEnergy(FSSolver s, PetscReal *kin)
{
  const PetscReal *v, *m;
  PetscInt         n, dim;

  PetscFunctionBegin;
  *kin = 0;
  PetscCall(FSSolverGetDimension(s, &dim));
  PetscCall(FSSolverGetField(s, "velocity", &n, NULL, &v));
  PetscCall(FSSolverGetField(s, "mass", NULL, NULL, &m));
  for (PetscInt k = 0; k < n; k++) {
    PetscReal v2 = 0;
    for (PetscInt d = 0; d < dim; d++) v2 += v[k * dim + d] * v[k * dim + d];
    *kin += 0.5 * m[k] * v2;
  }
  PetscCall(FSSolverRestoreField(s, "mass", NULL, NULL, &m));
  PetscCall(FSSolverRestoreField(s, "velocity", NULL, NULL, &v));
  PetscCallMPI(MPI_Allreduce(MPI_IN_PLACE, kin, 1, MPIU_REAL, MPI_SUM, PetscObjectComm((PetscObject)s)));
  PetscFunctionReturn(0);
}

static PetscErrorCode KinMonitor(FSSolver s, PetscInt step, PetscReal t, void *ctx)
{
  KinCtx *c = (KinCtx *)ctx;

  PetscFunctionBegin;
  PetscCheck(c->calls < NSTEPS + 2, PETSC_COMM_SELF, PETSC_ERR_PLIB, "test_monitor: more calls than steps");
  c->step[c->calls] = step;
  c->t[c->calls]    = t;
  PetscCall(KineticEnergy(s, &c->kin[c->calls]));
  c->calls++;
  PetscFunctionReturn(0);
}

static PetscErrorCode KinDestroy(void **ctx)
{
  KinCtx *c = (KinCtx *)*ctx;

  PetscFunctionBegin;
  (*c->destroyed)++;
  PetscCall(PetscFree(c));
  *ctx = NULL;
  PetscFunctionReturn(0);
}

/* ---------------------------------------------------------------- a monitor type: the mass, in the batched rows */

typedef struct {
  PetscInt  rows, steps, ends;
  PetscReal mass, maxmass; /* the last row's: summed and largest over the ranks */
} MassData;

static MassData *LastMass; /* the data of the last monitor of this type, read after its solver is gone */

static PetscErrorCode MassRowSize(FSMonitor m, FSSolver s, PetscBool *due, PetscInt *nsum, PetscInt *nmax)
{
  PetscFunctionBegin;
  *due  = PETSC_TRUE;
  *nsum = 1;
  *nmax = 1;
  PetscFunctionReturn(0);
}

static PetscErrorCode MassRowLocal(FSMonitor m, FSSolver s, PetscReal sum[], PetscReal max[])
{
  const PetscReal *mass;
  PetscInt         n;

  PetscFunctionBegin;
  sum[0] = 0;
  PetscCall(FSSolverGetField(s, "mass", &n, NULL, &mass));
  for (PetscInt k = 0; k < n; k++) sum[0] += mass[k];
  PetscCall(FSSolverRestoreField(s, "mass", &n, NULL, &mass));
  max[0] = sum[0];
  PetscFunctionReturn(0);
}

static PetscErrorCode MassRowValues(FSMonitor m, FSSolver s, const PetscReal sum[], const PetscReal max[])
{
  MassData *d;

  PetscFunctionBegin;
  PetscCall(FSMonitorGetContext(m, &d));
  d->mass    = sum[0];
  d->maxmass = max[0];
  PetscFunctionReturn(0);
}

static PetscErrorCode MassRowWrite(FSMonitor m, FSSolver s)
{
  MassData *d;

  PetscFunctionBegin;
  PetscCall(FSMonitorGetContext(m, &d));
  d->rows++;
  PetscFunctionReturn(0);
}

static PetscErrorCode MassStep(FSMonitor m, FSSolver s, PetscInt step, PetscReal t, PetscBool first)
{
  MassData *d;

  PetscFunctionBegin;
  PetscCall(FSMonitorGetContext(m, &d));
  PetscCheck(first == (d->steps == 0), PETSC_COMM_SELF, PETSC_ERR_PLIB, "test_monitor: first is %d at call %d",
             (int)first, (int)d->steps);
  d->steps++;
  PetscFunctionReturn(0);
}

static PetscErrorCode MassEnd(FSMonitor m, FSSolver s)
{
  MassData *d;

  PetscFunctionBegin;
  PetscCall(FSMonitorGetContext(m, &d));
  d->ends++;
  PetscFunctionReturn(0);
}

static PetscErrorCode MassDestroy(FSMonitor m)
{
  PetscFunctionBegin;
  PetscCall(FSMonitorGetContext(m, &LastMass)); /* freed by the test */
  PetscFunctionReturn(0);
}

/* the type's create routine, as a plug-in's: the ops and the context through the public API */
static PetscErrorCode FSMonitorCreate_Mass(FSMonitor m)
{
  MassData    *d;
  FSMonitorOps ops = {0};

  PetscFunctionBegin;
  PetscCall(PetscNew(&d));
  ops.rowsize   = MassRowSize;
  ops.rowlocal  = MassRowLocal;
  ops.rowvalues = MassRowValues;
  ops.rowwrite  = MassRowWrite;
  ops.step      = MassStep;
  ops.end       = MassEnd;
  ops.destroy   = MassDestroy;
  PetscCall(FSMonitorSetOps(m, &ops));
  PetscCall(FSMonitorSetContext(m, d));
  PetscFunctionReturn(0);
}

/* ---------------------------------------------------------------- the run */

/* kinetic_energy of every row of timeseries.csv (rank 0 reads, every rank gets them) */
static PetscErrorCode ReadKinetic(MPI_Comm comm, const char dir[], PetscInt *nrows, PetscReal kin[])
{
  char        path[PETSC_MAX_PATH_LEN], line[8192];
  PetscMPIInt rank;
  PetscInt    n = 0, col = -1;
  FILE       *f;

  PetscFunctionBegin;
  PetscCallMPI(MPI_Comm_rank(comm, &rank));
  if (!rank) {
    PetscCall(PetscSNPrintf(path, sizeof(path), "%s/timeseries.csv", dir));
    f = fopen(path, "r");
    PetscCheck(f, PETSC_COMM_SELF, PETSC_ERR_FILE_OPEN, "test_monitor: no %s", path);
    while (fgets(line, sizeof(line), f)) {
      char    *tok = strtok(line, ",\n");
      PetscInt c   = 0;
      for (; tok; tok = strtok(NULL, ",\n"), c++) {
        if (col < 0 && !strcmp(tok, "kinetic_energy")) col = c;
        else if (col >= 0 && c == col && n < NSTEPS + 2) kin[n++] = atof(tok);
      }
    }
    fclose(f);
  }
  PetscCallMPI(MPI_Bcast(&n, 1, MPIU_INT, 0, comm));
  PetscCallMPI(MPI_Bcast(kin, NSTEPS + 2, MPIU_REAL, 0, comm));
  *nrows = n;
  PetscFunctionReturn(0);
}

static PetscErrorCode TestRun(MPI_Comm comm, const char dir[])
{
  FSSolver         s;
  FSMonitor        mass;
  KinCtx          *kc;
  PetscInt         destroyed = 0, n, nrows, step;
  const FSMonitor *mons;
  const char      *type;
  const char      *expect[] = {FSMONITORTIMESERIES, FSMONITORENERGY,  FSMONITORSNAPSHOTS, FSMONITORRESTCHECK,
                               FSMONITORPROGRESS,   FSMONITORSUMMARY, "test_mass"};
  PetscReal        kin[NSTEPS + 2], seen[NSTEPS + 2], t, fieldmass;
  char             opts[PETSC_MAX_PATH_LEN + 256];

  PetscFunctionBegin;
  PetscCall(PetscSNPrintf(opts, sizeof(opts),
                          "-fs_case taylor_green -fs_dx 0.1 -fs_progress 0 -fs_output_interval 0 -ts_max_steps %d "
                          "-fs_output_dir %s",
                          NSTEPS, dir));
  PetscCall(PetscOptionsInsertString(NULL, opts));
  PetscCall(FSMonitorRegister("test_mass", "the particles' mass (test_monitor)", FSMonitorCreate_Mass));
  PetscCall(FSSolverCreate(comm, &s));
  PetscCall(FSSolverSetFromOptions(s));
  PetscCall(PetscNew(&kc));
  kc->destroyed = &destroyed;
  PetscCall(FSSolverMonitorSet(s, KinMonitor, kc, KinDestroy));
  PetscCall(FSMonitorCreate(comm, &mass));
  PetscCall(FSMonitorSetType(mass, "test_mass"));
  PetscCall(FSSolverMonitorAdd(s, mass)); /* before the run: after the built-in ones */
  PetscCall(FSMonitorDestroy(&mass));     /* the solver holds its reference */
  PetscCall(FSSolverSolve(s));
  PetscCall(FSSolverGetTime(s, &t, &step));

  /* the plain monitor: step 0, then each step, with the TS's time */
  TCHECK(comm, kc->calls == NSTEPS + 1 && step == NSTEPS, "%" PetscInt_FMT " calls for %" PetscInt_FMT " steps",
         kc->calls, step);
  for (PetscInt k = 0; k < kc->calls; k++)
    TCHECK(comm, kc->step[k] == k, "call %" PetscInt_FMT " at step %" PetscInt_FMT, k, kc->step[k]);
  TCHECK(comm, kc->t[0] == 0 && kc->t[NSTEPS] == t, "the calls' times %g .. %g, the run's %g", (double)kc->t[0],
         (double)kc->t[NSTEPS], (double)t);
  TCHECK(comm, kc->kin[NSTEPS] < kc->kin[0] && kc->kin[NSTEPS] > 0.5 * kc->kin[0],
         "the decaying vortex's kinetic energy %g -> %g", (double)kc->kin[0], (double)kc->kin[NSTEPS]);

  /* the list: the run's own monitors first */
  PetscCall(FSSolverGetMonitors(s, &n, &mons));
  TCHECK(comm, n == 7, "%" PetscInt_FMT " monitors attached: expected 7", n);
  for (PetscInt k = 0; k < n; k++) {
    PetscCall(FSMonitorGetType(mons[k], &type));
    TCHECK(comm, !strcmp(type, expect[k]), "monitor %" PetscInt_FMT " is %s: expected %s", k, type, expect[k]);
  }
  PetscCall(FSMonitorView(mons[0], PETSC_VIEWER_STDOUT_(comm)));

  /* the mass monitor's row, reduced with the others' */
  {
    const PetscReal *m;
    MassData        *d;
    PetscCall(FSMonitorGetContext(mons[6], &d));
    PetscCall(FSSolverGetField(s, "mass", &n, NULL, &m));
    fieldmass = 0;
    for (PetscInt k = 0; k < n; k++) fieldmass += m[k];
    PetscCall(FSSolverRestoreField(s, "mass", &n, NULL, &m));
    PetscCallMPI(MPI_Allreduce(MPI_IN_PLACE, &fieldmass, 1, MPIU_REAL, MPI_SUM, comm));
    TCHECK(comm, d->rows == NSTEPS + 1 && d->steps == NSTEPS + 1 && d->ends == 1,
           "the mass monitor: %" PetscInt_FMT " rows, %" PetscInt_FMT " steps, %" PetscInt_FMT " ends", d->rows,
           d->steps, d->ends);
    TCHECK(
        comm,
        PetscAbsReal(d->mass - fieldmass) <= 1e-12 * fieldmass && d->maxmass <= d->mass * (1 + 1e-12) && d->maxmass > 0,
        "the row's mass %g (largest share %g), the fields' %g", (double)d->mass, (double)d->maxmass, (double)fieldmass);
  }
  for (PetscInt k = 0; k <= NSTEPS; k++) seen[k] = kc->kin[k];
  PetscCall(FSSolverMonitorCancel(s)); /* the user's monitors go; the run's stay */
  PetscCall(FSSolverGetMonitors(s, &n, NULL));
  TCHECK(comm, n == 6 && destroyed == 1 && LastMass && LastMass->rows == NSTEPS + 1,
         "after FSSolverMonitorCancel: %" PetscInt_FMT " monitors, %" PetscInt_FMT " contexts destroyed", n, destroyed);
  PetscCall(PetscFree(LastMass));
  PetscCall(FSSolverDestroy(&s));
  TCHECK(comm, destroyed == 1, "the plain monitor's context destroyed %" PetscInt_FMT " times", destroyed);

  /* timeseries.csv's kinetic energy is the state's the plain monitor saw at each step (the file's 10 digits) */
  PetscCall(ReadKinetic(comm, dir, &nrows, kin));
  TCHECK(comm, nrows == NSTEPS + 1, "timeseries.csv has %" PetscInt_FMT " rows: expected %d", nrows, NSTEPS + 1);
  for (PetscInt k = 0; k <= NSTEPS; k++)
    TCHECK(comm, PetscAbsReal(kin[k] - seen[k]) <= 1e-9 * seen[0],
           "step %" PetscInt_FMT ": timeseries.csv's kinetic energy %.10e, the plain monitor's %.10e", k,
           (double)kin[k], (double)seen[k]);
  PetscFunctionReturn(0);
}

/* an unknown type: an error naming it and the registered ones */
static PetscErrorCode TestUnknownType(MPI_Comm comm)
{
  FSMonitor      m;
  PetscErrorCode ierr;
  char          *msg = NULL;

  PetscFunctionBegin;
  PetscCall(FSMonitorCreate(comm, &m));
  PetscCall(PetscPushErrorHandler(PetscReturnErrorHandler, NULL));
  ierr = FSMonitorSetType(m, "nosuch");
  PetscCall(PetscPopErrorHandler());
  PetscCall(PetscErrorMessage(ierr, NULL, &msg));
  TCHECK(comm, ierr == PETSC_ERR_ARG_UNKNOWN_TYPE && msg && strstr(msg, "\"nosuch\"") && strstr(msg, "timeseries"),
         "FSMonitorSetType(\"nosuch\") gave %d (%s)", (int)ierr, msg ? msg : "");
  PetscCall(FSMonitorDestroy(&m));
  PetscFunctionReturn(0);
}

/* the probes monitor's values, and the checkpoints monitor's write, asked of another type: an error naming it */
static PetscErrorCode TestWrongType(MPI_Comm comm)
{
  FSMonitor      m;
  PetscErrorCode ierr;
  PetscInt       n   = -1;
  char          *msg = NULL;

  PetscFunctionBegin;
  PetscCall(FSMonitorCreate(comm, &m));
  PetscCall(FSMonitorSetType(m, FSMONITORENERGY));
  PetscCall(PetscPushErrorHandler(PetscReturnErrorHandler, NULL));
  ierr = FSMonitorProbesGetValues(m, NULL, &n, NULL, NULL, NULL);
  PetscCall(PetscPopErrorHandler());
  PetscCall(PetscErrorMessage(ierr, NULL, &msg));
  TCHECK(comm, ierr == PETSC_ERR_ARG_WRONGSTATE && n == -1 && msg && strstr(msg, "not a probes monitor (energy)"),
         "FSMonitorProbesGetValues() of an energy monitor gave %d (%s)", (int)ierr, msg ? msg : "");
  PetscCall(PetscPushErrorHandler(PetscReturnErrorHandler, NULL));
  ierr = FSMonitorCheckpointsWrite(m, NULL);
  PetscCall(PetscPopErrorHandler());
  PetscCall(PetscErrorMessage(ierr, NULL, &msg));
  TCHECK(comm, ierr == PETSC_ERR_ARG_WRONGSTATE && msg && strstr(msg, "not a checkpoints monitor (energy)"),
         "FSMonitorCheckpointsWrite() of an energy monitor gave %d (%s)", (int)ierr, msg ? msg : "");
  PetscCall(FSMonitorDestroy(&m));
  PetscFunctionReturn(0);
}

int main(int argc, char **argv)
{
  MPI_Comm    comm;
  PetscMPIInt size, rank;
  char        dir[PETSC_MAX_PATH_LEN] = "/tmp/fs_test_monitor.XXXXXX";

  PetscCall(PetscInitialize(&argc, &argv, NULL, "Unit test of flexslosh's monitors"));
  comm = PETSC_COMM_WORLD;
  PetscCallMPI(MPI_Comm_size(comm, &size));
  PetscCallMPI(MPI_Comm_rank(comm, &rank));
  if (!rank) PetscCheck(mkdtemp(dir), PETSC_COMM_SELF, PETSC_ERR_FILE_OPEN, "mkdtemp failed");
  PetscCallMPI(MPI_Bcast(dir, sizeof(dir), MPI_CHAR, 0, comm));
  PetscCall(TestRun(comm, dir));
  PetscCall(TestUnknownType(comm));
  PetscCall(TestWrongType(comm));
  PetscCallMPI(MPI_Barrier(comm));
  if (!rank) PetscCall(FSTestRemoveTree(dir));
  PetscCall(PetscPrintf(comm, "test_monitor: OK (%d ranks)\n", (int)size));
  PetscCall(PetscFinalize());
  return 0;
}
