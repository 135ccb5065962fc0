/*
   The structure models as the solver uses them (src/structure): creation by name, -help of all.
*/
#pragma once
#include <flexslosh.h>

PETSC_INTERN PetscErrorCode FSStructureCreate(FSSolver, const char name[], FSStructure *);
PETSC_INTERN PetscErrorCode FSStructureDestroy(FSStructure *);
PETSC_INTERN PetscErrorCode FSStructureHelpAll(FSSolver, FSStructure selected, PetscOptionItems *);
PETSC_INTERN PetscErrorCode FSStructureFind(const char name[], FSStructureCreateFn *);
