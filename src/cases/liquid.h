#pragma once
#include "../walls/walls.h"
PETSC_INTERN PetscErrorCode FSCaseFillLiquid(FSSolver, FSWalls *, PetscReal x0, PetscReal x1, PetscReal y0, PetscReal ysurf, const char what[]);
