/*
   Neighbour search: a cell-linked list built by counting sort once per time step (cells as wide as
   the kernel support plus a skin), from it the candidate (Verlet) list of every owned particle,
   and at every right-hand side the exact neighbour list picked from the candidates, in CSR form
   (the neighbours' indices only: each pass computes the kernel gradient factor from r^2 itself).
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

static PetscErrorCode FSNeighboursGrow(FSNeighbours *nb, PetscInt64 need)
{
  PetscInt        *nbr;
  const PetscInt64 cap = need; /* the callers add their margins */

  PetscFunctionBegin;
  PetscCheck(cap < PETSC_MAX_INT, PETSC_COMM_SELF, PETSC_ERR_SUP,
             "More than %d neighbour pairs on one rank: use more ranks", PETSC_MAX_INT);
  PetscCall(PetscMalloc1(cap, &nbr));
  PetscCall(PetscArraycpy(nbr, nb->nbr, nb->pcap));
  PetscCall(PetscFree(nb->nbr));
  nb->nbr  = nbr;
  nb->pcap = (PetscInt)cap;
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
    PetscCall(PetscFree2(nb->start, nb->cstart));
    nb->scap = PetscMax(nowned + 1, (PetscInt)(1.25 * nb->scap));
    PetscCall(PetscMalloc2(nb->scap, &nb->start, nb->scap, &nb->cstart));
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

/*
   FSNeighboursReserveList - makes room in the neighbour list (nbr) for the pairs of this right-hand
   side: all = PETSC_TRUE, for every candidate pair (the most the list can hold); otherwise for an
   estimate, the pairs of the last list (or, the first time, the candidates' share within the support,
   (support / candidate radius)^dim) and a tenth more, plus one particle's candidates (the builders
   write each candidate before they know whether it is kept). The builders check the room particle by
   particle: FSNeighboursBuildList grows the list, the first pass of the right-hand side (src/solver/rhs.c),
   which picks the neighbours from the candidates itself while it visits them, starts again with all.
   A list sized for every candidate held twice the pairs in 3-D (about 520 candidates, 270 neighbours).
*/
PetscErrorCode FSNeighboursReserveList(FSNeighbours *nb, PetscReal share, PetscBool all)
{
  PetscInt64 need = nb->ncand;

  PetscFunctionBegin;
  if (!all) {
    const PetscInt64 pairs = nb->npairs > 0 ? nb->npairs : (PetscInt64)(share * nb->ncand);
    if (pairs + nb->maxcand + 1 <= nb->pcap) PetscFunctionReturn(0); /* room enough as it is */
    need = PetscMin(need, (PetscInt64)(1.1 * pairs) + nb->maxcand + 1);
  }
  if (need > nb->pcap) PetscCall(FSNeighboursGrow(nb, need));
  PetscFunctionReturn(0);
}

/*
   FSNeighboursBuildList - the neighbours j != i within the kernel support of each owned particle i
   at the current positions, picked from the candidates (the passes compute F(r_ij), grad_i W = F (x_i - x_j),
   from r^2 as they visit the pairs). Needs FSNeighboursBuildCandidates at the start of the step.
*/
PetscErrorCode FSNeighboursBuildList(FSNeighbours *nb, const FSKernel *kern, PetscInt nowned, const PetscReal rec[],
                                     PetscInt stride)
{
  const PetscInt  dim = nb->dim;
  const PetscReal R2  = kern->support2;
  PetscInt        np  = 0;

  PetscFunctionBegin;
  PetscCall(FSNeighboursReserveList(nb, FSNeighboursShare(nb, kern), PETSC_FALSE));
  for (PetscInt i = 0; i < nowned; i++) {
    const PetscReal *xi = &rec[i * stride];
    nb->start[i]        = np;
    if (np + (nb->cstart[i + 1] - nb->cstart[i]) > nb->pcap)
      PetscCall(FSNeighboursGrow(nb, PetscMax((PetscInt64)np + (nb->cstart[i + 1] - nb->cstart[i]) + nb->maxcand,
                                              (PetscInt64)(1.25 * nb->pcap))));
    /* without branches, as in FSNeighboursBuildCandidates */
    if (dim == 2) {
      for (PetscInt q = nb->cstart[i]; q < nb->cstart[i + 1]; q++) {
        const PetscInt   j  = nb->cand[q];
        const PetscReal *xj = &rec[j * stride];
        const PetscReal  a = xi[0] - xj[0], b = xi[1] - xj[1], r2 = a * a + b * b;
        nb->nbr[np] = j;
        np += r2 < R2;
      }
    } else {
      for (PetscInt q = nb->cstart[i]; q < nb->cstart[i + 1]; q++) {
        const PetscInt   j  = nb->cand[q];
        const PetscReal *xj = &rec[j * stride];
        const PetscReal  a = xi[0] - xj[0], b = xi[1] - xj[1], c = xi[2] - xj[2], r2 = a * a + b * b + c * c;
        nb->nbr[np] = j;
        np += r2 < R2;
      }
    }
  }
  nb->start[nowned] = np;
  nb->npairs        = np;
  PetscFunctionReturn(0);
}

PetscErrorCode FSNeighboursDestroy(FSNeighbours *nb)
{
  PetscFunctionBegin;
  PetscCall(PetscFree(nb->cellstart));
  PetscCall(PetscFree2(nb->cellof, nb->order));
  PetscCall(PetscFree2(nb->start, nb->cstart));
  PetscCall(PetscFree(nb->cand));
  PetscCall(PetscFree(nb->nbr));
  PetscFunctionReturn(0);
}
