/*
   Neighbour search: a cell-linked list built by counting sort when the lists are rebuilt (cells as wide
   as the kernel support plus a skin) and from it the candidate (Verlet) list of every owned particle (bits
   over the positions of the rows of cells around it, fsparticles.h);
   the passes over the pairs pick the pairs within the support from the candidates as they visit them
   (FSNeighboursPick, fsparticles.h).
*/
#include "particles/fsparticles.h"

/*
   FSNeighboursBuildCells - bins particles (owned and ghosts) into cells of the given size.

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
  PetscReal lo[3] = {PETSC_MAX_REAL, PETSC_MAX_REAL, PETSC_MAX_REAL},
            hi[3] = {-PETSC_MAX_REAL, -PETSC_MAX_REAL, -PETSC_MAX_REAL};
  PetscInt ncells = 1;

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
      nb->nc[d] = (PetscInt)span + 1;
      nb->lo[d] = lo[d];
    } else nb->nc[d] = 1;
    ncells *= nb->nc[d];
  }
  PetscCheck(ncells < 400000000, PETSC_COMM_SELF, PETSC_ERR_MEM,
             "Cell list of %" PetscInt_FMT " cells is too large: particles are spread too thinly", ncells);
  nb->ncells = ncells;
  if (ncells + 1 > nb->ccap) {
    PetscCall(PetscFree(nb->cellstart));
    nb->ccap = PetscMax(ncells + 1, 2 * nb->ccap);
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
      PetscInt         c = (PetscInt)((x[0] - lo[0]) * inv) + nx * (PetscInt)((x[1] - lo[1]) * inv);
      if (dim == 3) c += nx * ny * (PetscInt)((x[2] - lo[2]) * inv);
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

/*
   FSNeighboursBuildCandidates - the candidate neighbours j != i of every owned particle i: all particles
   within radius (the kernel support plus a skin) at the start of the time step, found through the cell
   list (FSNeighboursBuildCells first, with cells at least radius wide), kept as bits over the positions of
   the rows of cells around i's cell (FSNeighboursRows). As long as no two particles approach each other by
   more than the skin, every pair within the kernel support at any stage is among the candidates (a Verlet
   list). The cell list must stay as it is while the candidates are used.
*/
PetscErrorCode FSNeighboursBuildCandidates(FSNeighbours *nb, PetscInt nowned, const PetscReal rec[], PetscInt stride,
                                           PetscReal radius)
{
  const PetscInt  dim = nb->dim;
  const PetscReal R2  = radius * radius;
  PetscInt64      nw = 0, nc = 0;

  PetscFunctionBegin;
  PetscCheck(radius <= nb->cellsize * (1 + 1e-12), PETSC_COMM_SELF, PETSC_ERR_PLIB,
             "Candidate radius %g exceeds the cell size %g", (double)radius, (double)nb->cellsize);
  if (nowned + 1 > nb->scap) {
    PetscCall(PetscFree(nb->mstart));
    nb->scap = PetscMax(nowned + 1, (PetscInt)(1.25 * nb->scap));
    PetscCall(PetscMalloc1(nb->scap, &nb->mstart));
  }
  /* the words of each particle: one bit per position of its rows */
  for (PetscInt i = 0; i < nowned; i++) {
    PetscInt q0[FS_NEIGHBOUR_ROWS], len[FS_NEIGHBOUR_ROWS], L = 0, nr = FSNeighboursRows(nb, i, q0, len);
    for (PetscInt r = 0; r < nr; r++) L += len[r];
    nb->mstart[i] = (PetscInt)nw;
    nw += (L + 63) / 64;
  }
  PetscCheck(nw < PETSC_MAX_INT, PETSC_COMM_SELF, PETSC_ERR_SUP,
             "More than %d words of candidate bits on one rank: use more ranks", PETSC_MAX_INT);
  nb->mstart[nowned] = (PetscInt)nw;
  if (nw > nb->mcap) {
    PetscCall(PetscFree(nb->mask));
    nb->mcap = (PetscInt)PetscMin((PetscInt64)PETSC_MAX_INT, PetscMax(nw, (PetscInt64)(1.25 * nb->mcap)));
    PetscCall(PetscMalloc1(nb->mcap, &nb->mask));
  }
  PetscCall(PetscArrayzero(nb->mask, nw));
  nb->maxcand = 0;
  for (PetscInt i = 0; i < nowned; i++) {
    const PetscReal *xi = &rec[i * stride];
    uint64_t        *w  = nb->mask + nb->mstart[i];
    PetscInt q0[FS_NEIGHBOUR_ROWS], len[FS_NEIGHBOUR_ROWS], nr = FSNeighboursRows(nb, i, q0, len), p = 0, ni = 0;
    /* without branches (whether a particle is within the radius is as good as random) */
    for (PetscInt r = 0; r < nr; r++) {
      if (dim == 2)
        for (PetscInt q = q0[r]; q < q0[r] + len[r]; q++, p++) {
          const PetscInt   j  = nb->order[q];
          const PetscReal *xj = &rec[j * stride];
          const PetscReal  r2 = (xi[0] - xj[0]) * (xi[0] - xj[0]) + (xi[1] - xj[1]) * (xi[1] - xj[1]);
          const uint64_t   in = (uint64_t)((r2 < R2) & (j != i));
          w[p >> 6] |= in << (p & 63);
          ni += (PetscInt)in;
        }
      else
        for (PetscInt q = q0[r]; q < q0[r] + len[r]; q++, p++) {
          const PetscInt   j  = nb->order[q];
          const PetscReal *xj = &rec[j * stride];
          const PetscReal  r2 = (xi[0] - xj[0]) * (xi[0] - xj[0]) + (xi[1] - xj[1]) * (xi[1] - xj[1]) +
                               (xi[2] - xj[2]) * (xi[2] - xj[2]);
          const uint64_t in = (uint64_t)((r2 < R2) & (j != i));
          w[p >> 6] |= in << (p & 63);
          ni += (PetscInt)in;
        }
    }
    nc += ni;
    nb->maxcand = PetscMax(nb->maxcand, ni);
  }
  nb->ncand = nc;
  PetscFunctionReturn(0);
}

PetscErrorCode FSNeighboursDestroy(FSNeighbours *nb)
{
  PetscFunctionBegin;
  PetscCall(PetscFree(nb->cellstart));
  PetscCall(PetscFree2(nb->cellof, nb->order));
  PetscCall(PetscFree(nb->mstart));
  PetscCall(PetscFree(nb->mask));
  PetscFunctionReturn(0);
}
