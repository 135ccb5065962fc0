/*
   A prescribed motion's component read from a time-series file (time, value): a natural cubic spline
   through the points, continued by straight lines outside them, so that the value, its velocity and
   its acceleration are continuous everywhere (src/structure/impls/motionseries.c).
*/
#pragma once
#include <flexslosh.h>

typedef struct {
  PetscInt   n;     /* points */
  PetscReal *t, *y; /* times (strictly increasing) and values */
  PetscReal *M;     /* the spline's second derivatives at the points (0 at both ends: natural) */
  char       file[PETSC_MAX_PATH_LEN];
} FSMotionSeries;

PETSC_INTERN PetscErrorCode FSMotionSeriesLoad(MPI_Comm, const char file[], const char option[], PetscReal scale,
                                               FSMotionSeries *);
#define FS_MOTION_MAX_COLUMNS 6
PETSC_INTERN PetscErrorCode FSMotionSeriesLoadColumns(MPI_Comm, const char file[], const char option[], PetscInt nc,
                                                      const PetscReal scale[], const char what[], FSMotionSeries[]);
PETSC_INTERN void           FSMotionSeriesEval(const FSMotionSeries *, PetscReal t, PetscReal v[3]);
PETSC_INTERN PetscErrorCode FSMotionSeriesDestroy(FSMotionSeries *);
