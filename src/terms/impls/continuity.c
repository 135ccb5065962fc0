/*
   Term "continuity": the SPH continuity equation, D rho_i/Dt = -rho_i sum_j (u_j - u_i) . grad_i W_ij V_j (seed Eq. 4).
   Its power, the rate of change of the compressibility energy it causes, V_i p_i/rho_i (D rho_i/Dt), is
   exactly minus the power of term pressure without walls (the pair exchanges kinetic and compressibility
   energy); near walls the pressure gradient is renormalized by gamma_i and this divergence is not, so the
   sum of the two powers is the boundaries' share of the energy budget (counted in P_wall, src/coupling/energy.c).
*/
#include <flexslosh.h>

/* the pair sum for a compile-time dimension (see FS_ALWAYS_INLINE); returns the term's power */
FS_ALWAYS_INLINE PetscReal InteractDim(const FSParticles *P, const FSNeighbourhood *nb, FSRate *rate,
                                       const PetscInt dim)
{
  const PetscReal rhoi = P->rec[nb->i * P->stride + 2 * dim];
  PetscReal       sum  = 0;
  for (PetscInt k = 0; k < nb->n; k++) {
    const PetscReal *du = &nb->du[k * dim], *g = &nb->gradW[k * dim];
    PetscReal        dot = 0;
    for (PetscInt d = 0; d < dim; d++) dot += du[d] * g[d];
    sum += dot * nb->Vj[k];
  }
  rate->drho -= rhoi * sum;
  return -P->vol[nb->i] * P->pressure[nb->i] * sum;
}

static void Interact(FSTerm t, const FSParticles *P, const FSNeighbourhood *nb, FSRate *rate)
{
  if (P->dim == 2) t->power += InteractDim(P, nb, rate, 2);
  else t->power += InteractDim(P, nb, rate, 3);
}

PETSC_EXTERN PetscErrorCode FSTermCreate_Continuity(FSTerm t)
{
  PetscFunctionBegin;
  t->has_power    = PETSC_TRUE; /* exchanged with term pressure: see above */
  t->ops.interact = Interact;
  PetscFunctionReturn(0);
}
