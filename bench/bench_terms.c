/*
   bench_terms: what the plug-in terms cost against the same physics written inline.

   Sets up the Taylor-Green case (options as for flexslosh, e.g. -fs_dx 0.005), evaluates the right-hand
   side with the registry's terms (continuity, delta, pressure, viscosity, les_viscosity), then computes
   the same rates with one hand-fused loop over the same candidate lists, checks that both agree to
   round-off, and prints the time of the pair pass per evaluation for both and their ratio.

     build/bench_terms -fs_dx 0.005 [-reps 20]
*/
#include "solver/solverimpl.h"

/* The five terms fused by hand: the same formulas as src/terms/impls/{continuity,delta,pressure,viscosity}.c. */
static void FusedRates(FSSolver s, const PetscReal *delta, const PetscReal *a, PetscReal *f, PetscReal Kvisc)
{
  const PetscInt   dim = s->opt.dim, S = s->pw.stride, US = s->state.ustride, A = s->pw.auxstride;
  const PetscReal *rec = s->pw.rec, *aux = s->pw.aux, *V = s->pw.vol, *p = s->pw.pressure;
  const PetscReal  hc = s->opt.h * s->opt.c0, nu = s->opt.nu, rho0 = s->opt.rho0;

  for (PetscInt i = 0; i < s->pw.nowned; i++) {
    const PetscReal *ri = &rec[i * S], *xi = ri, *ui = ri + dim, rhoi = ri[2 * dim], *gi = &aux[i * A];
    const PetscReal  di = delta[i], ai = a[i];
    PetscReal        cont = 0, diff = 0, acc_p[3] = {0, 0, 0}, acc_v[3] = {0, 0, 0}, acc_t[3] = {0, 0, 0};
    FSCandidateIter  it;
    PetscInt         j;
    FSNeighboursCandidateBegin(&s->pw.nbrs, i, &it);
    while (FSNeighboursCandidateNext(&s->pw.nbrs, &it, &j)) { /* the candidates within the support */
      const PetscReal *rj = &rec[j * S], *gj = &aux[j * A];
      PetscReal        dx[3], gw[3], r2 = 0, F, du_dx = 0, du_g = 0, corr = 0, proj = 0;
      for (PetscInt d = 0; d < dim; d++) {
        dx[d] = rj[d] - xi[d];
        r2 += dx[d] * dx[d];
      }
      if (r2 >= s->pw.kernel.support2) continue;
      F = FSKernelF(&s->pw.kernel, PetscSqrtReal(r2));
      for (PetscInt d = 0; d < dim; d++) gw[d] = -F * dx[d];
      for (PetscInt d = 0; d < dim; d++) {
        du_g += (rj[dim + d] - ui[d]) * gw[d];
        du_dx += (rj[dim + d] - ui[d]) * dx[d];
        corr += (gi[d] + gj[d]) * dx[d];
        proj += dx[d] * gw[d];
      }
      cont += du_g * V[j];
      if (di + delta[j] > 0)
        diff += 2.0 * di * delta[j] / (di + delta[j]) * 2.0 * ((rj[2 * dim] - rhoi) - 0.5 * corr) / r2 * proj * V[j];
      for (PetscInt d = 0; d < dim; d++) {
        acc_p[d] += (p[i] + p[j]) * V[j] * gw[d];
        acc_v[d] += du_dx / r2 * V[j] * gw[d];
        if (ai > 0 && a[j] > 0) acc_t[d] += 2.0 * ai * a[j] / (ai + a[j]) * du_dx / r2 * V[j] * gw[d];
      }
    }
    for (PetscInt d = 0; d < dim; d++) {
      f[i * US + d]       = ui[d];
      f[i * US + dim + d] = -acc_p[d] / rhoi + Kvisc * nu * rho0 / rhoi * acc_v[d] + hc * rho0 / rhoi * acc_t[d];
    }
    f[i * US + 2 * dim] = -rhoi * cont + hc * diff;
  }
}

int main(int argc, char **argv)
{
  FSSolver           s;
  Vec                F;
  PetscScalar       *f, *g;
  const PetscScalar *u;
  PetscInt           reps = 20, n;
  PetscReal         *delta, *a, err = 0, scale = 0;
  PetscLogDouble     t0, t1;
  PetscEventPerfInfo info;
  PetscMPIInt        size;

  PetscFunctionBeginUser;
  PetscCall(PetscInitialize(&argc, &argv, NULL, "bench_terms: plug-in terms against the same physics inline\n"));
  PetscCallMPI(MPI_Comm_size(PETSC_COMM_WORLD, &size));
  PetscCheck(size == 1, PETSC_COMM_WORLD, PETSC_ERR_SUP, "Run bench_terms on one rank");
  PetscCall(PetscLogDefaultBegin());
  PetscCall(PetscOptionsGetInt(NULL, NULL, "-reps", &reps, NULL));
  PetscCall(PetscOptionsSetValue(NULL, "-fs_terms", "continuity,delta,pressure,viscosity,les_viscosity"));
  PetscCall(PetscOptionsSetValue(NULL, "-fs_output", "0"));
  PetscCall(FSSolverCreate(PETSC_COMM_WORLD, &s));
  PetscCall(FSSolverSetFromOptions(s));
  PetscCall(FSSolverSetUp(s));
  n = s->pw.nowned;
  PetscCall(VecDuplicate(s->state.U, &F));
  PetscCall(PetscMalloc2(n + s->pw.halo.nghost, &delta, n + s->pw.halo.nghost, &a));

  /* the registry: reps evaluations, pair-pass time from its log event */
  PetscCall(VecGetArrayRead(s->state.U, &u));
  PetscCall(VecGetArray(F, &f));
  PetscCall(FSSolverEvaluateRates(s, u, f, PETSC_FALSE)); /* warm-up; fills lists, aux, volumes, pressures */
  PetscCall(PetscLogEventGetPerfInfo(PETSC_DETERMINE, FS_PairPass, &info));
  t0 = info.time;
  for (PetscInt r = 0; r < reps; r++) PetscCall(FSSolverEvaluateRates(s, u, f, PETSC_FALSE));
  PetscCall(PetscLogEventGetPerfInfo(PETSC_DETERMINE, FS_PairPass, &info));
  t1 = info.time;
  {
    const PetscReal treg = (t1 - t0) / reps;
    const PetscReal L = 2.0 * s->opt.h, cd = 1.5 * 1.5 * L * L / (s->opt.c0 * s->opt.h),
                    ca = 0.12 * 0.12 * L * L * 2.0 * (s->opt.dim + 2) / (s->opt.c0 * s->opt.h);
    PetscLogDouble w0, w1;
    PetscCall(PetscMalloc1(n * s->state.ustride, &g));
    PetscCall(PetscTime(&w0));
    for (PetscInt r = 0; r < reps; r++) {
      /* per-particle coefficients, as the terms' prepare does */
      for (PetscInt k = 0; k < n + s->pw.halo.nghost; k++) {
        delta[k] = cd * s->pw.aux[k * s->pw.auxstride + s->opt.dim];
        a[k]     = ca * s->pw.aux[k * s->pw.auxstride + s->opt.dim];
      }
      FusedRates(s, delta, a, g, 2.0 * (s->opt.dim + 2));
    }
    PetscCall(PetscTime(&w1));
    for (PetscInt k = 0; k < n * s->state.ustride; k++) {
      err   = PetscMax(err, PetscAbsReal(f[k] - g[k]));
      scale = PetscMax(scale, PetscAbsReal(f[k]));
    }
    PetscCall(PetscPrintf(PETSC_COMM_WORLD,
                          "bench_terms: %" PetscInt_FMT " particles, %" PetscInt64_FMT " pairs, %" PetscInt_FMT
                          " repetitions\n",
                          n, s->pw.nbrs.npairs, reps));
    PetscCall(PetscPrintf(PETSC_COMM_WORLD,
                          "  pair pass with the plug-in terms   %.4f s per evaluation (%.3g pair visits/s)\n", treg,
                          (double)s->pw.nbrs.npairs / treg));
    PetscCall(PetscPrintf(PETSC_COMM_WORLD,
                          "  the same terms fused inline        %.4f s per evaluation (%.3g pair visits/s)\n",
                          (w1 - w0) / reps, (double)s->pw.nbrs.npairs / ((w1 - w0) / reps)));
    PetscCall(
        PetscPrintf(PETSC_COMM_WORLD, "  cost of the registry: %.2f x the inline loop\n", treg / ((w1 - w0) / reps)));
    PetscCall(PetscPrintf(PETSC_COMM_WORLD,
                          "  largest difference of the rates: %.3g (relative to the largest rate %.3g)\n",
                          (double)(err / scale), (double)scale));
    PetscCall(PetscFree(g));
  }
  PetscCall(VecRestoreArray(F, &f));
  PetscCall(VecRestoreArrayRead(s->state.U, &u));
  PetscCheck(err <= 1e-10 * scale, PETSC_COMM_WORLD, PETSC_ERR_PLIB,
             "The plug-in terms and the inline loop disagree: %g", (double)(err / scale));
  PetscCall(PetscFree2(delta, a));
  PetscCall(VecDestroy(&F));
  PetscCall(FSSolverDestroy(&s));
  PetscCall(PetscFinalize());
  return 0;
}
