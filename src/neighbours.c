/*
   Neighbour search: a cell-linked list built by counting sort (cell size = kernel support 2h),
   then the full neighbour list of every owned particle in CSR form with the kernel gradient
   factor of each pair, computed once and shared by every pass and every term.
*/
#include "fsimpl.h"

/*
   FSNeighboursBuildCells - bins particles (owned and ghosts) into cells of the given size.

   Input Parameters:
+  dim      - 2 or 3
.  n        - number of particles (owned + ghosts)
.  rec      - particle records, position first
.  stride   - reals per record
-  cellsize - cell size (the kernel support)
*/
PetscErrorCode FSNeighboursBuildCells(FSNeighbours *nb, PetscInt dim, PetscInt n, const PetscReal rec[], PetscInt stride, PetscReal cellsize)
{
  PetscReal lo[3] = {PETSC_MAX_REAL, PETSC_MAX_REAL, PETSC_MAX_REAL}, hi[3] = {-PETSC_MAX_REAL, -PETSC_MAX_REAL, -PETSC_MAX_REAL};
  PetscInt  ncells = 1;

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
      PetscCheck(span < 1e8, PETSC_COMM_SELF, PETSC_ERR_PLIB, "Particles spread over %g cells in direction %" PetscInt_FMT ": a particle has run away (NaN or huge velocity)", (double)span, d);
      nb->nc[d] = (PetscInt)span + 1;
      nb->lo[d] = lo[d];
    } else nb->nc[d] = 1;
    ncells *= nb->nc[d];
  }
  PetscCheck(ncells < 400000000, PETSC_COMM_SELF, PETSC_ERR_MEM, "Cell list of %" PetscInt_FMT " cells is too large: particles are spread too thinly", ncells);
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

static PetscErrorCode FSNeighboursGrow(FSNeighbours *nb, PetscInt64 need)
{
  PetscInt  *nbr;
  PetscReal *F;
  PetscInt64 cap = PetscMax(need, (PetscInt64)(1.5 * nb->pcap));

  PetscFunctionBegin;
  PetscCheck(cap < PETSC_MAX_INT, PETSC_COMM_SELF, PETSC_ERR_SUP, "More than %d neighbour pairs on one rank: use more ranks", PETSC_MAX_INT);
  PetscCall(PetscMalloc2(cap, &nbr, cap, &F));
  PetscCall(PetscArraycpy(nbr, nb->nbr, nb->pcap));
  PetscCall(PetscArraycpy(F, nb->F, nb->pcap));
  PetscCall(PetscFree2(nb->nbr, nb->F));
  nb->nbr  = nbr;
  nb->F    = F;
  nb->pcap = (PetscInt)cap;
  PetscFunctionReturn(0);
}

/*
   FSNeighboursBuildList - the neighbours j != i within the kernel support of each owned particle i,
   with F(r_ij) such that grad_i W = F (x_i - x_j). Needs FSNeighboursBuildCells first.
*/
PetscErrorCode FSNeighboursBuildList(FSNeighbours *nb, const FSKernel *k, PetscInt nowned, const PetscReal rec[], PetscInt stride)
{
  const PetscInt  dim = nb->dim, nx = nb->nc[0], ny = nb->nc[1], nz = nb->nc[2];
  const PetscReal R2 = k->support2, inv = 1.0 / nb->cellsize;
  PetscInt        npairs = 0;

  PetscFunctionBegin;
  if (nowned + 1 > nb->scap) {
    PetscCall(PetscFree(nb->start));
    nb->scap = PetscMax(nowned + 1, (PetscInt)(1.25 * nb->scap));
    PetscCall(PetscMalloc1(nb->scap, &nb->start));
  }
  if (!nb->pcap) PetscCall(FSNeighboursGrow(nb, (PetscInt64)nowned * (dim == 2 ? 64 : 256) + 64));
  for (PetscInt i = 0; i < nowned; i++) {
    const PetscReal *xi = &rec[i * stride];
    PetscInt         ci[3] = {0, 0, 0};
    nb->start[i] = npairs;
    for (PetscInt d = 0; d < dim; d++) ci[d] = (PetscInt)((xi[d] - nb->lo[d]) * inv);
    if (npairs + (dim == 2 ? 128 : 512) > nb->pcap) PetscCall(FSNeighboursGrow(nb, (PetscInt64)npairs + (dim == 2 ? 4096 : 16384)));
    for (PetscInt cz = (dim == 3 ? PetscMax(ci[2] - 1, 0) : 0); cz <= (dim == 3 ? PetscMin(ci[2] + 1, nz - 1) : 0); cz++) {
      for (PetscInt cy = PetscMax(ci[1] - 1, 0); cy <= PetscMin(ci[1] + 1, ny - 1); cy++) {
        const PetscInt row = nx * (cy + ny * cz);
        const PetscInt c0 = row + PetscMax(ci[0] - 1, 0), c1 = row + PetscMin(ci[0] + 1, nx - 1);
        /* the cells of one row are contiguous in the sorted order */
        for (PetscInt q = nb->cellstart[c0]; q < nb->cellstart[c1 + 1]; q++) {
          const PetscInt   j  = nb->order[q];
          const PetscReal *xj = &rec[j * stride];
          PetscReal        r2 = 0;
          for (PetscInt d = 0; d < dim; d++) r2 += (xi[d] - xj[d]) * (xi[d] - xj[d]);
          if (r2 < R2 && j != i) {
            if (npairs == nb->pcap) PetscCall(FSNeighboursGrow(nb, (PetscInt64)npairs + 4096));
            nb->nbr[npairs] = j;
            nb->F[npairs]   = FSKernelF(k, PetscSqrtReal(r2));
            npairs++;
          }
        }
      }
    }
  }
  nb->start[nowned] = npairs;
  nb->npairs        = npairs;
  PetscFunctionReturn(0);
}

PetscErrorCode FSNeighboursDestroy(FSNeighbours *nb)
{
  PetscFunctionBegin;
  PetscCall(PetscFree(nb->cellstart));
  PetscCall(PetscFree2(nb->cellof, nb->order));
  PetscCall(PetscFree(nb->start));
  PetscCall(PetscFree2(nb->nbr, nb->F));
  PetscFunctionReturn(0);
}
