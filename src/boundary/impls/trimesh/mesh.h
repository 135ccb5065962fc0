/*
   Walls of the boundary-integral method in 3-D: closed triangle meshes of named wall parts ("tank",
   "baffles", "floor", ...), from the built-in tanks (a 2-D tank outline extruded across a width) or
   from STL files, checked (watertight, oriented, no degenerate or intersecting triangles) and refined
   into elements small enough for the quadrature of the boundary integrals.

   Orientation convention: the normal of triangle (a, b, c) is (b - a) x (c - a) / |...| and points out
   of the liquid. The container (the first closed surface, holding the liquid) then encloses a positive
   volume; an obstacle inside it (a free-standing baffle given as its own closed solid) a negative one.
   STL files give every solid with outward normals; FSMeshCheck turns obstacles inside out.

   Coordinates: x along the tank's length, y up (gravity -y), z across its width; a 2-D tank is the
   cross-section z = const of its 3-D extrusion.
*/
#pragma once
#include <flexslosh.h>
#include "boundary/impls/polygon/walls.h"

typedef struct {
  /* the input triangles, as given (built-in tank or STL files) */
  PetscInt   nvert, vcap;
  PetscReal *vert; /* 3 reals per vertex */
  PetscInt   ntri, tcap;
  PetscInt  *tri;     /* 3 vertex indices per triangle */
  PetscInt  *triwall; /* wall (part) index of each triangle */
  PetscInt  *trisrc;  /* index of each triangle in its source (file or builder), for error messages: 0-based */
  PetscInt   nwalls;
  char (*name)[64];                   /* nwalls wall names */
  char (*source)[PETSC_MAX_PATH_LEN]; /* per wall: the file (or builder) it came from, for error messages */
  PetscReal lo[3], hi[3];             /* bounding box of the vertices, after FSMeshCheck */
  PetscReal volume;                   /* volume enclosed by the container, after FSMeshCheck */
  PetscBool checked;                  /* FSMeshCheck passed, and no vertex or triangle was added since */
  /* elements, after FSMeshRefine: the triangles subdivided to edges of at most hmax; after FSMeshRefineRegion those
     of them near a box only, in the same order */
  PetscInt   nel;
  PetscReal *el;        /* per element FS_TRI_STRIDE reals */
  PetscInt  *elwall;    /* wall index of each element */
  PetscInt  *eltri;     /* input triangle of each element */
  PetscInt  *elgid;     /* each element's index among all the refinement's elements (increasing) */
  PetscInt   nelglobal; /* the elements of the whole refinement */
  PetscReal  elradius;  /* the largest distance from an element's centroid to its vertices, over all the elements */
} FSMesh;

/* the reals of an element's row in el[] */
#define FS_TRI_P0       0  /* first vertex a (3) */
#define FS_TRI_P1       3  /* second vertex b (3) */
#define FS_TRI_P2       6  /* third vertex c (3) */
#define FS_TRI_CENTROID 9  /* (a + b + c)/3 (3) */
#define FS_TRI_NORMAL   12 /* unit normal out of the liquid (3) */
#define FS_TRI_AREA     15
#define FS_TRI_RADIUS   16 /* the largest distance from the centroid to a vertex */
#define FS_TRI_STRIDE   17 /* (the quadrature points are computed from the vertices where used: integrals.c) */

PETSC_INTERN PetscErrorCode FSMeshCreate(FSMesh *);
PETSC_INTERN PetscErrorCode FSMeshDestroy(FSMesh *);
/* adds a wall part (or returns the index of the one of that name) */
PETSC_INTERN PetscErrorCode FSMeshAddWall(FSMesh *, const char name[], const char source[], PetscInt *wall);
/* adds a vertex, returns its index */
PETSC_INTERN PetscErrorCode FSMeshAddVertex(FSMesh *, const PetscReal x[3], PetscInt *v);
/* adds the triangle (a, b, c) of wall `wall`, numbered `src` in its source */
PETSC_INTERN PetscErrorCode FSMeshAddTriangle(FSMesh *, PetscInt wall, PetscInt a, PetscInt b, PetscInt c,
                                              PetscInt src);

/* builders: a 2-D tank outline (closed polygons, FSWalls' orientation convention) made of horizontal and
   vertical edges, extruded across the width z in [0, width]; each side face keeps the wall of its edge,
   the two end faces belong to the wall of the container polygon */
PETSC_INTERN PetscErrorCode FSMeshExtrude(FSMesh *, MPI_Comm, const FSWalls *, PetscReal width);
/* STL, ASCII or binary (told apart by content): every solid of the file a wall part, named by its solid
   name (ASCII) or by `name` (binary, or an unnamed solid); rank 0 reads, all ranks get the triangles */
PETSC_INTERN PetscErrorCode FSMeshLoadSTL(FSMesh *, MPI_Comm, const char path[], const char name[]);
/* the vertices' bounding box as they are (before FSMeshCheck); every vertex x moved to R (scale x) + shift, R the
   rotation by rot[0] degrees about x, then rot[1] about y, then rot[2] about z (fixed axes: R = Rz Ry Rx) */
PETSC_INTERN void FSMeshVertexBox(const FSMesh *, PetscReal lo[3], PetscReal hi[3]);
PETSC_INTERN void FSMeshTransform(FSMesh *, PetscReal scale, const PetscReal rot[3], const PetscReal shift[3]);

/* the checks before a run, once (again only after vertices or triangles were added; each failure an
   error naming the file and the triangle): no degenerate triangle, every edge shared by exactly two
   triangles with opposite orientation, no two triangles intersecting, the container (the closed
   surface that holds the others) of positive volume; then the obstacles oriented out of the liquid,
   the bounding box and volume */
PETSC_INTERN PetscErrorCode FSMeshCheck(FSMesh *, MPI_Comm);
/* the elements: each triangle split into m^2 similar triangles, m = ceil(longest edge / hmax) */
PETSC_INTERN PetscErrorCode FSMeshRefine(FSMesh *, PetscReal hmax);
/* the same refinement, keeping only the elements whose bounding sphere meets the box lo..hi (NULL: all), numbered by
   elgid as in the whole refinement */
PETSC_INTERN PetscErrorCode FSMeshRefineRegion(FSMesh *, PetscReal hmax, const PetscReal lo[], const PetscReal hi[]);

/* is x inside the liquid region (winding number of the input triangles, from their solid angles) and
   farther than margin from every triangle? */
PETSC_INTERN PetscBool FSMeshInLiquid(const FSMesh *, const PetscReal x[], PetscReal margin);
/* distance from x to the nearest triangle of the input mesh */
PETSC_INTERN PetscReal FSMeshDistance(const FSMesh *, const PetscReal x[]);
/* the volume of the liquid region in the column lo..hi (x and z) below the level y = t, and the integral of
   t - y over it */
PETSC_INTERN void FSMeshLiquidBelow(const FSMesh *, const PetscReal lo[], const PetscReal hi[], PetscReal t,
                                    PetscReal *vol, PetscReal *moment);

/* geometry of one triangle given by its three vertices */
/* squared distance from x to the triangle */
PETSC_INTERN PetscReal FSTriangleDistance2(const PetscReal a[], const PetscReal b[], const PetscReal c[],
                                           const PetscReal x[]);
/* the signed solid angle of the triangle seen from x (Van Oosterom & Strackee 1983), positive when x is
   on the side opposite to the normal (b - a) x (c - a) */
PETSC_INTERN PetscReal FSTriangleSolidAngle(const PetscReal a[], const PetscReal b[], const PetscReal c[],
                                            const PetscReal x[]);
/* does the open segment p-q cross the triangle? */
PETSC_INTERN PetscBool FSTriangleCrossesSegment(const PetscReal a[], const PetscReal b[], const PetscReal c[],
                                                const PetscReal p[], const PetscReal q[]);

/* Shepard factor from the elements (docs/boundary-integrals.md), integrals.c */
/* fills the row's quadrature points from its vertices (FSMeshRefine calls it) */
PETSC_INTERN void           FSTriangleIntegrals(PetscReal h, const PetscReal x[], const PetscReal el[], PetscBool all,
                                                PetscReal *gammak, PetscReal *wint);
PETSC_INTERN PetscErrorCode FSMeshShepard(const FSMesh *, PetscReal h, const PetscReal x[], PetscBool all,
                                          PetscReal *gamma, PetscReal grad[]);

/* The triangle-mesh boundary's geometry: gives b (of type "trimesh") the mesh m, which it then owns (m is
   zeroed). Called by the cases. */
PETSC_INTERN PetscErrorCode FSBoundaryTrimeshSetMesh(FSBoundary, FSMesh *);
