/*
   Case "taylor_green": Taylor-Green vortices in the periodic box [0, L]^2 (extruded over a periodic
   depth in 3-D, where they stay an exact solution):
     u = U sin(2 pi x/L) cos(2 pi y/L),  v = -U cos(2 pi x/L) sin(2 pi y/L),
     p = rho0 U^2/4 (cos(4 pi x/L) + cos(4 pi y/L)),  nu = U L / Re.
   The kinetic energy decays as exp(-16 pi^2 nu t / L^2); the time series has it as kinetic_energy_exact.
   Options: -fs_tg_U (1), -fs_tg_L (1), -fs_tg_Re (100), -fs_tg_depth (L, 3-D only).
   Defaults: dx = L/50, rho0 = 1, c0 = 10 U, final time L/U.
*/
#include <flexslosh.h>
#include "lattice.h"

typedef struct {
  PetscReal U, L, Re, depth, ke0;
} TaylorGreen;

static PetscErrorCode SetFromOptions(FSSolver s, PetscOptionItems *PetscOptionsObject)
{
  TaylorGreen *tg;
  PetscReal    g[3] = {0, 0, 0};
  PetscInt     dim;

  PetscFunctionBegin;
  PetscCall(FSSolverGetCaseData(s, &tg));
  PetscCall(FSSolverGetDimension(s, &dim));
  PetscOptionsHeadBegin(PetscOptionsObject, "Case taylor_green");
  PetscCall(FSOptionsReal(PetscOptionsObject, "-fs_tg_U", "Velocity amplitude U", "", &tg->U, NULL, 0, PETSC_INFINITY,
                          FS_RANGE_OPEN_LOWER));
  PetscCall(FSOptionsReal(PetscOptionsObject, "-fs_tg_L", "Box side L", "", &tg->L, NULL, 0, PETSC_INFINITY,
                          FS_RANGE_OPEN_LOWER));
  PetscCall(FSOptionsReal(PetscOptionsObject, "-fs_tg_Re", "Reynolds number U L / nu", "", &tg->Re, NULL, 0,
                          PETSC_INFINITY, FS_RANGE_OPEN_LOWER));
  tg->depth = tg->L;
  if (dim == 3)
    PetscCall(FSOptionsReal(PetscOptionsObject, "-fs_tg_depth", "Periodic depth of the extruded box (3-D)", "",
                            &tg->depth, NULL, 0, PETSC_INFINITY, FS_RANGE_OPEN_LOWER));
  PetscOptionsHeadEnd();
  PetscCheck(tg->U > 0 && tg->L > 0 && tg->Re > 0 && tg->depth > 0, PETSC_COMM_WORLD, PETSC_ERR_ARG_OUTOFRANGE,
             "-fs_tg_U %g, -fs_tg_L %g, -fs_tg_Re %g, -fs_tg_depth %g must all be positive", (double)tg->U,
             (double)tg->L, (double)tg->Re, (double)tg->depth);
  PetscCall(FSSolverSetDefaultPhysics(s, 1.0, 10.0 * tg->U, tg->U * tg->L / tg->Re, g));
  PetscCall(FSSolverSetDefaultSpacing(s, tg->L / 50));
  PetscCall(FSSolverSetDefaultFinalTime(s, tg->L / tg->U));
  PetscFunctionReturn(0);
}

static PetscErrorCode SetUp(FSSolver s)
{
  TaylorGreen *tg;
  PetscReal    lo[3] = {0, 0, 0}, hi[3], *x, *u, *rho, *m, vol = 1, ke = 0, k, dx, rho0, c0;
  PetscBool    per[3] = {PETSC_TRUE, PETSC_TRUE, PETSC_TRUE};
  PetscInt     n, dim;

  PetscFunctionBegin;
  PetscCall(FSSolverGetCaseData(s, &tg));
  PetscCall(FSSolverGetDimension(s, &dim));
  PetscCall(FSSolverGetParameters(s, &dx, NULL, &rho0, &c0, NULL));
  hi[0] = tg->L;
  hi[1] = tg->L;
  hi[2] = tg->depth;
  k     = 2 * PETSC_PI / tg->L;
  PetscCall(FSSolverSetDomain(s, lo, hi, per));
  PetscCall(FSLatticeCreate(s, lo, hi, &n, &x));
  PetscCall(PetscMalloc3(n * dim + 1, &u, n + 1, &rho, n + 1, &m));
  for (PetscInt d = 0; d < dim; d++) vol *= dx;
  for (PetscInt p = 0; p < n; p++) {
    const PetscReal X = x[p * dim], Y = x[p * dim + 1];
    const PetscReal pr = rho0 * tg->U * tg->U / 4 * (PetscCosReal(2 * k * X) + PetscCosReal(2 * k * Y));
    u[p * dim]         = tg->U * PetscSinReal(k * X) * PetscCosReal(k * Y);
    u[p * dim + 1]     = -tg->U * PetscCosReal(k * X) * PetscSinReal(k * Y);
    if (dim == 3) u[p * dim + 2] = 0;
    rho[p] = rho0 + pr / (c0 * c0);
    m[p]   = rho[p] * vol;
    ke += 0.5 * m[p] * (u[p * dim] * u[p * dim] + u[p * dim + 1] * u[p * dim + 1]);
  }
  PetscCallMPI(MPI_Allreduce(&ke, &tg->ke0, 1, MPIU_REAL, MPI_SUM, PetscObjectComm((PetscObject)s)));
  PetscCall(FSSolverAddParticles(s, n, x, u, rho, m));
  PetscCall(PetscFree(x));
  PetscCall(PetscFree3(u, rho, m));
  PetscFunctionReturn(0);
}

static PetscErrorCode Analytic(FSSolver s, PetscReal t, PetscReal *value)
{
  TaylorGreen *tg;
  PetscReal    nu;

  PetscFunctionBegin;
  PetscCall(FSSolverGetCaseData(s, &tg));
  PetscCall(FSSolverGetParameters(s, NULL, NULL, NULL, NULL, &nu));
  *value = tg->ke0 * PetscExpReal(-16 * PETSC_PI * PETSC_PI * nu * t / (tg->L * tg->L));
  PetscFunctionReturn(0);
}

PETSC_EXTERN PetscErrorCode FSCaseCreate_TaylorGreen(FSSolver s, FSCaseOps *ops)
{
  TaylorGreen *tg;

  PetscFunctionBegin;
  PetscCall(PetscNew(&tg));
  tg->U  = 1;
  tg->L  = 1;
  tg->Re = 100;
  PetscCall(FSSolverSetCaseData(s, tg));
  ops->setfromoptions  = SetFromOptions;
  ops->setup           = SetUp;
  ops->columns         = Analytic;
  ops->ncolumns        = 1;
  ops->column_names[0] = "kinetic_energy_exact";
  PetscFunctionReturn(0);
}
