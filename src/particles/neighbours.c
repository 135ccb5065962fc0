/*
   Neighbour search: a cell-linked list built by counting sort when the lists are rebuilt (cells as wide
   as the kernel support plus a skin) and from it the candidate (Verlet) list of every owned particle;
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

static PetscErrorCode FSNeighboursGrowCandidates(FSNeighbours *nb, PetscInt64 need)
{
  PetscInt  *cand;
  PetscInt64 cap = PetscMax(need, (PetscInt64)(1.25 * nb->ccandcap));

  PetscFunctionBegin;
  PetscCheck(cap < PETSC_MAX_INT, PETSC_COMM_SELF, PETSC_ERR_SUP,
             "More than %d candidate pairs on one rank: use more ranks", PETSC_MAX_INT);
  PetscCall(PetscMalloc1(cap, &cand));
  PetscCall(PetscArraycpy(cand, nb->cand, nb->ccandcap));
  PetscCall(PetscFree(nb->cand));
  nb->cand     = cand;
  nb->ccandcap = (PetscInt)cap;
  PetscFunctionReturn(0);
}

/*
   FSNeighboursBuildCandidates - the candidate neighbours j != i of every owned particle i: all
   particles within radius (the kernel support plus a skin) at the start of the time step, found
   through the cell list (FSNeighboursBuildCells first, with cells at least radius wide).
   As long as no two particles approach each other by more than the skin during the step, every
   pair within the kernel support at any stage is among the candidates (a Verlet list).
*/
PetscErrorCode FSNeighboursBuildCandidates(FSNeighbours *nb, PetscInt nowned, const PetscReal rec[], PetscInt stride,
                                           PetscReal radius)
{
  const PetscInt  dim = nb->dim, nx = nb->nc[0], ny = nb->nc[1], nz = nb->nc[2];
  const PetscReal R2 = radius * radius, inv = 1.0 / nb->cellsize;
  const PetscInt  room = dim == 2 ? 256 : 1024;
  PetscInt        nc   = 0;

  PetscFunctionBegin;
  PetscCheck(radius <= nb->cellsize * (1 + 1e-12), PETSC_COMM_SELF, PETSC_ERR_PLIB,
             "Candidate radius %g exceeds the cell size %g", (double)radius, (double)nb->cellsize);
  if (nowned + 1 > nb->scap) {
    PetscCall(PetscFree(nb->cstart));
    nb->scap = PetscMax(nowned + 1, (PetscInt)(1.25 * nb->scap));
    PetscCall(PetscMalloc1(nb->scap, &nb->cstart));
  }
  if (!nb->ccandcap) PetscCall(FSNeighboursGrowCandidates(nb, (PetscInt64)nowned * (dim == 2 ? 96 : 400) + room));
  for (PetscInt i = 0; i < nowned; i++) {
    const PetscReal *xi    = &rec[i * stride];
    PetscInt         ci[3] = {0, 0, 0};
    nb->cstart[i]          = nc;
    for (PetscInt d = 0; d < dim; d++) ci[d] = (PetscInt)((xi[d] - nb->lo[d]) * inv);
    for (PetscInt cz = (dim == 3 ? PetscMax(ci[2] - 1, 0) : 0); cz <= (dim == 3 ? PetscMin(ci[2] + 1, nz - 1) : 0);
         cz++) {
      for (PetscInt cy = PetscMax(ci[1] - 1, 0); cy <= PetscMin(ci[1] + 1, ny - 1); cy++) {
        const PetscInt row = nx * (cy + ny * cz);
        const PetscInt c0 = row + PetscMax(ci[0] - 1, 0), c1 = row + PetscMin(ci[0] + 1, nx - 1);
        /* the cells of one row are contiguous in the sorted order */
        const PetscInt q0 = nb->cellstart[c0], q1 = nb->cellstart[c1 + 1];
        if (nc + (q1 - q0) > nb->ccandcap)
          PetscCall(FSNeighboursGrowCandidates(nb, (PetscInt64)nc + (q1 - q0) + room * 16));
        /* without branches (whether a particle is within the radius is as good as random): each one is
           written at the end of the list, which moves on only for those within */
        if (dim == 2)
          for (PetscInt q = q0; q < q1; q++) {
            const PetscInt   j  = nb->order[q];
            const PetscReal *xj = &rec[j * stride];
            const PetscReal  r2 = (xi[0] - xj[0]) * (xi[0] - xj[0]) + (xi[1] - xj[1]) * (xi[1] - xj[1]);
            nb->cand[nc]        = j;
            nc += (r2 < R2) & (j != i);
          }
        else
          for (PetscInt q = q0; q < q1; q++) {
            const PetscInt   j  = nb->order[q];
            const PetscReal *xj = &rec[j * stride];
            const PetscReal  r2 = (xi[0] - xj[0]) * (xi[0] - xj[0]) + (xi[1] - xj[1]) * (xi[1] - xj[1]) +
                                 (xi[2] - xj[2]) * (xi[2] - xj[2]);
            nb->cand[nc] = j;
            nc += (r2 < R2) & (j != i);
          }
      }
    }
  }
  nb->cstart[nowned] = nc;
  nb->ncand          = nc;
  nb->maxcand        = 0;
  for (PetscInt i = 0; i < nowned; i++) nb->maxcand = PetscMax(nb->maxcand, nb->cstart[i + 1] - nb->cstart[i]);
  PetscFunctionReturn(0);
}

PetscErrorCode FSNeighboursDestroy(FSNeighbours *nb)
{
  PetscFunctionBegin;
  PetscCall(PetscFree(nb->cellstart));
  PetscCall(PetscFree2(nb->cellof, nb->order));
  PetscCall(PetscFree(nb->cstart));
  PetscCall(PetscFree(nb->cand));
  PetscFunctionReturn(0);
}
