#pragma once
#include <flexslosh.h>
PETSC_INTERN PetscErrorCode FSLatticeCreate(FSSolver, const PetscReal[], const PetscReal[], PetscInt *, PetscReal **);
