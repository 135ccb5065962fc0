/*
   The relaxed packing (-fs_fill_packing relaxed): the particles of a body of liquid moved, from the lattice, until
   they are evenly spread in the closed region of their walls and fill level (packregion.c).

   A particle i is evenly surrounded when

     e_i = sum_j V_j grad_i W_ij + sum_k n_k int_k W dS = 0,

   the particles' kernel-gradient sum and the walls' boundary integral (n_k out of the liquid), zero for a
   continuum: the sum that the pressure gradient's boundary-integral form (p_i + p_j) multiplies with a particle's
   own pressure (docs/walls.md), so that a packing with e_i = 0 is at rest under a uniform pressure in the solver's
   own discretization. With -fs_walls_repulsion kappa the wall term weighs a particle's own pressure f_ik = 1 +
   kappa (d0 - d_ik)/d0 times within d0 of an element (wall.c), so an element's share in e_i is weighed (1 + f_ik)/2
   here: without it the relaxed particles that sit closer than d0 to a wall start pushed off it (a 3-D box turned
   30 degrees rang at 0.015 sqrt(gH), docs/walls.md). With -fs_walls_visibility all the run's wall terms count every
   element within the support, those that face away (a rib's far face, seen through the rib with the particles
   beyond it) with their signed distance, and so does e_i here; counting only the facing ones left a rib's nearest
   rows pulled towards it at 0.3 g (docs/own-tank.md). This is the background-pressure relaxation of SPHinXsys (Zhu,
   Zhang & Hu 2021), with the boundary integrals in place of its level set's kernel integral: each iteration moves a
   particle by -step h^2 e_i (at most dx/10), keeping it at least dx/4 from the walls and the fill level. The fill level
   is a wall during the relaxation (a lid), so that the free surface stays flat at the fill level; the lid is dropped
   after it. Before it, the lattice is thinned where it is over-full (-fs_fill_packing_thin, ThinOverfull): a gap
   thinner than two spacings gets up to twice its volume in points, a surplus the relaxation does not carry out.

   The work is split over the ranks by particle, every rank holding all positions (gathered after each iteration):
   each particle's sums run over the same neighbours in the same order on any number of ranks, so that the
   packing is the same bit for bit.
*/
#include <stdio.h>
#include <sys/stat.h>
#include "packing.h"
#include "particles/fsparticles.h"
#include "sys/fssys.h"

/* a grid of cells of side `cell` over lo..lo + nc cell: for each cell its items (CSR) */
typedef struct {
  PetscInt  dim, nc[3], ncell;
  PetscReal lo[3], cell;
  PetscInt *start, *item;
} Grid;

static inline PetscInt CellCoord(const Grid *gr, const PetscReal x[], PetscInt d)
{
  const PetscInt c = (PetscInt)PetscFloorReal((x[d] - gr->lo[d]) / gr->cell);
  return PetscMax(0, PetscMin(gr->nc[d] - 1, c));
}

/* the 3 x 3 (x 3) cells around x's, clipped to the grid: [lo, hi] per dimension (0, 0 beyond dim) */
static inline void NeighbourCells(const Grid *gr, const PetscReal x[], PetscInt dim, PetscInt lo[3], PetscInt hi[3])
{
  for (PetscInt d = 0; d < 3; d++) lo[d] = hi[d] = 0;
  for (PetscInt d = 0; d < dim; d++) {
    const PetscInt c = CellCoord(gr, x, d);
    lo[d]            = PetscMax(0, c - 1);
    hi[d]            = PetscMin(gr->nc[d] - 1, c + 1);
  }
}

static inline PetscInt CellOf(const Grid *gr, const PetscReal x[])
{
  PetscInt c = 0;
  for (PetscInt d = gr->dim - 1; d >= 0; d--) c = c * gr->nc[d] + CellCoord(gr, x, d);
  return c;
}

static PetscErrorCode GridSetUp(Grid *gr, const FSPackRegion *g, PetscReal cell)
{
  PetscFunctionBegin;
  PetscCall(PetscMemzero(gr, sizeof(*gr)));
  gr->dim   = g->dim;
  gr->cell  = cell;
  gr->ncell = 1;
  for (PetscInt d = 0; d < 3; d++) gr->nc[d] = 1;
  for (PetscInt d = 0; d < g->dim; d++) {
    gr->lo[d] = g->lo[d] - cell;
    gr->nc[d] = (PetscInt)PetscCeilReal((g->hi[d] - g->lo[d]) / cell) + 2;
    gr->ncell *= gr->nc[d];
  }
  PetscCall(PetscCalloc1(gr->ncell + 1, &gr->start));
  PetscFunctionReturn(0);
}

/* the particles x (N) into the grid's cells, in the order of their indices within a cell */
static PetscErrorCode GridFillPoints(Grid *gr, PetscInt N, const PetscReal x[], PetscInt *cellof)
{
  PetscFunctionBegin;
  PetscCall(PetscArrayzero(gr->start, gr->ncell + 1));
  for (PetscInt i = 0; i < N; i++) {
    cellof[i] = CellOf(gr, &x[gr->dim * i]);
    gr->start[cellof[i] + 1]++;
  }
  for (PetscInt c = 0; c < gr->ncell; c++) gr->start[c + 1] += gr->start[c];
  for (PetscInt i = 0; i < N; i++) gr->item[gr->start[cellof[i]]++] = i;
  for (PetscInt c = gr->ncell; c > 0; c--) gr->start[c] = gr->start[c - 1];
  gr->start[0] = 0;
  PetscFunctionReturn(0);
}

/* each element into every cell within R of its corners' box: the candidates of a point in that cell */
static PetscErrorCode GridFillElements(Grid *gr, const FSPackRegion *g, PetscReal R)
{
  const PetscInt nv = g->dim == 2 ? 2 : 3;
  PetscInt       pass, total = 0;

  PetscFunctionBegin;
  for (pass = 0; pass < 2; pass++) {
    if (pass == 1) {
      for (PetscInt c = 0; c < gr->ncell; c++) gr->start[c + 1] += gr->start[c];
      total = gr->start[gr->ncell];
      PetscCall(PetscMalloc1(total + 1, &gr->item));
    }
    for (PetscInt k = 0; k < g->nel; k++) {
      const PetscReal *el = &g->el[k * g->stride];
      PetscReal        blo[3], bhi[3];
      PetscInt         c0[3] = {0, 0, 0}, c1[3] = {0, 0, 0};
      for (PetscInt d = 0; d < g->dim; d++) {
        blo[d] = bhi[d] = el[d];
        for (PetscInt v = 1; v < nv; v++) {
          blo[d] = PetscMin(blo[d], el[v * g->dim + d]);
          bhi[d] = PetscMax(bhi[d], el[v * g->dim + d]);
        }
        blo[d] -= R;
        bhi[d] += R;
        c0[d] = CellCoord(gr, blo, d);
        c1[d] = CellCoord(gr, bhi, d);
      }
      for (PetscInt c = c0[2]; c <= c1[2]; c++)
        for (PetscInt b = c0[1]; b <= c1[1]; b++)
          for (PetscInt a = c0[0]; a <= c1[0]; a++) {
            const PetscInt cell = (c * gr->nc[1] + b) * gr->nc[0] + a;
            if (pass == 0) gr->start[cell + 1]++;
            else gr->item[gr->start[cell]++] = k;
          }
    }
  }
  for (PetscInt c = gr->ncell; c > 0; c--) gr->start[c] = gr->start[c - 1];
  gr->start[0] = 0;
  PetscFunctionReturn(0);
}

static PetscErrorCode GridDestroy(Grid *gr)
{
  PetscFunctionBegin;
  PetscCall(PetscFree(gr->start));
  PetscCall(PetscFree(gr->item));
  PetscFunctionReturn(0);
}

/* the distance of x from the plane of element el (its first corner FS_SEG_P0 / FS_TRI_P0, its normal n out of the
   liquid): > 0 on the liquid's side */
static inline PetscReal ElementPlaneDistance(PetscInt dim, const PetscReal el[], const PetscReal n[],
                                             const PetscReal x[])
{
  PetscReal s = 0;
  for (PetscInt d = 0; d < dim; d++) s += (el[d] - x[d]) * n[d];
  return s;
}

/* e_i of the particle i (packing.c's header); push: the wall_pressure term's kappa and d0 (a length), whose f_ik
   weighs an element's share near contact as the run's wall term does under a uniform pressure; all: every element
   within the support counts, those facing away too (-fs_walls_visibility all), else the facing ones */
static void ParticleSum(const FSPackRegion *g, const Grid *pg, const Grid *eg, const FSKernel *k, PetscReal V,
                        const PetscReal push[2], PetscBool all, const PetscReal X[], PetscInt i, PetscReal e[])
{
  const PetscInt   dim = g->dim;
  const PetscReal *xi  = &X[dim * i];
  PetscInt         lo[3], hi[3];

  for (PetscInt d = 0; d < 3; d++) e[d] = 0;
  NeighbourCells(pg, xi, dim, lo, hi);
  for (PetscInt cz = lo[2]; cz <= hi[2]; cz++)
    for (PetscInt cy = lo[1]; cy <= hi[1]; cy++)
      for (PetscInt cx = lo[0]; cx <= hi[0]; cx++) {
        const PetscInt cell = (cz * pg->nc[1] + cy) * pg->nc[0] + cx;
        for (PetscInt q = pg->start[cell]; q < pg->start[cell + 1]; q++) {
          const PetscInt   j  = pg->item[q];
          const PetscReal *xj = &X[dim * j];
          PetscReal        r2 = 0, f;
          if (j == i) continue;
          for (PetscInt d = 0; d < dim; d++) r2 += (xi[d] - xj[d]) * (xi[d] - xj[d]);
          if (r2 >= k->support2) continue;
          f = V * FSKernelF(k, PetscSqrtReal(r2));
          for (PetscInt d = 0; d < dim; d++) e[d] += f * (xi[d] - xj[d]);
        }
      }
  {
    const PetscInt cell = CellOf(eg, xi);
    for (PetscInt q = eg->start[cell]; q < eg->start[cell + 1]; q++) {
      const PetscReal *el = &g->el[eg->item[q] * g->stride], *n;
      PetscReal        gk, wint;
      if (dim == 2) {
        FSSegmentIntegrals(k->h, xi, el, all, &gk, &wint);
        n = el + FS_SEG_NORMAL;
      } else {
        FSTriangleIntegrals(k->h, xi, el, all, &gk, &wint);
        n = el + FS_TRI_NORMAL;
      }
      PetscReal f = 1; /* the wall term's weight (1 + f_ik)/2 under a uniform pressure (wall.c) */
      if (push[0] > 0) {
        const PetscReal dist = ElementPlaneDistance(dim, el, n, xi);
        if (dist > 0 && dist < push[1]) f += 0.5 * push[0] * (push[1] - dist) / push[1];
      }
      for (PetscInt d = 0; d < dim; d++) e[d] += f * wint * n[d];
    }
  }
}

/* x kept at least dmin inside the box (the fill level) and from the planes of the elements whose nearest point to it
   lies inside them (a wall it faces, not one around a corner) within dx/2 */
static void KeepFromWalls(const FSPackRegion *g, const Grid *eg, PetscReal dmin, PetscReal reach, PetscReal x[])
{
  PetscInt cell;
  for (PetscInt d = 0; d < g->dim; d++) x[d] = PetscMax(g->lo[d] + dmin, PetscMin(g->hi[d] - dmin, x[d])); /* the box */
  cell = CellOf(eg, x);
  for (PetscInt q = eg->start[cell]; q < eg->start[cell + 1]; q++) {
    const PetscReal *el = &g->el[eg->item[q] * g->stride], *n = el + (g->dim == 2 ? FS_SEG_NORMAL : FS_TRI_NORMAL);
    const PetscReal  s = ElementPlaneDistance(g->dim, el, n, x);
    PetscReal        d2;
    if (s >= dmin || s <= -dmin) continue;
    d2 = g->dim == 2 ? FSSegmentDistance2(el, x)
                     : FSTriangleDistance2(el + FS_TRI_P0, el + FS_TRI_P1, el + FS_TRI_P2, x);
    if (d2 < reach * reach && PetscAbsReal(d2 - s * s) <= 1e-6 * reach * reach)
      for (PetscInt d = 0; d < g->dim; d++) x[d] -= (dmin - s) * n[d];
  }
}

/* a max-heap of candidates (value, index), the larger value first and the lower index among equals */
typedef struct {
  PetscInt   n;
  PetscReal *v;
  PetscInt  *i;
} Heap;

static inline PetscBool HeapAbove(const Heap *hp, PetscInt a, PetscInt b)
{
  return (PetscBool)(hp->v[a] > hp->v[b] || (hp->v[a] == hp->v[b] && hp->i[a] < hp->i[b]));
}

static inline void HeapSwap(Heap *hp, PetscInt a, PetscInt b)
{
  const PetscReal v = hp->v[a];
  const PetscInt  i = hp->i[a];
  hp->v[a]          = hp->v[b];
  hp->i[a]          = hp->i[b];
  hp->v[b]          = v;
  hp->i[b]          = i;
}

static void HeapPush(Heap *hp, PetscReal v, PetscInt i)
{
  PetscInt c = hp->n++;
  hp->v[c]   = v;
  hp->i[c]   = i;
  while (c > 0 && HeapAbove(hp, c, (c - 1) / 2)) {
    HeapSwap(hp, c, (c - 1) / 2);
    c = (c - 1) / 2;
  }
}

static void HeapPop(Heap *hp)
{
  PetscInt c = 0;
  HeapSwap(hp, 0, --hp->n);
  for (;;) {
    const PetscInt l = 2 * c + 1, r = l + 1;
    PetscInt       b = c;
    if (l < hp->n && HeapAbove(hp, l, b)) b = l;
    if (r < hp->n && HeapAbove(hp, r, b)) b = r;
    if (b == c) break;
    HeapSwap(hp, b, c);
    c = b;
  }
}

/* sum_j V W(|x - Y_j|) over the points Y_j of the grid pg within the kernel's support of x (those with keep[j] where
   keep is given); with o, each such term is also taken off o[j] */
static PetscReal KernelShare(const Grid *pg, const FSKernel *k, PetscReal V, PetscInt dim, const PetscReal Y[],
                             const PetscReal x[], const PetscBool keep[], PetscReal o[])
{
  PetscReal sum = 0;
  PetscInt  lo[3], hi[3];

  NeighbourCells(pg, x, dim, lo, hi);
  for (PetscInt cz = lo[2]; cz <= hi[2]; cz++)
    for (PetscInt cy = lo[1]; cy <= hi[1]; cy++)
      for (PetscInt cx = lo[0]; cx <= hi[0]; cx++) {
        const PetscInt cl = (cz * pg->nc[1] + cy) * pg->nc[0] + cx;
        for (PetscInt q = pg->start[cl]; q < pg->start[cl + 1]; q++) {
          const PetscInt   j  = pg->item[q];
          const PetscReal *xj = &Y[dim * j];
          PetscReal        r2 = 0, w;
          if (keep && !keep[j]) continue;
          for (PetscInt d = 0; d < dim; d++) r2 += (x[d] - xj[d]) * (x[d] - xj[d]);
          if (r2 >= k->support2) continue;
          w = V * FSKernelW(k, PetscSqrtReal(r2));
          sum += w;
          if (o) o[j] -= w;
        }
      }
  return sum;
}

/*
   ThinOverfull - the points X (N, every rank all of them, in the ranks' order) of a region where they crowd
   removed, one at a time: a point's fullness o_i = sum_j V W_ij - gamma_i, the particles' kernel sum (its own
   term included) less the region's geometric gamma (the kernel's part inside the liquid, the boundary integrals
   over every element within the support), 0 where the points are spread at V each (the interior of a lattice of
   spacing V^(1/dim), one cut by walls along its planes). The points above `over` are the candidates: the most
   over-full goes first (the lower index among equals), its neighbours' fullness lowered by its term, until no
   candidate is over-full (o_i > 0). A thin gap between walls gets the lattice's rows
   wherever their points fall in it, up to twice its volume (under a wing bay's rib, docs/own-tank.md), a surplus
   that the relaxation's moves of dx/10 do not carry out. The points are judged where the relaxation starts them
   (KeepFromWalls). keep[i] is false for a removed point; *removed their number, *omax the largest fullness before;
   the same on every rank.
*/
static PetscErrorCode ThinOverfull(const FSPackRegion *g, const Grid *eg, const FSKernel *k, PetscReal V,
                                   PetscReal over, PetscReal dx, PetscInt N, const PetscReal X[], PetscBool keep[],
                                   PetscInt *removed, PetscReal *omax)
{
  const PetscInt dim = g->dim;
  Grid           pg;
  PetscReal     *Y, *o;
  PetscInt      *cellof;
  Heap           hp;

  PetscFunctionBegin;
  *removed = 0;
  *omax    = 0;
  PetscCall(PetscMalloc3(dim * N, &Y, N, &o, N, &cellof));
  PetscCall(PetscArraycpy(Y, X, dim * N));
  for (PetscInt i = 0; i < N; i++) KeepFromWalls(g, eg, 0.25 * dx, 0.5 * dx, &Y[dim * i]);
  PetscCall(GridSetUp(&pg, g, k->support));
  PetscCall(PetscMalloc1(N, &pg.item));
  PetscCall(GridFillPoints(&pg, N, Y, cellof));
  for (PetscInt i = 0; i < N; i++) { /* o_i */
    const PetscReal *xi   = &Y[dim * i];
    const PetscInt   cell = CellOf(eg, xi);
    PetscReal        sum = KernelShare(&pg, k, V, dim, Y, xi, NULL, NULL), gamma = 1;
    for (PetscInt q = eg->start[cell]; q < eg->start[cell + 1]; q++) {
      const PetscReal *el = &g->el[eg->item[q] * g->stride];
      PetscReal        gk, wint;
      if (dim == 2) FSSegmentIntegrals(k->h, xi, el, PETSC_TRUE, &gk, &wint);
      else FSTriangleIntegrals(k->h, xi, el, PETSC_TRUE, &gk, &wint);
      gamma += gk;
    }
    o[i]    = sum - gamma;
    keep[i] = PETSC_TRUE;
    *omax   = PetscMax(*omax, o[i]);
  }
  hp.n = 0;
  PetscCall(PetscMalloc2(N, &hp.v, N, &hp.i));
  for (PetscInt i = 0; i < N; i++)
    if (o[i] > over) HeapPush(&hp, o[i], i);
  while (hp.n > 0 && *removed < N - 1) { /* one point at least is left */
    const PetscInt   i  = hp.i[0];
    const PetscReal  v  = hp.v[0];
    const PetscReal *xi = &Y[dim * i];
    HeapPop(&hp);
    if (!keep[i]) continue;
    if (v != o[i] || o[i] <= 0) { /* lowered since it was pushed: back at its place while still over-full */
      if (o[i] > 0) HeapPush(&hp, o[i], i);
      continue;
    }
    keep[i] = PETSC_FALSE;
    (*removed)++;
    (void)KernelShare(&pg, k, V, dim, Y, xi, keep, o); /* its term off its neighbours' fullness */
  }
  PetscCall(PetscFree2(hp.v, hp.i));
  PetscCall(GridDestroy(&pg));
  PetscCall(PetscFree3(Y, o, cellof));
  PetscFunctionReturn(0);
}

/* FNV-1a over bytes, continued from h */
static PetscInt64 Hash(PetscInt64 h, const void *data, size_t len)
{
  const unsigned char *b = (const unsigned char *)data;
  uint64_t             u = (uint64_t)h;
  for (size_t i = 0; i < len; i++) {
    u ^= b[i];
    u *= 1099511628211ULL;
  }
  return (PetscInt64)u;
}

/* the cache's file for this packing: <folder>/packing-<hash>.bin, the hash of the region, the start, the volume,
   the spacing and the settings */
static PetscErrorCode CachePath(const FSFillPacking *opt, const FSPackRegion *g, PetscInt N, const PetscReal X[],
                                const PetscReal par[4], char path[], size_t len)
{
  PetscInt64 h = (PetscInt64)1469598103934665603ULL;

  PetscFunctionBegin;
  h = Hash(h, &g->dim, sizeof(g->dim));
  h = Hash(h, &N, sizeof(N));
  h = Hash(h, par, 4 * sizeof(PetscReal));
  h = Hash(h, &opt->iterations, sizeof(opt->iterations));
  h = Hash(h, &opt->step, sizeof(opt->step));
  if (opt->repulsion > 0) { /* the wall weights near contact (none: the hashes of before) */
    h = Hash(h, &opt->repulsion, sizeof(opt->repulsion));
    h = Hash(h, &opt->repulsion_distance, sizeof(opt->repulsion_distance));
  }
  if (opt->visall) h = Hash(h, &opt->visall, sizeof(opt->visall)); /* the elements facing away (none: as before) */
  h = Hash(h, g->el, sizeof(PetscReal) * g->nel * g->stride);
  h = Hash(h, X, sizeof(PetscReal) * g->dim * N);
  PetscCall(PetscSNPrintf(path, len, "%s/packing-%016llx.bin", opt->cache, (unsigned long long)h));
  PetscFunctionReturn(0);
}

#define FS_PACKING_MAGIC "flexslosh relaxed packing 1\n"

/* rank 0 reads the packing X (N points) from path if it is there and whole; *found on every rank */
static PetscErrorCode CacheRead(MPI_Comm comm, const char path[], PetscInt dim, PetscInt N, PetscReal X[],
                                PetscBool *found)
{
  PetscMPIInt rank, ok = 0;

  PetscFunctionBegin;
  PetscCallMPI(MPI_Comm_rank(comm, &rank));
  if (rank == 0) {
    FILE *f = fopen(path, "rb");
    if (f) {
      char     magic[sizeof(FS_PACKING_MAGIC)] = "";
      PetscInt hdr[2];
      ok = fread(magic, 1, sizeof(FS_PACKING_MAGIC) - 1, f) == sizeof(FS_PACKING_MAGIC) - 1 &&
           !strcmp(magic, FS_PACKING_MAGIC) && fread(hdr, sizeof(PetscInt), 2, f) == 2 && hdr[0] == dim &&
           hdr[1] == N && fread(X, sizeof(PetscReal), (size_t)dim * N, f) == (size_t)dim * N;
      fclose(f);
    }
  }
  PetscCallMPI(MPI_Bcast(&ok, 1, MPI_INT, 0, comm));
  if (ok) PetscCallMPI(MPI_Bcast(X, (PetscMPIInt)(dim * N), MPIU_REAL, 0, comm));
  *found = ok ? PETSC_TRUE : PETSC_FALSE;
  PetscFunctionReturn(0);
}

/* rank 0 writes the packing X to path (through a temporary file, renamed: a reader never sees half of it) */
static PetscErrorCode CacheWrite(MPI_Comm comm, const char folder[], const char path[], PetscInt dim, PetscInt N,
                                 const PetscReal X[])
{
  PetscMPIInt rank;

  PetscFunctionBegin;
  PetscCallMPI(MPI_Comm_rank(comm, &rank));
  if (rank == 0) {
    char     tmp[PETSC_MAX_PATH_LEN + 16];
    FILE    *f;
    PetscInt hdr[2] = {dim, N};
    (void)mkdir(folder, 0777);
    PetscCall(PetscSNPrintf(tmp, sizeof(tmp), "%s.tmp", path));
    f = fopen(tmp, "wb");
    PetscCheck(f, PETSC_COMM_SELF, PETSC_ERR_FILE_OPEN,
               "-fs_fill_packing_cache %s: cannot write %s: expected a folder that can be written", folder, tmp);
    PetscCheck(fwrite(FS_PACKING_MAGIC, 1, sizeof(FS_PACKING_MAGIC) - 1, f) == sizeof(FS_PACKING_MAGIC) - 1 &&
                   fwrite(hdr, sizeof(PetscInt), 2, f) == 2 &&
                   fwrite(X, sizeof(PetscReal), (size_t)dim * N, f) == (size_t)dim * N && fclose(f) == 0,
               PETSC_COMM_SELF, PETSC_ERR_FILE_WRITE, "-fs_fill_packing_cache %s: writing %s failed", folder, tmp);
    PetscCheck(rename(tmp, path) == 0, PETSC_COMM_SELF, PETSC_ERR_FILE_WRITE,
               "-fs_fill_packing_cache %s: cannot rename %s to %s", folder, tmp, path);
  }
  PetscFunctionReturn(0);
}

/* the points X (N of them, this rank's n from i0) thinned where the lattice is over-full (ThinOverfull, above
   `over`): X compacted, *n, *N, *i0 and the ranks' counts and displacements (in reals) updated */
static PetscErrorCode PackThin(FSSolver s, const FSPackRegion *g, const Grid *eg, const FSKernel *k, PetscReal volume,
                               PetscReal over, PetscReal dx, const char what[], PetscInt *n, PetscInt *N, PetscInt *i0,
                               PetscReal X[], PetscMPIInt counts[], PetscMPIInt displs[])
{
  MPI_Comm       comm = PetscObjectComm((PetscObject)s);
  const PetscInt dim  = g->dim;
  PetscBool     *keep;
  PetscInt       removed, m = 0, mine = 0;
  PetscReal      omax;
  PetscMPIInt    size, rank, c;

  PetscFunctionBegin;
  PetscCallMPI(MPI_Comm_size(comm, &size));
  PetscCallMPI(MPI_Comm_rank(comm, &rank));
  PetscCall(PetscMalloc1(*N, &keep));
  PetscCall(ThinOverfull(g, eg, k, volume / *N, over, dx, *N, X, keep, &removed, &omax));
  PetscCall(
      PetscInfo(s, "%s: %" PetscInt_FMT " of %" PetscInt_FMT " points removed where over-full (largest fullness %g)\n",
                what, removed, *N, (double)omax));
  if (removed) {
    for (PetscInt i = 0; i < *N; i++)
      if (keep[i]) {
        if (i >= *i0 && i < *i0 + *n) mine++;
        for (PetscInt d = 0; d < dim; d++) X[dim * m + d] = X[dim * i + d];
        m++;
      }
    *N = m;
    *n = mine;
    PetscCall(PetscMPIIntCast(dim * mine, &c));
    PetscCallMPI(MPI_Allgather(&c, 1, MPI_INT, counts, 1, MPI_INT, comm));
    m = 0;
    for (PetscMPIInt r = 0; r < size; r++) {
      displs[r] = (PetscMPIInt)(dim * m);
      if (r == rank) *i0 = m;
      m += counts[r] / dim;
    }
  }
  PetscCall(PetscFree(keep));
  PetscFunctionReturn(0);
}

/*
   FSCasePackRelax - relaxes the points x of one body of liquid (*n on this rank, dim reals each; the ranks' points
   one after the other make the body) in its closed region g, whose exact volume is volume (every point standing
   for volume / N): the lattice thinned first where it is over-full (-fs_fill_packing_thin; *n then this rank's
   points left, x compacted), then -fs_fill_packing_iterations moves of -step h^2 e_i (packing.c's header). With
   -fs_fill_packing_cache the packing is read from the cache's folder when it is there, else written to it.

   Collective

   Level: developer
*/
PetscErrorCode FSCasePackRelax(FSSolver s, const FSPackRegion *g, PetscReal volume, PetscInt *n, PetscReal x[],
                               const char what[])
{
  MPI_Comm       comm = PetscObjectComm((PetscObject)s);
  const PetscInt dim  = g->dim;
  FSFillPacking  opt;
  FSKernel       k;
  Grid           pg, eg;
  PetscMPIInt    size, rank, *counts, *displs;
  PetscInt       N = 0, i0 = 0, *cellof;
  PetscReal      dx, h, V, *X, *Xn, res[2][2] = {{0, 0}, {0, 0}}, resmax[2] = {0, 0}, par[4], push[2];
  char           path[PETSC_MAX_PATH_LEN + 64] = "";
  PetscBool      found                         = PETSC_FALSE;

  PetscFunctionBegin;
  PetscCall(PetscLogEventBegin(FS_FillPacking, 0, 0, 0, 0));
  PetscCall(FSSolverGetFillPacking(s, &opt));
  PetscCall(FSSolverGetParameters(s, &dx, &h, NULL, NULL, NULL));
  PetscCall(FSKernelSetUp(&k, dim, h));
  push[0] = opt.repulsion;
  push[1] = opt.repulsion_distance * dx;
  PetscCallMPI(MPI_Comm_size(comm, &size));
  PetscCallMPI(MPI_Comm_rank(comm, &rank));
  PetscCall(PetscMalloc2(size, &counts, size, &displs));
  {
    PetscMPIInt mine;
    PetscCall(PetscMPIIntCast(dim * (*n), &mine));
    PetscCallMPI(MPI_Allgather(&mine, 1, MPI_INT, counts, 1, MPI_INT, comm));
  }
  for (PetscMPIInt r = 0; r < size; r++) {
    displs[r] = (PetscMPIInt)(dim * N);
    if (r == rank) i0 = N;
    N += counts[r] / dim;
  }
  if (N == 0) {
    PetscCall(PetscFree2(counts, displs));
    PetscCall(PetscLogEventEnd(FS_FillPacking, 0, 0, 0, 0));
    PetscFunctionReturn(0);
  }
  PetscCall(PetscInfo(s, "%s: region of %" PetscInt_FMT " elements, %" PetscInt_FMT " of them the box's faces\n", what,
                      g->nel, g->nlid));
  PetscCall(PetscMalloc3(dim * N, &X, dim * N, &Xn, N, &cellof));
  PetscCallMPI(MPI_Allgatherv(x, counts[rank], MPIU_REAL, X, counts, displs, MPIU_REAL, comm));
  PetscCall(GridSetUp(&eg, g, h));
  PetscCall(GridFillElements(&eg, g, 2 * h));
  if (opt.thin > 0) PetscCall(PackThin(s, g, &eg, &k, volume, opt.thin, dx, what, n, &N, &i0, X, counts, displs));
  V      = volume / N;
  par[0] = dx;
  par[1] = h;
  par[2] = volume;
  par[3] = (PetscReal)g->nlid;
  if (opt.cache[0]) {
    PetscCall(CachePath(&opt, g, N, X, par, path, sizeof(path)));
    PetscCall(CacheRead(comm, path, dim, N, X, &found));
  }
  if (!found) {
    const PetscReal cap = 0.1 * dx, dmin = 0.25 * dx;
    PetscCall(GridSetUp(&pg, g, 2 * h));
    PetscCall(PetscMalloc1(N, &pg.item));
    for (PetscInt i = 0; i < N; i++) KeepFromWalls(g, &eg, dmin, 0.5 * dx, &X[dim * i]); /* the lattice's points */
    for (PetscInt it = 0; it < opt.iterations; it++) {
      const PetscBool first = (PetscBool)(it == 0), last = (PetscBool)(it == opt.iterations - 1);
      PetscCall(GridFillPoints(&pg, N, X, cellof));
      for (PetscInt i = i0; i < i0 + *n; i++) {
        PetscReal e[3], e2 = 0, move = 0, *xn = &Xn[dim * i];
        ParticleSum(g, &pg, &eg, &k, V, push, opt.visall, X, i, e);
        for (PetscInt d = 0; d < dim; d++) e2 += e[d] * e[d];
        if (first || last) { /* |e_i| dx: its largest and its mean square */
          resmax[last] = PetscMax(resmax[last], PetscSqrtReal(e2) * dx);
          res[last][1] += e2 * dx * dx;
        }
        move = opt.step * h * h * PetscSqrtReal(e2);
        for (PetscInt d = 0; d < dim; d++)
          xn[d] = X[dim * i + d] - opt.step * h * h * e[d] * (move > cap ? cap / move : 1);
        KeepFromWalls(g, &eg, dmin, 0.5 * dx, xn);
      }
      PetscCallMPI(MPI_Allgatherv(&Xn[dim * i0], counts[rank], MPIU_REAL, X, counts, displs, MPIU_REAL, comm));
    }
    PetscCall(GridDestroy(&pg));
    PetscCallMPI(MPI_Allreduce(MPI_IN_PLACE, resmax, 2, MPIU_REAL, MPIU_MAX, comm));
    PetscCallMPI(MPI_Allreduce(MPI_IN_PLACE, res, 4, MPIU_REAL, MPIU_SUM, comm));
    PetscCall(PetscInfo(s,
                        "%s: %" PetscInt_FMT " particles relaxed in %" PetscInt_FMT
                        " iterations: |e_i| dx largest %g -> %g, rms %g -> %g\n",
                        what, N, opt.iterations, (double)resmax[0], (double)resmax[1],
                        (double)PetscSqrtReal(res[0][1] / N), (double)PetscSqrtReal(res[1][1] / N)));
    if (opt.cache[0]) PetscCall(CacheWrite(comm, opt.cache, path, dim, N, X));
  } else PetscCall(PetscInfo(s, "%s: %" PetscInt_FMT " particles' packing read from %s\n", what, N, path));
  PetscCall(GridDestroy(&eg));
  PetscCall(PetscArraycpy(x, &X[dim * i0], dim * (*n)));
  PetscCall(PetscFree3(X, Xn, cellof));
  PetscCall(PetscFree2(counts, displs));
  PetscCall(PetscLogEventEnd(FS_FillPacking, 0, 0, 0, 0));
  PetscFunctionReturn(0);
}
