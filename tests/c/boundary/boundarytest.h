/*
   What the boundary's unit tests (test_boundary.c: polygons, test_trimesh.c: triangle meshes) share:
   hand-placed particles with their records, volumes, pressures and gamma, the boundary's work of a
   step and of a right-hand side as the solver does it, and a wall's index by name.
*/
#pragma once
#include <string.h>
#include "boundary/fsboundary.h"

/* n particles with their records (position dim, velocity dim, density, mass: 2 dim + 2 reals), volumes,
   pressures and the gamma FSBoundaryPrepare gives them */
typedef struct {
  PetscInt   dim, n, stride;
  PetscReal *rec, *vol, *p, *gamma;
} TestParticles;

static inline PetscErrorCode TestParticlesCreate(PetscInt dim, PetscInt n, TestParticles *pa)
{
  PetscFunctionBegin;
  pa->dim    = dim;
  pa->n      = n;
  pa->stride = 2 * dim + 2;
  PetscCall(PetscCalloc4(pa->stride * n + 1, &pa->rec, n + 1, &pa->vol, n + 1, &pa->p, n + 1, &pa->gamma));
  PetscFunctionReturn(0);
}

static inline PetscErrorCode TestParticlesDestroy(TestParticles *pa)
{
  PetscFunctionBegin;
  PetscCall(PetscFree4(pa->rec, pa->vol, pa->p, pa->gamma));
  PetscFunctionReturn(0);
}

/* The boundary's work of a step and of a right-hand side, as the solver does it: the candidate lists
   (cells as wide as the candidate radius 2.5 h), FSBoundaryUpdate, then FSBoundaryPrepare (collective)
   with the body acceleration g (gravity, no rotation) */
static inline PetscErrorCode TestUpdateAndPrepare(FSBoundary b, PetscReal h, PetscReal g, TestParticles *pa,
                                                  FSBoundaryLeak *leak)
{
  const PetscInt      S = pa->stride;
  FSNeighbours        nb;
  FSBoundaryParticles bp;
  FSFrameField        body = {{0, -g, 0}, 0, 0, {0, 0}};

  PetscFunctionBegin;
  PetscCall(PetscMemzero(&nb, sizeof(nb)));
  PetscCall(FSNeighboursBuildCells(&nb, pa->dim, pa->n, pa->rec, S, 2.5 * h));
  PetscCall(FSNeighboursBuildCandidates(&nb, pa->n, pa->rec, S, 2.5 * h));
  PetscCall(FSBoundaryUpdate(b, pa->n, pa->rec, S, &nb, leak));
  PetscCall(FSNeighboursDestroy(&nb));
  bp.dim                 = pa->dim;
  bp.nowned              = pa->n;
  bp.stride              = S;
  bp.rec                 = pa->rec;
  bp.vol                 = pa->vol;
  bp.pressure            = pa->p;
  bp.body                = &body;
  bp.background_pressure = 0;
  PetscCall(FSBoundaryPrepare(b, &bp, pa->gamma, NULL));
  PetscFunctionReturn(0);
}

/* the index of the wall named name */
static inline PetscErrorCode TestWallIndex(FSBoundary b, const char name[], PetscInt *index)
{
  PetscInt           nwalls;
  const char *const *names;

  PetscFunctionBegin;
  PetscCall(FSBoundaryGetWallNames(b, &nwalls, &names));
  *index = -1;
  for (PetscInt q = 0; q < nwalls; q++)
    if (!strcmp(names[q], name)) *index = q;
  PetscCheck(*index >= 0, PETSC_COMM_SELF, PETSC_ERR_PLIB, "the boundary has no wall \"%s\"", name);
  PetscFunctionReturn(0);
}
