/*
   The cases as the solver uses them (src/cases): lookup by name, -help of all.
*/
#pragma once
#include <flexslosh.h>

PETSC_INTERN PetscErrorCode FSCaseFind(const char name[], FSCaseCreateFn *);
PETSC_INTERN PetscErrorCode FSCaseHelpAll(FSSolver, const char selected[], PetscOptionItems *);
