/*
   Term "tensile_control": the tensile instability control of the delta+-SPH model (Sun, Colagrossi,
   Marrone & Zhang 2017): where the liquid is in tension (p_i < 0) away from the free surface, the pressure
   gradient takes the (p_j - p_i) form instead of the (p_i + p_j) one, in the fluid sum and in the walls'
   boundary integral alike. With term pressure and wall_pressure left as they are this term adds the
   difference,
     D u_i/Dt += w_i 2 p_i^- / rho_i [ sum_j grad_i W_ij V_j + sum_k n_k W_ik s_k ],   p_i^- = min(p_i, 0),
   divided by gamma_i by the core as the pressure terms are. The bracket is the particle distribution's
   error: it vanishes for a uniform distribution in the bulk and against the walls, and is what drives
   particles apart where the (p_i + p_j) form lets a liquid in tension fracture along the rows of particles
   (the tensile instability). Near the free surface the bracket is the missing kernel support, not an
   error, so the term fades out there: w_i = 0 for a Shepard sum
     theta_i = W(0) V_i + sum_j W_ij V_j + (1 - gamma_i)   (the walls' share of the support counted full)
   below -fs_tensile_control_surface (0.95), rising linearly to 1 at 0.05 above it.
   Not in the seed's model (its Eq. 4 keeps (p_i + p_j) everywhere); offered for flows that put the liquid in
   tension, as the seed's tank does while the beam pulls it down faster than g (docs/performance.md).
   Power: m_i u_i . (D u_i/Dt) of the term (with the core's 1/gamma_i), booked with the dissipated terms.

   -fs_tensile_control_type artificial_pressure takes Monaghan's artificial pressure instead (Monaghan 2000,
   "SPH without a tensile instability"; Gray, Monaghan & Swift 2001): a short-range repulsion between pairs in
   tension,
     D u_i/Dt += -sum_j m_j (R_i + R_j) f_ij^n grad_i W_ij,   R_i = eps |p_i^-| / rho_i^2,   f_ij = W_ij / W(dx),
   with eps = -fs_tensile_control_epsilon (0.2) and n = -fs_tensile_control_exponent (4). Pairwise antisymmetric,
   so it conserves momentum (not divided by gamma_i, no wall part); it acts only where particles of a liquid in
   tension come closer than dx, the clumping by which the (p_i + p_j) form fractures.
*/
#include <flexslosh.h>

typedef enum { TENSILE_DELTAPLUS, TENSILE_ARTIFICIAL_PRESSURE } TensileControlType;
static const char *const TensileControlTypes[] = {"deltaplus", "artificial_pressure"};

typedef struct {
  TensileControlType type;
  PetscReal          epsilon, exponent; /* artificial_pressure: eps and n */
  PetscReal          W0;                /* artificial_pressure: W(dx), set by Prepare */
  PetscReal          surface;           /* the Shepard sum below which a particle is on the free surface */
  PetscReal         *weight;            /* w_i of the owned particles, from the pair pass, for the wall pass */
  PetscInt           cap;
} TensileControl;

/* w_i from the Shepard sum: 0 on the free surface, 1 a little inside it */
static inline PetscReal Weight(const TensileControl *ctx, PetscReal theta)
{
  const PetscReal w = (theta - ctx->surface) / 0.05;
  return w <= 0 ? 0 : w >= 1 ? 1 : w;
}

FS_ALWAYS_INLINE void InteractDim(FSTerm t, const FSParticles *P, const FSNeighbourhood *nb, FSRate *rate,
                                  const PetscInt dim)
{
  TensileControl  *ctx = (TensileControl *)t->data;
  const PetscInt   i = nb->i, S = P->stride;
  const PetscReal *V = P->vol, pi = P->pressure[i], rhoi = P->rec[i * S + 2 * dim];
  PetscReal        theta = FSWendland(dim, P->h, 0) * V[i] + (P->gamma ? 1.0 - P->gamma[i] : 0), sum[3] = {0, 0, 0};
  PetscReal        f, pw                                                                                = 0;
  for (PetscInt k = 0; k < nb->n; k++) {
    const PetscInt   j = nb->j[k];
    const PetscReal *g = &nb->gradW[k * dim];
    theta += FSWendland(dim, P->h, PetscSqrtReal(nb->r2[k])) * V[j];
    for (PetscInt d = 0; d < dim; d++) sum[d] += g[d] * V[j];
  }
  ctx->weight[i] = Weight(ctx, theta);
  if (pi >= 0 || ctx->weight[i] == 0) return;
  f = 2 * ctx->weight[i] * pi / rhoi;
  for (PetscInt d = 0; d < dim; d++) {
    rate->du[d] += f * sum[d];
    pw += P->rec[i * S + dim + d] * sum[d];
  }
  t->power += P->rec[i * S + 2 * dim + 1] * f * pw * (P->invgamma ? P->invgamma[i] : 1.0);
}

/* Monaghan's artificial pressure: -sum_j m_j (R_i + R_j) f_ij^n grad_i W_ij, R_k = eps |p_k^-| / rho_k^2 */
FS_ALWAYS_INLINE void ArtificialPressureDim(FSTerm t, const FSParticles *P, const FSNeighbourhood *nb, FSRate *rate,
                                            const PetscInt dim)
{
  const TensileControl *ctx = (const TensileControl *)t->data;
  const PetscInt        i = nb->i, S = P->stride, M = 2 * dim + 1;
  const PetscReal      *p = P->pressure, rhoi = P->rec[i * S + 2 * dim], W0 = ctx->W0;
  const PetscReal       Ri     = p[i] < 0 ? -ctx->epsilon * p[i] / (rhoi * rhoi) : 0;
  PetscReal             acc[3] = {0, 0, 0}, pw = 0;
  for (PetscInt k = 0; k < nb->n; k++) {
    const PetscInt   j    = nb->j[k];
    const PetscReal  rhoj = P->rec[j * S + 2 * dim], Rj = p[j] < 0 ? -ctx->epsilon * p[j] / (rhoj * rhoj) : 0;
    const PetscReal *g = &nb->gradW[k * dim];
    PetscReal        f;
    if (Ri + Rj == 0) continue;
    f = (Ri + Rj) * P->rec[j * S + M] *
        PetscPowReal(FSWendland(dim, P->h, PetscSqrtReal(nb->r2[k])) / W0, ctx->exponent);
    for (PetscInt d = 0; d < dim; d++) acc[d] += f * g[d];
  }
  for (PetscInt d = 0; d < dim; d++) {
    rate->du[d] -= acc[d];
    pw += P->rec[i * S + dim + d] * acc[d];
  }
  t->power -= P->rec[i * S + M] * pw;
}

static void Interact(FSTerm t, const FSParticles *P, const FSNeighbourhood *nb, FSRate *rate)
{
  const TensileControl *ctx = (const TensileControl *)t->data;
  if (ctx->type == TENSILE_ARTIFICIAL_PRESSURE) {
    if (P->dim == 2) ArtificialPressureDim(t, P, nb, rate, 2);
    else ArtificialPressureDim(t, P, nb, rate, 3);
  } else if (P->dim == 2) InteractDim(t, P, nb, rate, 2);
  else InteractDim(t, P, nb, rate, 3);
}

/* the walls' part of the bracket, with the weight the pair pass found */
static void Wall(FSTerm t, const FSParticles *P, const FSWallView *B, const FSWallNeighbourhood *nb, FSRate *rate)
{
  const TensileControl *ctx = (const TensileControl *)t->data;
  const PetscInt        i = nb->i, dim = P->dim, S = P->stride;
  const PetscReal       pi = P->pressure[i], rhoi = P->rec[i * S + 2 * dim];
  PetscReal             sum[3] = {0, 0, 0}, f, pw = 0;

  if (ctx->type != TENSILE_DELTAPLUS || pi >= 0 || ctx->weight[i] == 0) return;
  for (PetscInt q = 0; q < nb->n; q++) {
    const PetscReal *e = &B->element[nb->k[q] * B->stride];
    for (PetscInt d = 0; d < dim; d++) sum[d] += e[B->normal + d] * nb->W[q] * e[B->measure];
  }
  f = 2 * ctx->weight[i] * pi / rhoi;
  for (PetscInt d = 0; d < dim; d++) {
    rate->du[d] += f * sum[d];
    pw += P->rec[i * S + dim + d] * sum[d];
  }
  t->power += P->rec[i * S + 2 * dim + 1] * f * pw * (P->invgamma ? P->invgamma[i] : 1.0);
}

/* the weights' room for this rank's owned particles (called twice a right-hand side, with the same nowned: the
   pair pass sets every owned particle's weight) */
static PetscErrorCode Prepare(FSTerm t, const FSParticles *P)
{
  TensileControl *ctx = (TensileControl *)t->data;

  PetscFunctionBegin;
  ctx->W0 = FSWendland(P->dim, P->h, P->dx);
  if (P->nowned > ctx->cap) {
    PetscCall(PetscFree(ctx->weight));
    ctx->cap = PetscMax(P->nowned, 2 * ctx->cap);
    PetscCall(PetscMalloc1(ctx->cap, &ctx->weight));
  }
  PetscFunctionReturn(0);
}

static PetscErrorCode SetFromOptions(FSTerm t, PetscOptionItems *PetscOptionsObject)
{
  TensileControl *ctx  = (TensileControl *)t->data;
  PetscInt        type = (PetscInt)ctx->type;

  PetscFunctionBegin;
  PetscOptionsHeadBegin(PetscOptionsObject, "Term tensile_control: holds a liquid in tension together");
  PetscCall(PetscOptionsEList("-fs_tensile_control_type",
                              "deltaplus: the (p_j - p_i) form where p_i < 0; artificial_pressure: Monaghan's pairwise "
                              "repulsion in tension (conserves momentum)",
                              "", TensileControlTypes, 2, TensileControlTypes[type], &type, NULL));
  ctx->type = (TensileControlType)type;
  PetscCall(FSOptionsReal(PetscOptionsObject, "-fs_tensile_control_epsilon",
                          "artificial_pressure: eps of R_i = eps |p_i| / rho_i^2", "", &ctx->epsilon, NULL, 0, 10,
                          FS_RANGE_CLOSED));
  PetscCall(FSOptionsReal(PetscOptionsObject, "-fs_tensile_control_exponent",
                          "artificial_pressure: n of (W_ij / W(dx))^n", "", &ctx->exponent, NULL, 1, 16,
                          FS_RANGE_CLOSED));
  PetscCall(FSOptionsReal(PetscOptionsObject, "-fs_tensile_control_surface",
                          "Shepard sum (walls counted full) below which a particle is on the free surface and the "
                          "control is off (full 0.05 above it)",
                          "", &ctx->surface, NULL, 0, 1, FS_RANGE_CLOSED));
  PetscOptionsHeadEnd();
  t->renormalized = (PetscBool)(ctx->type == TENSILE_DELTAPLUS); /* the pairwise form stays antisymmetric */
  PetscFunctionReturn(0);
}

static PetscErrorCode View(FSTerm t, PetscViewer v)
{
  const TensileControl *ctx = (const TensileControl *)t->data;

  PetscFunctionBegin;
  if (ctx->type == TENSILE_ARTIFICIAL_PRESSURE)
    PetscCall(PetscViewerASCIIPrintf(v, "tensile_control: artificial pressure, eps %g, n %g\n", (double)ctx->epsilon,
                                     (double)ctx->exponent));
  else
    PetscCall(PetscViewerASCIIPrintf(v, "tensile_control: (p_j - p_i) where p_i < 0, off below a Shepard sum of %g\n",
                                     (double)ctx->surface));
  PetscFunctionReturn(0);
}

static PetscErrorCode Destroy(FSTerm t)
{
  TensileControl *ctx = (TensileControl *)t->data;

  PetscFunctionBegin;
  PetscCall(PetscFree(ctx->weight));
  PetscCall(PetscFree(t->data));
  PetscFunctionReturn(0);
}

PETSC_EXTERN PetscErrorCode FSTermCreate_TensileControl(FSTerm t)
{
  TensileControl *ctx;

  PetscFunctionBegin;
  PetscCall(PetscNew(&ctx));
  ctx->surface          = 0.95;
  ctx->epsilon          = 0.2;
  ctx->exponent         = 4;
  t->data               = ctx;
  t->renormalized       = PETSC_TRUE; /* divided by gamma_i, as the pressure terms it corrects */
  t->has_power          = PETSC_TRUE;
  t->ops.interact       = Interact;
  t->ops.wall           = Wall;
  t->ops.prepare        = Prepare;
  t->ops.setfromoptions = SetFromOptions;
  t->ops.view           = View;
  t->ops.destroy        = Destroy;
  PetscFunctionReturn(0);
}
