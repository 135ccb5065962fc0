/*
   Term "pressure": the pressure gradient in the (p_i + p_j) form (seed Eq. 4),
     D u_i/Dt += -1/rho_i sum_j (p_i + p_j) grad_i W_ij V_j,
   with the linear equation of state p = c0^2 (rho - rho0) + p_b (seed Eq. 2; p_b is -fs_background_pressure,
   0 by default). With walls the core divides it by gamma_i and term wall_pressure adds the boundary part
   (seed Eq. 14).
   Renormalization near walls: the gradient (this term, wall_pressure) is divided by gamma_i, the
   divergence of the continuity equation (continuity, delta, wall_continuity) is not. Dividing both
   by gamma_i with the geometric gamma makes the scheme create energy under gravity: in a hydrostatic
   tank the velocities grow to tenths of m/s within a second; with the divergence left as it is they
   stay at about 0.03 sqrt(g H) (tests/python/test_walls.py).
   Power: m_i u_i . (D u_i/Dt), with the core's 1/gamma_i; without walls it is exactly minus the power of
   term continuity, with walls their sum is the boundaries' share of the energy budget (src/coupling/energy.c).
*/
#include <flexslosh.h>

/* the pair sum for a compile-time dimension (see FS_ALWAYS_INLINE); returns the term's power */
FS_ALWAYS_INLINE PetscReal InteractDim(const FSParticles *P, const FSNeighbourhood *nb, FSRate *rate,
                                       const PetscInt dim)
{
  const PetscInt   S = P->stride, i = nb->i;
  const PetscReal *p = P->pressure, *V = P->vol, pi = p[i], rhoi = P->rec[i * S + 2 * dim];
  PetscReal        acc[3] = {0, 0, 0}, pw = 0;
  for (PetscInt k = 0; k < nb->n; k++) {
    const PetscInt   j = nb->j[k];
    const PetscReal *g = &nb->gradW[k * dim], f = (pi + p[j]) * nb->Vj[k];
    for (PetscInt d = 0; d < dim; d++) acc[d] += f * g[d];
  }
  for (PetscInt d = 0; d < dim; d++) {
    rate->du[d] -= acc[d] / rhoi;
    pw += P->rec[i * S + dim + d] * acc[d];
  }
  return -V[i] * (P->invgamma ? P->invgamma[i] : 1.0) * pw;
}

static void Interact(FSTerm t, const FSParticles *P, const FSNeighbourhood *nb, FSRate *rate)
{
  if (P->dim == 2) t->power += InteractDim(P, nb, rate, 2);
  else t->power += InteractDim(P, nb, rate, 3);
}

PETSC_EXTERN PetscErrorCode FSTermCreate_Pressure(FSTerm t)
{
  PetscFunctionBegin;
  t->renormalized = PETSC_TRUE; /* divided by gamma_i near walls */
  t->has_power    = PETSC_TRUE; /* exchanged with term continuity */
  t->ops.interact = Interact;
  PetscFunctionReturn(0);
}
