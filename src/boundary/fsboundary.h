/*
   The boundary (src/boundary) as the rest of the library uses it: the FSBoundary object and its
   stages in a run. The solver drives it; the cases give it its geometry; the coupling reads its loads.

     FSBoundaryCreate / SetType / SetFromOptions / SetUp     from the case's geometry
     FSBoundaryUpdate     once per step: the candidate wall elements of each particle, the pairs cut
                          by walls, the leak check
     FSBoundaryPrepare    at every right-hand side: gamma of the owned particles, each particle's wall
                          elements within the support, the wall pressure and loads (FSBoundaryGetView)
     FSBoundaryBounce     after each step: particles too close to a wall bounce back
     FSBoundaryShepardAt  the walls' Shepard factor at any point (the wave gauges)
     FSBoundaryLocate     whether a point is in the liquid region, its nearest wall (the probes' checks)
     FSBoundaryGetGeometryHash  a fingerprint of the walls as given (checkpoints record it)
     FSBoundaryGetLoads, FSBoundaryDraw, FSBoundaryWriteGeometry, FSBoundarySummary, FSBoundaryView

   Implementations register with FSBoundaryRegister (src/boundary/impls/<name>/) and are chosen with
   -fs_boundary <name>: "polygon", 2-D boundary integrals on closed polygons, and "trimesh", 3-D
   boundary integrals on closed triangle meshes.
*/
#pragma once
#include <flexslosh.h>
#include "io/fsimage.h"
#include "io/fsoutput.h"
#include "particles/fsparticles.h"

PETSC_EXTERN PetscClassId FSBOUNDARY_CLASSID;

#define FSBOUNDARYPOLYGON "polygon"
#define FSBOUNDARYTRIMESH "trimesh"

typedef PetscErrorCode (*FSBoundaryCreateFn)(FSBoundary);

/* The particles as a boundary sees them: owned records 0..nowned-1 (position at 0, density at 2 dim;
   FSParticles' layout), their volumes and pressures, the body acceleration of the tank's frame and
   the ambient pressure. */
typedef struct {
  PetscInt            dim, nowned, stride;
  const PetscReal    *rec, *vol, *pressure;
  const FSFrameField *body;
  PetscReal           background_pressure;
} FSBoundaryParticles;

/* A particle found outside the liquid region by FSBoundaryUpdate (particle < 0: none on this rank), the
   wall nearest to it and the element of the wall's geometry there (a segment, or a triangle of the
   input mesh numbered as in its file). */
typedef struct {
  PetscInt particle, wall, element;
} FSBoundaryLeak;

/* The change of a particle's energy (e[0]: tank frame, e[1]: absolute frame) for the bounces' budget */
typedef void (*FSParticleEnergyFn)(void *ctx, const PetscReal x[], const PetscReal v[], PetscReal m, PetscReal e[2]);

PETSC_INTERN PetscErrorCode FSBoundaryRegister(const char[], const char[], FSBoundaryCreateFn);
PETSC_INTERN PetscErrorCode FSBoundaryRegisterAll(void);
PETSC_INTERN PetscErrorCode FSBoundaryListView(PetscViewer);
PETSC_INTERN PetscErrorCode FSBoundaryCreate(MPI_Comm, FSBoundary *);
PETSC_INTERN PetscErrorCode FSBoundarySetType(FSBoundary, const char[]);
PETSC_INTERN PetscErrorCode FSBoundarySetFromOptions(FSBoundary);
PETSC_INTERN PetscErrorCode FSBoundaryHelpAll(MPI_Comm);
PETSC_INTERN PetscErrorCode FSBoundarySetUp(FSBoundary, PetscInt dim, PetscReal dx, PetscReal h, PetscReal radius);
PETSC_INTERN PetscErrorCode FSBoundaryUpdate(FSBoundary, PetscInt nowned, const PetscReal rec[], PetscInt stride,
                                             FSNeighbours *, FSBoundaryLeak *);
PETSC_INTERN PetscErrorCode FSBoundaryPrepare(FSBoundary, const FSBoundaryParticles *, PetscReal gamma[],
                                              PetscReal noslip[]);
PETSC_INTERN PetscErrorCode FSBoundaryPrepareBegin(FSBoundary, const FSBoundaryParticles *, PetscReal gamma[],
                                                   PetscReal noslip[]);
PETSC_INTERN PetscErrorCode FSBoundaryPrepareExchange(FSBoundary);
PETSC_INTERN PetscErrorCode FSBoundaryPrepareEnd(FSBoundary);
PETSC_INTERN PetscErrorCode FSBoundaryHasNoSlip(FSBoundary, PetscBool *);
PETSC_INTERN PetscErrorCode FSBoundaryGetView(FSBoundary, const FSWallView **, const PetscInt **wstart,
                                              const PetscInt **wk, const PetscReal **wW);
PETSC_INTERN PetscErrorCode FSBoundaryGetBounce(FSBoundary, PetscBool *);
PETSC_INTERN PetscErrorCode FSBoundaryGetVisibilityOption(PetscObject, PetscBool *all);
PETSC_INTERN PetscErrorCode FSBoundaryBounce(FSBoundary, PetscInt n, PetscReal x[], PetscReal v[], const PetscReal m[],
                                             FSParticleEnergyFn, void *, PetscReal de[2]);
PETSC_INTERN PetscErrorCode FSBoundaryGetLoads(FSBoundary, PetscInt *nwalls, const PetscReal **loads);
PETSC_INTERN PetscErrorCode FSBoundaryGetWallLoads(FSBoundary, PetscInt *nwalls, const PetscReal **loads);
PETSC_INTERN PetscErrorCode FSBoundaryGetLoadsLocal(FSBoundary, PetscInt *nwalls, const PetscReal **local);
PETSC_INTERN PetscErrorCode FSBoundaryGetWallLoadsSummed(FSBoundary, const PetscReal summed[], PetscInt *nwalls,
                                                         const PetscReal **loads);
PETSC_INTERN PetscErrorCode FSBoundaryGetWallLoadPoints(FSBoundary, PetscInt *nwalls, const PetscReal **points);
/* the rank that owns the point x (the particles' domain decomposition) */
typedef PetscMPIInt (*FSBoundaryRankOfFn)(void *ctx, const PetscReal x[]);
PETSC_INTERN PetscErrorCode FSBoundarySetPartition(FSBoundary, FSBoundaryRankOfFn, void *ctx, const PetscReal lo[],
                                                   const PetscReal hi[], const PetscBool periodic[]);
PETSC_INTERN PetscErrorCode FSBoundaryOwnsElement(FSBoundary, PetscInt k, PetscBool *owns);
PETSC_INTERN PetscErrorCode FSBoundaryGetElementCounts(FSBoundary, PetscInt *nlocal, PetscInt *nglobal, PetscBool *all);
PETSC_INTERN PetscErrorCode FSBoundaryGetFullView(FSBoundary, const FSWallView **full);
PETSC_INTERN PetscErrorCode FSBoundaryRestoreFullView(FSBoundary, const FSWallView **full);
PETSC_INTERN PetscErrorCode FSBoundaryLocalElement(FSBoundary, PetscInt number, PetscInt *k);
PETSC_INTERN PetscErrorCode FSBoundaryGetWallNames(FSBoundary, PetscInt *nwalls, const char *const **names);
PETSC_INTERN PetscErrorCode FSBoundaryShepardAt(FSBoundary, const PetscReal x[], PetscReal *gamma);
PETSC_INTERN PetscErrorCode FSBoundaryLocate(FSBoundary, const PetscReal x[], PetscBool *inliquid, PetscInt *wall,
                                             PetscReal *distance);
PETSC_INTERN PetscErrorCode FSBoundaryGetBoundingBox(FSBoundary, PetscReal lo[], PetscReal hi[]);
PETSC_INTERN PetscErrorCode FSBoundaryGetLoadPoint(FSBoundary, PetscReal point[3]);
PETSC_INTERN PetscErrorCode FSBoundaryDraw(FSBoundary, FSImage *, const FSImageMap *);
PETSC_INTERN PetscErrorCode FSBoundaryWriteGeometry(FSBoundary, const char dir[], PetscBool verbose);
PETSC_INTERN PetscErrorCode FSBoundarySummary(FSBoundary, FSJSON);
PETSC_INTERN PetscErrorCode FSBoundaryGetMemory(FSBoundary, PetscInt64 *lists, PetscInt64 *elements);
PETSC_INTERN PetscErrorCode FSBoundaryAddWork(FSBoundary, PetscInt nowned, PetscInt64 work[]);
PETSC_INTERN PetscErrorCode FSBoundaryGetGeometryHash(FSBoundary, char hash[], size_t len);
PETSC_INTERN PetscErrorCode FSBoundaryView(FSBoundary, PetscViewer);
PETSC_INTERN PetscErrorCode FSBoundaryDestroy(FSBoundary *);
