/* The solver's wall data: geometry, the static cell grid of segments, and the per-step and
   per-right-hand-side lists of segments near each owned particle. Private to the core. */
#pragma once
#include "walls.h"

struct _n_FSWallData {
  FSWalls    walls;
  PetscBool *noslip;        /* per wall */
  PetscReal  loadpoint[3];  /* moments of the wall loads are taken about this point */
  /* static grid of segments (cell size = candidate radius) */
  PetscReal  glo[2], gcell;
  PetscInt   gnc[2], *gstart, *gseg;
  /* per step: candidate segments of each owned particle (CSR) */
  PetscInt  *cstart, *cand, ccap, scap;
  PetscBool  occlusion;      /* the walls can hide segments from a particle behind others (a non-convex container or obstacles) */
  PetscBool  visall;         /* -fs_walls_visibility all: no pair cut, no facing filter, no occlusion */
  /* per right-hand side: facing segments within the support, with W at their midpoints */
  PetscInt  *wstart, *wnbr, wcap, wscap;
  PetscReal *wW, *gamma, *invgamma; /* gamma and 1/gamma of the owned and ghost particles */
  PetscInt   gcap;           /* capacity of gamma (owned and ghosts) */
  PetscReal  bounce_distance, restitution; /* elastic bounce near walls (FSSolverWallsBounce) */
  PetscInt64 nbounce;
  PetscReal *wp;             /* per segment: wall pressure interpolated from the liquid; then 2*nseg work */
  PetscReal *wetfull;        /* per segment: the container's Shepard factor at its midpoint, the liquid's sum there when it covers the segment */
  PetscReal *load;           /* nwalls * 6: force (3), moment (3): this rank's share of the last RHS */
  PetscReal *loadsum;        /* the same summed over the ranks (FSSolverWallsGetLoads) */
};
typedef struct _n_FSWallData FSWallData;

PETSC_INTERN PetscErrorCode FSSolverSetWalls(FSSolver, FSWalls *);
PETSC_INTERN PetscErrorCode FSSolverWallsSetUp(FSSolver);
PETSC_INTERN PetscErrorCode FSSolverWallsUpdate(FSSolver);
PETSC_INTERN PetscErrorCode FSSolverWallsPrepare(FSSolver);
PETSC_INTERN PetscErrorCode FSSolverWallsBounce(FSSolver, PetscReal de[2]);
PETSC_INTERN PetscErrorCode FSSolverWallsGetLoads(FSSolver, const PetscReal **);
PETSC_INTERN PetscErrorCode FSSolverWallsDestroy(FSSolver);
