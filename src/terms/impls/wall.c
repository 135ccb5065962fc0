/*
   Wall terms of the boundary-integral method (seed Eq. 14; Calderon-Sanchez et al. 2019; Cercos-Pita
   2015): the boundary parts of the renormalized operators, summed over the wall segments k that face
   particle i within the kernel support (normal n_k out of the liquid, length s_k, W_ik the mean kernel
   value over the segment), from the boundary's view (FSWallView) and the particle's wall
   neighbourhood. Like the fluid terms they join, they are divided by gamma_i by the core.
   The walls are at rest in the tank's frame (u_k = 0).

   wall_continuity:  D rho_i/Dt += -rho_i sum_k (u_k - u_i) . n_k W_ik s_k
   wall_pressure:    D u_i/Dt   += -1/rho_i sum_k (p_i + p_k) n_k W_ik s_k, the wall pressure p_k
                     interpolated from the liquid near the segment (Shepard sum over all ranks with the
                     hydrostatic correction rho_j g . (x_k - x_j)). The liquid's pressure force on each
                     wall is the integral of that wall pressure, F_w = sum_{k in w} p_k s_k n_k (the
                     continuous form of seed Eq. 29, exact for a liquid at rest), computed by the core
                     with the wall pressures, and its moment about -fs_walls_load_point.
   wall_viscosity:   on no-slip walls (-fs_walls_noslip), the wall shear stress from the one-sided
                     normal derivative (u_k - u_i)/d_ik, d_ik the distance from x_i to the segment's line:
                     D u_i/Dt += nu rho0/rho_i sum_k (u_k - u_i)/max(d_ik, dx/2) W_ik s_k;
                     free-slip walls carry no shear (the term adds nothing there).
   Their powers, the rates of change of the liquid's kinetic (m_i u_i . D u_i/Dt, with the core's
   1/gamma_i) and compressibility (V_i p_i/rho_i D rho_i/Dt) energies through the walls, make the
   wall power P_s of the energy budget (seed Eq. 39): the sum of the dissipated_wall_* columns.
   The wall pressure term does no net work on a liquid at rest; it exchanges energy with the fluid
   pressure term where gamma < 1.
*/
#include <flexslosh.h>

/* In the element rows of the boundary's view: p0 the element's point, c its centroid, n its normal
   (out of the liquid), a its length (2-D). */
static void Continuity(FSTerm t, const FSParticles *P, const FSWallView *B, const FSWallNeighbourhood *nb, FSRate *rate)
{
  const PetscInt   dim = P->dim, N = B->normal, A = B->measure;
  const PetscReal *ri  = &P->rec[nb->i * P->stride];
  PetscReal        sum = 0;
  for (PetscInt q = 0; q < nb->n; q++) {
    const PetscReal *e = &B->element[nb->k[q] * B->stride];
    sum += (ri[dim] * e[N] + ri[dim + 1] * e[N + 1]) * nb->W[q] * e[A];
  }
  rate->drho += ri[2 * dim] * sum;
  t->power += P->vol[nb->i] * P->pressure[nb->i] * sum;
}

static void Pressure(FSTerm t, const FSParticles *P, const FSWallView *B, const FSWallNeighbourhood *nb, FSRate *rate)
{
  const PetscInt   dim = P->dim, i = nb->i, N = B->normal, A = B->measure;
  const PetscReal *ri = &P->rec[i * P->stride], rhoi = ri[2 * dim], pi = P->pressure[i];
  PetscReal        acc[2] = {0, 0};
  for (PetscInt q = 0; q < nb->n; q++) {
    const PetscInt   k = nb->k[q];
    const PetscReal *e = &B->element[k * B->stride];
    const PetscReal  f = (pi + B->pressure[k]) * nb->W[q] * e[A];
    acc[0] += f * e[N];
    acc[1] += f * e[N + 1];
  }
  rate->du[0] -= acc[0] / rhoi;
  rate->du[1] -= acc[1] / rhoi;
  t->power -= P->vol[i] * P->invgamma[i] * (ri[dim] * acc[0] + ri[dim + 1] * acc[1]);
}

static void Viscosity(FSTerm t, const FSParticles *P, const FSWallView *B, const FSWallNeighbourhood *nb, FSRate *rate)
{
  const PetscInt   dim = P->dim, i = nb->i, N = B->normal, A = B->measure, C = B->centroid;
  const PetscReal *ri = &P->rec[i * P->stride], rhoi = ri[2 * dim];
  const PetscReal  c = P->nu * P->rho0 / rhoi, Vi = P->vol[i], dmin = 0.5 * P->dx;
  PetscReal        acc[2] = {0, 0};
  for (PetscInt q = 0; q < nb->n; q++) {
    const PetscInt   k = nb->k[q];
    const PetscReal *e = &B->element[k * B->stride];
    PetscReal        d, f, *L;
    if (!B->noslip[B->elementwall[k]]) continue;
    d = (e[0] - ri[0]) * e[N] + (e[1] - ri[1]) * e[N + 1];
    if (d <= 0) continue; /* a face turned away (-fs_walls_visibility all): the other side's wall */
    f = c * nb->W[q] * e[A] / PetscMax(d, dmin);
    acc[0] -= f * ri[dim];
    acc[1] -= f * ri[dim + 1];
    L = &B->load[6 * B->elementwall[k]];
    L[0] += Vi * rhoi * f * ri[dim];
    L[1] += Vi * rhoi * f * ri[dim + 1];
    L[5] += Vi * rhoi * f * ((e[C] - B->loadpoint[0]) * ri[dim + 1] - (e[C + 1] - B->loadpoint[1]) * ri[dim]);
  }
  rate->du[0] += acc[0];
  rate->du[1] += acc[1];
  t->power += ri[2 * dim + 1] * P->invgamma[i] * (ri[dim] * acc[0] + ri[dim + 1] * acc[1]);
}

PETSC_EXTERN PetscErrorCode FSTermCreate_WallContinuity(FSTerm t)
{
  PetscFunctionBegin;
  t->has_power = PETSC_TRUE;
  t->ops.wall  = Continuity;
  PetscFunctionReturn(0);
}

PETSC_EXTERN PetscErrorCode FSTermCreate_WallPressure(FSTerm t)
{
  PetscFunctionBegin;
  t->renormalized = PETSC_TRUE;
  t->has_power    = PETSC_TRUE;
  t->ops.wall     = Pressure;
  PetscFunctionReturn(0);
}

PETSC_EXTERN PetscErrorCode FSTermCreate_WallViscosity(FSTerm t)
{
  PetscFunctionBegin;
  t->renormalized = PETSC_TRUE;
  t->has_power    = PETSC_TRUE;
  t->ops.wall     = Viscosity;
  PetscFunctionReturn(0);
}
