/*
   Domain decomposition: an orthogonal grid of ranks over the domain box. Each rank owns a box
   [cut[d][c_d], cut[d][c_d+1]) in every direction; the cuts are balanced on the particles.
*/
#include "particles/fsparticles.h"

/* Choose the process grid np[0..dim-1] (product = size) that minimizes the interface area while
   every subdomain stays at least minwidth wide. */
static PetscErrorCode FSDecompChooseGrid(FSDecomp *dd, MPI_Comm comm, PetscReal minwidth)
{
  PetscReal   best = PETSC_MAX_REAL;
  PetscMPIInt a, b, size = dd->size;
  PetscInt    dim = dd->dim;

  PetscFunctionBegin;
  dd->np[0] = dd->np[1] = dd->np[2] = 1;
  for (a = 1; a <= size; a++) {
    if (size % a) continue;
    for (b = 1; b <= size / a; b++) {
      PetscMPIInt c, n[3];
      PetscReal   area = 0;
      PetscBool   ok   = PETSC_TRUE;
      if ((size / a) % b) continue;
      c = size / a / b;
      if (dim == 2 && c != 1) continue;
      n[0] = a;
      n[1] = b;
      n[2] = c;
      for (PetscInt d = 0; d < dim; d++) {
        PetscReal cross = 1;
        if (dd->len[d] / n[d] < minwidth && n[d] > 1) ok = PETSC_FALSE;
        if (dd->periodic[d] && n[d] > 1 && dd->len[d] / n[d] < minwidth) ok = PETSC_FALSE;
        for (PetscInt e = 0; e < dim; e++)
          if (e != d) cross *= dd->len[e];
        area += (dd->periodic[d] ? n[d] : n[d] - 1) * cross;
      }
      if (ok && area < best) {
        best = area;
        for (PetscInt d = 0; d < 3; d++) dd->np[d] = n[d];
      }
    }
  }
  PetscCheck(best < PETSC_MAX_REAL, comm, PETSC_ERR_ARG_OUTOFRANGE,
             "Cannot split the domain (%g x %g x %g) over %d ranks with subdomains at least %g wide (the halo width): "
             "use fewer ranks or a larger domain",
             (double)dd->len[0], (double)dd->len[1], dim == 3 ? (double)dd->len[2] : 0.0, (int)size, (double)minwidth);
  PetscFunctionReturn(0);
}

/*
   FSDecompSetUp - creates the process grid over the box [lo, hi] with uniform cuts.

   Input Parameters:
+  comm     - communicator of the run
.  dim      - 2 or 3
.  lo, hi   - the domain box
.  periodic - periodicity per direction
-  minwidth - the smallest subdomain width allowed (the halo width)
*/
PetscErrorCode FSDecompSetUp(FSDecomp *dd, MPI_Comm comm, PetscInt dim, const PetscReal lo[], const PetscReal hi[],
                             const PetscBool periodic[], PetscReal minwidth)
{
  PetscMPIInt r;

  PetscFunctionBegin;
  PetscCall(PetscMemzero(dd, sizeof(*dd)));
  dd->dim = dim;
  PetscCallMPI(MPI_Comm_size(comm, &dd->size));
  PetscCallMPI(MPI_Comm_rank(comm, &dd->rank));
  for (PetscInt d = 0; d < 3; d++) {
    dd->lo[d]       = d < dim ? lo[d] : 0;
    dd->hi[d]       = d < dim ? hi[d] : 1;
    dd->len[d]      = dd->hi[d] - dd->lo[d];
    dd->periodic[d] = d < dim ? periodic[d] : PETSC_FALSE;
  }
  PetscCall(FSDecompChooseGrid(dd, comm, minwidth));
  r            = dd->rank;
  dd->coord[0] = r % dd->np[0];
  dd->coord[1] = (r / dd->np[0]) % dd->np[1];
  dd->coord[2] = r / (dd->np[0] * dd->np[1]);
  for (PetscInt d = 0; d < 3; d++) {
    PetscCall(PetscMalloc1(dd->np[d] + 1, &dd->cut[d]));
    for (PetscMPIInt i = 0; i <= dd->np[d]; i++) dd->cut[d][i] = dd->lo[d] + dd->len[d] * i / dd->np[d];
  }
  PetscFunctionReturn(0);
}

/*
   FSDecompBalance - moves the cuts so that each slab of ranks in every direction holds about
   the same weight of particles (from a global histogram of the coordinates, 4096 bins a direction), keeping
   every subdomain at least minwidth wide.

   Input Parameters:
+  n, x     - this rank's particles and their positions (dim each)
.  w        - their weights (e.g. their work in a right-hand side), or NULL: 1 each
-  minwidth - the smallest subdomain width allowed (the halo width)

   Notes: collective; the histogram is integer, so every rank computes the same cuts.
*/
PetscErrorCode FSDecompBalance(FSDecomp *dd, MPI_Comm comm, PetscInt n, const PetscReal x[], const PetscInt64 w[],
                               PetscReal minwidth)
{
  const PetscInt nbins = 4096;
  PetscInt64    *hist, total;

  PetscFunctionBegin;
  PetscCall(PetscMalloc1(nbins, &hist));
  for (PetscInt d = 0; d < dd->dim; d++) {
    PetscInt64  acc = 0;
    PetscMPIInt k   = 1;
    if (dd->np[d] == 1) continue;
    PetscCall(PetscArrayzero(hist, nbins));
    for (PetscInt p = 0; p < n; p++) {
      PetscInt b = (PetscInt)((x[p * dd->dim + d] - dd->lo[d]) / dd->len[d] * nbins);
      hist[PetscMax(0, PetscMin(nbins - 1, b))] += w ? w[p] : 1;
    }
    PetscCallMPI(MPI_Allreduce(MPI_IN_PLACE, hist, nbins, MPIU_INT64, MPI_SUM, comm));
    total = 0;
    for (PetscInt b = 0; b < nbins; b++) total += hist[b];
    if (!total) continue;
    /* cut k at the bin edge where the weight below comes closest to k/np of the total: before or after the bin
       that crosses it (a lattice puts whole planes of particles in one bin) */
    for (PetscInt b = 0; b < nbins && k < dd->np[d]; b++) {
      const PetscInt64 below = acc;
      acc += hist[b];
      while (k < dd->np[d] && acc * dd->np[d] >= total * k) {
        const PetscBool before = (PetscBool)(b > 0 && total * k - below * dd->np[d] < acc * dd->np[d] - total * k);
        dd->cut[d][k]          = dd->lo[d] + dd->len[d] * (before ? b : b + 1) / nbins;
        k++;
      }
    }
    /* enforce the minimum width, sweeping forward then backward */
    for (PetscMPIInt i = 1; i < dd->np[d]; i++) dd->cut[d][i] = PetscMax(dd->cut[d][i], dd->cut[d][i - 1] + minwidth);
    for (PetscMPIInt i = dd->np[d] - 1; i > 0; i--)
      dd->cut[d][i] = PetscMin(dd->cut[d][i], dd->cut[d][i + 1] - minwidth);
  }
  PetscCall(PetscFree(hist));
  PetscFunctionReturn(0);
}

/* FSDecompLayoutSize - the number of values FSDecompGetLayout writes: np[0..2] and the np[d]+1 cuts of each
   direction. Not collective */
PetscInt FSDecompLayoutSize(const FSDecomp *dd) { return 3 + dd->np[0] + dd->np[1] + dd->np[2] + 3; }

/*
   FSDecompGetLayout - the process grid and its cuts as FSDecompLayoutSize() values: np[0..2], then the
   np[d]+1 cuts of each direction (what a checkpoint keeps, so that a restart on as many ranks splits the
   domain as the run that wrote it).

   Not collective
*/
PetscErrorCode FSDecompGetLayout(const FSDecomp *dd, PetscReal v[])
{
  PetscInt k = 3;

  PetscFunctionBegin;
  for (PetscInt d = 0; d < 3; d++) {
    v[d] = (PetscReal)dd->np[d];
    for (PetscMPIInt i = 0; i <= dd->np[d]; i++) v[k++] = dd->cut[d][i];
  }
  PetscFunctionReturn(0);
}

/*
   FSDecompSetLayout - takes the cuts of n layout values (FSDecompGetLayout) when their process grid is this one;
   *taken says whether it was (a layout of another grid, another rank count, is left alone).

   Not collective
*/
PetscErrorCode FSDecompSetLayout(FSDecomp *dd, PetscInt n, const PetscReal v[], PetscBool *taken)
{
  PetscInt k = 3;

  PetscFunctionBegin;
  *taken = PETSC_FALSE;
  if (n != FSDecompLayoutSize(dd)) PetscFunctionReturn(0);
  for (PetscInt d = 0; d < 3; d++)
    if (v[d] != (PetscReal)dd->np[d]) PetscFunctionReturn(0);
  for (PetscInt d = 0; d < 3; d++)
    for (PetscMPIInt i = 0; i <= dd->np[d]; i++) dd->cut[d][i] = v[k++];
  *taken = PETSC_TRUE;
  PetscFunctionReturn(0);
}

PetscErrorCode FSDecompDestroy(FSDecomp *dd)
{
  PetscFunctionBegin;
  for (PetscInt d = 0; d < 3; d++) PetscCall(PetscFree(dd->cut[d]));
  PetscFunctionReturn(0);
}

/* The rank at grid coordinates c (no wrapping). */
PetscMPIInt FSDecompRankAt(const FSDecomp *dd, const PetscMPIInt c[])
{
  return c[0] + dd->np[0] * (c[1] + dd->np[1] * c[2]);
}

/* The rank owning point x (coordinates already wrapped into the box); points outside the box
   go to the nearest subdomain. */
PetscMPIInt FSDecompRankOf(const FSDecomp *dd, const PetscReal x[])
{
  PetscMPIInt c[3] = {0, 0, 0};
  for (PetscInt d = 0; d < dd->dim; d++) {
    PetscMPIInt      i = 0, np = dd->np[d];
    const PetscReal *cut = dd->cut[d];
    while (i < np - 1 && x[d] >= cut[i + 1]) i++;
    c[d] = i;
  }
  return FSDecompRankAt(dd, c);
}
