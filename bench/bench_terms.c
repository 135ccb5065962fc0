/*
   bench_terms: what the plug-in terms cost against the same physics written inline.

   Sets up the Taylor-Green case (options as for flexslosh, e.g. -fs_dx 0.005), evaluates the right-hand
   side with the registry's terms (continuity, delta, pressure, viscosity, les_viscosity), then computes
   the same rates with one hand-fused loop over the same candidate lists, checks that both agree to
   round-off, and prints the time of the pair pass per evaluation for both and their ratio. Then the same
   fused loop visiting each pair once (a half list of the pairs within the support, picked once as the pair
   cache picks them: an owned particle's pairs with the owned particles after it and with its ghosts), each
   pair's terms added to both particles with the signs of their symmetry: what evaluating a pair once would
   buy, at rates equal to round-off only (the sums are taken in another order).

     build/bench_terms -fs_dx 0.005 [-reps 20]
*/
#include "solver/solverimpl.h"

/* a pair's shared quantities: grad W = -F (x_j - x_i), (u_j - u_i).grad W, (u_j - u_i).(x_j - x_i), the delta term's
   correction (<grad rho>_i + <grad rho>_j).(x_j - x_i) and (x_j - x_i).grad W */
static inline void PairDots(PetscInt dim, PetscReal F, const PetscReal dx[], const PetscReal ui[], const PetscReal uj[],
                            const PetscReal gi[], const PetscReal gj[], PetscReal gw[], PetscReal *du_g,
                            PetscReal *du_dx, PetscReal *corr, PetscReal *proj)
{
  *du_g = *du_dx = *corr = *proj = 0;
  for (PetscInt d = 0; d < dim; d++) gw[d] = -F * dx[d];
  for (PetscInt d = 0; d < dim; d++) {
    *du_g += (uj[d] - ui[d]) * gw[d];
    *du_dx += (uj[d] - ui[d]) * dx[d];
    *corr += (gi[d] + gj[d]) * dx[d];
    *proj += dx[d] * gw[d];
  }
}

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
      PairDots(dim, F, dx, ui, rj + dim, gi, gj, gw, &du_g, &du_dx, &corr, &proj);
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

/* The half list: for each owned particle its pairs within the support with owned particles after it and with
   ghosts (start[i]..start[i+1] in js[], their F(r) in Fs[]) */
static PetscErrorCode HalfPairs(FSSolver s, PetscInt **start, PetscInt **js, PetscReal **Fs)
{
  const PetscInt   dim = s->opt.dim, S = s->pw.stride, n = s->pw.nowned;
  const PetscReal *rec = s->pw.rec;
  PetscInt         np  = 0;

  PetscFunctionBegin;
  PetscCall(PetscMalloc1(n + 1, start));
  PetscCall(PetscMalloc2(s->pw.nbrs.npairs, js, s->pw.nbrs.npairs, Fs));
  for (PetscInt i = 0; i < n; i++) {
    FSCandidateIter it;
    PetscInt        j;
    (*start)[i] = np;
    FSNeighboursCandidateBegin(&s->pw.nbrs, i, &it);
    while (FSNeighboursCandidateNext(&s->pw.nbrs, &it, &j)) {
      PetscReal r2 = 0;
      if (j < n && j <= i) continue;
      for (PetscInt d = 0; d < dim; d++) r2 += (rec[j * S + d] - rec[i * S + d]) * (rec[j * S + d] - rec[i * S + d]);
      if (r2 >= s->pw.kernel.support2) continue;
      (*js)[np]   = j;
      (*Fs)[np++] = FSKernelF(&s->pw.kernel, PetscSqrtReal(r2));
    }
  }
  (*start)[n] = np;
  PetscFunctionReturn(0);
}

/* FusedRates() visiting each pair of the half list once; acc: scratch of 2 + 3 dim values a particle */
static void FusedRatesSymmetric(FSSolver s, const PetscInt *start, const PetscInt *js, const PetscReal *Fs,
                                const PetscReal *delta, const PetscReal *a, PetscReal *acc, PetscReal *f,
                                PetscReal Kvisc)
{
  const PetscInt   dim = s->opt.dim, S = s->pw.stride, US = s->state.ustride, A = s->pw.auxstride, n = s->pw.nowned;
  const PetscInt   W   = 2 + 3 * dim; /* cont, diff, acc_p, acc_v, acc_t */
  const PetscReal *rec = s->pw.rec, *aux = s->pw.aux, *V = s->pw.vol, *p = s->pw.pressure;
  const PetscReal  hc = s->opt.h * s->opt.c0, nu = s->opt.nu, rho0 = s->opt.rho0;

  for (PetscInt k = 0; k < n * W; k++) acc[k] = 0;
  for (PetscInt i = 0; i < n; i++) {
    const PetscReal *ri = &rec[i * S], *xi = ri, *ui = ri + dim, rhoi = ri[2 * dim], *gi = &aux[i * A];
    const PetscReal  di = delta[i], ai = a[i];
    PetscReal       *ci = &acc[i * W];
    for (PetscInt q = start[i]; q < start[i + 1]; q++) {
      const PetscInt   j  = js[q];
      const PetscReal *rj = &rec[j * S], *gj = &aux[j * A], F = Fs[q];
      PetscReal        dx[3], gw[3], r2 = 0, du_dx = 0, du_g = 0, corr = 0, proj = 0, diff = 0, visc, turb = 0;
      for (PetscInt d = 0; d < dim; d++) {
        dx[d] = rj[d] - xi[d];
        r2 += dx[d] * dx[d];
      }
      PairDots(dim, F, dx, ui, rj + dim, gi, gj, gw, &du_g, &du_dx, &corr, &proj);
      if (di + delta[j] > 0)
        diff = 2.0 * di * delta[j] / (di + delta[j]) * 2.0 * ((rj[2 * dim] - rhoi) - 0.5 * corr) / r2 * proj;
      visc = du_dx / r2;
      if (ai > 0 && a[j] > 0) turb = 2.0 * ai * a[j] / (ai + a[j]) * du_dx / r2;
      ci[0] += du_g * V[j];
      ci[1] += diff * V[j];
      for (PetscInt d = 0; d < dim; d++) {
        ci[2 + d] += (p[i] + p[j]) * V[j] * gw[d];
        ci[2 + dim + d] += visc * V[j] * gw[d];
        ci[2 + 2 * dim + d] += turb * V[j] * gw[d];
      }
      if (j < n) { /* the pair's share of the owned particle j: grad W and x_j - x_i change sign */
        PetscReal *cj = &acc[j * W];
        cj[0] += du_g * V[i];
        cj[1] -= diff * V[i];
        for (PetscInt d = 0; d < dim; d++) {
          cj[2 + d] -= (p[i] + p[j]) * V[i] * gw[d];
          cj[2 + dim + d] -= visc * V[i] * gw[d];
          cj[2 + 2 * dim + d] -= turb * V[i] * gw[d];
        }
      }
    }
  }
  for (PetscInt i = 0; i < n; i++) {
    const PetscReal *ri = &rec[i * S], *ui = ri + dim, rhoi = ri[2 * dim], *ci = &acc[i * W];
    for (PetscInt d = 0; d < dim; d++) {
      f[i * US + d]       = ui[d];
      f[i * US + dim + d] = -ci[2 + d] / rhoi + Kvisc * nu * rho0 / rhoi * ci[2 + dim + d] +
                            hc * rho0 / rhoi * ci[2 + 2 * dim + d];
    }
    f[i * US + 2 * dim] = -rhoi * ci[0] + hc * ci[1];
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
    { /* each pair once */
      PetscInt  *start, *js;
      PetscReal *Fs, *acc, errs = 0;
      PetscCall(HalfPairs(s, &start, &js, &Fs));
      PetscCall(PetscMalloc1(n * (2 + 3 * s->opt.dim), &acc));
      PetscCall(PetscTime(&w0));
      for (PetscInt r = 0; r < reps; r++) {
        for (PetscInt k = 0; k < n + s->pw.halo.nghost; k++) {
          delta[k] = cd * s->pw.aux[k * s->pw.auxstride + s->opt.dim];
          a[k]     = ca * s->pw.aux[k * s->pw.auxstride + s->opt.dim];
        }
        FusedRatesSymmetric(s, start, js, Fs, delta, a, acc, g, 2.0 * (s->opt.dim + 2));
      }
      PetscCall(PetscTime(&w1));
      for (PetscInt k = 0; k < n * s->state.ustride; k++) errs = PetscMax(errs, PetscAbsReal(f[k] - g[k]));
      PetscCall(PetscPrintf(PETSC_COMM_WORLD,
                            "  the same, each pair once            %.4f s per evaluation (%" PetscInt_FMT
                            " pairs; the registry %.2f x it; rates to %.3g)\n",
                            (w1 - w0) / reps, start[n], treg / ((w1 - w0) / reps), (double)(errs / scale)));
      PetscCheck(errs <= 1e-10 * scale, PETSC_COMM_WORLD, PETSC_ERR_PLIB,
                 "The terms evaluated once a pair disagree with the plug-in terms: %g", (double)(errs / scale));
      PetscCall(PetscFree(acc));
      PetscCall(PetscFree(start));
      PetscCall(PetscFree2(js, Fs));
    }
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
