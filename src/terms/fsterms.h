/*
   The physics terms as the solver uses them (src/terms): the selected set, creation by name.
*/
#pragma once
#include <flexslosh.h>

#define FS_MAX_TERMS 32

/* Selected terms and the per-particle work of one right-hand side. */
typedef struct {
  PetscInt nterms;
  FSTerm   term[FS_MAX_TERMS];
  PetscInt needs;
} FSTermSet;

PETSC_INTERN PetscErrorCode FSTermCreate(FSSolver, const char name[], FSTerm *);
PETSC_INTERN PetscErrorCode FSTermDestroy(FSTerm *);
PETSC_INTERN PetscErrorCode FSTermHelpAll(FSSolver, const FSTermSet *, PetscOptionItems *);
PETSC_INTERN PetscErrorCode FSTermWallPressureGetRepulsion(FSTerm, PetscReal *, PetscReal *);
