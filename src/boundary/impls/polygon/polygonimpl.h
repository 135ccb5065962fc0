/*
   Private data of the polygon boundary (src/boundary/impls/polygon): the walls' polygons and segments,
   the static cell grid of segments, the per-step candidate segments of each owned particle, and the
   per-right-hand-side wall pressure.
*/
#pragma once
#include "boundary/boundaryimpl.h"
#include "walls.h"

typedef struct {
  FSWalls      walls;
  const char **names; /* pointers to the wall names, for the boundary's wallname */
  /* static grid of segments (cell size = candidate radius) */
  PetscReal glo[2], gcell;
  PetscInt  gnc[2], *gstart, *gseg;
  /* per step: candidate segments of each owned particle (CSR) */
  PetscInt *cstart, *cand, ccap, scap;
  PetscBool
      occlusion; /* the walls can hide segments from a particle behind others (a non-convex container or obstacles) */
  PetscReal *wp; /* per segment: wall pressure interpolated from the liquid; then 2*nseg work */
  PetscReal *wetfull; /* per segment: the container's Shepard factor at its midpoint, the liquid's sum there when it
                         covers the segment */
} FSBoundary_Polygon;
