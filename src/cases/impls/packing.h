/*
   The relaxed packing of a body of liquid (-fs_fill_packing relaxed, docs/walls.md): the particles of a lattice
   moved until they are evenly spread against the walls and the fill level, so that a tank whose walls are not
   along the axes starts at rest. packregion.c builds the closed region the liquid is packed in, packing.c
   relaxes the particles in it.
*/
#pragma once
#include <flexslosh.h>
#include "boundary/impls/polygon/walls.h"
#include "boundary/impls/trimesh/mesh.h"

/* The closed region of one body of liquid: the walls' elements clipped to its box lo..hi (hi[1] the fill level),
   and the box's faces where they lie in the liquid (the fill level a lid, the sides of a liquid box) as elements
   whose normals point out of the box. Elements are rows of the walls' layouts: segments (FS_SEG_*) in 2-D,
   triangles (FS_TRI_*) in 3-D. */
typedef struct {
  PetscInt   dim, nel, stride;
  PetscReal *el;
  PetscInt   nlid; /* the last nlid elements are the box's faces */
  PetscReal  lo[3], hi[3];
} FSPackRegion;

PETSC_INTERN PetscErrorCode FSPackRegionFromWalls(FSPackRegion *, const FSWalls *, const PetscReal lo[],
                                                  const PetscReal hi[], PetscReal dx);
PETSC_INTERN PetscErrorCode FSPackRegionFromMesh(FSPackRegion *, FSMesh *, const PetscReal lo[], const PetscReal hi[],
                                                 PetscReal dx, PetscReal h);
PETSC_INTERN PetscErrorCode FSPackRegionDestroy(FSPackRegion *);
/* the points x (*n on this rank, dim each, in the ranks' order) thinned where over-full (*n, x: those left) and relaxed
   in the region, volume the body's; what names the liquid in messages */
PETSC_INTERN PetscErrorCode FSCasePackRelax(FSSolver, const FSPackRegion *, PetscReal volume, PetscInt *n,
                                            PetscReal x[], const char what[]);
