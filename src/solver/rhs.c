/*
   The right-hand side of the particle ODE system, evaluated by TS at every stage:
     halo refresh -> first pass (correction matrix L_i, renormalized density gradient, strain rate
     ||D||_i) -> ghost refresh of those -> the terms' pair pass.
   The first pass picks the pairs within the support from the candidate lists as it visits them
   (FSNeighboursPick) with their kernel factors F(r), and keeps both in the pair cache (-fs_pair_cache), from which the
   pair pass takes them (else it picks them again); the kernel gradients are computed once per pair and pass, for all
   terms. The first pass runs only when a selected term needs it.
*/
#include "solver/solverimpl.h"

/* Inverse of the dim x dim matrix M (row-major); falls back to the identity when M is nearly
   singular (a particle with too few neighbours, e.g. isolated spray), as is usual for L_i. */
static inline void FSInvertCorrection(PetscInt dim, const PetscReal M[], PetscReal Minv[])
{
  if (dim == 2) {
    const PetscReal det = M[0] * M[3] - M[1] * M[2];
    if (PetscAbsReal(det) < 1e-2) {
      Minv[0] = Minv[3] = 1;
      Minv[1] = Minv[2] = 0;
      return;
    }
    Minv[0] = M[3] / det;
    Minv[1] = -M[1] / det;
    Minv[2] = -M[2] / det;
    Minv[3] = M[0] / det;
  } else {
    const PetscReal c0 = M[4] * M[8] - M[5] * M[7], c1 = M[5] * M[6] - M[3] * M[8], c2 = M[3] * M[7] - M[4] * M[6];
    const PetscReal det = M[0] * c0 + M[1] * c1 + M[2] * c2;
    if (PetscAbsReal(det) < 1e-3) {
      for (PetscInt a = 0; a < 9; a++) Minv[a] = (a % 4 == 0) ? 1 : 0;
      return;
    }
    Minv[0] = c0 / det;
    Minv[1] = (M[2] * M[7] - M[1] * M[8]) / det;
    Minv[2] = (M[1] * M[5] - M[2] * M[4]) / det;
    Minv[3] = c1 / det;
    Minv[4] = (M[0] * M[8] - M[2] * M[6]) / det;
    Minv[5] = (M[2] * M[3] - M[0] * M[5]) / det;
    Minv[6] = c2 / det;
    Minv[7] = (M[1] * M[6] - M[0] * M[7]) / det;
    Minv[8] = (M[0] * M[4] - M[1] * M[3]) / det;
  }
}

/*
   The first pass's sums over the m pairs of a particle in 2-D (FSSolverFirstPassDim's loop for dim 2) with the two
   components of each vector in one register: each component gets the same operations in the same order as the
   scalar loop's (the same sums bit for bit), in half the instructions. M, G, Au: the sums, row-major.
*/
#if defined(FS_HAVE_REAL2)
FS_ALWAYS_INLINE void FSFirstPassSums2(PetscInt m, const PetscInt js[], const PetscReal Fs[], const PetscReal dx[],
                                       const PetscReal rec[], PetscInt S, const PetscReal ri[], const PetscReal vol[],
                                       PetscReal M[], PetscReal G[], PetscReal Au[])
{
  const FSReal2 ui = FSLoad2(&ri[2]);
  FSReal2       m0 = {0, 0}, m1 = {0, 0}, gs = {0, 0}, a0 = {0, 0}, a1 = {0, 0};

  for (PetscInt k = 0; k < m; k++) {
    const PetscReal *rj = &rec[js[k] * S], Vj = vol[js[k]], drho = (rj[4] - ri[4]) * Vj;
    const FSReal2    d = FSLoad2(&dx[2 * k]), g = -Fs[k] * d, du = (FSLoad2(&rj[2]) - ui) * Vj, dd = d * Vj;
    gs += drho * g;
    m0 += dd[0] * g;
    m1 += dd[1] * g;
    a0 += du[0] * g;
    a1 += du[1] * g;
  }
  M[0]  = m0[0];
  M[1]  = m0[1];
  M[2]  = m1[0];
  M[3]  = m1[1];
  G[0]  = gs[0];
  G[1]  = gs[1];
  Au[0] = a0[0];
  Au[1] = a0[1];
  Au[2] = a1[0];
  Au[3] = a1[1];
}
#endif

/*
   First pass over the pairs of each owned particle i:
     M_i = sum_j (x_j - x_i) (x) grad_i W_ij V_j,  L_i = M_i^{-1}   (Randles & Libersky)
     <grad rho>^L_i = L_i^T sum_j (rho_j - rho_i) grad_i W_ij V_j
     (grad u)_i = [sum_j (u_j - u_i) (x) grad_i W_ij V_j] L_i,  D_i = sym(grad u)_i,  ||D||_i = sqrt(2 D:D)
   Results go to aux[i*(dim+1)]: the density gradient, then ||D||.
   The pass picks each particle's neighbours from its candidates (FSNeighboursPick) and returns the number
   of pairs it visited. The body is written for a compile-time dimension (FS_ALWAYS_INLINE) so that the
   small dim x dim loops unroll and the sums stay in registers.
*/
FS_ALWAYS_INLINE PetscInt64 FSSolverFirstPassDim(FSSolver s, const PetscInt dim, PetscBool keep)
{
  const PetscInt   S = 2 * dim + 2, A = s->pw.auxstride, n = s->pw.nowned; /* the records' stride as a constant */
  const PetscReal *rec = s->pw.rec, *vol = s->pw.vol, R2 = s->pw.kernel.support2;
  PetscReal       *dx  = s->pw.scratch;               /* x_j - x_i of the neighbours of i */
  PetscReal       *r2s = dx + dim * s->pw.scratchcap; /* their r^2 */
  PetscInt64       np  = 0;

  for (PetscInt i = 0; i < n; i++) {
    FSCommProgress(i); /* the walls' and the ghosts' messages travel meanwhile */
    const PetscReal *ri   = &rec[i * S];
    PetscReal        M[9] = {0}, Minv[9], G[3] = {0, 0, 0}, Au[9] = {0}, J[9] = {0}, nrm = 0;
    PetscReal       *out = &s->pw.aux[i * A];
    PetscInt        *js  = keep ? s->pw.pairj + np : s->pw.scratchj; /* into the pair cache: room for i's candidates */
    PetscReal       *Fs  = keep ? s->pw.pairF + np : r2s + s->pw.scratchcap;
    const PetscInt   m   = FSNeighboursPick(&s->pw.nbrs, dim, i, rec, S, R2, js, dx, r2s);
    if (keep) s->pw.pairstart[i] = (PetscInt)np;
    np += m;
    /* F(r) of the pairs (a loop the compiler vectorizes: square roots and divisions in pairs) */
    for (PetscInt k = 0; k < m; k++) Fs[k] = FSKernelF(&s->pw.kernel, PetscSqrtReal(r2s[k]));
#if defined(FS_HAVE_REAL2)
    if (dim == 2) FSFirstPassSums2(m, js, Fs, dx, rec, S, ri, vol, M, G, Au);
    else
#endif
      for (PetscInt k = 0; k < m; k++) {
        const PetscInt   j  = js[k];
        const PetscReal *rj = &rec[j * S], *d = &dx[k * dim], F = Fs[k];
        const PetscReal  Vj = vol[j], drho = (rj[2 * dim] - ri[2 * dim]) * Vj;
        PetscReal        g[3];
        for (PetscInt a = 0; a < dim; a++) g[a] = -F * d[a];
        for (PetscInt a = 0; a < dim; a++) {
          const PetscReal du = (rj[dim + a] - ri[dim + a]) * Vj, dd = d[a] * Vj;
          G[a] += drho * g[a];
          for (PetscInt b = 0; b < dim; b++) {
            M[a * dim + b] += dd * g[b];
            Au[a * dim + b] += du * g[b];
          }
        }
      }
    FSInvertCorrection(dim, M, Minv);
    for (PetscInt a = 0; a < dim; a++) {
      PetscReal v = 0;
      for (PetscInt b = 0; b < dim; b++) v += Minv[b * dim + a] * G[b];
      out[a] = v;
      for (PetscInt b = 0; b < dim; b++) {
        PetscReal w = 0;
        for (PetscInt c = 0; c < dim; c++) w += Au[a * dim + c] * Minv[c * dim + b];
        J[a * dim + b] = w;
      }
    }
    for (PetscInt a = 0; a < dim; a++)
      for (PetscInt b = 0; b < dim; b++) {
        const PetscReal Dab = 0.5 * (J[a * dim + b] + J[b * dim + a]);
        nrm += Dab * Dab;
      }
    out[dim] = PetscSqrtReal(2.0 * nrm);
  }
  if (keep) s->pw.pairstart[n] = (PetscInt)np;
  return np;
}

/*
   FSSolverFirstPass - the first pass over the pairs (FSSolverFirstPassDim). With the pair cache (-fs_pair_cache) it
   leaves the pairs it picked and their F(r) there for the passes that follow at the same positions (the terms' pair
   pass, the split step's stages: FSSolverNeighbourhood), which then need not search the candidates again. The cache
   is sized for every candidate (an upper bound on the pairs) and the last particle's scratch; only the pairs' part of
   it is written (and resident). Without it, or past PetscInt's range, the passes pick the pairs again.
*/
PetscErrorCode FSSolverFirstPass(FSSolver s)
{
  const PetscInt   n    = s->pw.nowned;
  const PetscInt64 need = s->pw.nbrs.ncand + s->pw.nbrs.maxcand + 1;
  const PetscBool  keep = (PetscBool)((s->opt.paircache == 1 || (s->opt.paircache == 0 && s->opt.dim == 2)) &&
                                     need < PETSC_MAX_INT);

  PetscFunctionBegin;
  PetscCall(PetscLogEventBegin(FS_FirstPass, 0, 0, 0, 0));
  PetscCheck(s->pw.stride == 2 * s->opt.dim + 2, PETSC_COMM_SELF, PETSC_ERR_PLIB,
             "Records of %" PetscInt_FMT " reals: the first pass expects 2 dim + 2", s->pw.stride);
  if (keep && n + 1 > s->pw.pairstartcap) {
    PetscCall(PetscFree(s->pw.pairstart));
    s->pw.pairstartcap = PetscMax(n + 1, (PetscInt)(1.25 * s->pw.pairstartcap));
    PetscCall(PetscMalloc1(s->pw.pairstartcap, &s->pw.pairstart));
  }
  if (keep && need > s->pw.paircap) {
    PetscCall(PetscFree2(s->pw.pairj, s->pw.pairF));
    s->pw.paircap = PetscMin(PETSC_MAX_INT - 1, PetscMax(need, (PetscInt64)(1.25 * s->pw.paircap)));
    PetscCall(PetscMalloc2(s->pw.paircap, &s->pw.pairj, s->pw.paircap, &s->pw.pairF));
  }
  s->pw.nbrs.npairs = s->opt.dim == 2 ? FSSolverFirstPassDim(s, 2, keep) : FSSolverFirstPassDim(s, 3, keep);
  s->pw.pairsvalid  = keep;
  PetscCall(PetscLogEventEnd(FS_FirstPass, 0, 0, 0, 0));
  PetscFunctionReturn(0);
}

/*
   FSSolverBoundaryPrepareBegin - the boundary's work of a right-hand side on the owned particles
   (FSBoundaryPrepareBegin): their gamma, wall elements and their sums of the wall pressure, which go on
   their way to the other ranks; then 1/gamma of the owned particles, and gamma of the ghosts (for the
   symmetric, dissipative viscous terms) on its way (FSSolverBoundaryGhosts). With no-slip walls also gamma_v,
   gamma plus the share of the support behind them, which the laminar viscous terms use (FSParticles). Needs
   the owned records only.
*/
static PetscErrorCode FSSolverBoundaryPrepareBegin(FSSolver s)
{
  const PetscInt      n = s->pw.nowned;
  FSBoundaryParticles bp;
  PetscBool           noslip;

  PetscFunctionBegin;
  PetscCall(PetscLogEventBegin(FS_Walls, 0, 0, 0, 0));
  PetscCall(FSBoundaryHasNoSlip(s->boundary, &noslip));
  if (s->pw.reccap > s->pw.gammacap) { /* gamma of the owned and ghost particles */
    PetscCall(PetscFree2(s->pw.gamma, s->pw.invgamma));
    PetscCall(PetscFree2(s->pw.gammav, s->pw.invgammav));
    s->pw.gammacap = s->pw.reccap;
    PetscCall(PetscMalloc2(s->pw.gammacap, &s->pw.gamma, s->pw.gammacap, &s->pw.invgamma));
    if (noslip) PetscCall(PetscMalloc2(s->pw.gammacap, &s->pw.gammav, s->pw.gammacap, &s->pw.invgammav));
  }
  bp.dim      = s->opt.dim;
  bp.nowned   = n;
  bp.stride   = s->pw.stride;
  bp.rec      = s->pw.rec;
  bp.vol      = s->pw.vol;
  bp.pressure = s->pw.pressure;
  PetscCall(FSCouplingGetBody(s->coupling, &bp.body));
  bp.background_pressure = s->opt.background_pressure;
  PetscCall(FSBoundaryPrepareBegin(s->boundary, &bp, s->pw.gamma, s->pw.gammav));
  for (PetscInt g = 0; g < s->pw.halo.nghost; g++) s->pw.gamma[n + g] = 1;
  PetscCall(FSHaloRefreshScalarBegin(&s->pw.halo, s->pw.gamma));
  for (PetscInt k = 0; k < n; k++) s->pw.invgamma[k] = 1.0 / s->pw.gamma[k];
  if (noslip) {
    for (PetscInt k = 0; k < n; k++) s->pw.gammav[k] += s->pw.gamma[k];
    for (PetscInt g = 0; g < s->pw.halo.nghost; g++) s->pw.gammav[n + g] = 1;
    PetscCall(FSHaloRefreshScalarBegin(&s->pw.halo, s->pw.gammav));
    for (PetscInt k = 0; k < n; k++) s->pw.invgammav[k] = 1.0 / s->pw.gammav[k];
  }
  PetscCall(PetscLogEventEnd(FS_Walls, 0, 0, 0, 0));
  PetscFunctionReturn(0);
}

/* FSSolverBoundaryGhosts - gamma (and gamma_v) of the ghosts arrived (FSSolverBoundaryPrepareBegin), and their
   inverses */
static PetscErrorCode FSSolverBoundaryGhosts(FSSolver s)
{
  const PetscInt n = s->pw.nowned, ng = s->pw.halo.nghost;

  PetscFunctionBegin;
  PetscCall(PetscLogEventBegin(FS_Walls, 0, 0, 0, 0));
  PetscCall(FSHaloRefreshScalarEnd(&s->pw.halo, s->pw.gamma));
  for (PetscInt k = n; k < n + ng; k++) s->pw.invgamma[k] = 1.0 / s->pw.gamma[k];
  if (s->pw.gammav) {
    PetscCall(FSHaloRefreshScalarEnd(&s->pw.halo, s->pw.gammav));
    for (PetscInt k = n; k < n + ng; k++) s->pw.invgammav[k] = 1.0 / s->pw.gammav[k];
  }
  PetscCall(PetscLogEventEnd(FS_Walls, 0, 0, 0, 0));
  PetscFunctionReturn(0);
}

/*
   FSSolverWallPass - the terms that act through the wall segments (boundary integrals), over the
   owned particles that have segments within their support, added to the rates f of the pair pass;
   the renormalized ones divided by gamma_i.
*/
static PetscErrorCode FSSolverWallPass(FSSolver s, const FSParticles *P, PetscReal *f)
{
  const PetscInt    dim = s->opt.dim, US = s->state.ustride, n = s->pw.nowned;
  const FSWallView *B;
  const PetscInt   *wstart, *wk;
  const PetscReal  *wW;

  PetscFunctionBegin;
  PetscCall(PetscLogEventBegin(FS_WallPass, 0, 0, 0, 0));
  PetscCall(FSBoundaryGetView(s->boundary, &B, &wstart, &wk, &wW));
  for (PetscInt i = 0; i < n; i++) {
    FSWallNeighbourhood nb;
    FSRate              rn = {0, {0, 0, 0}, {0, 0, 0}}, ru = {0, {0, 0, 0}, {0, 0, 0}};
    PetscReal           ig;
    if (wstart[i + 1] == wstart[i]) continue;
    nb.i = i;
    nb.n = wstart[i + 1] - wstart[i];
    nb.k = wk + wstart[i];
    nb.W = wW + wstart[i];
    for (PetscInt t = 0; t < s->terms.nterms; t++) {
      FSTerm term = s->terms.term[t];
      if (!term->ops.wall) continue;
      term->ops.wall(term, P, B, &nb, term->renormalized ? &rn : &ru);
    }
    ig = s->pw.invgamma[i];
    for (PetscInt d = 0; d < dim; d++) {
      f[i * US + d] += rn.dx[d] * ig + ru.dx[d];
      f[i * US + dim + d] += rn.du[d] * ig + ru.du[d];
    }
    f[i * US + 2 * dim] += rn.drho * ig + ru.drho;
  }
  PetscCall(PetscLogEventEnd(FS_WallPass, 0, 0, 0, 0));
  PetscFunctionReturn(0);
}

/* the volumes and pressures of particles k0 .. k1-1 (owned, then ghosts), shared by the passes and the terms */
void FSSolverVolumesAndPressures(FSSolver s, PetscInt k0, PetscInt k1)
{
  const PetscInt dim = s->opt.dim, S = s->pw.stride;

  for (PetscInt k = k0; k < k1; k++) {
    const PetscReal *rk = &s->pw.rec[k * S];
    s->pw.vol[k]        = rk[2 * dim + 1] / rk[2 * dim];
    s->pw.pressure[k]   = s->opt.c0 * s->opt.c0 * (rk[2 * dim] - s->opt.rho0) + s->opt.background_pressure;
  }
}

/*
   FSSolverGatherRecordsBegin - the start of a right-hand side: the owned particles' records from the packed
   state u, the neighbourhood scratch, and the volumes and pressures of the owned particles, which the passes and
   the terms share; the ghosts' records on their way from the halo (FSSolverGatherRecordsEnd).
*/
PetscErrorCode FSSolverGatherRecordsBegin(FSSolver s, const PetscReal *u)
{
  const PetscInt dim = s->opt.dim, S = s->pw.stride, US = s->state.ustride, n = s->pw.nowned;
  const PetscInt maxn = s->pw.nbrs.maxcand; /* the scratch holds one particle's neighbours: its candidates bound them */

  PetscFunctionBegin;
  s->pw.pairsvalid = PETSC_FALSE; /* new positions: the pair cache waits for the first pass */
  for (PetscInt i = 0; i < n; i++)
    for (PetscInt a = 0; a < US; a++) s->pw.rec[i * S + a] = u[i * US + a];
  PetscCall(PetscLogEventBegin(FS_Halo, 0, 0, 0, 0));
  PetscCall(FSHaloRefreshBegin(&s->pw.halo, s->pw.rec));
  PetscCall(PetscLogEventEnd(FS_Halo, 0, 0, 0, 0));
  if (maxn > s->pw.scratchcap) {
    PetscCall(PetscFree2(s->pw.scratch, s->pw.scratchj));
    s->pw.scratchcap = PetscMax(maxn, 2 * s->pw.scratchcap);
    PetscCall(PetscMalloc2((3 * dim + 3) * s->pw.scratchcap, &s->pw.scratch, s->pw.scratchcap, &s->pw.scratchj));
  }
  FSSolverVolumesAndPressures(s, 0, n);
  PetscFunctionReturn(0);
}

/* FSSolverGatherRecordsEnd - the ghosts' records arrived (FSSolverGatherRecordsBegin), and their volumes and
   pressures */
PetscErrorCode FSSolverGatherRecordsEnd(FSSolver s)
{
  PetscFunctionBegin;
  PetscCall(PetscLogEventBegin(FS_Halo, 0, 0, 0, 0));
  PetscCall(FSHaloRefreshEnd(&s->pw.halo, s->opt.dim, s->pw.nowned, s->pw.rec));
  PetscCall(PetscLogEventEnd(FS_Halo, 0, 0, 0, 0));
  FSSolverVolumesAndPressures(s, s->pw.nowned, s->pw.nowned + s->pw.halo.nghost);
  PetscFunctionReturn(0);
}

/*
   FSSolverPairPass - the terms' pass over the neighbours of the owned particles passorder[k0 .. k1): the
   renormalized terms first (their sum divided by gamma_i near walls), then the others; the rates into f.
   Adds the count of pairs within the support to *npairs.
*/
static PetscErrorCode FSSolverPairPass(FSSolver s, const FSParticles *P, PetscReal *f, PetscInt k0, PetscInt k1,
                                       PetscInt64 *npairs)
{
  const PetscInt dim = s->opt.dim, S = s->pw.stride, US = s->state.ustride;
  PetscInt64     np = 0;

  PetscFunctionBegin;
  PetscCall(PetscLogEventBegin(FS_PairPass, 0, 0, 0, 0));
  for (PetscInt k = k0; k < k1; k++) {
    const PetscInt  i = s->pw.passorder[k];
    FSNeighbourhood nb;
    FSCommProgress(k); /* the ghosts' first-pass fields and gamma, and the walls' sums, travel meanwhile */
    FSRate rate = {0, {0, 0, 0}, {0, 0, 0}};
    FSSolverNeighbourhood(s, i, &nb);
    np += nb.n;
    /* renormalized terms (boundary integrals) first: their sum is divided by gamma_i */
    for (PetscInt t = 0; t < s->terms.nterms; t++) {
      FSTerm term = s->terms.term[t];
      if (!term->renormalized || term->split) continue;
      if (term->ops.interact) term->ops.interact(term, P, &nb, &rate);
      if (term->ops.source) term->ops.source(term, P, i, &rate);
    }
    if (s->boundary) {
      const PetscReal ig = s->pw.invgamma[i];
      rate.drho *= ig;
      for (PetscInt d = 0; d < dim; d++) {
        rate.du[d] *= ig;
        rate.dx[d] *= ig;
      }
    }
    for (PetscInt t = 0; t < s->terms.nterms; t++) {
      FSTerm term = s->terms.term[t];
      if (term->renormalized || term->split) continue; /* split: FSSolverSplitStep */
      if (term->ops.interact) term->ops.interact(term, P, &nb, &rate);
      if (term->ops.source) term->ops.source(term, P, i, &rate);
    }
    for (PetscInt d = 0; d < dim; d++) {
      f[i * US + d]       = s->pw.rec[i * S + dim + d] + rate.dx[d];
      f[i * US + dim + d] = rate.du[d];
    }
    f[i * US + 2 * dim] = rate.drho;
  }
  *npairs += np;
  PetscCall(PetscLogEventEnd(FS_PairPass, 0, 0, 0, 0));
  PetscFunctionReturn(0);
}

/* FSSolverRelaxationRate - the start-up relaxation's rate zeta(t) (-fs_relax_time: du/dt -= zeta u), fading smoothly
   to 0 at the relaxation time, 0 after it */
static PetscReal FSSolverRelaxationRate(FSSolver s)
{
  if (s->state.rhs_time >= s->opt.relax_time) return 0;
  return 10.0 / s->opt.relax_time * 0.5 * (1 + PetscCosReal(PETSC_PI * s->state.rhs_time / s->opt.relax_time));
}

/* FSSolverRelaxation - the start-up relaxation's rates -zeta u added to f (f NULL: none), and with power its
   power, this rank's share -zeta sum m u^2 (a coupled run needs it before the reaction, the rates after) */
static void FSSolverRelaxation(FSSolver s, PetscReal zeta, PetscReal *f, PetscReal *power)
{
  const PetscInt dim = s->opt.dim, S = s->pw.stride, US = s->state.ustride, n = s->pw.nowned;

  if (power) *power = 0;
  if (zeta == 0) return;
  for (PetscInt i = 0; i < n; i++)
    for (PetscInt d = 0; d < dim; d++) {
      const PetscReal ud = s->pw.rec[i * S + dim + d];
      if (f) f[i * US + dim + d] -= zeta * ud;
      if (power) *power -= zeta * s->pw.rec[i * S + 2 * dim + 1] * ud * ud;
    }
}

/*
   FSSolverPowerRates - the rates of the global DOFs after the structure's (rank 0): the dissipated
   energies of the terms with a power, and the energy block's integrals (P_ext, the relaxation's power,
   the structure's damping power, the coupling's power or a prescribed motion's) from this rank's shares summed over the
   ranks; reaction is this rank's share of the reaction of the walls' forces (FSCouplingReaction).
   With summed (coupled: the sums rode on the reaction's MPI_Allreduce, FSSolverEvaluateRates) the terms' powers,
   P_ext, the relaxation's power and the reaction are sums over the ranks already, in that order, and nothing is
   reduced here.

   Collective unless summed
*/
static PetscErrorCode FSSolverPowerRates(FSSolver s, PetscBool coupled, const PetscReal *summed,
                                         const PetscReal reaction[3], PetscReal *f)
{
  const PetscInt US = s->state.ustride, n = s->pw.nowned;
  PetscReal      power[FS_MAX_TERMS + 5];
  PetscInt       npower = 0;

  PetscFunctionBegin;
  for (PetscInt t = 0; t < s->terms.nterms; t++)
    if (s->terms.term[t]->has_power) power[npower++] = s->terms.term[t]->power;
  power[npower]     = s->state.ext_power;
  power[npower + 1] = s->state.relax_power;
  for (PetscInt c = 0; c < 3; c++) power[npower + 2 + c] = reaction[c];
  {
    PetscMPIInt rank;
    PetscReal  *fe = f + n * US + s->state.genergy;
    PetscCallMPI(MPI_Comm_rank(PetscObjectComm((PetscObject)s), &rank));
    if (summed) PetscCall(PetscArraycpy(power, summed, npower + 5));
    else {
      PetscCallMPI(MPI_Reduce(rank ? power : MPI_IN_PLACE, power, (PetscMPIInt)(npower + 5), MPIU_REAL, MPI_SUM, 0,
                              PetscObjectComm((PetscObject)s)));
      if (s->pw.decomp.size > 1) s->mon.par.uncounted++; /* PETSc's counters miss MPI_Reduce */
    }
    PetscErrorCode ierr = 0; /* the structure's energy (rank 0): its failure is raised on every rank below */
    if (!rank) {
      FSStructure st   = s->structure;
      PetscReal   E[3] = {0, 0, 0};
      for (PetscInt k = 0; k < npower; k++) f[n * US + s->state.gdiss + k] = power[k];
      for (PetscInt e = 0; e < FS_ENERGY_NDOF; e++) fe[e] = 0;                /* the constants and the bounces' jumps */
      if (coupled) PetscCall(PetscArraycpy(E, s->state.structure_energy, 3)); /* FSSolverCouplingRates' */
      else if (st && st->ndof && st->ops.energy) ierr = (*st->ops.energy)(st, s->sy, E);
      fe[FS_ENERGY_WORK_EXT]     = power[npower];
      fe[FS_ENERGY_WORK_RELAX]   = power[npower + 1];
      fe[FS_ENERGY_WORK_DAMPING] = -E[2];
      if (coupled && st->prescribed)
        PetscCall(FSCouplingMotionPower(s->coupling, &power[npower + 2], &fe[FS_ENERGY_WORK_MOTION]));
      else if (coupled) PetscCall(FSCouplingPower(s->coupling, &power[npower + 2], &fe[FS_ENERGY_WORK_COUPLING]));
    }
    if (rank && !coupled && FSSolverStructureHere(s) && s->structure->ndof && s->structure->ops.energy) {
      PetscReal E[3]; /* the others call it too (and fail as rank 0 does), so that no rank waits for rank 0's status */
      ierr = (*s->structure->ops.energy)(s->structure, s->sy, E);
    }
    if (!coupled && s->structure && s->structure->ndof && s->structure->ops.energy)
      PetscCall(FSSolverStructureResultRank0(s, ierr, "energy", 0, NULL));
  }
  PetscFunctionReturn(0);
}

/*
   FSSolverEvaluateRates - the rates (dx/dt, du/dt, drho/dt) of the owned particles for the packed
   state u, into f (same layout); the global DOFs' rates (the structure's, at time s->state.rhs_time,
   and the dissipated energies) on rank 0.
   count: add the work to the run's statistics (PETSC_FALSE for evaluations made for output).
   u and f may be one array: u is read (the particles into the records, the structure's DOFs) before a
   rate is written.

   Collective
*/
PetscErrorCode FSSolverEvaluateRates(FSSolver s, const PetscReal *u, PetscReal *f, PetscBool count)
{
  const PetscInt S = s->pw.stride, US = s->state.ustride, n = s->pw.nowned;
  FSParticles    P;
  PetscReal      reaction[3] = {0, 0, 0}, extra[FS_COUPLING_MAX_EXTRA];
  PetscBool      coupled;
  PetscInt64     npairs;

  PetscFunctionBegin;
  PetscCall(PetscLogEventBegin(FS_RHS, 0, 0, 0, 0));
  PetscCall(FSCouplingGetActive(s->coupling, &coupled));
  /* The order lets each rank go on with its own particles while the others' fields travel (the ranks' work
     differs, by their walls above all): the ghosts' records travel during the walls' work on the owned particles;
     the ghosts' first-pass fields and gamma, and the wall pressure's sums, during the pair pass over the owned
     particles that have no ghost among their candidates (passorder). */
  if (count && s->ts) { /* FLEXSLOSH_FAULT (tests only): an error on one rank, amid the collectives */
    PetscInt step;
    PetscCall(TSGetStepNumber(s->ts, &step));
    PetscCall(FSDebugFault(PetscObjectComm((PetscObject)s), "alloc", step, NULL));
  }
  if (coupled) { /* before the messages start: a structure's error stops the run with none in flight */
    PetscCall(PetscLogEventBegin(FS_Coupling, 0, 0, 0, 0));
    PetscCall(FSSolverCouplingPredict(s, u));
    PetscCall(PetscLogEventEnd(FS_Coupling, 0, 0, 0, 0));
  }
  PetscCall(FSSolverGatherRecordsBegin(s, u));
  if (s->boundary) PetscCall(FSSolverBoundaryPrepareBegin(s));
  PetscCall(FSSolverGatherRecordsEnd(s));
  PetscCall(FSSolverGetParticles(s, &P));

  if (s->terms.needs) {
    PetscCall(FSSolverFirstPass(s));
    PetscCall(PetscLogEventBegin(FS_Halo, 0, 0, 0, 0));
    PetscCall(FSHaloRefreshAuxBegin(&s->pw.halo, s->pw.aux));
    PetscCall(PetscLogEventEnd(FS_Halo, 0, 0, 0, 0));
    if (count) s->mon.pair_visits += s->pw.nbrs.npairs;
  }
  if (s->boundary) {
    PetscCall(PetscLogEventBegin(FS_Walls, 0, 0, 0, 0));
    PetscCall(FSBoundaryPrepareExchange(s->boundary));
    PetscCall(PetscLogEventEnd(FS_Walls, 0, 0, 0, 0));
  }
  { /* the terms' per-particle fields of the owned particles now, of all once the ghosts' have arrived */
    FSParticles Pown = P;
    Pown.nghost      = 0;
    for (PetscInt t = 0; t < s->terms.nterms; t++) {
      FSTerm term = s->terms.term[t];
      term->power = 0;
      if (term->ops.setup && !term->setupcalled) PetscCall((*term->ops.setup)(term, &Pown));
      term->setupcalled = PETSC_TRUE;
      if (term->ops.prepare) PetscCall((*term->ops.prepare)(term, &Pown));
    }
  }
  if (count) { /* the viscosity bound of the next time step comes from the integrator's own evaluations only */
    s->state.nu_src[0] = s->opt.nu;
    for (PetscInt t = 0; t < s->terms.nterms; t++) {
      const FSTerm term      = s->terms.term[t];
      s->state.nu_src[1 + t] = term->split ? 0 /* its own stages resolve it (FSSolverSplitStep) */
                               : term->dt_coefficient > 0
                                   ? term->max_viscosity * (s->opt.cfl_visc / term->dt_coefficient)
                                   : term->max_viscosity;
    }
  }

  npairs = 0;
  PetscCall(FSSolverPairPass(s, &P, f, 0, s->pw.ninterior, &npairs));
  if (s->terms.needs) {
    PetscCall(PetscLogEventBegin(FS_Halo, 0, 0, 0, 0));
    PetscCall(FSHaloRefreshAuxEnd(&s->pw.halo, s->pw.aux));
    PetscCall(PetscLogEventEnd(FS_Halo, 0, 0, 0, 0));
  }
  if (s->boundary) PetscCall(FSSolverBoundaryGhosts(s));
  for (PetscInt t = 0; t < s->terms.nterms; t++) {
    FSTerm term = s->terms.term[t];
    if (term->ops.prepare) PetscCall((*term->ops.prepare)(term, &P));
  }
  PetscCall(FSSolverPairPass(s, &P, f, s->pw.ninterior, n, &npairs));
  s->pw.nbrs.npairs = npairs;
  if (s->boundary) {
    PetscCall(PetscLogEventBegin(FS_Walls, 0, 0, 0, 0));
    PetscCall(FSBoundaryPrepareEnd(s->boundary));
    PetscCall(PetscLogEventEnd(FS_Walls, 0, 0, 0, 0));
  }
  if (s->boundary) PetscCall(FSSolverWallPass(s, &P, f));
  /* the reaction of the forces on the liquid: for a structure before the start-up relaxation, for a prescribed
     motion after it (the motion also does the relaxation's work in the absolute frame: work_motion) */
  const PetscBool prescribed = (PetscBool)(coupled && s->structure->prescribed);
  const PetscBool early      = (PetscBool)(!coupled || prescribed); /* the relaxation's rates before any reaction */
  const PetscReal zeta       = FSSolverRelaxationRate(s);
  FSSolverRelaxation(s, zeta, early ? f : NULL, &s->state.relax_power); /* its power, its rates here or below */
  if (coupled) { /* the stage's one collective: the reaction, and riding on it the powers' sums (FSSolverPowerRates) */
    PetscInt nextra = 0;
    for (PetscInt t = 0; t < s->terms.nterms; t++)
      if (s->terms.term[t]->has_power) extra[nextra++] = s->terms.term[t]->power;
    extra[nextra++] = s->state.relax_power;
    FSCouplingInertiaSums(s->coupling, n, S, s->pw.rec, &extra[nextra]);
    PetscCall(PetscLogEventBegin(FS_Coupling, 0, 0, 0, 0));
    PetscCall(
        FSCouplingReaction(s->coupling, n, S, s->pw.rec, US, f, reaction, nextra + FS_COUPLING_NINERTIA_SUMS, extra));
    PetscCall(PetscLogEventEnd(FS_Coupling, 0, 0, 0, 0));
  }
  if (!early) FSSolverRelaxation(s, zeta, f, NULL);
  if (count) {
    s->mon.pair_visits += s->pw.nbrs.npairs;
    s->mon.nrhs++;
  }

  /* the structure's DOFs (first block of the global DOFs, rank 0) */
  s->state.ext_power = 0;
  if (coupled) { /* loads of this stage to the structure, the tank's motion back to the liquid */
    PetscCall(PetscLogEventBegin(FS_Coupling, 0, 0, 0, 0));
    PetscCall(FSSolverCouplingRates(s, f));
    PetscCall(FSCouplingInertia(s->coupling, n, S, s->pw.rec, US, f, &s->state.ext_power));
    PetscCall(PetscLogEventEnd(FS_Coupling, 0, 0, 0, 0));
  } else PetscCall(FSSolverStructureRates(s, PETSC_TRUE, u, f, NULL));
  if (coupled) { /* the powers and the reaction summed over the ranks, from the reaction's MPI_Allreduce */
    PetscReal summed[FS_MAX_TERMS + 5];
    PetscInt  q = 0;
    for (PetscInt t = 0; t < s->terms.nterms; t++)
      if (s->terms.term[t]->has_power) summed[q] = extra[q], q++;
    PetscCall(FSCouplingInertiaPower(s->coupling, &extra[q + 1], &summed[q]));
    summed[q + 1] = extra[q];
    PetscCall(FSCouplingGetReaction(s->coupling, &summed[q + 2]));
    PetscCall(FSSolverPowerRates(s, coupled, summed, reaction, f));
  } else PetscCall(FSSolverPowerRates(s, coupled, NULL, reaction, f));
  PetscCall(PetscLogEventEnd(FS_RHS, 0, 0, 0, 0));
  PetscFunctionReturn(0);
}

/*
   FSSolverGetParticles - the view of the particles and parameters the terms work on, pointing into
   the solver's work arrays as the last right-hand side left them.
*/
PetscErrorCode FSSolverGetParticles(FSSolver s, FSParticles *P)
{
  PetscFunctionBegin;
  PetscCall(PetscMemzero(P, sizeof(*P)));
  P->dim                 = s->opt.dim;
  P->nowned              = s->pw.nowned;
  P->nghost              = s->pw.halo.nghost;
  P->stride              = s->pw.stride;
  P->rec                 = s->pw.rec;
  P->aux                 = s->pw.aux;
  P->vol                 = s->pw.vol;
  P->pressure            = s->pw.pressure;
  P->rho0                = s->opt.rho0;
  P->c0                  = s->opt.c0;
  P->h                   = s->opt.h;
  P->nu                  = s->opt.nu;
  P->dx                  = s->opt.dx;
  P->umax                = s->state.umax;
  P->background_pressure = s->opt.background_pressure;
  for (PetscInt d = 0; d < 3; d++) P->gravity[d] = s->opt.gravity[d];
  if (s->boundary) {
    P->gamma     = s->pw.gamma;
    P->invgamma  = s->pw.invgamma;
    P->invgammav = s->pw.gammav ? s->pw.invgammav : s->pw.invgamma;
  }
  PetscFunctionReturn(0);
}

/* FSSolverRHS - the TS right-hand side callback. */
PetscErrorCode FSSolverRHS(TS ts, PetscReal t, Vec U, Vec F, void *ctx)
{
  FSSolver           s = (FSSolver)ctx;
  const PetscScalar *u;
  PetscScalar       *f;

  PetscFunctionBegin;
  (void)ts;
  s->state.rhs_time  = t;
  s->state.evaluated = PETSC_FALSE; /* the work arrays now hold this stage's evaluation */
  PetscCall(VecGetArray(F, &f));
  if (U != F) PetscCall(VecGetArrayRead(U, &u));
  else u = f; /* in place (FSTSRK4LeanSetInPlace): the state is read into the records before a rate is written */
  PetscCall(FSSolverEvaluateRates(s, u, f, PETSC_TRUE));
  if (U != F) PetscCall(VecRestoreArrayRead(U, &u));
  PetscCall(VecRestoreArray(F, &f));
  PetscFunctionReturn(0);
}
