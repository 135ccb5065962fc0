/*
   Unit test of the C API for drivers (the Python package uses it through ctypes): a structure model
   registered with callbacks (FSStructureRegisterCallbacks) run dry, a callback's error message as a
   PETSc error, FSSolverGetField against the swarm and the equation of state, FSSolverGetEnergy against
   the fields, FSSolverGetWallLoads and FSSolverGetLiquidMass on the coupled tank.

   Usage: mpirun -n <1..3> test_driver     Prints "test_driver: OK" and returns 0 on success.
*/
#include <flexslosh.h>

#define TCHECK(comm, cond, ...) PetscCheck(cond, comm, PETSC_ERR_PLIB, "test_driver: " __VA_ARGS__)

/* ---------------------------------------------------------------- a callback model: w'' = -w */

static PetscErrorCode OscSetUp(void *impl, FSStructure st, PetscInt *ndof, PetscReal *T)
{
  PetscFunctionBegin;
  *ndof = 2;
  *T    = 2 * PETSC_PI;
  PetscCall(FSStructureAddColumn(st, "w2"));
  PetscFunctionReturn(0);
}

static PetscErrorCode OscInitial(void *impl, PetscInt n, PetscReal y[])
{
  PetscFunctionBegin;
  y[0] = 1;
  PetscFunctionReturn(0);
}

static PetscErrorCode OscRHS(void *impl, PetscReal t, PetscInt n, const PetscReal y[], const FSLoads *loads,
                             PetscReal ydot[])
{
  PetscFunctionBegin;
  ydot[0] = y[1];
  ydot[1] = -y[0];
  PetscFunctionReturn(0);
}

static PetscErrorCode OscMotion(void *impl, PetscInt n, const PetscReal y[], const PetscReal ydot[], FSTankMotion *m)
{
  PetscFunctionBegin;
  m->disp[1] = y[0];
  m->vel[1]  = y[1];
  m->acc[1]  = ydot[1];
  PetscFunctionReturn(0);
}

static PetscErrorCode OscColumns(void *impl, PetscReal t, PetscInt n, const PetscReal y[], const PetscReal ydot[],
                                 PetscInt nc, PetscReal v[])
{
  PetscFunctionBegin;
  v[0] = y[0] * y[0];
  PetscFunctionReturn(0);
}

static PetscErrorCode FailSetUp(void *impl, FSStructure st, PetscInt *ndof, PetscReal *T)
{
  PetscFunctionBegin;
  PetscCall(FSStructureCallbacksSetError((const char *)impl));
  PetscFunctionReturn(1);
}

/* a solver from an options string, in a database of its own (pushed as the default one) */
static PetscErrorCode SolverFrom(const char opts[], PetscOptions *db, FSSolver *s)
{
  PetscFunctionBegin;
  PetscCall(PetscOptionsCreate(db));
  PetscCall(PetscOptionsInsertString(*db, opts));
  PetscCall(PetscOptionsPush(*db));
  PetscCall(FSSolverCreate(PETSC_COMM_WORLD, s));
  PetscCall(FSSolverSetFromOptions(*s));
  PetscFunctionReturn(0);
}

static PetscErrorCode SolverEnd(PetscOptions *db, FSSolver *s)
{
  PetscFunctionBegin;
  PetscCall(FSSolverDestroy(s));
  PetscCall(PetscOptionsPop());
  PetscCall(PetscOptionsDestroy(db));
  PetscFunctionReturn(0);
}

static PetscErrorCode TestCallbacks(MPI_Comm comm)
{
  FSStructureCallbacks cb = {NULL, OscSetUp, OscInitial, OscRHS, OscMotion, OscColumns, NULL, NULL}, bad = cb;
  FSSolver             s;
  PetscOptions         db;
  FSTankMotion         m;
  PetscReal            y[2], t;
  PetscInt             n;
  PetscErrorCode       ierr;
  char                *msg = NULL;

  PetscFunctionBegin;
  PetscCall(FSStructureRegisterCallbacks("c_osc", "w'' = -w (test_driver)", &cb, NULL));
  PetscCall(SolverFrom("-fs_case beam -fs_structure c_osc -fs_output 0 -fs_progress 0 -ts_max_time 3.141592653589793",
                       &db, &s));
  PetscCall(FSSolverSolve(s));
  PetscCall(FSSolverGetTime(s, &t, &n));
  PetscCall(FSSolverGetStructureState(s, &n, y));
  PetscCall(FSSolverGetTankMotion(s, &m));
  TCHECK(comm, n == 2 && PetscAbsReal(t - PETSC_PI) < 1e-12, "the run ended at t = %g with %" PetscInt_FMT " DOFs",
         (double)t, n);
  TCHECK(comm, PetscAbsReal(y[0] + 1) < 1e-5 && PetscAbsReal(y[1]) < 1e-5, "w(pi) = %g, w'(pi) = %g: expected -1, 0",
         (double)y[0], (double)y[1]);
  TCHECK(comm, m.disp[1] == y[0] && m.vel[1] == y[1] && m.acc[1] == -y[0], "the motion is not the callback's");
  PetscCall(SolverEnd(&db, &s));

  /* a failing callback: its message in a PETSc error on every rank (setup runs on all) */
  bad.setup = FailSetUp;
  PetscCall(FSStructureRegisterCallbacks("c_fail", NULL, &bad, (void *)"RuntimeError: no beam"));
  PetscCall(SolverFrom("-fs_case beam -fs_structure c_fail -fs_output 0 -fs_progress 0", &db, &s));
  PetscCall(PetscPushErrorHandler(PetscReturnErrorHandler, NULL));
  ierr = FSSolverSetUp(s);
  PetscCall(PetscPopErrorHandler());
  PetscCall(PetscErrorMessage(ierr, NULL, &msg));
  TCHECK(comm,
         ierr == PETSC_ERR_USER && msg &&
             strstr(msg, "Structure c_fail: its setup callback failed: RuntimeError: no beam"),
         "FSSolverSetUp returned %d (%s)", (int)ierr, msg ? msg : "");
  PetscCall(SolverEnd(&db, &s));
  PetscFunctionReturn(0);
}

/* ---------------------------------------------------------------- fields and energy */

static PetscErrorCode TestFields(MPI_Comm comm)
{
  FSSolver         s;
  PetscOptions     db;
  const PetscReal *x, *rho, *p, *v, *m, *id;
  const char      *names[FS_ENERGY_MAX_COLUMNS];
  PetscReal        E[FS_ENERGY_MAX_COLUMNS], *sx, rho0, c0, kin = 0;
  PetscInt         n, bs, nsw, ne, nw, dim;
  PetscErrorCode   ierr;

  PetscFunctionBegin;
  PetscCall(SolverFrom("-fs_case taylor_green -fs_dx 0.1 -fs_output 0 -fs_progress 0", &db, &s));
  PetscCall(FSSolverStep(s));
  PetscCall(FSSolverGetDimension(s, &dim));
  PetscCall(FSSolverGetParameters(s, NULL, NULL, &rho0, &c0, NULL));
  PetscCall(FSSolverGetField(s, "position", &n, &bs, &x));
  {
    DM sw;
    PetscCall(FSSolverGetSwarm(s, &sw));
    PetscCall(DMSwarmGetLocalSize(sw, &nsw));
    PetscCall(DMSwarmGetField(sw, "position", NULL, NULL, (void **)&sx));
    TCHECK(comm, n == nsw && bs == dim, "position: %" PetscInt_FMT " x %" PetscInt_FMT ", the swarm has %" PetscInt_FMT,
           n, bs, nsw);
    for (PetscInt k = 0; k < n * bs; k++)
      TCHECK(PETSC_COMM_SELF, x[k] == sx[k], "position %" PetscInt_FMT " differs from the swarm's", k);
    PetscCall(DMSwarmRestoreField(sw, "position", NULL, NULL, (void **)&sx));
  }
  PetscCall(FSSolverGetField(s, "density", &n, &bs, &rho));
  PetscCall(FSSolverGetField(s, "pressure", NULL, NULL, &p));
  PetscCall(FSSolverGetField(s, "velocity", NULL, NULL, &v));
  PetscCall(FSSolverGetField(s, "mass", NULL, NULL, &m));
  PetscCall(FSSolverGetField(s, "id", NULL, NULL, &id));
  for (PetscInt k = 0; k < n; k++) {
    TCHECK(PETSC_COMM_SELF, p[k] == c0 * c0 * (rho[k] - rho0), "particle %g: p = %g is not c0^2 (rho - rho0)",
           (double)id[k], (double)p[k]);
    TCHECK(PETSC_COMM_SELF, id[k] >= 0 && id[k] < 100, "id %g out of range", (double)id[k]);
    for (PetscInt d = 0; d < dim; d++) kin += 0.5 * m[k] * v[k * dim + d] * v[k * dim + d];
  }
  PetscCallMPI(MPI_Allreduce(MPI_IN_PLACE, &kin, 1, MPIU_REAL, MPI_SUM, comm));
  PetscCall(FSSolverGetEnergy(s, &ne, names, E));
  TCHECK(comm, ne == 21 && !strcmp(names[0], "time") && !strcmp(names[1], "E_kin"),
         "energy columns %" PetscInt_FMT ": %s, %s", ne, names[0], names[1]);
  TCHECK(comm, PetscAbsReal(E[1] - kin) <= 1e-12 * kin, "E_kin %g, from the fields %g", (double)E[1], (double)kin);
  PetscCall(FSSolverGetWallLoads(s, &nw, NULL, NULL));
  TCHECK(comm, nw == 0, "Taylor-Green has %" PetscInt_FMT " walls", nw);
  PetscCall(FSSolverRestoreField(s, "id", NULL, NULL, &id));
  PetscCall(FSSolverRestoreField(s, "mass", NULL, NULL, &m));
  PetscCall(FSSolverRestoreField(s, "velocity", NULL, NULL, &v));
  PetscCall(FSSolverRestoreField(s, "pressure", NULL, NULL, &p));
  PetscCall(FSSolverRestoreField(s, "density", &n, &bs, &rho));
  PetscCall(FSSolverRestoreField(s, "position", &n, &bs, &x));
  TCHECK(comm, !x && !n && !bs, "FSSolverRestoreField left values behind");
  PetscCall(PetscPushErrorHandler(PetscReturnErrorHandler, NULL));
  ierr = FSSolverGetField(s, "nosuch", &n, &bs, &x);
  PetscCall(PetscPopErrorHandler());
  TCHECK(comm, ierr == PETSC_ERR_ARG_UNKNOWN_TYPE, "an unknown field gave %d", (int)ierr);
  PetscCall(SolverEnd(&db, &s));
  PetscFunctionReturn(0);
}

/* ---------------------------------------------------------------- the coupled tank: wall loads, liquid mass */

static PetscErrorCode TestTank(MPI_Comm comm)
{
  FSSolver         s;
  PetscOptions     db;
  const PetscReal *L, *m;
  const char      *names[4];
  PetscReal        mass, sum = 0;
  PetscInt         nw, n;

  PetscFunctionBegin;
  PetscCall(SolverFrom("-fs_case tank -fs_tank_length 0.7 -fs_tank_height 0.06 -fs_fill 0.5 -fs_dx 0.01 -fs_structure "
                       "msd -fs_beam_tank_mass 5 -fs_tank_width 0.2 -fs_output 0 -fs_progress 0",
                       &db, &s));
  PetscCall(FSSolverStep(s));
  PetscCall(FSSolverGetWallLoads(s, &nw, names, &L));
  TCHECK(comm, nw == 1 && !strcmp(names[0], "tank"), "%" PetscInt_FMT " walls, the first %s", nw, nw ? names[0] : "");
  TCHECK(comm, L[1] < 0 && PetscAbsReal(L[0]) < 1e-6 * PetscAbsReal(L[1]),
         "the liquid's load on the tank (%g, %g): expected down", (double)L[0], (double)L[1]);
  PetscCall(FSSolverGetField(s, "mass", &n, NULL, &m));
  for (PetscInt k = 0; k < n; k++) sum += m[k];
  PetscCall(FSSolverRestoreField(s, "mass", &n, NULL, &m));
  PetscCallMPI(MPI_Allreduce(MPI_IN_PLACE, &sum, 1, MPIU_REAL, MPI_SUM, comm));
  PetscCall(FSSolverGetLiquidMass(s, &mass));
  TCHECK(comm, PetscAbsReal(mass - 0.2 * sum) <= 1e-12 * mass && mass > 0, "liquid mass %g, the particles' %g x 0.2",
         (double)mass, (double)sum);
  PetscCall(SolverEnd(&db, &s));
  PetscFunctionReturn(0);
}

int main(int argc, char **argv)
{
  MPI_Comm    comm;
  PetscMPIInt size;

  PetscCall(PetscInitialize(&argc, &argv, NULL, "Unit test of flexslosh's C API for drivers"));
  comm = PETSC_COMM_WORLD;
  PetscCallMPI(MPI_Comm_size(comm, &size));
  PetscCall(TestCallbacks(comm));
  PetscCall(TestFields(comm));
  PetscCall(TestTank(comm));
  PetscCall(PetscPrintf(comm, "test_driver: OK (%d ranks)\n", (int)size));
  PetscCall(PetscFinalize());
  return 0;
}
