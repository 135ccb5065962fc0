/*
   Walls of the boundary-integral method (2-D): closed polygons discretized into segments of about dx,
   each segment with its midpoint, length s_k and normal n_k pointing out of the liquid, grouped into
   named walls ("tank", "baffles", ...).

   Orientation convention: the container polygon (the first one, holding all the others) runs
   counter-clockwise, so the liquid is inside; obstacle polygons (free-standing baffles) run clockwise,
   so the liquid is outside. The normal of the edge p0 -> p1 is then (dy, -dx)/|p1 - p0| in both cases.
*/
#pragma once
#include <flexslosh.h>

#define FS_WALLS_WHERE_LEN (PETSC_MAX_PATH_LEN + 64)

typedef struct {
  PetscInt   npoly, nvert, vcap;
  PetscInt  *pstart; /* npoly+1 offsets into the vertices */
  PetscInt  *pwall;  /* wall (name) index of each polygon */
  PetscInt  *vwall;  /* wall index of each edge, by its first vertex: the polygon's unless FSWallsSetEdgeWall */
  PetscReal *vert;   /* vertices, 2 per vertex */
  PetscReal *area;   /* signed area of each polygon (> 0 counter-clockwise) */
  char (*where)[FS_WALLS_WHERE_LEN]; /* where each polygon comes from (a file and its lines, a built-in tank) */
  PetscInt nwalls;
  char (*name)[64];
  /* segments, after FSWallsDiscretize */
  PetscInt   nseg;
  PetscReal *seg;     /* per segment: p0 (2), p1 (2), midpoint (2), normal (2), length: 9 reals */
  PetscInt  *segwall; /* wall index of each segment */
  PetscReal  dx;
  PetscReal  lo[2], hi[2]; /* bounding box of all vertices */
} FSWalls;

/* the reals of a segment's row in seg[] */
#define FS_SEG_P0     0 /* first end point (2) */
#define FS_SEG_P1     2 /* second end point (2) */
#define FS_SEG_MID    4 /* midpoint (2) */
#define FS_SEG_NORMAL 6 /* unit normal out of the liquid (2) */
#define FS_SEG_LENGTH 8
#define FS_SEG_STRIDE 9

/* Squared distance from x to the segment seg (p0, p1 first). */
static inline PetscReal FSSegmentDistance2(const PetscReal seg[], const PetscReal x[])
{
  const PetscReal tx = seg[FS_SEG_P1] - seg[FS_SEG_P0], ty = seg[FS_SEG_P1 + 1] - seg[FS_SEG_P0 + 1];
  PetscReal       u = ((x[0] - seg[FS_SEG_P0]) * tx + (x[1] - seg[FS_SEG_P0 + 1]) * ty) / (tx * tx + ty * ty), px, py;
  u                 = PetscMax(0.0, PetscMin(1.0, u));
  px                = seg[FS_SEG_P0] + u * tx - x[0];
  py                = seg[FS_SEG_P0 + 1] + u * ty - x[1];
  return px * px + py * py;
}

PETSC_INTERN const char    *FSWallNameProblem(const char name[]);
PETSC_INTERN PetscErrorCode FSWallsCreate(FSWalls *);
PETSC_INTERN PetscErrorCode FSWallsDestroy(FSWalls *);
PETSC_INTERN PetscErrorCode FSWallsAddPolygon(FSWalls *, MPI_Comm, const char name[], PetscInt n, const PetscReal xy[],
                                              const char where[]);
PETSC_INTERN PetscErrorCode FSWallsSetEdgeWall(FSWalls *, MPI_Comm, PetscInt poly, PetscInt edge, const char name[]);
PETSC_INTERN PetscErrorCode FSWallsLoad(FSWalls *, MPI_Comm, const char path[]);
PETSC_INTERN PetscErrorCode FSWallsRectangularTank(FSWalls *, MPI_Comm, PetscReal L, PetscReal H);
PETSC_INTERN PetscErrorCode FSWallsBaffledTank(FSWalls *, MPI_Comm, PetscInt ncomp, PetscReal Lc, PetscReal thickness,
                                               PetscReal H, PetscReal bottom_gap, PetscReal baffle_height);
PETSC_INTERN PetscErrorCode FSWallsCheck(FSWalls *, MPI_Comm);
PETSC_INTERN PetscErrorCode FSWallsDiscretize(FSWalls *, PetscReal dx);
PETSC_INTERN PetscBool      FSWallsInLiquid(const FSWalls *, const PetscReal x[], PetscReal margin);
PETSC_INTERN PetscReal      FSWallsDistance(const FSWalls *, const PetscReal x[]);
/* the area of the liquid region in the strip x0..x1 below the level t, and the integral of t - y over it */
PETSC_INTERN void FSWallsLiquidBelow(const FSWalls *, PetscReal x0, PetscReal x1, PetscReal t, PetscReal *area,
                                     PetscReal *moment);

/* Shepard factor from the walls alone (docs/boundary-integrals.md): gamma(x) and its gradient
   from the segments within the kernel support that face x. */
PETSC_INTERN void           FSSegmentIntegrals(PetscReal h, const PetscReal x[], const PetscReal seg[], PetscBool all,
                                               PetscReal *gammak, PetscReal *wint);
PETSC_INTERN PetscErrorCode FSWallsShepard(const FSWalls *, PetscReal h, const PetscReal x[], PetscBool all,
                                           PetscReal *gamma, PetscReal grad[]);

/* The polygon boundary's geometry: gives b (of type "polygon") the walls w, which it then owns (w is
   zeroed). Called by the cases. */
PETSC_INTERN PetscErrorCode FSBoundaryPolygonSetWalls(FSBoundary, FSWalls *);
