/*
   Term "surface_tension": surface tension as a pairwise cohesion force between the liquid's particles, derived
   from a pair potential so that it conserves momentum exactly and its work is the change of a potential energy
   (in the spirit of Tartakovsky & Meakin 2005: a short-range repulsion and a longer-range attraction, here
   built on the run's kernel and calibrated analytically instead of by trial runs).

   The pair potential, with W the run's Wendland kernel (support 2h), q = r/h and the liquid's energy
   E_s = sum over pairs m_i m_j phi(r_ij):
     phi(r) = A (c - q^2) W(r),    c = <q^2>_W = 5/9 (2-D), 4/5 (3-D),
   repulsive for q < sqrt(c), attractive beyond. The choice of c makes the volume integral of phi vanish, so a
   uniform liquid feels no cohesion pressure: inside the bulk the particles' pressure is the mechanical one and a
   drop's pressure jump is the Laplace jump alone. A flat surface of a continuum of density rho0 then has the
   energy per area (half the work of parting two half-spaces)
     2-D: sigma = -rho0^2 int_0^inf r^2 phi dr            = A rho0^2 h K2,  K2 = 11/(135 pi)
     3-D: sigma = -(pi/2) rho0^2 int_0^inf r^3 phi dr     = A rho0^2 h K3,  K3 = 1/44
   so A = sigma / (rho0^2 h K_dim) with sigma = -fs_surface_tension_sigma. The acceleration of particle i is
     D u_i/Dt = -sum_j m_j phi'(r_ij) (x_i - x_j)/r_ij
              = -A sum_j m_j [ (c - q^2) grad_i W_ij - (2/h^2) W_ij (x_i - x_j) ],
   antisymmetric in i and j. Its power m_i u_i . D u_i/Dt is booked as the term's work (energy.csv's
   work_viscous column, timeseries.csv's dissipated_surface_tension): summed over the liquid it is -dE_s/dt,
   so the budget closes with the surface energy counted as work done.

   Walls: the term has no wall part. The walls neither attract nor repel through it, so the liquid sees a wall as
   it sees the air: a liquid-wall interface costs sigma as a free surface does, which is a non-wetting wall
   (contact angle 180 degrees) in the mean-field sense. The pull it exerts on the liquid next to a wall is
   sigma/h per unit area at most (36 Pa for water at h = 2 mm). Not divided by gamma_i (the pairwise form stays
   antisymmetric).
*/
#include <flexslosh.h>

typedef struct {
  PetscReal sigma; /* N/m (2-D: N per metre of depth, the same number) */
  PetscReal A, c;  /* the potential's amplitude and the zero of its repulsive part, set by SetUp */
} SurfaceTension;

FS_ALWAYS_INLINE void InteractDim(FSTerm t, const FSParticles *P, const FSNeighbourhood *nb, FSRate *rate,
                                  const PetscInt dim)
{
  const SurfaceTension *ctx = (const SurfaceTension *)t->data;
  const PetscInt        i = nb->i, S = P->stride, M = 2 * dim + 1;
  const PetscReal       h = P->h, ih2 = 1.0 / (h * h), c = ctx->c;
  PetscReal             acc[3] = {0, 0, 0}, pw = 0;

  for (PetscInt k = 0; k < nb->n; k++) {
    const PetscInt   j = nb->j[k];
    const PetscReal *g = &nb->gradW[k * dim], *dxij = &nb->dx[k * dim], r2 = nb->r2[k], mj = P->rec[j * S + M];
    const PetscReal  W = FSWendland(dim, h, PetscSqrtReal(r2)), a = mj * (c - r2 * ih2), b = mj * 2 * ih2 * W;
    /* dxij = x_j - x_i: -(2/h^2) W (x_i - x_j) = +(2/h^2) W dxij */
    for (PetscInt d = 0; d < dim; d++) acc[d] += a * g[d] + b * dxij[d];
  }
  for (PetscInt d = 0; d < dim; d++) {
    rate->du[d] -= ctx->A * acc[d];
    pw += P->rec[i * S + dim + d] * acc[d];
  }
  t->power -= P->rec[i * S + M] * ctx->A * pw;
}

static void Interact(FSTerm t, const FSParticles *P, const FSNeighbourhood *nb, FSRate *rate)
{
  if (P->dim == 2) InteractDim(t, P, nb, rate, 2);
  else InteractDim(t, P, nb, rate, 3);
}

/* the potential's constants for the run's dimension, smoothing length and density, and the stiffness check: once
   before the first right-hand side (ops.setup) */
static PetscErrorCode SetUp(FSTerm t, const FSParticles *P)
{
  SurfaceTension *ctx = (SurfaceTension *)t->data;
  const PetscReal K   = P->dim == 2 ? 11.0 / (135.0 * PETSC_PI) : 1.0 / 44.0;

  PetscFunctionBegin;
  ctx->c = P->dim == 2 ? 5.0 / 9.0 : 4.0 / 5.0;
  ctx->A = ctx->sigma / (P->rho0 * P->rho0 * P->h * K);
  /* the surface layer's stresses, about sigma/(h K), must stay well below the liquid's stiffness rho0 c0^2 */
  PetscCheck(
      ctx->sigma / (P->h * K) <= 0.1 * P->rho0 * P->c0 * P->c0, PETSC_COMM_SELF, PETSC_ERR_ARG_OUTOFRANGE,
      "-fs_surface_tension_sigma %g is too stiff for this liquid: sigma/(h K) = %g Pa (h %g, K %g) must stay below "
      "0.1 rho0 c0^2 = %g Pa; lower sigma or raise -fs_c0",
      (double)ctx->sigma, (double)(ctx->sigma / (P->h * K)), (double)P->h, (double)K,
      (double)(0.1 * P->rho0 * P->c0 * P->c0));
  PetscFunctionReturn(0);
}

static PetscErrorCode SetFromOptions(FSTerm t, PetscOptionItems *PetscOptionsObject)
{
  SurfaceTension *ctx = (SurfaceTension *)t->data;

  PetscFunctionBegin;
  PetscOptionsHeadBegin(PetscOptionsObject, "Term surface_tension: pairwise cohesion calibrated to sigma");
  PetscCall(FSOptionsReal(PetscOptionsObject, "-fs_surface_tension_sigma",
                          "surface tension sigma (N/m; water 0.0728) of the pair potential's flat surface", "",
                          &ctx->sigma, NULL, 0, 1e4, FS_RANGE_CLOSED));
  PetscOptionsHeadEnd();
  PetscFunctionReturn(0);
}

static PetscErrorCode View(FSTerm t, PetscViewer v)
{
  const SurfaceTension *ctx = (const SurfaceTension *)t->data;

  PetscFunctionBegin;
  PetscCall(PetscViewerASCIIPrintf(v, "surface_tension: pairwise cohesion, sigma %g N/m, no wall part (non-wetting)\n",
                                   (double)ctx->sigma));
  PetscFunctionReturn(0);
}

static PetscErrorCode Destroy(FSTerm t)
{
  PetscFunctionBegin;
  PetscCall(PetscFree(t->data));
  PetscFunctionReturn(0);
}

PETSC_EXTERN PetscErrorCode FSTermCreate_SurfaceTension(FSTerm t)
{
  SurfaceTension *ctx;

  PetscFunctionBegin;
  PetscCall(PetscNew(&ctx));
  ctx->sigma            = 0.0728;
  t->data               = ctx;
  t->has_power          = PETSC_TRUE;
  t->ops.interact       = Interact;
  t->ops.setup          = SetUp;
  t->ops.setfromoptions = SetFromOptions;
  t->ops.view           = View;
  t->ops.destroy        = Destroy;
  PetscFunctionReturn(0);
}
