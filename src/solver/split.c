/*
   The split step: terms flagged split (term delta with -fs_delta_split) are not evaluated in the integrator's
   stages; after each step the density diffusion they make is advanced over the step's dt by RKL2, the
   second-order Runge-Kutta-Legendre super-time-stepping method (Meyer, Balsara & Aslam 2014), whose s stages
   are stable for dt lambda <= (s^2 + s - 2)/2 where explicit RK4 needs dt lambda <= 2.79: the stages grow as
   sqrt(dt lambda), the steps of an explicit method as dt lambda.
   Within the split step the particles do not move; the diffusion's coefficients (delta_i from the strain
   rates, the renormalized density gradients of the correction) are taken at the state after the step and held
   over its stages (the volumes follow the stages' densities), which keeps the operator, to the order of
   |rho/rho0 - 1|, a linear, symmetric (in the volume-weighted product) diffusion with real eigenvalues in
   [-lambda, 0], as RKL2 needs; lambda is bounded by Gershgorin's theorem with the largest
   diffusivity kappa: lambda <= FS_SPLIT_GERSHGORIN kappa / h^2 (docs/performance.md, "The density diffusion
   split off"). The change of the compressibility energy the stages make is booked as the term's work, so the
   energy budget closes as with the term in the stages.
*/
#include "solver/solverimpl.h"

/* Gershgorin's bound on the diffusion operator's eigenvalues: 2 sum_j 2 h c0 delta_ij |W'_ij|/r_ij V_j, that is
   14 kappa/h^2 on a lattice with the Wendland kernel (2-D; 3-D less), with a margin for compressed arrangements */
#define FS_SPLIT_GERSHGORIN 16.0

/*
   FSRKL2Coefficients - the coefficients of stage j (1 <= j <= s) of RKL2 with s stages:
     Y_1 = Y_0 + mut_1 dt L(Y_0),
     Y_j = mu_j Y_{j-1} + nu_j Y_{j-2} + (1 - mu_j - nu_j) Y_0 + mut_j dt L(Y_{j-1}) + gt_j dt L(Y_0),
   with w1 = 4/(s^2 + s - 2), b_j = (j^2 + j - 2)/(2 j (j + 1)) (b_0 = b_1 = 1/3), mu_j = (2j - 1)/j b_j/b_{j-1},
   nu_j = -(j - 1)/j b_j/b_{j-2}, mut_j = mu_j w1 (mut_1 = b_1 w1), gt_j = -(1 - b_{j-1}) mut_j.

   Not collective
*/
void FSRKL2Coefficients(PetscInt s, PetscInt j, PetscReal *mu, PetscReal *nu, PetscReal *mut, PetscReal *gt)
{
  const PetscReal w1 = 4.0 / (PetscReal)(s * s + s - 2);
#define FS_RKL2_B(k) ((k) < 2 ? 1.0 / 3.0 : (PetscReal)((k) * (k) + (k)-2) / (2.0 * (k) * ((k) + 1)))
  if (j == 1) {
    *mu = *nu = *gt = 0;
    *mut            = FS_RKL2_B(1) * w1;
    return;
  }
  *mu  = (2.0 * j - 1.0) / j * FS_RKL2_B(j) / FS_RKL2_B(j - 1);
  *nu  = -(j - 1.0) / j * FS_RKL2_B(j) / FS_RKL2_B(j - 2);
  *mut = *mu * w1;
  *gt  = -(1.0 - FS_RKL2_B(j - 1)) * *mut;
#undef FS_RKL2_B
}

/* FSRKL2Stages - the fewest stages (at least 2) for which RKL2 is stable at dt lambda = z: (s^2 + s - 2)/2 >= z */
PetscInt FSRKL2Stages(PetscReal z)
{
  PetscInt s = 2;
  while ((PetscReal)(s * s + s - 2) < 2.0 * z) s++;
  return s;
}

/* the split terms' drho/dt of the owned particles at the records' densities, into L */
static void FSSplitRates(FSSolver s, const FSParticles *P, PetscReal *L)
{
  for (PetscInt i = 0; i < s->pw.nowned; i++) {
    FSNeighbourhood nb;
    FSRate          rate = {0, {0, 0, 0}, {0, 0, 0}};
    FSSolverNeighbourhood(s, i, &nb);
    for (PetscInt t = 0; t < s->terms.nterms; t++) {
      FSTerm term = s->terms.term[t];
      if (term->split) term->ops.interact(term, P, &nb, &rate);
    }
    L[i] = rate.drho;
  }
}

/* the densities rho (owned, then the ghosts' filled here) into the records, with the volumes and pressures */
static PetscErrorCode FSSplitSetDensities(FSSolver s, PetscReal *rho)
{
  const PetscInt dim = s->opt.dim, S = s->pw.stride, n = s->pw.nowned, ng = s->pw.halo.nghost;

  PetscFunctionBegin;
  PetscCall(PetscLogEventBegin(FS_Halo, 0, 0, 0, 0));
  PetscCall(FSHaloRefreshScalar(&s->pw.halo, rho));
  PetscCall(PetscLogEventEnd(FS_Halo, 0, 0, 0, 0));
  for (PetscInt k = 0; k < n + ng; k++) s->pw.rec[k * S + 2 * dim] = rho[k];
  FSSolverVolumesAndPressures(s, 0, n + ng);
  PetscFunctionReturn(0);
}

/*
   FSSolverSplitStep - advances the split terms' density diffusion over dt at the state U after a step
   (see the top of this file); books the change of the compressibility energy as the terms' work. Does nothing
   without a split term.

   Collective
*/
PetscErrorCode FSSolverSplitStep(FSSolver s, PetscReal dt)
{
  const PetscInt dim = s->opt.dim, S = s->pw.stride, US = s->state.ustride, n = s->pw.nowned;
  FSTerm         split = NULL;
  FSParticles    P;
  PetscReal      kappa = 0, de = 0, *Y0, *Y1, *Y2, *M0, *L, *rho;
  PetscScalar   *u;
  PetscInt       nstages, ng;

  PetscFunctionBegin;
  for (PetscInt t = 0; t < s->terms.nterms; t++) {
    if (!s->terms.term[t]->split) continue;
    PetscCheck(!split, PetscObjectComm((PetscObject)s), PETSC_ERR_SUP,
               "Terms %s and %s are both split: the split step books its energy to one term", split->name,
               s->terms.term[t]->name);
    split = s->terms.term[t];
  }
  if (!split || dt <= 0 || s->pw.nglobal_particles == 0) PetscFunctionReturn(0);
  PetscCall(PetscLogEventBegin(FS_Split, 0, 0, 0, 0));
  s->state.evaluated = PETSC_FALSE; /* the work arrays will hold the split stages, not an evaluation at U */
  PetscCall(VecGetArray(s->state.U, &u));
  /* the state's records, the first pass's fields (density gradients, strain rates) and the term's coefficients (its
     prepare; the power its pair sums add up is the next right-hand side's to reset) */
  PetscCall(FSSolverGatherRecordsBegin(s, u));
  PetscCall(FSSolverGatherRecordsEnd(s));
  PetscCall(FSSolverFirstPass(s));
  PetscCall(PetscLogEventBegin(FS_Halo, 0, 0, 0, 0));
  PetscCall(FSHaloRefreshAux(&s->pw.halo, s->pw.aux));
  PetscCall(PetscLogEventEnd(FS_Halo, 0, 0, 0, 0));
  PetscCall(FSSolverGetParticles(s, &P));
  if (split->ops.prepare) PetscCall((*split->ops.prepare)(split, &P));
  kappa = split->max_viscosity;
  PetscCall(MPIU_Allreduce(MPI_IN_PLACE, &kappa, 1, MPIU_REAL, MPI_MAX, PetscObjectComm((PetscObject)s)));
  nstages = FSRKL2Stages(dt * FS_SPLIT_GERSHGORIN * kappa / (s->opt.h * s->opt.h));
  s->state.split_stages += nstages;
  s->state.split_max_stages = PetscMax(s->state.split_max_stages, nstages);

  ng = s->pw.halo.nghost;
  if (n + ng > s->pw.splitcap) { /* kept between steps, grown as the particles are */
    PetscCall(PetscFree(s->pw.split));
    s->pw.splitcap = PetscMax(n + ng, (PetscInt)(1.25 * s->pw.splitcap));
    PetscCall(PetscMalloc1(6 * (PetscInt64)s->pw.splitcap, &s->pw.split));
  }
  Y0  = s->pw.split;
  Y1  = Y0 + s->pw.splitcap;
  Y2  = Y1 + s->pw.splitcap;
  M0  = Y2 + s->pw.splitcap;
  L   = M0 + s->pw.splitcap;
  rho = L + s->pw.splitcap;
  for (PetscInt i = 0; i < n; i++) Y0[i] = s->pw.rec[i * S + 2 * dim];
  FSSplitRates(s, &P, M0);
  { /* Y1 (then Y_{j-1}) in Y1, Y_{j-2} in Y2 */
    PetscReal mu, nu, mut, gt;
    FSRKL2Coefficients(nstages, 1, &mu, &nu, &mut, &gt);
    for (PetscInt i = 0; i < n; i++) {
      Y2[i] = Y0[i];
      Y1[i] = Y0[i] + mut * dt * M0[i];
    }
    for (PetscInt j = 2; j <= nstages; j++) {
      for (PetscInt i = 0; i < n; i++) rho[i] = Y1[i];
      PetscCall(FSSplitSetDensities(s, rho));
      FSSplitRates(s, &P, L);
      FSRKL2Coefficients(nstages, j, &mu, &nu, &mut, &gt);
      for (PetscInt i = 0; i < n; i++) {
        const PetscReal y = mu * Y1[i] + nu * Y2[i] + (1 - mu - nu) * Y0[i] + mut * dt * L[i] + gt * dt * M0[i];
        Y2[i]             = Y1[i];
        Y1[i]             = y;
      }
    }
  }
  for (PetscInt i = 0; i < n; i++) {
    const PetscReal m = s->pw.rec[i * S + 2 * dim + 1];
    de += m * (FSSolverCompressibilityEnergy(s, Y1[i]) - FSSolverCompressibilityEnergy(s, Y0[i]));
    u[i * US + 2 * dim] = Y1[i];
  }
  PetscCall(VecRestoreArray(s->state.U, &u));
  PetscCall(FSSolverEnergyAddTermWork(s, split, de));
  PetscCall(PetscLogEventEnd(FS_Split, 0, 0, 0, 0));
  PetscFunctionReturn(0);
}
