/* A lattice of particles filling a box, enumerated globally and split in chunks over the ranks
   (so ids do not depend on the number of ranks). Used by the periodic cases. */
#include <flexslosh.h>
#include "lattice.h"
#include "sys/fssys.h"

/*
   FSLatticeCreate - the particles of this rank's chunk of the lattice (i + 1/2) dx in [lo, hi].

   Output Parameters:
+  n - number of particles on this rank
-  x - their positions (n*dim), to free with PetscFree
*/
PetscErrorCode FSLatticeCreate(FSSolver s, const PetscReal lo[], const PetscReal hi[], PetscInt *n, PetscReal **x)
{
  PetscInt    dim, nc[3] = {1, 1, 1};
  PetscInt64  total = 1, first, last;
  PetscMPIInt rank, size;
  PetscReal   dx, len[3];
  char        region[128];

  PetscFunctionBegin;
  PetscCall(FSSolverGetDimension(s, &dim));
  PetscCall(FSSolverGetParameters(s, &dx, NULL, NULL, NULL, NULL));
  PetscCallMPI(MPI_Comm_rank(PetscObjectComm((PetscObject)s), &rank));
  PetscCallMPI(MPI_Comm_size(PetscObjectComm((PetscObject)s), &size));
  for (PetscInt d = 0; d < dim; d++) len[d] = hi[d] - lo[d];
  if (dim == 3)
    PetscCall(PetscSNPrintf(region, sizeof(region), "The periodic box %g x %g x %g", (double)len[0], (double)len[1],
                            (double)len[2]));
  else PetscCall(PetscSNPrintf(region, sizeof(region), "The periodic box %g x %g", (double)len[0], (double)len[1]));
  PetscCall(FSCheckParticleCount(PetscObjectComm((PetscObject)s), dim, dx, FSLatticeCount(dim, len, dx), region, NULL));
  for (PetscInt d = 0; d < dim; d++) {
    nc[d] = (PetscInt)PetscFloorReal((hi[d] - lo[d]) / dx + 0.5);
    PetscCheck(nc[d] >= 1, PetscObjectComm((PetscObject)s), PETSC_ERR_ARG_OUTOFRANGE,
               "-fs_dx %g is larger than the box (%g) in direction %" PetscInt_FMT, (double)dx, (double)(hi[d] - lo[d]),
               d);
    PetscCheck(PetscAbsReal(nc[d] * dx - (hi[d] - lo[d])) < 1e-8 * (hi[d] - lo[d]), PetscObjectComm((PetscObject)s),
               PETSC_ERR_ARG_OUTOFRANGE,
               "-fs_dx %g does not divide the periodic box length %g in direction %" PetscInt_FMT
               ": choose dx = length/N",
               (double)dx, (double)(hi[d] - lo[d]), d);
    total *= nc[d];
  }
  first = total * rank / size;
  last  = total * (rank + 1) / size;
  *n    = (PetscInt)(last - first);
  PetscCall(PetscMalloc1(*n * dim + 1, x));
  for (PetscInt64 g = first; g < last; g++) {
    PetscInt64 i[3] = {g % nc[0], (g / nc[0]) % nc[1], g / (nc[0] * nc[1])};
    for (PetscInt d = 0; d < dim; d++) (*x)[(g - first) * dim + d] = lo[d] + (i[d] + 0.5) * dx;
  }
  PetscFunctionReturn(0);
}
