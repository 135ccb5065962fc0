/*
   Term "shifting": particle shifting (Sun, Colagrossi, Marrone & Zhang 2017, the delta+-SPH model),
   which keeps the particle distribution regular where the flow stretches it (hyperbolic points of
   vortices); not part of the seed's equations, an option for flows that need it (Taylor-Green).
   Particles are transported with u_i + du_i,
     du_i = -C (2h)^2 / h * U sum_j [1 + R (W_ij / W(dx))^n] grad_i W_ij V_j ,   R = 0.2, n = 4,
   U the largest particle speed (at least -fs_shifting_umin). With C = -fs_shifting_c = 1 this is
   Sun et al.'s shift CFL Ma (2h)^2 sum(...) per time step of CFL h/c0, written as a velocity so that
   it does not depend on the time step. |du_i| is limited to -fs_shifting_max U.
   Free surfaces need a projection of the shift (not done here: use it in flows without one).
*/
#include <flexslosh.h>

typedef struct {
  PetscReal C, R, umin, limit;
  PetscInt  n;
} Shifting;

static void Interact(FSTerm t, const FSParticles *P, const FSNeighbourhood *nb, FSRate *rate)
{
  const Shifting *ctx = (const Shifting *)t->data;
  const PetscInt  dim = P->dim;
  const PetscReal W0 = FSWendland(dim, P->h, P->dx), U = PetscMax(P->umax, ctx->umin);
  const PetscReal coef   = -ctx->C * 4.0 * P->h * U;
  PetscReal       acc[3] = {0, 0, 0}, mag = 0;
  for (PetscInt k = 0; k < nb->n; k++) {
    const PetscReal *g = &nb->gradW[k * dim];
    const PetscReal  w = FSWendland(dim, P->h, PetscSqrtReal(nb->r2[k])) / W0, w2 = w * w;
    const PetscReal  f = (1.0 + ctx->R * w2 * w2) * P->vol[nb->j[k]];
    for (PetscInt d = 0; d < dim; d++) acc[d] += f * g[d];
  }
  for (PetscInt d = 0; d < dim; d++) {
    acc[d] *= coef;
    mag += acc[d] * acc[d];
  }
  mag = PetscSqrtReal(mag);
  if (mag > ctx->limit * U) {
    for (PetscInt d = 0; d < dim; d++) acc[d] *= ctx->limit * U / mag;
  }
  for (PetscInt d = 0; d < dim; d++) rate->dx[d] += acc[d];
}

static PetscErrorCode SetFromOptions(FSTerm t, PetscOptionItems *PetscOptionsObject)
{
  Shifting *ctx = (Shifting *)t->data;

  PetscFunctionBegin;
  PetscOptionsHeadBegin(PetscOptionsObject, "Term shifting: particle shifting (delta+-SPH)");
  PetscCall(FSOptionsReal(PetscOptionsObject, "-fs_shifting_c", "Shifting coefficient C", "", &ctx->C, NULL, 0,
                          PETSC_INFINITY, FS_RANGE_CLOSED));
  PetscCall(FSOptionsReal(PetscOptionsObject, "-fs_shifting_umin",
                          "Smallest reference speed U of the shifting velocity", "", &ctx->umin, NULL, 0,
                          PETSC_INFINITY, FS_RANGE_CLOSED));
  PetscCall(FSOptionsReal(PetscOptionsObject, "-fs_shifting_max", "Largest shifting velocity, as a fraction of U", "",
                          &ctx->limit, NULL, 0, PETSC_INFINITY, FS_RANGE_OPEN_LOWER));
  PetscOptionsHeadEnd();
  PetscFunctionReturn(0);
}

static PetscErrorCode View(FSTerm t, PetscViewer v)
{
  Shifting *ctx = (Shifting *)t->data;

  PetscFunctionBegin;
  PetscCall(PetscViewerASCIIPrintf(v, "shifting: C = %g, R = %g, n = %" PetscInt_FMT ", limit %g U\n", (double)ctx->C,
                                   (double)ctx->R, ctx->n, (double)ctx->limit));
  PetscFunctionReturn(0);
}

static PetscErrorCode Destroy(FSTerm t)
{
  PetscFunctionBegin;
  PetscCall(PetscFree(t->data));
  PetscFunctionReturn(0);
}

PETSC_EXTERN PetscErrorCode FSTermCreate_Shifting(FSTerm t)
{
  Shifting *ctx;

  PetscFunctionBegin;
  PetscCall(PetscNew(&ctx));
  ctx->C                = 1.0;
  ctx->R                = 0.2;
  ctx->n                = 4;
  ctx->limit            = 1.0;
  t->data               = ctx;
  t->ops.interact       = Interact;
  t->ops.setfromoptions = SetFromOptions;
  t->ops.view           = View;
  t->ops.destroy        = Destroy;
  PetscFunctionReturn(0);
}
