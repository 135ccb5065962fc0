/*
   Private data of the triangle-mesh boundary (src/boundary/impls/trimesh): the checked mesh and its
   elements, the static cell grid of elements, the per-step candidate elements of each owned particle,
   and the per-right-hand-side wall pressure.
*/
#pragma once
#include "boundary/boundaryimpl.h"
#include "mesh.h"

typedef struct {
  FSMesh       mesh;
  FSMesh       full;    /* with local elements: every element, during FSBoundaryGetFullView (its input arrays mesh's) */
  const char **names;   /* pointers to the wall names, for the boundary's wallname */
  PetscReal    element; /* -fs_walls_element_size: the longest element edge, in h */
  PetscBool    distribute; /* -fs_walls_distribute: on more than one rank each holds the elements near its part */
  PetscBool    local;      /* the elements are this rank's share (FSBoundarySetPartition), not the whole refinement */
  PetscBool    deferred;   /* distributing, no partition yet: no element made (EnsureElements makes them all) */
  PetscReal    corelo[3], corehi[3]; /* with local elements: where their wetfull is that of the whole mesh */
  /* static grid of elements by centroid (cell = candidate radius + the largest centroid-vertex distance) */
  PetscReal glo[3], gcell;
  PetscInt  gnc[3], *gstart, *gel;
  /* per step: candidate elements of each owned particle (CSR), as runs of consecutive elements (EncodeRuns) */
  PetscInt *cstart, *cand, ccap, scap;
  PetscInt *tmark, *tlist; /* per input triangle: the last particle that listed it; the particle's input triangles */
  PetscBool occlusion;     /* the liquid region is not convex: walls can hide elements and cut pairs */
  /* per right-hand side */
  PetscReal *wp;      /* per element: the wall pressure; then 2 nel work */
  PetscReal *wetfull; /* per element: the container's Shepard factor just inside its centroid */
} FSBoundary_Trimesh;
