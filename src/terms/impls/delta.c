/*
   Term "delta": the delta-LES diffusive term of the continuity equation (seed Eqs. 4-9),
     D rho_i/Dt += h c0 sum_j delta_ij D_ij . grad_i W_ij V_j,
     D_ij = 2 [(rho_j - rho_i) - 1/2 (<grad rho>^L_i + <grad rho>^L_j) . (x_j - x_i)] (x_j - x_i) / |x_j - x_i|^2,
     delta_ij = 2 delta_i delta_j / (delta_i + delta_j),  delta_i = (C_delta L_LES)^2 ||D||_i / (c0 h),  L_LES = 2h.
   Its dissipation power (seed Eq. 38, with the sign that closes the budget of Eq. 40) is
     P_delta = sum_i V_i p_i / rho_i (D rho_i/Dt)_delta.
   Options: -fs_delta_c (C_delta, 1.5), -fs_delta_constant (a fixed delta instead of the LES one: classic delta-SPH),
   -fs_delta_min (a floor under the LES delta_i: delta_LES vanishes in a liquid at rest, where it then leaves
   odd-even density modes undamped), -fs_delta_hydrostatic (the density difference corrected by the hydrostatic
   one, rho0 g . (x_j - x_i) / c0^2, instead of the renormalized gradients; Antuono et al. 2012, Fourtakas
   et al. 2019), -fs_delta_split (advance the term after each step by RKL2 super-time-stepping instead of in the
   integrator's stages, so that its diffusivity does not limit the step: src/solver/split.c).
*/
#include <flexslosh.h>

typedef struct {
  PetscReal  C, fixed, dmin, dmax;
  PetscBool  hydrostatic;
  PetscReal *delta;
  PetscInt   cap;
} Delta;

/* The pair sum for a compile-time dimension and correction (hydro: the hydrostatic one), so that each
   variant is a branch-free loop (see FS_ALWAYS_INLINE). */
FS_ALWAYS_INLINE void InteractDim(FSTerm t, const FSParticles *P, const FSNeighbourhood *nb, FSRate *rate,
                                  const PetscInt dim, const PetscBool hydro)
{
  Delta           *ctx = (Delta *)t->data;
  const PetscInt   S = P->stride, i = nb->i;
  const PetscReal *ri = &P->rec[i * S], rhoi = ri[2 * dim], *gi = &P->aux[i * (dim + 1)], *delta = ctx->delta,
                  *V  = P->vol;
  const PetscReal di  = delta[i];
  PetscReal       sum = 0, gh[3] = {0, 0, 0};
  if (hydro)
    for (PetscInt d = 0; d < dim; d++) gh[d] = P->rho0 * P->gravity[d] / (P->c0 * P->c0);
  for (PetscInt k = 0; k < nb->n; k++) {
    const PetscInt   j  = nb->j[k];
    const PetscReal *rj = &P->rec[j * S], *gj = &P->aux[j * (dim + 1)], *dx = &nb->dx[k * dim],
                    *g = &nb->gradW[k * dim];
    const PetscReal dj = delta[j], dsum = di + dj;
    PetscReal       corr = 0, proj = 0, Dij;
    if (dsum <= 0) continue;
    for (PetscInt d = 0; d < dim; d++) {
      corr += (hydro ? 2.0 * gh[d] : gi[d] + gj[d]) * dx[d];
      proj += dx[d] * g[d];
    }
    Dij = 2.0 * ((rj[2 * dim] - rhoi) - 0.5 * corr) * nb->rinv2[k];
    sum += (2.0 * di * dj / dsum) * Dij * proj * nb->Vj[k];
  }
  sum *= P->h * P->c0;
  rate->drho += sum;
  t->power += V[i] * P->pressure[i] / rhoi * sum;
}

static void Interact(FSTerm t, const FSParticles *P, const FSNeighbourhood *nb, FSRate *rate)
{
  const PetscBool hydro = ((Delta *)t->data)->hydrostatic;
  if (P->dim == 2) {
    if (hydro) InteractDim(t, P, nb, rate, 2, PETSC_TRUE);
    else InteractDim(t, P, nb, rate, 2, PETSC_FALSE);
  } else {
    if (hydro) InteractDim(t, P, nb, rate, 3, PETSC_TRUE);
    else InteractDim(t, P, nb, rate, 3, PETSC_FALSE);
  }
}

static PetscErrorCode Prepare(FSTerm t, const FSParticles *P)
{
  Delta          *ctx = (Delta *)t->data;
  const PetscInt  n = P->nowned + P->nghost, dim = P->dim;
  const PetscReal L = 2.0 * P->h, coef = ctx->C * ctx->C * L * L / (P->c0 * P->h);

  PetscFunctionBegin;
  if (n > ctx->cap) {
    PetscCall(PetscFree(ctx->delta));
    ctx->cap = PetscMax(n, (PetscInt)(1.25 * ctx->cap));
    PetscCall(PetscMalloc1(ctx->cap, &ctx->delta));
  }
  if (ctx->fixed > 0)
    for (PetscInt k = 0; k < n; k++) ctx->delta[k] = ctx->fixed;
  else
    for (PetscInt k = 0; k < n; k++) ctx->delta[k] = PetscMax(coef * P->aux[k * (dim + 1) + dim], ctx->dmin);
  if (ctx->dmax > 0)
    for (PetscInt k = 0; k < n; k++) ctx->delta[k] = PetscMin(ctx->delta[k], ctx->dmax);
  /* the term diffuses the density with diffusivity delta_i h c0: the time step must resolve it like a
     viscosity (in a slam the strain rate, hence delta-LES, jumps by orders of magnitude) */
  {
    PetscReal dmax = 0;
    for (PetscInt k = 0; k < P->nowned; k++) dmax = PetscMax(dmax, ctx->delta[k]);
    t->max_viscosity = dmax * P->h * P->c0;
  }
  PetscFunctionReturn(0);
}

static PetscErrorCode SetFromOptions(FSTerm t, PetscOptionItems *PetscOptionsObject)
{
  Delta *ctx = (Delta *)t->data;

  PetscFunctionBegin;
  PetscOptionsHeadBegin(PetscOptionsObject, "Term delta: delta-LES diffusive term in the continuity equation");
  PetscCall(FSOptionsReal(PetscOptionsObject, "-fs_delta_c", "C_delta of the delta-LES model (seed Eq. 8)", "", &ctx->C,
                          NULL, 0, PETSC_INFINITY, FS_RANGE_CLOSED));
  PetscCall(FSOptionsReal(PetscOptionsObject, "-fs_delta_constant",
                          "A constant delta (classic delta-SPH, e.g. 0.1) instead of the LES one; 0 = LES", "",
                          &ctx->fixed, NULL, 0, PETSC_INFINITY, FS_RANGE_CLOSED));
  PetscCall(FSOptionsReal(PetscOptionsObject, "-fs_delta_min",
                          "Floor under the delta-LES delta_i (damps the density modes of a liquid at rest); 0 = none",
                          "", &ctx->dmin, NULL, 0, PETSC_INFINITY, FS_RANGE_CLOSED));
  PetscCall(FSOptionsReal(PetscOptionsObject, "-fs_delta_max",
                          "Cap on the delta-LES delta_i (its diffusivity delta_i h c0 bounds the time step); 0 = none",
                          "", &ctx->dmax, NULL, 0, PETSC_INFINITY, FS_RANGE_CLOSED));
  PetscCall(FSOptionsReal(PetscOptionsObject, "-fs_delta_cfl",
                          "Coefficient of the density diffusion's time-step limit dt <= c h^2/(delta_max h c0) "
                          "(0: 0.1875 with RK4, -fs_cfl_viscous's with other integrators)",
                          "FSSolverComputeStableDt", &t->dt_coefficient, NULL, 0, PETSC_INFINITY, FS_RANGE_CLOSED));
  PetscCall(PetscOptionsBool("-fs_delta_hydrostatic",
                             "Correct the density difference by the hydrostatic one rho0 g.(x_j - x_i)/c0^2 instead of "
                             "the renormalized gradients",
                             "", ctx->hydrostatic, &ctx->hydrostatic, NULL));
  PetscCall(PetscOptionsBool("-fs_delta_split",
                             "Advance the density diffusion after each step by RKL2 super-time-stepping, not in the "
                             "integrator's stages: its diffusivity then does not limit the time step",
                             "FSSolverSplitStep", t->split, &t->split, NULL));
  PetscOptionsHeadEnd();
  PetscCheck(ctx->dmax == 0 || ctx->dmax >= ctx->dmin, PETSC_COMM_WORLD, PETSC_ERR_ARG_OUTOFRANGE,
             "-fs_delta_max %g is below -fs_delta_min %g: expected a cap above the floor", (double)ctx->dmax,
             (double)ctx->dmin);
  PetscFunctionReturn(0);
}

static PetscErrorCode View(FSTerm t, PetscViewer v)
{
  Delta *ctx = (Delta *)t->data;

  PetscFunctionBegin;
  if (ctx->fixed > 0) PetscCall(PetscViewerASCIIPrintf(v, "delta: constant delta = %g\n", (double)ctx->fixed));
  else
    PetscCall(PetscViewerASCIIPrintf(v, "delta: delta-LES, C_delta = %g, L_LES = 2h, delta_i >= %g\n", (double)ctx->C,
                                     (double)ctx->dmin));
  PetscCall(
      PetscViewerASCIIPrintf(v, "delta: density differences corrected by the %s\n",
                             ctx->hydrostatic ? "hydrostatic density difference" : "renormalized density gradients"));
  if (t->split)
    PetscCall(PetscViewerASCIIPrintf(v, "delta: advanced after each step by RKL2 super-time-stepping (split)\n"));
  PetscFunctionReturn(0);
}

static PetscErrorCode Destroy(FSTerm t)
{
  Delta *ctx = (Delta *)t->data;

  PetscFunctionBegin;
  PetscCall(PetscFree(ctx->delta));
  PetscCall(PetscFree(t->data));
  PetscFunctionReturn(0);
}

PETSC_EXTERN PetscErrorCode FSTermCreate_Delta(FSTerm t)
{
  Delta *ctx;

  PetscFunctionBegin;
  PetscCall(PetscNew(&ctx));
  ctx->C       = 1.5;
  t->data      = ctx;
  t->needs     = FS_NEED_DENSITY_GRADIENT | FS_NEED_STRAIN_RATE;
  t->has_power = PETSC_TRUE;
  /* RK4's stability for this operator alone reaches about 0.2 h^2/kappa on any particle arrangement (a Gershgorin
     bound; 0.41 on a lattice): 0.1875 keeps a margin (docs/performance.md, "The seed case's time step") */
  t->dt_coefficient_rk4 = 0.1875;
  t->ops.interact       = Interact;
  t->ops.prepare        = Prepare;
  t->ops.setfromoptions = SetFromOptions;
  t->ops.view           = View;
  t->ops.destroy        = Destroy;
  PetscFunctionReturn(0);
}
