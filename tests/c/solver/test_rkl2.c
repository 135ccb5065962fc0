/*
   Unit tests of RKL2, the super-time-stepping of the split density diffusion (src/solver/split.c), on the
   scalar problem y' = -lambda y, whose one step of dt multiplies y by R(z), z = lambda dt:
   - FSRKL2Stages: the fewest stages s >= 2 with (s^2 + s - 2)/2 >= z;
   - stability: |R(z)| <= 1 for z up to (s^2 + s - 2)/2 (s = 2 .. 16), and the bound is tight (|R| > 1 just
     past it for s = 2 and 4, whose stability polynomials end there);
   - consistency: R(z) = 1 - z + z^2/2 + O(z^3), the local error of a second-order method (its ratio between
     z and z/2 near 8), for every s.
*/
#include <math.h>
#include "solver/solverimpl.h"

#define CHECK(cond, ...) PetscCheck(cond, PETSC_COMM_SELF, PETSC_ERR_PLIB, "test_rkl2: " __VA_ARGS__)

/* R(z): one RKL2 step of s stages of y' = -lambda y from y = 1, with z = lambda dt */
static PetscReal Amplification(PetscInt s, PetscReal z)
{
  PetscReal y0 = 1, m0 = -z, y1, y2 = 1, mu, nu, mut, gt;

  FSRKL2Coefficients(s, 1, &mu, &nu, &mut, &gt);
  y1 = y0 + mut * m0;
  for (PetscInt j = 2; j <= s; j++) {
    PetscReal y;
    FSRKL2Coefficients(s, j, &mu, &nu, &mut, &gt);
    y  = mu * y1 + nu * y2 + (1 - mu - nu) * y0 + mut * (-z * y1) + gt * m0;
    y2 = y1;
    y1 = y;
  }
  return y1;
}

int main(int argc, char **argv)
{
  PetscFunctionBeginUser;
  PetscCall(PetscInitialize(&argc, &argv, NULL, NULL));
  CHECK(FSRKL2Stages(0) == 2 && FSRKL2Stages(2) == 2 && FSRKL2Stages(2.01) == 3, "stages for z = 0, 2, 2.01");
  CHECK(FSRKL2Stages(9) == 4 && FSRKL2Stages(9.5) == 5 && FSRKL2Stages(90) == 13, "stages for z = 9, 9.5, 90");
  for (PetscInt s = 2; s <= 16; s++) {
    const PetscReal zmax = 0.5 * (s * s + s - 2);
    for (PetscInt k = 0; k <= 400; k++) {
      const PetscReal z = zmax * k / 400.0, R = Amplification(s, z);
      CHECK(PetscAbsReal(R) <= 1 + 1e-12, "s = %" PetscInt_FMT ": |R(%g)| = %g > 1 within the bound %g", s, (double)z,
            (double)PetscAbsReal(R), (double)zmax);
    }
    for (PetscInt k = 0; k < 2; k++) { /* second order: the local error falls by 8 when z halves */
      const PetscReal z = 0.02 / (1 << k), e1 = Amplification(s, z) - PetscExpReal(-z);
      const PetscReal e2 = Amplification(s, z / 2) - PetscExpReal(-z / 2);
      CHECK(PetscAbsReal(e1 / e2 - 8) < 0.2, "s = %" PetscInt_FMT ": error ratio %g, not 8 (second order)", s,
            (double)(e1 / e2));
    }
  }
  CHECK(PetscAbsReal(Amplification(2, 2.05)) > 1 && PetscAbsReal(Amplification(4, 9.2)) > 1,
        "the stability bound must be tight for s = 2 and 4");
  PetscCall(PetscPrintf(PETSC_COMM_SELF, "test_rkl2: RKL2 stable to (s^2+s-2)/2 and second order, s = 2..16\n"));
  PetscCall(PetscFinalize());
  return 0;
}
