/* Term "continuity": the SPH continuity equation, D rho_i/Dt = -rho_i sum_j (u_j - u_i) . grad_i W_ij V_j (seed Eq. 4). */
#include <flexslosh.h>

/* the pair sum for a compile-time dimension (see FS_ALWAYS_INLINE) */
FS_ALWAYS_INLINE void InteractDim(const FSParticles *P, const FSNeighbourhood *nb, FSRate *rate, const PetscInt dim)
{
  const PetscInt   S  = P->stride;
  const PetscReal *ri = &P->rec[nb->i * S], rhoi = ri[2 * dim], *V = P->vol;
  PetscReal        sum = 0;
  for (PetscInt k = 0; k < nb->n; k++) {
    const PetscInt   j  = nb->j[k];
    const PetscReal *rj = &P->rec[j * S], *g = &nb->gradW[k * dim];
    PetscReal        dot = 0;
    for (PetscInt d = 0; d < dim; d++) dot += (rj[dim + d] - ri[dim + d]) * g[d];
    sum += dot * V[j];
  }
  rate->drho -= rhoi * sum;
}

static void Interact(FSTerm t, const FSParticles *P, const FSNeighbourhood *nb, FSRate *rate)
{
  (void)t;
  if (P->dim == 2) InteractDim(P, nb, rate, 2);
  else InteractDim(P, nb, rate, 3);
}

PETSC_EXTERN PetscErrorCode FSTermCreate_Continuity(FSTerm t)
{
  PetscFunctionBegin;
  t->ops.interact = Interact;
  PetscFunctionReturn(0);
}
