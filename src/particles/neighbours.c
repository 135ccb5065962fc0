/*
   Neighbour search: a cell-linked list built by counting sort when the lists are rebuilt (cells as wide
   as the kernel support plus a skin) and from it the candidate (Verlet) list of every owned particle (its
   indices, or bits over the positions of the rows of cells around it: fsparticles.h);
   the passes over the pairs pick the pairs within the support from the candidates as they visit them
   (FSNeighboursPick, fsparticles.h).
*/
#include "particles/fsparticles.h"

/*
   FSNeighboursBuildCells - bins particles (owned and ghosts) into cells of the given size, with a layer of
   empty cells around them (so that the cells around any particle's cell exist: FSNeighboursRows).

   Input Parameters:
+  dim      - 2 or 3
.  n        - number of particles (owned + ghosts)
.  rec      - particle records, position first
.  stride   - reals per record
-  cellsize - cell size (the kernel support)
*/
PetscErrorCode FSNeighboursBuildCells(FSNeighbours *nb, PetscInt dim, PetscInt n, const PetscReal rec[],
                                      PetscInt stride, PetscReal cellsize)
{
  PetscReal lo[3]   = {PETSC_MAX_REAL, PETSC_MAX_REAL, PETSC_MAX_REAL},
            hi[3]   = {-PETSC_MAX_REAL, -PETSC_MAX_REAL, -PETSC_MAX_REAL};
  PetscInt64 ncells = 1; /* a product of three counts up to 1e8: past PetscInt before the check below */

  PetscFunctionBegin;
  nb->dim      = dim;
  nb->cellsize = cellsize;
  for (PetscInt p = 0; p < n; p++)
    for (PetscInt d = 0; d < dim; d++) {
      lo[d] = PetscMin(lo[d], rec[p * stride + d]);
      hi[d] = PetscMax(hi[d], rec[p * stride + d]);
    }
  if (!n)
    for (PetscInt d = 0; d < dim; d++) lo[d] = hi[d] = 0;
  for (PetscInt d = 0; d < 3; d++) {
    if (d < dim) {
      PetscReal span = (hi[d] - lo[d]) / cellsize;
      PetscCheck(span < 1e8, PETSC_COMM_SELF, PETSC_ERR_PLIB,
                 "Particles spread over %g cells in direction %" PetscInt_FMT
                 ": a particle has run away (NaN or huge velocity)",
                 (double)span, d);
      nb->nc[d] = (PetscInt)span + 3; /* and an empty layer of cells on either side (FSNeighboursRows) */
      nb->lo[d] = lo[d];
    } else nb->nc[d] = 1;
    ncells *= nb->nc[d];
  }
  PetscCheck(ncells < 400000000, PETSC_COMM_SELF, PETSC_ERR_MEM,
             "Cell list of %" PetscInt64_FMT " cells is too large: particles are spread too thinly", ncells);
  nb->ncells = (PetscInt)ncells;
  if (ncells + 1 > nb->ccap) {
    PetscCall(PetscFree(nb->cellstart));
    nb->ccap = (PetscInt)PetscMax(ncells + 1, 2 * (PetscInt64)nb->ccap);
    PetscCall(PetscMalloc1(nb->ccap, &nb->cellstart));
  }
  if (n > nb->ncap) {
    PetscCall(PetscFree2(nb->cellof, nb->order));
    nb->ncap = PetscMax(n, (PetscInt)(1.25 * nb->ncap));
    PetscCall(PetscMalloc2(nb->ncap, &nb->cellof, nb->ncap, &nb->order));
  }
  PetscCall(PetscArrayzero(nb->cellstart, ncells + 1));
  {
    const PetscReal inv = 1.0 / cellsize;
    const PetscInt  nx = nb->nc[0], ny = nb->nc[1];
    for (PetscInt p = 0; p < n; p++) {
      const PetscReal *x = &rec[p * stride];
      PetscInt         c = 1 + (PetscInt)((x[0] - lo[0]) * inv) + nx * (1 + (PetscInt)((x[1] - lo[1]) * inv));
      if (dim == 3) c += nx * ny * (1 + (PetscInt)((x[2] - lo[2]) * inv));
      nb->cellof[p] = c;
      nb->cellstart[c + 1]++;
    }
  }
  for (PetscInt c = 0; c < ncells; c++) nb->cellstart[c + 1] += nb->cellstart[c];
  for (PetscInt p = 0; p < n; p++) nb->order[nb->cellstart[nb->cellof[p]]++] = p;
  for (PetscInt c = ncells; c > 0; c--) nb->cellstart[c] = nb->cellstart[c - 1];
  nb->cellstart[0] = 0;
  PetscFunctionReturn(0);
}

static PetscErrorCode FSNeighboursGrowCandidates(FSNeighbours *nb, PetscInt64 need)
{
  const PetscInt64 cap = PetscMax(need, (PetscInt64)(1.25 * nb->ccandcap));

  PetscFunctionBegin;
  PetscCheck(cap < PETSC_MAX_INT, PETSC_COMM_SELF, PETSC_ERR_SUP,
             "More than %d candidate pairs on one rank: use more ranks", PETSC_MAX_INT);
  PetscCall(PetscRealloc((size_t)cap * sizeof(PetscInt), &nb->cand));
  nb->ccandcap = (PetscInt)cap;
  PetscFunctionReturn(0);
}

/* whether particle j is a candidate of i (within the radius, not i), without a branch */
#define FS_IS_CANDIDATE(dim, xi, xj, j, i, R2)                                              \
  ((((xi)[0] - (xj)[0]) * ((xi)[0] - (xj)[0]) + ((xi)[1] - (xj)[1]) * ((xi)[1] - (xj)[1]) + \
        ((dim) == 3 ? ((xi)[2] - (xj)[2]) * ((xi)[2] - (xj)[2]) : 0) <                      \
    (R2)) &                                                                                 \
   ((j) != (i)))

/* the candidates of each particle as indices (FS_CANDIDATES_INDICES), in the order of its rows */
FS_ALWAYS_INLINE PetscErrorCode FSNeighboursBuildIndices(FSNeighbours *nb, const PetscInt dim, PetscInt nowned,
                                                         const PetscReal rec[], PetscInt stride, PetscReal R2)
{
  const PetscInt room = dim == 2 ? 256 : 1024;
  PetscInt64     nc   = 0;

  PetscFunctionBegin;
  if (!nb->ccandcap) PetscCall(FSNeighboursGrowCandidates(nb, (PetscInt64)nowned * (dim == 2 ? 96 : 400) + room));
  nb->maxcand = 0;
  for (PetscInt i = 0; i < nowned; i++) {
    const PetscReal *xi = &rec[i * stride];
    PetscInt         q0[FS_NEIGHBOUR_ROWS], len[FS_NEIGHBOUR_ROWS], nr = FSNeighboursRows(nb, i, q0, len);
    nb->cstart[i] = (PetscInt)nc;
    for (PetscInt r = 0; r < nr; r++) {
      if (nc + len[r] > nb->ccandcap) PetscCall(FSNeighboursGrowCandidates(nb, nc + len[r] + 16 * room));
      /* every one written at the end of the list, which moves on only for those within */
      for (PetscInt q = q0[r]; q < q0[r] + len[r]; q++) {
        const PetscInt   j  = nb->order[q];
        const PetscReal *xj = &rec[j * stride];
        nb->cand[nc]        = j;
        nc += FS_IS_CANDIDATE(dim, xi, xj, j, i, R2);
      }
    }
    nb->cend[i] = (PetscInt)nc;
    nb->maxcand = PetscMax(nb->maxcand, nb->cend[i] - nb->cstart[i]);
  }
  nb->cstart[nowned] = nb->cend[nowned] = (PetscInt)nc;
  nb->ncand                             = nc;
  PetscFunctionReturn(0);
}

/* the candidates of each particle as bits (FS_CANDIDATES_BITS): one per position of its rows, each row from a word
   of its own */
FS_ALWAYS_INLINE PetscErrorCode FSNeighboursBuildBits(FSNeighbours *nb, const PetscInt dim, PetscInt nowned,
                                                      const PetscReal rec[], PetscInt stride, PetscReal R2)
{
  PetscInt64 nw = 0, nc = 0;

  PetscFunctionBegin;
  for (PetscInt i = 0; i < nowned; i++) {
    PetscInt q0[FS_NEIGHBOUR_ROWS], len[FS_NEIGHBOUR_ROWS], nr = FSNeighboursRows(nb, i, q0, len);
    nb->cstart[i] = (PetscInt)nw;
    for (PetscInt r = 0; r < nr; r++) nw += (len[r] + 63) / 64;
  }
  PetscCheck(nw < PETSC_MAX_INT, PETSC_COMM_SELF, PETSC_ERR_SUP,
             "More than %d words of candidate bits on one rank: use more ranks", PETSC_MAX_INT);
  nb->cstart[nowned] = (PetscInt)nw;
  if (nw > nb->mcap) {
    PetscCall(PetscFree(nb->mask));
    nb->mcap = (PetscInt)PetscMin((PetscInt64)PETSC_MAX_INT, PetscMax(nw, (PetscInt64)(1.25 * nb->mcap)));
    PetscCall(PetscMalloc1(nb->mcap, &nb->mask));
  }
  PetscCall(PetscArrayzero(nb->mask, nw));
  nb->maxcand = 0;
  for (PetscInt i = 0; i < nowned; i++) {
    const PetscReal *xi = &rec[i * stride];
    uint64_t        *w  = nb->mask + nb->cstart[i];
    PetscInt         q0[FS_NEIGHBOUR_ROWS], len[FS_NEIGHBOUR_ROWS], nr = FSNeighboursRows(nb, i, q0, len), ni = 0;
    for (PetscInt r = 0; r < nr; w += (len[r] + 63) / 64, r++)
      for (PetscInt p = 0; p < len[r]; p++) { /* without branches */
        const PetscInt   j  = nb->order[q0[r] + p];
        const PetscReal *xj = &rec[j * stride];
        const uint64_t   in = (uint64_t)FS_IS_CANDIDATE(dim, xi, xj, j, i, R2);
        w[p >> 6] |= in << (p & 63);
        ni += (PetscInt)in;
      }
    nc += ni;
    nb->maxcand = PetscMax(nb->maxcand, ni);
  }
  nb->ncand = nc;
  PetscFunctionReturn(0);
}

/*
   FSNeighboursBuildCandidates - the candidate neighbours j != i of every owned particle i: all particles
   within radius (the kernel support plus a skin) at the start of the time step, found through the cell
   list (FSNeighboursBuildCells first, with cells at least radius wide) among the rows of cells around i's
   cell (FSNeighboursRows), kept in the form nb->form. As long as no two particles approach each other by
   more than the skin, every pair within the kernel support at any stage is among the candidates (a Verlet
   list). With the candidates as bits the cell list must stay as it is while they are used.
*/
PetscErrorCode FSNeighboursBuildCandidates(FSNeighbours *nb, PetscInt nowned, const PetscReal rec[], PetscInt stride,
                                           PetscReal radius)
{
  const PetscReal R2 = radius * radius;

  PetscFunctionBegin;
  PetscCheck(radius <= nb->cellsize * (1 + 1e-12), PETSC_COMM_SELF, PETSC_ERR_PLIB,
             "Candidate radius %g exceeds the cell size %g", (double)radius, (double)nb->cellsize);
  if (nowned + 1 > nb->scap) {
    PetscCall(PetscFree2(nb->cstart, nb->cend));
    nb->scap = PetscMax(nowned + 1, (PetscInt)(1.25 * nb->scap));
    PetscCall(PetscMalloc2(nb->scap, &nb->cstart, nb->scap, &nb->cend));
  }
  if (nb->form == FS_CANDIDATES_INDICES) {
    PetscCall(PetscFree(nb->mask)); /* a change of form drops the other's storage */
    nb->mcap = 0;
    if (nb->dim == 2) PetscCall(FSNeighboursBuildIndices(nb, 2, nowned, rec, stride, R2));
    else PetscCall(FSNeighboursBuildIndices(nb, 3, nowned, rec, stride, R2));
  } else {
    PetscCall(PetscFree(nb->cand));
    nb->ccandcap = 0;
    if (nb->dim == 2) PetscCall(FSNeighboursBuildBits(nb, 2, nowned, rec, stride, R2));
    else PetscCall(FSNeighboursBuildBits(nb, 3, nowned, rec, stride, R2));
  }
  PetscFunctionReturn(0);
}

/*
   FSNeighboursSplitByGhosts - the owned particles in two groups, each in ascending order: first those none of whose
   candidates can be a ghost (no ghost in the rows of cells around them), then the others, into pass[0..nowned),
   with the size of the first group. A pass over the pairs can do the first group while the ghosts' fields are
   still on their way (FSSolverEvaluateRates). ntotal: the owned and ghost particles of the cell list.
*/
PetscErrorCode FSNeighboursSplitByGhosts(const FSNeighbours *nb, PetscInt nowned, PetscInt ntotal, PetscInt pass[],
                                         PetscInt *ninterior)
{
  PetscInt *ghosts, ni = 0, nb2 = 0;

  PetscFunctionBegin;
  PetscCall(PetscMalloc1(ntotal + 1, &ghosts)); /* ghosts[q]: the ghosts among the first q of the cell-sorted order */
  ghosts[0] = 0;
  for (PetscInt q = 0; q < ntotal; q++) ghosts[q + 1] = ghosts[q] + (nb->order[q] >= nowned);
  for (PetscInt i = 0; i < nowned; i++) {
    PetscInt  q0[FS_NEIGHBOUR_ROWS], len[FS_NEIGHBOUR_ROWS], nr = ghosts[ntotal] ? FSNeighboursRows(nb, i, q0, len) : 0;
    PetscBool border = PETSC_FALSE;
    for (PetscInt r = 0; r < nr && !border; r++) border = (PetscBool)(ghosts[q0[r] + len[r]] > ghosts[q0[r]]);
    if (!border) pass[ni++] = i;
  }
  for (PetscInt i = 0, k = 0; i < nowned; i++) { /* the others after, in order */
    if (k < ni && pass[k] == i) k++;
    else pass[ni + nb2++] = i;
  }
  PetscCall(PetscFree(ghosts));
  *ninterior = ni;
  PetscFunctionReturn(0);
}

PetscErrorCode FSNeighboursDestroy(FSNeighbours *nb)
{
  PetscFunctionBegin;
  PetscCall(PetscFree(nb->cellstart));
  PetscCall(PetscFree2(nb->cellof, nb->order));
  PetscCall(PetscFree2(nb->cstart, nb->cend));
  PetscCall(PetscFree(nb->cand));
  PetscCall(PetscFree(nb->mask));
  PetscFunctionReturn(0);
}
