/* Term "pressure": the pressure gradient in the (p_i + p_j) form, -1/rho_i sum_j (p_i + p_j) grad_i W_ij V_j (seed Eq. 4),
   with the linear equation of state p = c0^2 (rho - rho0) + p_b (seed Eq. 2; p_b is -fs_background_pressure, 0 by default).
   With -fs_pressure_form difference: -1/rho_i sum_j (p_j - p_i) grad_i W_ij V_j, exact for a constant pressure whatever the
   particle distribution; the walls' cases use it, because with boundary integrals the (p_i + p_j) form leaves an error
   2 p_i (sum_j grad W_ij V_j - grad gamma_i) proportional to the absolute pressure (0.4 g at the bottom of a 3 cm column). */
#include <flexslosh.h>

static void Interact(FSTerm t, const FSParticles *P, const FSNeighbourhood *nb, FSRate *rate)
{
  const PetscInt   dim = P->dim, S = P->stride;
  const PetscReal *p = P->pressure, *V = P->vol, rhoi = P->rec[nb->i * S + 2 * dim];
  /* difference form: everywhere with -fs_pressure_form difference; with "wall" only where the kernel meets a wall */
  const PetscReal  pi = (P->pressure_difference || (P->pressure_wall_difference && nb->nw)) ? -p[nb->i] : p[nb->i];
  PetscReal        acc[3] = {0, 0, 0};
  (void)t;
  for (PetscInt k = 0; k < nb->n; k++) {
    const PetscInt   j = nb->j[k];
    const PetscReal *g = &nb->gradW[k * dim], f = (pi + p[j]) * V[j];
    for (PetscInt d = 0; d < dim; d++) acc[d] += f * g[d];
  }
  for (PetscInt d = 0; d < dim; d++) rate->du[d] -= acc[d] / rhoi;
}

PETSC_EXTERN PetscErrorCode FSTermCreate_Pressure(FSTerm t)
{
  PetscFunctionBegin;
  t->renormalized = PETSC_TRUE; /* divided by gamma_i near walls */
  t->ops.interact = Interact;
  PetscFunctionReturn(0);
}
