/*
   Case "standing_wave": a small standing wave (linear sloshing) in a rectangular tank with free-slip
   walls, the validation of docs/validation.md. Non-dimensional, as the delta-SPH reference: g = 1,
   rho0 = 1, lengths in units of the depth h.
     -fs_sw_length L (2), -fs_sw_depth h (1): the tank [0, L] x [0, 1.5 h] holds liquid up to y = h;
     -fs_sw_mode n (1): the mode cos(k x), k = n pi / L (n = 1: the first, sloshing mode; the
                  reference's omega = 1.76915 sqrt(g/h) is n = 2 in L = 2h, i.e. k = pi/h);
     -fs_sw_amplitude A/h (0.05, the reference's 2A/h = 0.1): the amplitude A of the surface elevation;
     -fs_sw_reynolds Re (250): nu = h sqrt(g h) / Re, unless -fs_nu is given.
   Linear theory: omega^2 = g k tanh(k h). The surface eta = A cos(k x) sin(omega t) starts flat, with
   the velocity potential phi = (g A / omega) cos(k x) cosh(k y) / cosh(k h) cos(omega t) at its
   largest, so the particles start with
     u = -A omega sin(k x) cosh(k y) / sinh(k h),   v = A omega cos(k x) sinh(k y) / sinh(k h)
   (the floor at y = 0) and the hydrostatic density. The kinetic energy (per unit width)
     E_k(t) = (rho0 g A^2 L / 8) (1 + cos 2 omega t) exp(-4 nu k^2 t)
   oscillates at 2 omega and decays, with free-slip walls, at 4 nu k^2 (the amplitude at 2 nu k^2,
   whatever the depth: the dissipation of the potential flow is 8 nu k^2 times its kinetic energy).
   This is the leading order in nu: the exact linear viscous mode (Lamb's relation at finite depth with
   a free-slip floor, tests/python/test_standing_wave.py) decays slower by a relative O((nu k^2/omega)^1/2),
   at 0.941 x 4 nu k^2 for the defaults.
   With eps = 2A/h this is the reference's (eps^2 g L h^2 / 32) (1 + cos 2 omega t) exp(-4 nu k^2 t).
   The time series has this E_k(t) as column kinetic_energy_linear, scaled to the particles' own initial
   kinetic energy (which differs from rho0 g A^2 L / 4 by O(dx^2) and the hydrostatic rho/rho0 - 1).
   Column mode_amplitude is the projection of the particles' velocity on the mode's initial field u0,
   a(t) = sum_p m_p u_p . u0(x_p) / sum_p m_p u0(x_p) . u0(x_p) (1 at the start), and mode_amplitude_linear
   linear theory's cos(omega t) exp(-2 nu k^2 t). Unlike the kinetic energy, a(t) does not hold the energy
   of the particles' own small-scale motion (settling at the walls, noise), which the mode does not project
   on: its decay is the wave's (docs/walls.md, "The standing wave in 3-D").
   The floor is a wall of its own, "floor", the sides and the lid wall "tank": -fs_walls_noslip floor
   makes the floor no-slip with free-slip sides, which the mode cos(k x) still satisfies exactly, so that
   the exact linear viscous mode with a no-slip floor (tests/python/test_standing_wave.py) is the
   reference for the no-slip wall term (no contact line moves along a no-slip wall).
   In 3-D (-fs_dim 3) the tank is -fs_sw_width Lz wide along z (default L) and the mode
   cos(k_x x) cos(k_z z), k_x = n pi / L, k_z = m pi / Lz with m = -fs_sw_mode_z (0: the 2-D wave across
   the width), k = sqrt(k_x^2 + k_z^2) in the dispersion relation and the decay; the velocity is the
   gradient of phi = (g A / omega) cos(k_x x) cos(k_z z) cosh(k y) / cosh(k h) cos(omega t).
   With gravity pointing up (-fs_gravity 0,g) the liquid hangs from the floor in tension (the hydrostatic start
   p = rho0 g (y - h)) and its surface is Rayleigh-Taylor unstable: the mode grows, omega above is the growth rate
   n = sqrt(g k tanh(k h)), and the linear columns are cosh(n t) and cosh^2(n t) in place of cos (the layer the seed's
   tank holds while it falls faster than g: docs/seed-experiment.md, tests/python/test_hanging_layer.py).
   Defaults: dx = h/50, c0 = 10 sqrt(g h) (the waves' speeds are below 0.1 sqrt(g h)), the wall cases'
   terms (delta-LES-SPH with boundary integrals) and CFL 1.5, final time 20 sqrt(h/g).
*/
#include <flexslosh.h>
#include "liquid.h"

typedef struct {
  PetscReal L, h, A, Re, k, kx, kz, omega, ke0, Lz;
  PetscInt  mode, modez, dim;
  PetscBool growing; /* gravity up: omega is the Rayleigh-Taylor growth rate */
} StandingWave;

static PetscErrorCode SetFromOptions(FSSolver s, PetscOptionItems *PetscOptionsObject)
{
  StandingWave *sw;
  PetscReal     g[3] = {0, -1, 0};
  PetscInt      dim;

  PetscFunctionBegin;
  PetscCall(FSSolverGetCaseData(s, &sw));
  PetscCall(FSSolverGetDimension(s, &dim));
  PetscOptionsHeadBegin(PetscOptionsObject, "Case standing_wave");
  PetscCall(FSOptionsReal(PetscOptionsObject, "-fs_sw_length", "Length L of the tank", "", &sw->L, NULL, 0,
                          PETSC_INFINITY, FS_RANGE_OPEN_LOWER));
  PetscCall(FSOptionsReal(PetscOptionsObject, "-fs_sw_depth", "Depth h of the liquid", "", &sw->h, NULL, 0,
                          PETSC_INFINITY, FS_RANGE_OPEN_LOWER));
  PetscCall(FSOptionsInt(PetscOptionsObject, "-fs_sw_mode", "Mode n of the wave: k = n pi / L", "", &sw->mode, NULL, 1,
                         PETSC_MAX_INT));
  PetscCall(FSOptionsReal(PetscOptionsObject, "-fs_sw_amplitude", "Amplitude A/h of the surface elevation", "", &sw->A,
                          NULL, 0, 0.25, FS_RANGE_OPEN_LOWER));
  PetscCall(FSOptionsReal(PetscOptionsObject, "-fs_sw_reynolds",
                          "Reynolds number h sqrt(g h) / nu (ignored when -fs_nu is given)", "", &sw->Re, NULL, 0,
                          PETSC_INFINITY, FS_RANGE_OPEN_LOWER));
  if (sw->Lz <= 0) sw->Lz = sw->L;
  PetscCall(FSOptionsReal(PetscOptionsObject, "-fs_sw_width", "Width Lz of the tank along z (3-D; default L)", "",
                          &sw->Lz, NULL, 0, PETSC_INFINITY, FS_RANGE_OPEN_LOWER));
  PetscCall(FSOptionsInt(PetscOptionsObject, "-fs_sw_mode_z",
                         "Mode m of the wave across the width (3-D): k_z = m pi / Lz", "", &sw->modez, NULL, 0,
                         PETSC_MAX_INT));
  PetscOptionsHeadEnd();
  sw->dim = dim;
  PetscCheck(sw->Lz > 0, PETSC_COMM_WORLD, PETSC_ERR_ARG_OUTOFRANGE, "-fs_sw_width %g must be positive",
             (double)sw->Lz);
  PetscCheck(sw->modez >= 0 && (dim == 3 || sw->modez == 0), PETSC_COMM_WORLD, PETSC_ERR_ARG_OUTOFRANGE,
             "-fs_sw_mode_z %" PetscInt_FMT " must be 0 or more, and 0 in 2-D", sw->modez);
  PetscCall(FSSolverSetDefaultPhysics(s, 1.0, 10 * PetscSqrtReal(sw->h), sw->h * PetscSqrtReal(sw->h) / sw->Re, g));
  PetscCall(FSSolverSetDefaultTerms(s, FS_WALL_CASE_TERMS));
  PetscCall(FSSolverSetDefaultSpacing(s, sw->h / 50));
  PetscCall(FSSolverSetDefaultCFL(s, 1.5)); /* RK4 only (docs/decisions.md) */
  PetscCall(FSSolverSetDefaultFinalTime(s, 20 * PetscSqrtReal(sw->h)));
  PetscFunctionReturn(0);
}

/* the velocity of the standing wave when its surface is flat (the header comment), 2-D or 3-D */
static PetscErrorCode Velocity(const PetscReal x[], PetscReal u[], void *ctx)
{
  StandingWave   *sw = (StandingWave *)ctx;
  const PetscReal a  = sw->A * sw->h * sw->omega / PetscSinhReal(sw->k * sw->h);
  const PetscReal cz = sw->dim == 3 ? PetscCosReal(sw->kz * x[2]) : 1;

  PetscFunctionBegin;
  u[0] = -a * (sw->kx / sw->k) * PetscSinReal(sw->kx * x[0]) * cz * PetscCoshReal(sw->k * x[1]);
  u[1] = a * PetscCosReal(sw->kx * x[0]) * cz * PetscSinhReal(sw->k * x[1]);
  if (sw->dim == 3)
    u[2] = -a * (sw->kz / sw->k) * PetscCosReal(sw->kx * x[0]) * PetscSinReal(sw->kz * x[2]) *
           PetscCoshReal(sw->k * x[1]);
  PetscFunctionReturn(0);
}

static PetscErrorCode SetUp(FSSolver s)
{
  StandingWave *sw;
  MPI_Comm      comm = PetscObjectComm((PetscObject)s);
  FSWalls       w;
  PetscReal     ke = 0, *u, *m, g[3], rho0, nu;
  PetscInt      n;
  DM            swarm;

  PetscFunctionBegin;
  PetscCall(FSSolverGetCaseData(s, &sw));
  PetscCall(FSSolverGetGravity(s, g));
  PetscCall(FSSolverGetParameters(s, NULL, NULL, &rho0, NULL, &nu));
  PetscCheck(g[0] == 0 && g[1] != 0 && (sw->dim == 2 || g[2] == 0), comm, PETSC_ERR_ARG_OUTOFRANGE,
             "Case standing_wave needs gravity along y (-fs_gravity 0,-g: down; 0,g: up, the Rayleigh-Taylor layer), "
             "not %g,%g,%g",
             (double)g[0], (double)g[1], (double)g[2]);
  sw->growing = (PetscBool)(g[1] > 0);
  sw->kx      = sw->mode * PETSC_PI / sw->L;
  sw->kz      = sw->dim == 3 ? sw->modez * PETSC_PI / sw->Lz : 0;
  sw->k       = PetscSqrtReal(sw->kx * sw->kx + sw->kz * sw->kz);
  sw->omega   = PetscSqrtReal(PetscAbsReal(g[1]) * sw->k * PetscTanhReal(sw->k * sw->h));
  PetscCall(FSWallsCreate(&w));
  PetscCall(FSWallsRectangularTank(&w, comm, sw->L, 1.5 * sw->h));
  PetscCall(FSWallsSetEdgeWall(&w, comm, 0, 0, "floor"));
  PetscCall(FSWallsCheck(&w, comm));
  if (sw->dim == 3)
    PetscCall(FSCaseFillLiquidExtruded(s, &w, sw->Lz, 0, sw->L, 0, sw->h,
                                       "the liquid (-fs_sw_length x -fs_sw_depth x -fs_sw_width)", Velocity, sw));
  else
    PetscCall(FSCaseFillLiquidWithVelocity(s, &w, 0, sw->L, 0, sw->h, "the liquid (-fs_sw_length x -fs_sw_depth)",
                                           Velocity, sw));
  /* the particles' initial kinetic energy, the scale of kinetic_energy_linear */
  PetscCall(FSSolverGetSwarm(s, &swarm));
  PetscCall(DMSwarmGetLocalSize(swarm, &n));
  PetscCall(DMSwarmGetField(swarm, FS_FIELD_VELOCITY, NULL, NULL, (void **)&u));
  PetscCall(DMSwarmGetField(swarm, FS_FIELD_MASS, NULL, NULL, (void **)&m));
  for (PetscInt p = 0; p < n; p++) {
    PetscReal u2 = 0;
    for (PetscInt d = 0; d < sw->dim; d++) u2 += u[sw->dim * p + d] * u[sw->dim * p + d];
    ke += 0.5 * m[p] * u2;
  }
  PetscCall(DMSwarmRestoreField(swarm, FS_FIELD_MASS, NULL, NULL, (void **)&m));
  PetscCall(DMSwarmRestoreField(swarm, FS_FIELD_VELOCITY, NULL, NULL, (void **)&u));
  PetscCallMPI(MPI_Allreduce(&ke, &sw->ke0, 1, MPIU_REAL, MPI_SUM, comm));
  PetscCall(PetscInfo(s,
                      "Standing wave: k = %g, %s %g, period %g, kinetic energy decay rate 4 nu k^2 = %g, E_k(0) = "
                      "%g (linear theory %g)\n",
                      (double)sw->k, sw->growing ? "growth rate" : "omega =", (double)sw->omega,
                      (double)(2 * PETSC_PI / sw->omega), (double)(4 * nu * sw->k * sw->k), (double)sw->ke0,
                      (double)(rho0 * -g[1] * PetscSqr(sw->A * sw->h) * sw->L / 4)));
  PetscFunctionReturn(0);
}

/* the time series' columns: linear theory's kinetic energy, the mode's amplitude and its linear theory. The
   particles' fields are the swarm's: at the monitors they are the state's (src/solver/stepping.c). */
static PetscErrorCode Columns(FSSolver s, PetscReal t, PetscReal values[])
{
  StandingWave *sw;
  DM            swarm;
  PetscReal     nu, *x, *u, *m, loc[2] = {0, 0}, sum[2];
  PetscInt      n;

  PetscFunctionBegin;
  PetscCall(FSSolverGetCaseData(s, &sw));
  PetscCall(FSSolverGetParameters(s, NULL, NULL, NULL, NULL, &nu));
  PetscCall(FSSolverGetSwarm(s, &swarm));
  PetscCall(DMSwarmGetLocalSize(swarm, &n));
  PetscCall(DMSwarmGetField(swarm, FS_FIELD_POSITION, NULL, NULL, (void **)&x));
  PetscCall(DMSwarmGetField(swarm, FS_FIELD_VELOCITY, NULL, NULL, (void **)&u));
  PetscCall(DMSwarmGetField(swarm, FS_FIELD_MASS, NULL, NULL, (void **)&m));
  for (PetscInt p = 0; p < n; p++) {
    PetscReal u0[3] = {0, 0, 0};
    PetscCall(Velocity(&x[sw->dim * p], u0, sw));
    for (PetscInt d = 0; d < sw->dim; d++) {
      loc[0] += m[p] * u[sw->dim * p + d] * u0[d];
      loc[1] += m[p] * u0[d] * u0[d];
    }
  }
  PetscCall(DMSwarmRestoreField(swarm, FS_FIELD_MASS, NULL, NULL, (void **)&m));
  PetscCall(DMSwarmRestoreField(swarm, FS_FIELD_VELOCITY, NULL, NULL, (void **)&u));
  PetscCall(DMSwarmRestoreField(swarm, FS_FIELD_POSITION, NULL, NULL, (void **)&x));
  PetscCallMPI(MPI_Allreduce(loc, sum, 2, MPIU_REAL, MPI_SUM, PetscObjectComm((PetscObject)s)));
  if (sw->growing) { /* the Rayleigh-Taylor mode grows as cosh(omega t) */
    const PetscReal c = PetscCoshReal(sw->omega * t);
    values[0]         = sw->ke0 * c * c * PetscExpReal(-4 * nu * sw->k * sw->k * t);
    values[2]         = c * PetscExpReal(-2 * nu * sw->k * sw->k * t);
  } else {
    values[0] = sw->ke0 * 0.5 * (1 + PetscCosReal(2 * sw->omega * t)) * PetscExpReal(-4 * nu * sw->k * sw->k * t);
    values[2] = PetscCosReal(sw->omega * t) * PetscExpReal(-2 * nu * sw->k * sw->k * t);
  }
  values[1] = sum[1] > 0 ? sum[0] / sum[1] : 0;
  PetscFunctionReturn(0);
}

PETSC_EXTERN PetscErrorCode FSCaseCreate_StandingWave(FSSolver s, FSCaseOps *ops)
{
  StandingWave *sw;

  PetscFunctionBegin;
  PetscCall(PetscNew(&sw));
  sw->L    = 2;
  sw->h    = 1;
  sw->mode = 1;
  sw->A    = 0.05;
  sw->Re   = 250;
  PetscCall(FSSolverSetCaseData(s, sw));
  ops->setfromoptions  = SetFromOptions;
  ops->setup           = SetUp;
  ops->columns         = Columns;
  ops->ncolumns        = 3;
  ops->column_names[0] = "kinetic_energy_linear";
  ops->column_names[1] = "mode_amplitude";
  ops->column_names[2] = "mode_amplitude_linear";
  PetscFunctionReturn(0);
}
