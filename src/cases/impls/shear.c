/*
   Case "shear": periodic shear flow u = U sin(2 pi y/L) e_x in the periodic box [0, L]^dim, an exact
   solution of the Navier-Stokes equations with uniform pressure; the kinetic energy decays as
   exp(-8 pi^2 nu t / L^2) (column kinetic_energy_exact). Works in 2-D and 3-D.
   Options: -fs_shear_U (1), -fs_shear_L (1), -fs_shear_Re (100). Defaults: dx = L/32, rho0 = 1,
   c0 = 10 U, final time L/U.
*/
#include <flexslosh.h>
#include "lattice.h"

typedef struct {
  PetscReal U, L, Re, ke0;
} Shear;

static PetscErrorCode SetFromOptions(FSSolver s, PetscOptionItems *PetscOptionsObject)
{
  Shear    *sh;
  PetscReal g[3] = {0, 0, 0};

  PetscFunctionBegin;
  PetscCall(FSSolverGetCaseData(s, &sh));
  PetscOptionsHeadBegin(PetscOptionsObject, "Case shear");
  PetscCall(FSOptionsReal(PetscOptionsObject, "-fs_shear_U", "Velocity amplitude U", "", &sh->U, NULL, 0,
                          PETSC_INFINITY, FS_RANGE_OPEN_LOWER));
  PetscCall(FSOptionsReal(PetscOptionsObject, "-fs_shear_L", "Box side L", "", &sh->L, NULL, 0, PETSC_INFINITY,
                          FS_RANGE_OPEN_LOWER));
  PetscCall(FSOptionsReal(PetscOptionsObject, "-fs_shear_Re", "Reynolds number U L / nu", "", &sh->Re, NULL, 0,
                          PETSC_INFINITY, FS_RANGE_OPEN_LOWER));
  PetscOptionsHeadEnd();
  PetscCheck(sh->U > 0 && sh->L > 0 && sh->Re > 0, PETSC_COMM_WORLD, PETSC_ERR_ARG_OUTOFRANGE,
             "-fs_shear_U %g, -fs_shear_L %g, -fs_shear_Re %g must all be positive", (double)sh->U, (double)sh->L,
             (double)sh->Re);
  PetscCall(FSSolverSetDefaultPhysics(s, 1.0, 10.0 * sh->U, sh->U * sh->L / sh->Re, g));
  PetscCall(FSSolverSetDefaultSpacing(s, sh->L / 32));
  PetscCall(FSSolverSetDefaultFinalTime(s, sh->L / sh->U));
  PetscFunctionReturn(0);
}

static PetscErrorCode SetUp(FSSolver s)
{
  Shear    *sh;
  PetscReal lo[3] = {0, 0, 0}, hi[3], *x, *u, *rho, *m, vol = 1, ke = 0, dx, rho0;
  PetscBool per[3] = {PETSC_TRUE, PETSC_TRUE, PETSC_TRUE};
  PetscInt  n, dim;

  PetscFunctionBegin;
  PetscCall(FSSolverGetCaseData(s, &sh));
  PetscCall(FSSolverGetDimension(s, &dim));
  PetscCall(FSSolverGetParameters(s, &dx, NULL, &rho0, NULL, NULL));
  for (PetscInt d = 0; d < 3; d++) hi[d] = sh->L;
  PetscCall(FSSolverSetDomain(s, lo, hi, per));
  PetscCall(FSLatticeCreate(s, lo, hi, &n, &x));
  PetscCall(PetscCalloc3(n * dim + 1, &u, n + 1, &rho, n + 1, &m));
  for (PetscInt d = 0; d < dim; d++) vol *= dx;
  for (PetscInt p = 0; p < n; p++) {
    u[p * dim] = sh->U * PetscSinReal(2 * PETSC_PI * x[p * dim + 1] / sh->L);
    rho[p]     = rho0;
    m[p]       = rho[p] * vol;
    ke += 0.5 * m[p] * u[p * dim] * u[p * dim];
  }
  PetscCallMPI(MPI_Allreduce(&ke, &sh->ke0, 1, MPIU_REAL, MPI_SUM, PetscObjectComm((PetscObject)s)));
  PetscCall(FSSolverAddParticles(s, n, x, u, rho, m));
  PetscCall(PetscFree(x));
  PetscCall(PetscFree3(u, rho, m));
  PetscFunctionReturn(0);
}

static PetscErrorCode Analytic(FSSolver s, PetscReal t, PetscReal *value)
{
  Shear    *sh;
  PetscReal nu;

  PetscFunctionBegin;
  PetscCall(FSSolverGetCaseData(s, &sh));
  PetscCall(FSSolverGetParameters(s, NULL, NULL, NULL, NULL, &nu));
  *value = sh->ke0 * PetscExpReal(-8 * PETSC_PI * PETSC_PI * nu * t / (sh->L * sh->L));
  PetscFunctionReturn(0);
}

PETSC_EXTERN PetscErrorCode FSCaseCreate_Shear(FSSolver s, FSCaseOps *ops)
{
  Shear *sh;

  PetscFunctionBegin;
  PetscCall(PetscNew(&sh));
  sh->U  = 1;
  sh->L  = 1;
  sh->Re = 100;
  PetscCall(FSSolverSetCaseData(s, sh));
  ops->setfromoptions  = SetFromOptions;
  ops->setup           = SetUp;
  ops->columns         = Analytic;
  ops->ncolumns        = 1;
  ops->column_names[0] = "kinetic_energy_exact";
  PetscFunctionReturn(0);
}
