/* The Wendland C2 smoothing kernel (support 2h) in two and three dimensions. */
#include "particles/fsparticles.h"

/*
   FSKernelSetUp - sets the normalization of the Wendland C2 kernel
   W(q) = a_d (1 - q/2)^4 (2q + 1), q = r/h, support 2h, with a_2 = 7/(4 pi h^2), a_3 = 21/(16 pi h^3).

   Input Parameters:
+  dim - 2 or 3
-  h   - smoothing length

   Notes:
   The gradient factor F(r) = W'(r)/r = -5 a_d / h^2 (1 - q/2)^3 is finite at r = 0, so
   grad_i W(x_i - x_j) = F(r) (x_i - x_j) needs no division by r.
*/
PetscErrorCode FSKernelSetUp(FSKernel *k, PetscInt dim, PetscReal h)
{
  PetscFunctionBegin;
  PetscCheck(dim == 2 || dim == 3, PETSC_COMM_SELF, PETSC_ERR_ARG_OUTOFRANGE,
             "Kernel dimension %" PetscInt_FMT " not supported: expected 2 or 3", dim);
  PetscCheck(h > 0, PETSC_COMM_SELF, PETSC_ERR_ARG_OUTOFRANGE, "Smoothing length %g must be positive", (double)h);
  k->dim      = dim;
  k->h        = h;
  k->support  = 2.0 * h;
  k->support2 = 4.0 * h * h;
  k->wnorm    = dim == 2 ? 7.0 / (4.0 * PETSC_PI * h * h) : 21.0 / (16.0 * PETSC_PI * h * h * h);
  k->fnorm    = -5.0 * k->wnorm / (h * h);
  PetscFunctionReturn(0);
}
