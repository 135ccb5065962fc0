/*
   Unit tests of the kernel and the neighbour search:
   - the Wendland C2 kernel integrates to 1 in 2-D and 3-D, and F(r) = W'(r)/r matches W;
   - the cell-list neighbour list equals a brute-force search (same pairs, same kernel factors)
     for random particles, owned and extra (ghost-like) ones, in 2-D and 3-D.
*/
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
  PetscCheck(PetscAbsReal(sum - 1) < 1e-4, PETSC_COMM_SELF, PETSC_ERR_PLIB,
             "Kernel integral %g in %" PetscInt_FMT "-D, expected 1", (double)sum, dim);
  for (PetscReal r = 0.01 * h; r < 1.99 * h; r += 0.05 * h) {
    PetscReal e = 1e-6 * h, dW = (FSKernelW(&k, r + e) - FSKernelW(&k, r - e)) / (2 * e);
    maxerr = PetscMax(maxerr, PetscAbsReal(dW / r - FSKernelF(&k, r)) / PetscAbsReal(k.fnorm));
  }
  PetscCheck(maxerr < 1e-6, PETSC_COMM_SELF, PETSC_ERR_PLIB, "Kernel gradient factor differs from dW/dr / r by %g",
             (double)maxerr);
  PetscCheck(FSKernelW(&k, 2 * h) == 0 && FSKernelW(&k, 2.5 * h) == 0, PETSC_COMM_SELF, PETSC_ERR_PLIB,
             "Kernel support is not 2h");
  PetscFunctionReturn(0);
}

static PetscErrorCode TestNeighbours(PetscInt dim, PetscInt nowned, PetscInt nextra)
{
  FSKernel     k;
  FSNeighbours nb;
  PetscRandom  rnd;
  PetscInt     n = nowned + nextra, S = 2 * dim + 2;
  PetscReal   *rec, h                 = 0.05;
  PetscInt64   brute = 0;

  PetscFunctionBegin;
  PetscCall(PetscMemzero(&nb, sizeof(nb)));
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
    PetscCall(FSNeighboursBuildList(&nb, &k, nowned, rec, S));
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
        for (PetscInt q = nb.start[i]; q < nb.start[i + 1]; q++)
          if (nb.nbr[q] == j) {
            found = PETSC_TRUE;
            PetscCheck(PetscAbsReal(nb.F[q] - FSKernelF(&k, PetscSqrtReal(r2))) <= 1e-12 * PetscAbsReal(k.fnorm),
                       PETSC_COMM_SELF, PETSC_ERR_PLIB,
                       "Wrong kernel factor for pair (%" PetscInt_FMT ", %" PetscInt_FMT ")", i, j);
          }
        PetscCheck(found, PETSC_COMM_SELF, PETSC_ERR_PLIB,
                   "Pair (%" PetscInt_FMT ", %" PetscInt_FMT
                   ") at distance %g missing from the neighbour list (%" PetscInt_FMT "-D)",
                   i, j, (double)PetscSqrtReal(r2), dim);
      }
    }
    PetscCheck(count == nb.start[i + 1] - nb.start[i], PETSC_COMM_SELF, PETSC_ERR_PLIB,
               "Particle %" PetscInt_FMT " has %" PetscInt_FMT " neighbours in the list, %" PetscInt_FMT
               " by brute force",
               i, nb.start[i + 1] - nb.start[i], count);
    brute += count;
  }
  PetscCheck(brute == nb.npairs && brute > 0, PETSC_COMM_SELF, PETSC_ERR_PLIB,
             "Pair count %" PetscInt64_FMT " differs from brute force %" PetscInt64_FMT, nb.npairs, brute);
  PetscCall(
      PetscPrintf(PETSC_COMM_SELF, "  %" PetscInt_FMT "-D: %" PetscInt64_FMT " pairs match brute force\n", dim, brute));
  PetscCall(FSNeighboursDestroy(&nb));
  PetscCall(PetscFree(rec));
  PetscCall(PetscRandomDestroy(&rnd));
  PetscFunctionReturn(0);
}

int main(int argc, char **argv)
{
  PetscMPIInt rank;

  PetscFunctionBeginUser;
  PetscCall(PetscInitialize(&argc, &argv, NULL, NULL));
  PetscCallMPI(MPI_Comm_rank(PETSC_COMM_WORLD, &rank));
  if (!rank) {
    PetscCall(TestKernel(2));
    PetscCall(TestKernel(3));
    PetscCall(TestNeighbours(2, 3000, 500));
    PetscCall(TestNeighbours(3, 2000, 400));
    PetscCall(PetscPrintf(PETSC_COMM_SELF, "test_neighbours: OK\n"));
  }
  PetscCall(PetscFinalize());
  return 0;
}
