/*
   Unit tests of the kernel and the neighbour search:
   - the Wendland C2 kernel integrates to 1 in 2-D and 3-D, and F(r) = W'(r)/r matches W;
   - the pairs the passes pick from the cell-list candidates (FSNeighboursPick) equal a brute-force
     search (same pairs, same kernel factors)
     for random particles, owned and extra (ghost-like) ones, in 2-D and 3-D (each rank on its own);
   - the distributed search as a run does it, on any number of ranks: random particles created on
     every rank, the decomposition balanced on them (FSDecomp), moved to their owners by a DMSwarm
     migration (every rank must own some), the halo built and refreshed (FSHalo), the lists built on
     owned + ghost records; then every rank's lists against a brute-force all-pairs search over the
     gathered global set (minimum image across periodic sides): each pair within the support found
     once, with its distance and kernel factor. Pairs whose partner is a ghost from another rank, and
     with a periodic direction pairs across it, must be among them (counted, > 0), and the same check
     on lists built without the ghosts must find the pairs missing (the check would see a halo that
     was not exchanged).
*/
#include <petscdmswarm.h>
#include "particles/fsparticles.h"

static PetscErrorCode TestKernel(PetscInt dim)
{
  FSKernel  k;
  PetscReal h = 0.3, sum = 0, step = h / 40, maxerr = 0;
  PetscInt  n = (PetscInt)(2 * h / step) + 1;

  PetscFunctionBegin;
  PetscCall(FSKernelSetUp(&k, dim, h));
  for (PetscInt a = -n; a <= n; a++)
    for (PetscInt b = -n; b <= n; b++)
      for (PetscInt c = (dim == 3 ? -n : 0); c <= (dim == 3 ? n : 0); c++) {
        PetscReal r = PetscSqrtReal((PetscReal)(a * a + b * b + c * c)) * step;
        sum += FSKernelW(&k, r) * (dim == 3 ? step * step * step : step * step);
      }
  /* measured: sum - 1 = 3.9e-10 in 2-D, 8.1e-12 in 3-D (the grid sum of a C2 kernel at h/40) */
  PetscCheck(PetscAbsReal(sum - 1) < 1e-9, PETSC_COMM_SELF, PETSC_ERR_PLIB,
             "Kernel integral %g in %" PetscInt_FMT "-D, expected 1", (double)sum, dim);
  for (PetscReal r = 0.01 * h; r < 1.99 * h; r += 0.05 * h) {
    PetscReal e = 1e-6 * h, dW = (FSKernelW(&k, r + e) - FSKernelW(&k, r - e)) / (2 * e);
    maxerr = PetscMax(maxerr, PetscAbsReal(dW / r - FSKernelF(&k, r)) / PetscAbsReal(k.fnorm));
  }
  /* measured: 7.4e-9 fnorm in 2-D, 4.8e-9 in 3-D (the round-off of the central difference) */
  PetscCheck(maxerr < 1e-8, PETSC_COMM_SELF, PETSC_ERR_PLIB, "Kernel gradient factor differs from dW/dr / r by %g",
             (double)maxerr);
  PetscCheck(FSKernelW(&k, 2 * h) == 0 && FSKernelW(&k, 2.5 * h) == 0, PETSC_COMM_SELF, PETSC_ERR_PLIB,
             "Kernel support is not 2h");
  PetscCall(PetscPrintf(PETSC_COMM_SELF,
                        "  kernel %" PetscInt_FMT "-D: integral - 1 = %.3g, F against dW/dr / r %.3g fnorm\n", dim,
                        (double)(sum - 1), (double)maxerr));
  PetscFunctionReturn(0);
}

/* The pairs within the support of each owned particle as the solver's passes see them: picked from the
   candidates by FSNeighboursPick, here gathered into a list (CSR) to compare with brute force. */
typedef struct {
  PetscInt  *start, *nbr;
  PetscInt64 npairs;
} PairList;

static PetscErrorCode PickPairs(const FSNeighbours *nb, const FSKernel *k, PetscInt nowned, const PetscReal rec[],
                                PetscInt S, PairList *pl)
{
  PetscInt  *j, np = 0;
  PetscReal *dx, *r2;

  PetscFunctionBegin;
  PetscCall(PetscFree2(pl->start, pl->nbr));
  PetscCall(PetscMalloc2(nowned + 1, &pl->start, nb->ncand + 1, &pl->nbr));
  PetscCall(PetscMalloc3(nb->maxcand + 1, &j, 3 * (nb->maxcand + 1), &dx, nb->maxcand + 1, &r2));
  for (PetscInt i = 0; i < nowned; i++) {
    const PetscInt m = FSNeighboursPick(nb, nb->dim, i, rec, S, k->support2, j, dx, r2);
    pl->start[i]     = np;
    for (PetscInt q = 0; q < m; q++) {
      PetscReal d2 = 0;
      for (PetscInt d = 0; d < nb->dim; d++) d2 += dx[q * nb->dim + d] * dx[q * nb->dim + d];
      PetscCheck(d2 == r2[q], PETSC_COMM_SELF, PETSC_ERR_PLIB, "FSNeighboursPick's r^2 is not |x_j - x_i|^2");
      pl->nbr[np++] = j[q];
    }
  }
  pl->start[nowned] = np;
  pl->npairs        = np;
  PetscCall(PetscFree3(j, dx, r2));
  PetscFunctionReturn(0);
}

static FSNeighboursForm Form; /* the candidates' form the tests build (main runs them with each) */

static PetscErrorCode TestNeighbours(PetscInt dim, PetscInt nowned, PetscInt nextra)
{
  FSKernel     k;
  FSNeighbours nb;
  PairList     pl;
  PetscRandom  rnd;
  PetscInt     n = nowned + nextra, S = 2 * dim + 2;
  PetscReal   *rec, h                 = 0.05;
  PetscInt64   brute = 0;
  PetscReal    maxdF = 0;

  PetscFunctionBegin;
  PetscCall(PetscMemzero(&nb, sizeof(nb)));
  nb.form = Form;
  PetscCall(PetscMemzero(&pl, sizeof(pl)));
  PetscCall(FSKernelSetUp(&k, dim, h));
  PetscCall(PetscRandomCreate(PETSC_COMM_SELF, &rnd));
  PetscCall(PetscRandomSetFromOptions(rnd));
  PetscCall(PetscMalloc1(n * S, &rec));
  for (PetscInt p = 0; p < n; p++)
    for (PetscInt d = 0; d < S; d++) {
      PetscReal v;
      PetscCall(PetscRandomGetValueReal(rnd, &v));
      rec[p * S + d] = d < dim ? (p < nowned ? v : 1.0 + 0.2 * v) : v; /* extra particles beyond the owned box */
    }
  /* run twice to exercise the reuse of the buffers */
  for (PetscInt rep = 0; rep < 2; rep++) {
    PetscReal skin = rep ? 0.25 * h : 0;
    PetscCall(FSNeighboursBuildCells(&nb, dim, n, rec, S, k.support + skin));
    PetscCall(FSNeighboursBuildCandidates(&nb, nowned, rec, S, k.support + skin));
    PetscCall(PickPairs(&nb, &k, nowned, rec, S, &pl));
  }
  for (PetscInt i = 0; i < nowned; i++) {
    PetscInt count = 0;
    for (PetscInt j = 0; j < n; j++) {
      PetscReal r2 = 0;
      if (j == i) continue;
      for (PetscInt d = 0; d < dim; d++) r2 += (rec[i * S + d] - rec[j * S + d]) * (rec[i * S + d] - rec[j * S + d]);
      if (r2 < k.support2) {
        PetscBool found = PETSC_FALSE;
        count++;
        for (PetscInt q = pl.start[i]; q < pl.start[i + 1]; q++)
          if (pl.nbr[q] == j) {
            /* the kernel factor a pass computes for the listed pair (the list holds no F: the passes compute
               it from x_j - x_i) */
            PetscReal rq2 = 0, Fq;
            for (PetscInt d = 0; d < dim; d++)
              rq2 += (rec[pl.nbr[q] * S + d] - rec[i * S + d]) * (rec[pl.nbr[q] * S + d] - rec[i * S + d]);
            Fq    = FSKernelF(&k, PetscSqrtReal(rq2));
            found = PETSC_TRUE;
            maxdF = PetscMax(maxdF, PetscAbsReal(Fq - FSKernelF(&k, PetscSqrtReal(r2))) / PetscAbsReal(k.fnorm));
            /* measured: 0 (the same arithmetic); 1e-15 leaves room for a contraction into a fused multiply-add
               that one of them might get on another build */
            PetscCheck(PetscAbsReal(Fq - FSKernelF(&k, PetscSqrtReal(r2))) <= 1e-15 * PetscAbsReal(k.fnorm),
                       PETSC_COMM_SELF, PETSC_ERR_PLIB,
                       "Wrong kernel factor for pair (%" PetscInt_FMT ", %" PetscInt_FMT ")", i, j);
          }
        PetscCheck(found, PETSC_COMM_SELF, PETSC_ERR_PLIB,
                   "Pair (%" PetscInt_FMT ", %" PetscInt_FMT
                   ") at distance %g missing from the neighbour list (%" PetscInt_FMT "-D)",
                   i, j, (double)PetscSqrtReal(r2), dim);
      }
    }
    PetscCheck(count == pl.start[i + 1] - pl.start[i], PETSC_COMM_SELF, PETSC_ERR_PLIB,
               "Particle %" PetscInt_FMT " has %" PetscInt_FMT " neighbours in the list, %" PetscInt_FMT
               " by brute force",
               i, pl.start[i + 1] - pl.start[i], count);
    brute += count;
  }
  PetscCheck(brute == pl.npairs && brute > 0, PETSC_COMM_SELF, PETSC_ERR_PLIB,
             "Pair count %" PetscInt64_FMT " differs from brute force %" PetscInt64_FMT, pl.npairs, brute);
  PetscCall(PetscPrintf(PETSC_COMM_SELF,
                        "  %" PetscInt_FMT "-D: %" PetscInt64_FMT
                        " pairs match brute force (kernel factor %.3g fnorm)\n",
                        dim, brute, (double)maxdF));
  PetscCall(FSNeighboursDestroy(&nb));
  PetscCall(PetscFree2(pl.start, pl.nbr));
  PetscCall(PetscFree(rec));
  PetscCall(PetscRandomDestroy(&rnd));
  PetscFunctionReturn(0);
}

/* the particles of a distributed test: N of them, random in the box [0, len] */
typedef struct {
  PetscInt  dim, N;
  PetscReal len[3];
  PetscBool periodic[3];
  PetscReal h, width; /* smoothing length; halo width and candidate radius (support + skin) */
} DistSetUp;

/*
   Distribute - the run's way of placing the particles: particle g is created on rank g % size (as a case
   creates its lattice in chunks, wherever it lies), the cuts are balanced on them and each is sent to
   the rank owning its position by a DMSwarm migration. Returns the owned positions (dim each) and ids.
*/
static PetscErrorCode Distribute(MPI_Comm comm, const DistSetUp *su, FSDecomp *dd, PetscInt *nowned, PetscReal **x,
                                 PetscInt **id)
{
  const PetscInt  dim   = su->dim;
  const PetscReal lo[3] = {0, 0, 0};
  PetscMPIInt     rank, size;
  PetscRandom     rnd;
  DM              sw;
  PetscInt        ncreate = 0, n, *pid, *prank;
  PetscReal      *px;

  PetscFunctionBegin;
  PetscCallMPI(MPI_Comm_rank(comm, &rank));
  PetscCallMPI(MPI_Comm_size(comm, &size));
  for (PetscInt g = 0; g < su->N; g++) ncreate += (g % size == rank);
  PetscCall(DMCreate(comm, &sw));
  PetscCall(DMSetType(sw, DMSWARM));
  PetscCall(DMSetDimension(sw, dim));
  PetscCall(DMSwarmSetType(sw, DMSWARM_BASIC));
  PetscCall(DMSwarmRegisterPetscDatatypeField(sw, "x", dim, PETSC_REAL));
  PetscCall(DMSwarmRegisterPetscDatatypeField(sw, "gid", 1, PETSC_INT));
  PetscCall(DMSwarmFinalizeFieldRegister(sw));
  PetscCall(DMSwarmSetLocalSizes(sw, ncreate, 16));
  PetscCall(DMSwarmGetField(sw, "x", NULL, NULL, (void **)&px));
  PetscCall(DMSwarmGetField(sw, "gid", NULL, NULL, (void **)&pid));
  /* the same sequence on every rank (a PetscRandom of its own, default seed): every rank draws all */
  PetscCall(PetscRandomCreate(PETSC_COMM_SELF, &rnd));
  for (PetscInt g = 0, p = 0; g < su->N; g++) {
    PetscReal v[3];
    for (PetscInt d = 0; d < dim; d++) {
      PetscCall(PetscRandomGetValueReal(rnd, &v[d]));
      v[d] *= su->len[d];
    }
    if (g % size != rank) continue;
    for (PetscInt d = 0; d < dim; d++) px[p * dim + d] = v[d];
    pid[p++] = g;
  }
  PetscCall(PetscRandomDestroy(&rnd));
  PetscCall(FSDecompSetUp(dd, comm, dim, lo, su->len, su->periodic, su->width));
  PetscCall(FSDecompBalance(dd, comm, ncreate, px, NULL, su->width));
  PetscCall(DMSwarmGetField(sw, DMSwarmField_rank, NULL, NULL, (void **)&prank));
  for (PetscInt p = 0; p < ncreate; p++) prank[p] = FSDecompRankOf(dd, &px[p * dim]);
  PetscCall(DMSwarmRestoreField(sw, DMSwarmField_rank, NULL, NULL, (void **)&prank));
  PetscCall(DMSwarmRestoreField(sw, "gid", NULL, NULL, (void **)&pid));
  PetscCall(DMSwarmRestoreField(sw, "x", NULL, NULL, (void **)&px));
  PetscCall(DMSwarmMigrate(sw, PETSC_TRUE));
  PetscCall(DMSwarmGetLocalSize(sw, &n));
  PetscCall(PetscMalloc2(n * dim, x, n, id));
  PetscCall(DMSwarmGetField(sw, "x", NULL, NULL, (void **)&px));
  PetscCall(DMSwarmGetField(sw, "gid", NULL, NULL, (void **)&pid));
  PetscCall(PetscArraycpy(*x, px, n * dim));
  PetscCall(PetscArraycpy(*id, pid, n));
  PetscCall(DMSwarmRestoreField(sw, "gid", NULL, NULL, (void **)&pid));
  PetscCall(DMSwarmRestoreField(sw, "x", NULL, NULL, (void **)&px));
  PetscCall(DMDestroy(&sw));
  *nowned = n;
  PetscFunctionReturn(0);
}

/* the global set gathered from the owners: position (dim) of each id and the rank that owns it */
typedef struct {
  PetscReal   *x;
  PetscMPIInt *owner;
} GlobalSet;

static PetscErrorCode Gather(MPI_Comm comm, const DistSetUp *su, PetscInt nowned, const PetscReal x[],
                             const PetscInt id[], GlobalSet *gs)
{
  const PetscInt dim = su->dim, R = dim + 1;
  PetscMPIInt    size, n          = (PetscMPIInt)(nowned * R), *counts, *displs;
  PetscReal     *mine, *all;
  PetscInt       total = 0;

  PetscFunctionBegin;
  PetscCallMPI(MPI_Comm_size(comm, &size));
  PetscCall(PetscMalloc2(size, &counts, size + 1, &displs));
  PetscCallMPI(MPI_Allgather(&n, 1, MPI_INT, counts, 1, MPI_INT, comm));
  displs[0] = 0;
  for (PetscMPIInt r = 0; r < size; r++) displs[r + 1] = displs[r] + counts[r];
  total = displs[size] / R;
  PetscCheck(total == su->N, comm, PETSC_ERR_PLIB,
             "the ranks own %" PetscInt_FMT " particles after the migration, %" PetscInt_FMT " were created", total,
             su->N);
  PetscCall(PetscMalloc2(nowned * R, &mine, total * R, &all));
  for (PetscInt p = 0; p < nowned; p++) {
    for (PetscInt d = 0; d < dim; d++) mine[p * R + d] = x[p * dim + d];
    mine[p * R + dim] = (PetscReal)id[p];
  }
  PetscCallMPI(MPI_Allgatherv(mine, n, MPIU_REAL, all, counts, displs, MPIU_REAL, comm));
  PetscCall(PetscMalloc2(su->N * dim, &gs->x, su->N, &gs->owner));
  for (PetscInt g = 0; g < su->N; g++) gs->owner[g] = -1;
  for (PetscMPIInt r = 0; r < size; r++)
    for (PetscInt q = displs[r] / R; q < displs[r + 1] / R; q++) {
      const PetscInt g = (PetscInt)all[q * R + dim];
      PetscCheck(g >= 0 && g < su->N && gs->owner[g] < 0, comm, PETSC_ERR_PLIB,
                 "particle %" PetscInt_FMT " is owned twice or is not one of those created", g);
      gs->owner[g] = r;
      for (PetscInt d = 0; d < dim; d++) gs->x[g * dim + d] = all[q * R + d];
    }
  PetscCall(PetscFree2(mine, all));
  PetscCall(PetscFree2(counts, displs));
  PetscFunctionReturn(0);
}

/* the difference a - b along d, the minimum image across a periodic side */
static inline PetscReal MinImage(const DistSetUp *su, PetscInt d, PetscReal a, PetscReal b)
{
  PetscReal v = a - b;
  if (su->periodic[d]) {
    if (v > 0.5 * su->len[d]) v -= su->len[d];
    else if (v < -0.5 * su->len[d]) v += su->len[d];
  }
  return v;
}

/* what a comparison of a rank's lists with the brute-force search found */
typedef struct {
  PetscInt64 pairs;     /* pairs in the lists */
  PetscInt64 expected;  /* pairs within the support by brute force */
  PetscInt64 missing;   /* expected pairs not in the lists */
  PetscInt64 wrong;     /* listed pairs outside the support, listed twice, or with a wrong distance or factor */
  PetscInt64 ghost;     /* listed pairs whose partner is a ghost */
  PetscInt64 crossrank; /* ... a ghost of a particle owned by another rank */
  PetscInt64 periodic;  /* ... a periodic image */
  PetscReal  dr, dF;    /* largest difference of distance (relative to the support) and kernel factor (to fnorm) */
} Comparison;

/*
   CompareLists - the lists of the owned particles (records rec: position, then the id; ghosts after the
   owned ones, with their periodic shifts) against the brute-force search over the global set.
*/
static PetscErrorCode CompareLists(const DistSetUp *su, const FSKernel *k, const PairList *nb, PetscInt nowned,
                                   const PetscReal rec[], const PetscReal shift[], const GlobalSet *gs,
                                   PetscMPIInt rank, Comparison *c)
{
  const PetscInt dim = su->dim, S = dim + 1;
  char          *mark; /* per global particle: 1 expected partner of i, 2 found in the list */
  PetscInt      *brute, nbrute;

  PetscFunctionBegin;
  PetscCall(PetscMemzero(c, sizeof(*c)));
  PetscCall(PetscCalloc1(su->N, &mark));
  PetscCall(PetscMalloc1(su->N, &brute));
  for (PetscInt i = 0; i < nowned; i++) {
    const PetscReal *xi = &rec[i * S];
    const PetscInt   gi = (PetscInt)xi[dim];
    nbrute              = 0;
    for (PetscInt g = 0; g < su->N; g++) {
      PetscReal r2 = 0;
      if (g == gi) continue;
      for (PetscInt d = 0; d < dim; d++) {
        const PetscReal v = MinImage(su, d, gs->x[gi * dim + d], gs->x[g * dim + d]);
        r2 += v * v;
      }
      if (r2 < k->support2) {
        mark[g]         = 1;
        brute[nbrute++] = g;
      }
    }
    c->expected += nbrute;
    for (PetscInt q = nb->start[i]; q < nb->start[i + 1]; q++) {
      const PetscInt   j  = nb->nbr[q];
      const PetscReal *xj = &rec[j * S];
      const PetscInt   gj = (PetscInt)xj[dim];
      PetscReal        r2 = 0, rb2 = 0, r, rb;
      c->pairs++;
      if (j >= nowned) {
        PetscBool shifted = PETSC_FALSE;
        for (PetscInt d = 0; d < dim; d++) shifted = (PetscBool)(shifted || shift[(j - nowned) * dim + d] != 0);
        c->ghost++;
        c->crossrank += (gs->owner[gj] != rank);
        c->periodic += shifted;
      }
      if (gj < 0 || gj >= su->N || mark[gj] != 1) {
        if (!c->wrong)
          PetscCall(PetscPrintf(PETSC_COMM_SELF, "[%d] pair (%" PetscInt_FMT ", %" PetscInt_FMT ") is listed %s\n",
                                (int)rank, gi, gj,
                                gj >= 0 && gj < su->N && mark[gj] == 2 ? "twice" : "but lies outside the support"));
        c->wrong++;
        continue;
      }
      mark[gj] = 2;
      for (PetscInt d = 0; d < dim; d++) {
        const PetscReal v = MinImage(su, d, gs->x[gi * dim + d], gs->x[gj * dim + d]);
        r2 += (xi[d] - xj[d]) * (xi[d] - xj[d]);
        rb2 += v * v;
      }
      r     = PetscSqrtReal(r2);
      rb    = PetscSqrtReal(rb2);
      c->dr = PetscMax(c->dr, PetscAbsReal(r - rb) / k->support);
      c->dF = PetscMax(c->dF, PetscAbsReal(FSKernelF(k, r) - FSKernelF(k, rb)) / PetscAbsReal(k->fnorm));
      /* measured: 0 for both in 2-D and 3-D on 1, 2 and 3 ranks: the coordinates have the 48 random bits of rand48,
         so that adding or taking off a period is exact, and the list and the brute force do the same arithmetic;
         1e-15 leaves room for a fused multiply-add on another build */
      if (PetscAbsReal(r - rb) > 1e-15 * k->support ||
          PetscAbsReal(FSKernelF(k, r) - FSKernelF(k, rb)) > 1e-15 * PetscAbsReal(k->fnorm)) {
        if (!c->wrong)
          PetscCall(PetscPrintf(PETSC_COMM_SELF,
                                "[%d] pair (%" PetscInt_FMT ", %" PetscInt_FMT
                                "): distance %.17g, by brute force %.17g; kernel factor %.17g, expected %.17g\n",
                                (int)rank, gi, gj, (double)r, (double)rb, (double)FSKernelF(k, r),
                                (double)FSKernelF(k, rb)));
        c->wrong++;
      }
    }
    for (PetscInt b = 0; b < nbrute; b++) {
      if (mark[brute[b]] == 1) c->missing++;
      mark[brute[b]] = 0;
    }
  }
  PetscCall(PetscFree(mark));
  PetscCall(PetscFree(brute));
  PetscFunctionReturn(0);
}

static PetscErrorCode SumComparison(MPI_Comm comm, Comparison *c)
{
  PetscInt64 v[7] = {c->pairs, c->expected, c->missing, c->wrong, c->ghost, c->crossrank, c->periodic};
  PetscReal  e[2] = {c->dr, c->dF};

  PetscFunctionBegin;
  PetscCallMPI(MPI_Allreduce(MPI_IN_PLACE, v, 7, MPIU_INT64, MPI_SUM, comm));
  PetscCallMPI(MPI_Allreduce(MPI_IN_PLACE, e, 2, MPIU_REAL, MPI_MAX, comm));
  c->pairs     = v[0];
  c->expected  = v[1];
  c->missing   = v[2];
  c->wrong     = v[3];
  c->ghost     = v[4];
  c->crossrank = v[5];
  c->periodic  = v[6];
  c->dr        = e[0];
  c->dF        = e[1];
  PetscFunctionReturn(0);
}

/* the images of global particle g (shifted by s[d] periods along the periodic directions) that lie outside this
   rank's box but within the halo width of it: the ghosts the halo must give this rank */
static PetscInt ExpectedGhosts(const DistSetUp *su, const FSDecomp *dd, const GlobalSet *gs, PetscInt g)
{
  const PetscInt dim = su->dim, nimg = dim == 2 ? 9 : 27;
  PetscInt       count = 0;
  for (PetscInt o = 0; o < nimg; o++) {
    const PetscInt s[3] = {o % 3 - 1, (o / 3) % 3 - 1, o / 9 - 1};
    PetscBool      use = PETSC_TRUE, inside = PETSC_TRUE;
    for (PetscInt d = 0; d < dim && use; d++) {
      const PetscReal lo = dd->cut[d][dd->coord[d]], hi = dd->cut[d][dd->coord[d] + 1];
      const PetscReal y = gs->x[g * dim + d] + s[d] * su->len[d];
      if (s[d] && !su->periodic[d]) use = PETSC_FALSE;
      else if (y <= lo - su->width || y >= hi + su->width) use = PETSC_FALSE;
      else if (y < lo || y >= hi) inside = PETSC_FALSE;
    }
    count += use && !inside;
  }
  return count;
}

/*
   TestDistributed - the distributed search (see the top of the file) for the set-up su on comm.
*/
static PetscErrorCode TestDistributed(MPI_Comm comm, const DistSetUp *su)
{
  const PetscInt dim = su->dim, S = dim + 1; /* record: position, then the id */
  PetscMPIInt    rank, size;
  FSDecomp       dd;
  FSHalo         hl;
  FSKernel       k;
  FSNeighbours   nb;
  PairList       pl;
  GlobalSet      gs;
  Comparison     c, c0;
  PetscInt       nowned, inbox = 0, range[2], *id;
  PetscInt64     gh[3] = {0, 0, 0}; /* ghosts, those of the expected ones, those that are periodic images */
  PetscReal     *x, *rec, dghost = 0;
  PetscBool      anyperiodic = PETSC_FALSE;

  PetscFunctionBegin;
  PetscCallMPI(MPI_Comm_rank(comm, &rank));
  PetscCallMPI(MPI_Comm_size(comm, &size));
  for (PetscInt d = 0; d < dim; d++) anyperiodic = (PetscBool)(anyperiodic || su->periodic[d]);
  PetscCall(FSKernelSetUp(&k, dim, su->h));
  PetscCall(Distribute(comm, su, &dd, &nowned, &x, &id));
  /* every rank owns particles, all in its own box */
  for (PetscInt p = 0; p < nowned; p++) inbox += (FSDecompRankOf(&dd, &x[p * dim]) == rank);
  PetscCheck(inbox == nowned, PETSC_COMM_SELF, PETSC_ERR_PLIB,
             "[%d] %" PetscInt_FMT " of the %" PetscInt_FMT " particles owned after the migration lie outside the box",
             (int)rank, nowned - inbox, nowned);
  range[0] = -nowned;
  range[1] = nowned;
  PetscCallMPI(MPI_Allreduce(MPI_IN_PLACE, range, 2, MPIU_INT, MPI_MAX, comm));
  range[0] = -range[0];
  PetscCheck(range[0] > 0, comm, PETSC_ERR_PLIB,
             "a rank owns no particle after the migration (%" PetscInt_FMT " to %" PetscInt_FMT "): no cut is tested",
             range[0], range[1]);
  PetscCall(Gather(comm, su, nowned, x, id, &gs));

  /* the halo, built and refreshed as in src/solver/stepping.c: the ghosts' records after the owned ones */
  PetscCall(PetscMalloc1(nowned * S, &rec));
  for (PetscInt p = 0; p < nowned; p++) {
    for (PetscInt d = 0; d < dim; d++) rec[p * S + d] = x[p * dim + d];
    rec[p * S + dim] = (PetscReal)id[p];
  }
  PetscCall(PetscMemzero(&hl, sizeof(hl)));
  hl.rectype = hl.auxtype = MPI_DATATYPE_NULL;
  PetscCall(FSHaloBuild(&hl, comm, &dd, nowned, rec, S, su->width));
  {
    PetscReal *all;
    PetscCall(PetscCalloc1((nowned + hl.nghost) * S, &all));
    PetscCall(PetscArraycpy(all, rec, nowned * S));
    PetscCall(PetscFree(rec));
    rec = all;
  }
  PetscCall(FSHaloRefresh(&hl, dim, nowned, rec));
  /* each ghost is a particle of the global set at its place or at a periodic image of it, and they are all the
     images within the halo width of this rank's box */
  for (PetscInt g = 0; g < hl.nghost; g++) {
    const PetscReal *xg      = &rec[(nowned + g) * S];
    const PetscInt   gid     = (PetscInt)xg[dim];
    PetscBool        shifted = PETSC_FALSE;
    PetscCheck(gid >= 0 && gid < su->N, PETSC_COMM_SELF, PETSC_ERR_PLIB, "[%d] ghost %" PetscInt_FMT " has the id %g",
               (int)rank, g, (double)xg[dim]);
    for (PetscInt d = 0; d < dim; d++) {
      const PetscReal s = hl.shift[g * dim + d];
      PetscCheck(s == 0 || (su->periodic[d] && PetscAbsReal(s) == su->len[d]), PETSC_COMM_SELF, PETSC_ERR_PLIB,
                 "[%d] ghost %" PetscInt_FMT " shifted by %g along %" PetscInt_FMT, (int)rank, g, (double)s, d);
      dghost  = PetscMax(dghost, PetscAbsReal(xg[d] - (gs.x[gid * dim + d] + s)));
      shifted = (PetscBool)(shifted || s != 0);
    }
    gh[0]++;
    gh[2] += shifted;
  }
  for (PetscInt g = 0; g < su->N; g++) gh[1] += ExpectedGhosts(su, &dd, &gs, g);
  PetscCallMPI(MPI_Allreduce(MPI_IN_PLACE, gh, 3, MPIU_INT64, MPI_SUM, comm));
  PetscCallMPI(MPI_Allreduce(MPI_IN_PLACE, &dghost, 1, MPIU_REAL, MPI_MAX, comm));
  PetscCheck(dghost == 0, comm, PETSC_ERR_PLIB, "a ghost lies %g from its owner's position (plus its shift)",
             (double)dghost);
  PetscCheck(gh[0] == gh[1], comm, PETSC_ERR_PLIB,
             "the halo holds %" PetscInt64_FMT " ghosts, %" PetscInt64_FMT " particles or images lie within its width",
             gh[0], gh[1]);

  /* the lists over the owned and ghost particles, as in src/solver/stepping.c and rhs.c */
  PetscCall(PetscMemzero(&nb, sizeof(nb)));
  nb.form = Form;
  PetscCall(PetscMemzero(&pl, sizeof(pl)));
  PetscCall(FSNeighboursBuildCells(&nb, dim, nowned + hl.nghost, rec, S, su->width));
  PetscCall(FSNeighboursBuildCandidates(&nb, nowned, rec, S, su->width));
  PetscCall(PickPairs(&nb, &k, nowned, rec, S, &pl));
  PetscCall(CompareLists(su, &k, &pl, nowned, rec, hl.shift, &gs, rank, &c));
  PetscCall(SumComparison(comm, &c));
  PetscCheck(c.missing == 0 && c.wrong == 0 && c.pairs == c.expected && c.expected > 0, comm, PETSC_ERR_PLIB,
             "%" PetscInt_FMT "-D on %d ranks: %" PetscInt64_FMT " pairs listed, %" PetscInt64_FMT
             " by brute force; %" PetscInt64_FMT " missing, %" PetscInt64_FMT " wrong",
             dim, (int)size, c.pairs, c.expected, c.missing, c.wrong);
  PetscCheck(size == 1 || c.crossrank > 0, comm, PETSC_ERR_PLIB,
             "%" PetscInt_FMT "-D on %d ranks: no pair has its partner on another rank: the cut is not tested", dim,
             (int)size);
  PetscCheck(!anyperiodic || c.periodic > 0, comm, PETSC_ERR_PLIB,
             "%" PetscInt_FMT "-D: no pair across the periodic side: it is not tested", dim);
  { /* the owned particles split by whether a ghost can be among their candidates (FSNeighboursSplitByGhosts): an
       ordered permutation, none of the first group with a ghost candidate; cnt: first group, second, second with one */
    PetscInt  *pass, ni;
    PetscBool *seen;
    PetscInt64 cnt[3] = {0, 0, 0};
    PetscCall(PetscMalloc1(nowned, &pass));
    PetscCall(PetscCalloc1(nowned, &seen));
    PetscCall(FSNeighboursSplitByGhosts(&nb, nowned, nowned + hl.nghost, pass, &ni));
    for (PetscInt q = 0; q < nowned; q++) {
      const PetscInt  i     = pass[q];
      PetscBool       ghost = PETSC_FALSE;
      FSCandidateIter it;
      PetscInt        j;
      PetscCheck(
          i >= 0 && i < nowned && !seen[i] && (q == 0 || q == ni || pass[q - 1] < i), PETSC_COMM_SELF, PETSC_ERR_PLIB,
          "[%d] the split is not the owned particles in two ordered groups (entry %" PetscInt_FMT ")", (int)rank, q);
      seen[i] = PETSC_TRUE;
      FSNeighboursCandidateBegin(&nb, i, &it);
      while (FSNeighboursCandidateNext(&nb, &it, &j)) ghost = (PetscBool)(ghost || j >= nowned);
      PetscCheck(q >= ni || !ghost, PETSC_COMM_SELF, PETSC_ERR_PLIB,
                 "[%d] particle %" PetscInt_FMT " is in the first group but has a ghost among its candidates",
                 (int)rank, i);
      cnt[q < ni ? 0 : 1]++;
      cnt[2] += q >= ni && ghost;
    }
    PetscCallMPI(MPI_Allreduce(MPI_IN_PLACE, cnt, 3, MPIU_INT64, MPI_SUM, comm));
    PetscCheck(cnt[0] > 0 && (gh[0] == 0 || cnt[2] > 0), comm, PETSC_ERR_PLIB,
               "the split has %" PetscInt64_FMT " particles without ghost candidates, %" PetscInt64_FMT
               " with a ghost among them: a group is not tested",
               cnt[0], cnt[2]);
    PetscCall(PetscPrintf(comm,
                          "  %" PetscInt_FMT "-D: %" PetscInt64_FMT
                          " particles with no ghost among their candidates, %" PetscInt64_FMT
                          " others (%" PetscInt64_FMT " of them with a ghost candidate)\n",
                          dim, cnt[0], cnt[1], cnt[2]));
    PetscCall(PetscFree(pass));
    PetscCall(PetscFree(seen));
  }
  /* the same lists without the ghosts: the check must find exactly the pairs with a ghost missing */
  PetscCall(FSNeighboursBuildCells(&nb, dim, nowned, rec, S, su->width));
  PetscCall(FSNeighboursBuildCandidates(&nb, nowned, rec, S, su->width));
  PetscCall(PickPairs(&nb, &k, nowned, rec, S, &pl));
  PetscCall(CompareLists(su, &k, &pl, nowned, rec, hl.shift, &gs, rank, &c0));
  PetscCall(SumComparison(comm, &c0));
  PetscCheck(c.ghost > 0 && c0.missing == c.ghost && c0.wrong == 0, comm, PETSC_ERR_PLIB,
             "without the halo the check finds %" PetscInt64_FMT " pairs missing (%" PetscInt64_FMT
             " wrong), the lists with it have %" PetscInt64_FMT " pairs with a ghost",
             c0.missing, c0.wrong, c.ghost);
  PetscCall(PetscPrintf(comm,
                        "  %" PetscInt_FMT "-D, %d rank(s), %" PetscInt_FMT " to %" PetscInt_FMT
                        " particles owned, %" PetscInt64_FMT " ghosts (%" PetscInt64_FMT
                        " periodic images): %" PetscInt64_FMT " pairs match brute force, %" PetscInt64_FMT
                        " with a partner on another rank, %" PetscInt64_FMT
                        " across a periodic side; largest distance difference %.3g support, kernel factor %.3g "
                        "fnorm; without the halo %" PetscInt64_FMT " pairs are missing\n",
                        dim, (int)size, range[0], range[1], gh[0], gh[2], c.pairs, c.crossrank, c.periodic,
                        (double)c.dr, (double)c.dF, c0.missing));
  PetscCall(FSNeighboursDestroy(&nb));
  PetscCall(PetscFree2(pl.start, pl.nbr));
  PetscCall(FSHaloDestroy(&hl));
  PetscCall(FSDecompDestroy(&dd));
  PetscCall(PetscFree2(gs.x, gs.owner));
  PetscCall(PetscFree2(x, id));
  PetscCall(PetscFree(rec));
  PetscFunctionReturn(0);
}

/*
   The cuts balanced on weighted particles (FSDecompBalance): a 2-D lattice of 400 x 10 particles in [0, 4] x [0, 1],
   dealt to the ranks by turns, three times as heavy below x = 1.013 (101 planes of x). Each cut must have below it
   the planes whose weight comes closest to k/size of the total (brute force over the planes; on 2 ranks the closest
   is the edge before the plane that crosses the half), and without weights the count's quantile.
*/
static PetscErrorCode TestBalanceWeights(MPI_Comm comm)
{
  const PetscInt  nx = 400, ny = 10;
  const PetscReal lo[2] = {0, 0}, hi[2] = {4, 1}, a = 0.01, heavy = 1.013;
  const PetscBool periodic[2] = {PETSC_FALSE, PETSC_FALSE};
  PetscMPIInt     rank, size;
  FSDecomp        dd;
  PetscReal      *x;
  PetscInt64     *w;
  PetscInt        n = 0;

  PetscFunctionBegin;
  PetscCallMPI(MPI_Comm_rank(comm, &rank));
  PetscCallMPI(MPI_Comm_size(comm, &size));
  if (size == 1) PetscFunctionReturn(0);
  PetscCall(PetscMalloc2(2 * nx * ny, &x, nx * ny, &w));
  for (PetscInt p = 0; p < nx * ny; p++) {
    if (p % size != rank) continue;
    x[2 * n]     = ((p / ny) + 0.5) * a;
    x[2 * n + 1] = ((p % ny) + 0.5) * 0.1;
    w[n++]       = x[2 * n] < heavy ? 3 : 1;
  }
  for (PetscInt weighted = 0; weighted < 2; weighted++) {
    PetscInt64 total = 0, acc = 0;
    PetscInt   k = 1;
    PetscCall(FSDecompSetUp(&dd, comm, 2, lo, hi, periodic, 0.05));
    PetscCheck(dd.np[0] == size, comm, PETSC_ERR_PLIB, "the grid splits x in %d, not in %d", (int)dd.np[0], (int)size);
    PetscCall(FSDecompBalance(&dd, comm, n, x, weighted ? w : NULL, 0.05));
    for (PetscInt i = 0; i < nx; i++) total += ny * (weighted && (i + 0.5) * a < heavy ? 3 : 1);
    for (PetscInt i = 0; i < nx && k < size; i++) { /* after plane i: the edge (i + 1) a */
      const PetscInt64 below = acc;
      acc += ny * (weighted && (i + 0.5) * a < heavy ? 3 : 1);
      while (k < size && acc * size >= total * k) {
        const PetscInt planes = (total * k - below * size < acc * size - total * k) ? i : i + 1; /* below the edge */
        PetscInt       got    = 0;
        for (PetscInt q = 0; q < nx; q++) got += (q + 0.5) * a < dd.cut[0][k];
        PetscCheck(got == planes, comm, PETSC_ERR_PLIB,
                   "%s cut %" PetscInt_FMT " at %g has %" PetscInt_FMT " planes below it; the closest to %" PetscInt_FMT
                   "/%d of the weight has %" PetscInt_FMT,
                   weighted ? "weighted" : "unweighted", k, (double)dd.cut[0][k], got, k, (int)size, planes);
        PetscCall(PetscPrintf(comm,
                              "  %s particles, %d ranks: cut %" PetscInt_FMT " at %g, %" PetscInt_FMT " planes below\n",
                              weighted ? "weighted" : "unweighted", (int)size, k, (double)dd.cut[0][k], got));
        k++;
      }
    }
    PetscCall(FSDecompDestroy(&dd));
  }
  PetscCall(PetscFree2(x, w));
  PetscFunctionReturn(0);
}

int main(int argc, char **argv)
{
  /* 2-D: a long box split along x, periodic along x (across the cut on 2 ranks, onto the rank itself on 1);
     3-D: split along x, periodic along z (one rank across: images of the rank's own particles) */
  const DistSetUp d2 = {2, 4000, {2.0, 0.5, 0}, {PETSC_TRUE, PETSC_FALSE, PETSC_FALSE}, 0.02, 2.5 * 0.02};
  const DistSetUp d3 = {3, 4000, {1.0, 0.5, 0.5}, {PETSC_FALSE, PETSC_FALSE, PETSC_TRUE}, 0.03, 2.5 * 0.03};

  PetscMPIInt rank;

  PetscFunctionBeginUser;
  PetscCall(PetscInitialize(&argc, &argv, NULL, NULL));
  PetscCallMPI(MPI_Comm_rank(PETSC_COMM_WORLD, &rank));
  if (!rank) { /* the serial checks, once */
    PetscCall(TestKernel(2));
    PetscCall(TestKernel(3));
  }
  for (PetscInt f = 0; f < 2; f++) { /* the candidates as indices, then as bits */
    Form = f ? FS_CANDIDATES_BITS : FS_CANDIDATES_INDICES;
    PetscCall(PetscPrintf(PETSC_COMM_WORLD, "candidates as %s:\n", f ? "bits" : "indices"));
    if (!rank) {
      PetscCall(TestNeighbours(2, 3000, 500));
      PetscCall(TestNeighbours(3, 2000, 400));
    }
    PetscCall(TestDistributed(PETSC_COMM_WORLD, &d2));
    PetscCall(TestDistributed(PETSC_COMM_WORLD, &d3));
  }
  PetscCall(TestBalanceWeights(PETSC_COMM_WORLD));
  PetscCall(PetscPrintf(PETSC_COMM_WORLD, "test_neighbours: OK\n"));
  PetscCall(PetscFinalize());
  return 0;
}
