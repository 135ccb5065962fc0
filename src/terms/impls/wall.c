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
   (out of the liquid), a its length (2-D) or area (3-D). Each body is written for a compile-time
   dimension D and called with 2 or 3 (FS_ALWAYS_INLINE in flexslosh.h). */
FS_ALWAYS_INLINE void ContinuityD(PetscInt D, FSTerm t, const FSParticles *P, const FSWallView *B,
                                  const FSWallNeighbourhood *nb, FSRate *rate)
{
  const PetscInt   N = B->normal, A = B->measure;
  const PetscReal *ri  = &P->rec[nb->i * P->stride];
  PetscReal        sum = 0;
  for (PetscInt q = 0; q < nb->n; q++) {
    const PetscReal *e  = &B->element[nb->k[q] * B->stride];
    PetscReal        un = 0;
    for (PetscInt d = 0; d < D; d++) un += ri[D + d] * e[N + d];
    sum += un * nb->W[q] * e[A];
  }
  rate->drho += ri[2 * D] * sum;
  t->power += P->vol[nb->i] * P->pressure[nb->i] * sum;
}

static void Continuity(FSTerm t, const FSParticles *P, const FSWallView *B, const FSWallNeighbourhood *nb, FSRate *rate)
{
  if (P->dim == 2) ContinuityD(2, t, P, B, nb, rate);
  else ContinuityD(3, t, P, B, nb, rate);
}

FS_ALWAYS_INLINE void PressureD(PetscInt D, FSTerm t, const FSParticles *P, const FSWallView *B,
                                const FSWallNeighbourhood *nb, FSRate *rate)
{
  const PetscInt   i = nb->i, N = B->normal, A = B->measure;
  const PetscReal *ri = &P->rec[i * P->stride], rhoi = ri[2 * D], pi = P->pressure[i];
  PetscReal        acc[3] = {0, 0, 0}, pw = 0;
  for (PetscInt q = 0; q < nb->n; q++) {
    const PetscInt   k = nb->k[q];
    const PetscReal *e = &B->element[k * B->stride];
    const PetscReal  f = (pi + B->pressure[k]) * nb->W[q] * e[A];
    for (PetscInt d = 0; d < D; d++) acc[d] += f * e[N + d];
  }
  for (PetscInt d = 0; d < D; d++) {
    rate->du[d] -= acc[d] / rhoi;
    pw += ri[D + d] * acc[d];
  }
  t->power -= P->vol[i] * P->invgamma[i] * pw;
}

static void Pressure(FSTerm t, const FSParticles *P, const FSWallView *B, const FSWallNeighbourhood *nb, FSRate *rate)
{
  if (P->dim == 2) PressureD(2, t, P, B, nb, rate);
  else PressureD(3, t, P, B, nb, rate);
}

FS_ALWAYS_INLINE void ViscosityD(PetscInt D, FSTerm t, const FSParticles *P, const FSWallView *B,
                                 const FSWallNeighbourhood *nb, FSRate *rate)
{
  const PetscInt   i = nb->i, N = B->normal, A = B->measure, C = B->centroid;
  const PetscReal *ri = &P->rec[i * P->stride], rhoi = ri[2 * D];
  const PetscReal  c = P->nu * P->rho0 / rhoi, Vi = P->vol[i], dmin = 0.5 * P->dx;
  PetscReal        acc[3] = {0, 0, 0}, pw = 0;
  for (PetscInt q = 0; q < nb->n; q++) {
    const PetscInt   k = nb->k[q];
    const PetscReal *e = &B->element[k * B->stride];
    PetscReal        d = 0, f, sw, r[3] = {0, 0, 0}, *L;
    if (!B->noslip[B->elementwall[k]]) continue;
    for (PetscInt a = 0; a < D; a++) d += (e[a] - ri[a]) * e[N + a];
    if (d <= 0) continue; /* a face turned away (-fs_walls_visibility all): the other side's wall */
    f  = c * nb->W[q] * e[A] / PetscMax(d, dmin);
    sw = Vi * rhoi * f; /* the shear force on the wall is sw u_i */
    L  = &B->load[FS_WALL_LOAD_STRIDE * B->elementwall[k]];
    for (PetscInt a = 0; a < D; a++) {
      acc[a] -= f * ri[D + a];
      L[a] += sw * ri[D + a];
      r[a] = e[C + a] - B->loadpoint[a];
    }
    if (D == 3) {
      L[3] += sw * (r[1] * ri[D + 2] - r[2] * ri[D + 1]);
      L[4] += sw * (r[2] * ri[D] - r[0] * ri[D + 2]);
    }
    L[5] += sw * (r[0] * ri[D + 1] - r[1] * ri[D]);
  }
  for (PetscInt a = 0; a < D; a++) {
    rate->du[a] += acc[a];
    pw += ri[D + a] * acc[a];
  }
  t->power += ri[2 * D + 1] * P->invgamma[i] * pw;
}

static void Viscosity(FSTerm t, const FSParticles *P, const FSWallView *B, const FSWallNeighbourhood *nb, FSRate *rate)
{
  if (P->dim == 2) ViscosityD(2, t, P, B, nb, rate);
  else ViscosityD(3, t, P, B, nb, rate);
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
