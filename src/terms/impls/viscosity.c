/*
   Terms "viscosity" (laminar) and "les_viscosity" (delta-LES turbulent viscosity), seed Eqs. 4, 5, 11-13:
     D u_i/Dt += h c0 rho0/rho_i sum_j alpha_ij Pi_ij grad_i W_ij V_j,   Pi_ij = (u_j - u_i).(x_j - x_i) / |x_j -
   x_i|^2. viscosity:      alpha_ij = alpha = K nu / (c0 h), nu = -fs_nu (the liquid's kinematic viscosity)
   les_viscosity:  alpha_ij = 2 a_i a_j / (a_i + a_j),  a_i = K nu_i / (c0 h),  nu_i = (C_alpha L_LES)^2 ||D||_i, L_LES
   = 2h K = 2 (dim + 2) (8 in 2-D, 10 in 3-D), so that the sum approximates nu lap u. The seed's Eqs. 11-12 add alpha
   inside a_i as well as in alpha_ij; we count the laminar part once (Antuono et al. 2021) so that the laminar term
   alone gives the exact viscous decay. Dissipation power (seed Eq. 38): P_alpha = sum_i m_i u_i . (D u_i/Dt)_alpha.
   With walls the pair sum carries (1/gamma_i + 1/gamma_j)/2, the renormalization that keeps the term
   dissipative (its power is a sum of squares) where gamma varies; the laminar term takes gamma_v, gamma
   plus the share behind no-slip walls, which wall_viscosity fills (wall.c): gamma without them.
   Options: -fs_viscosity_K, -fs_les_c (C_alpha, the Smagorinsky constant, 0.12).
*/
#include <flexslosh.h>

typedef struct {
  PetscBool  les;
  PetscReal  K, C;
  PetscReal *a;
  PetscInt   cap;
} Viscosity;

/* The pair sums for a compile-time dimension, model (les) and presence of walls (gam: the pair factor
   (1/gamma_i + 1/gamma_j)/2), so that each of the eight variants is a branch-free loop (see FS_ALWAYS_INLINE). */
FS_ALWAYS_INLINE void InteractDim(FSTerm t, const FSParticles *P, const FSNeighbourhood *nb, FSRate *rate,
                                  const PetscInt dim, const PetscBool les, const PetscBool gam)
{
  Viscosity       *ctx = (Viscosity *)t->data;
  const PetscInt   S = P->stride, i = nb->i;
  const PetscReal *ri = &P->rec[i * S], rhoi = ri[2 * dim];
  const PetscReal *ig     = les || !P->invgammav ? P->invgamma : P->invgammav;
  PetscReal        acc[3] = {0, 0, 0}, f, pw = 0;
  if (les) {
    const PetscReal ai = ctx->a[i], *a = ctx->a;
    if (ai <= 0) { /* a_i = 0 makes every alpha_ij zero */
      return;
    }
    for (PetscInt k = 0; k < nb->n; k++) {
      const PetscInt   j  = nb->j[k];
      const PetscReal *du = &nb->du[k * dim], *dx = &nb->dx[k * dim], *g = &nb->gradW[k * dim];
      const PetscReal  aj = a[j];
      PetscReal        pi = 0;
      if (aj <= 0) continue;
      for (PetscInt d = 0; d < dim; d++) pi += du[d] * dx[d];
      pi *= 2.0 * ai * aj / (ai + aj) * nb->rinv2[k] * nb->Vj[k];
      if (gam) pi *= 0.5 * (ig[i] + ig[j]);
      for (PetscInt d = 0; d < dim; d++) acc[d] += pi * g[d];
    }
    f = P->h * P->c0 * P->rho0 / rhoi;
  } else {
    for (PetscInt k = 0; k < nb->n; k++) {
      const PetscInt   j  = nb->j[k];
      const PetscReal *du = &nb->du[k * dim], *dx = &nb->dx[k * dim], *g = &nb->gradW[k * dim];
      PetscReal        pi = 0;
      for (PetscInt d = 0; d < dim; d++) pi += du[d] * dx[d];
      pi *= nb->rinv2[k] * nb->Vj[k];
      if (gam) pi *= 0.5 * (ig[i] + ig[j]);
      for (PetscInt d = 0; d < dim; d++) acc[d] += pi * g[d];
    }
    f = ctx->K * P->nu * P->rho0 / rhoi;
  }
  for (PetscInt d = 0; d < dim; d++) {
    rate->du[d] += f * acc[d];
    pw += ri[dim + d] * f * acc[d];
  }
  t->power += ri[2 * dim + 1] * pw;
}

static void Interact(FSTerm t, const FSParticles *P, const FSNeighbourhood *nb, FSRate *rate)
{
  const PetscBool les = ((Viscosity *)t->data)->les, gam = P->invgamma ? PETSC_TRUE : PETSC_FALSE;
  if (P->dim == 2) {
    if (les) {
      if (gam) InteractDim(t, P, nb, rate, 2, PETSC_TRUE, PETSC_TRUE);
      else InteractDim(t, P, nb, rate, 2, PETSC_TRUE, PETSC_FALSE);
    } else {
      if (gam) InteractDim(t, P, nb, rate, 2, PETSC_FALSE, PETSC_TRUE);
      else InteractDim(t, P, nb, rate, 2, PETSC_FALSE, PETSC_FALSE);
    }
  } else {
    if (les) {
      if (gam) InteractDim(t, P, nb, rate, 3, PETSC_TRUE, PETSC_TRUE);
      else InteractDim(t, P, nb, rate, 3, PETSC_TRUE, PETSC_FALSE);
    } else {
      if (gam) InteractDim(t, P, nb, rate, 3, PETSC_FALSE, PETSC_TRUE);
      else InteractDim(t, P, nb, rate, 3, PETSC_FALSE, PETSC_FALSE);
    }
  }
}

static PetscErrorCode Prepare(FSTerm t, const FSParticles *P)
{
  Viscosity      *ctx = (Viscosity *)t->data;
  const PetscInt  n = P->nowned + P->nghost, dim = P->dim;
  const PetscReal L = 2.0 * P->h, nucoef = ctx->C * ctx->C * L * L, acoef = ctx->K / (P->c0 * P->h);
  PetscReal       numax = 0;

  PetscFunctionBegin;
  if (!ctx->les) {
    t->max_viscosity = P->nu;
    PetscFunctionReturn(0);
  }
  if (n > ctx->cap) {
    PetscCall(PetscFree(ctx->a));
    ctx->cap = PetscMax(n, (PetscInt)(1.25 * ctx->cap));
    PetscCall(PetscMalloc1(ctx->cap, &ctx->a));
  }
  for (PetscInt k = 0; k < n; k++) {
    PetscReal nut = nucoef * P->aux[k * (dim + 1) + dim];
    ctx->a[k]     = acoef * nut;
    if (k < P->nowned) numax = PetscMax(numax, nut);
  }
  t->max_viscosity = numax;
  PetscFunctionReturn(0);
}

static PetscErrorCode Field(FSTerm t, const char name[], const FSParticles *P, PetscReal *out, PetscBool *has)
{
  Viscosity *ctx = (Viscosity *)t->data;
  PetscBool  match;

  PetscFunctionBegin;
  PetscCall(PetscStrcmp(name, "turbulent_viscosity", &match));
  *has = (PetscBool)(match && ctx->les);
  if (!*has) PetscFunctionReturn(0);
  for (PetscInt k = 0; k < P->nowned; k++) out[k] = ctx->a[k] * P->c0 * P->h / ctx->K;
  PetscFunctionReturn(0);
}

static PetscErrorCode SetFromOptions(FSTerm t, PetscOptionItems *PetscOptionsObject)
{
  Viscosity *ctx = (Viscosity *)t->data;
  FSSolver   s;
  PetscInt   dim;

  PetscFunctionBegin;
  PetscCall(FSTermGetSolver(t, &s));
  PetscCall(FSSolverGetDimension(s, &dim));
  ctx->K = 2.0 * (dim + 2);
  PetscOptionsHeadBegin(PetscOptionsObject, ctx->les ? "Term les_viscosity: delta-LES turbulent viscosity"
                                                     : "Term viscosity: laminar viscosity");
  PetscCall(FSOptionsReal(PetscOptionsObject, "-fs_viscosity_K", "K of the viscous term, 2(dim+2) (seed Eq. 12)", "",
                          &ctx->K, NULL, 0, PETSC_INFINITY, FS_RANGE_OPEN_LOWER));
  if (ctx->les)
    PetscCall(FSOptionsReal(PetscOptionsObject, "-fs_les_c", "C_alpha, the Smagorinsky constant (seed Eq. 13)", "",
                            &ctx->C, NULL, 0, PETSC_INFINITY, FS_RANGE_CLOSED));
  PetscOptionsHeadEnd();
  PetscFunctionReturn(0);
}

static PetscErrorCode View(FSTerm t, PetscViewer v)
{
  Viscosity *ctx = (Viscosity *)t->data;

  PetscFunctionBegin;
  if (ctx->les)
    PetscCall(
        PetscViewerASCIIPrintf(v, "les_viscosity: C_alpha = %g, K = %g, L_LES = 2h\n", (double)ctx->C, (double)ctx->K));
  else PetscCall(PetscViewerASCIIPrintf(v, "viscosity: K = %g\n", (double)ctx->K));
  PetscFunctionReturn(0);
}

static PetscErrorCode Destroy(FSTerm t)
{
  Viscosity *ctx = (Viscosity *)t->data;

  PetscFunctionBegin;
  PetscCall(PetscFree(ctx->a));
  PetscCall(PetscFree(t->data));
  PetscFunctionReturn(0);
}

static PetscErrorCode Create(FSTerm t, PetscBool les)
{
  Viscosity *ctx;

  PetscFunctionBegin;
  PetscCall(PetscNew(&ctx));
  ctx->les              = les;
  ctx->C                = 0.12;
  t->data               = ctx;
  t->needs              = les ? FS_NEED_STRAIN_RATE : FS_NEED_NONE;
  t->has_power          = PETSC_TRUE;
  t->ops.interact       = Interact;
  t->ops.prepare        = Prepare;
  t->ops.field          = Field;
  t->ops.setfromoptions = SetFromOptions;
  t->ops.view           = View;
  t->ops.destroy        = Destroy;
  PetscFunctionReturn(0);
}

PETSC_EXTERN PetscErrorCode FSTermCreate_Viscosity(FSTerm t)
{
  PetscFunctionBegin;
  PetscCall(Create(t, PETSC_FALSE));
  PetscFunctionReturn(0);
}

PETSC_EXTERN PetscErrorCode FSTermCreate_LESViscosity(FSTerm t)
{
  PetscFunctionBegin;
  PetscCall(Create(t, PETSC_TRUE));
  PetscFunctionReturn(0);
}
