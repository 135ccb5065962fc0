/*
   Private header of the boundary object (src/boundary): its ops table and the data every
   implementation fills. Only src/boundary includes it; an implementation in impls/<name>/ fills the
   ops in its FSBoundaryCreate_<Name>() and keeps its own data in b->data.
*/
#pragma once
#include "boundary/fsboundary.h"
#include <petsc/private/petscimpl.h>

#define FS_BOUNDARY_MAX_NAMES 32 /* walls -fs_walls_noslip can name */

typedef struct _FSBoundaryOps *FSBoundaryOps;
struct _FSBoundaryOps {
  PetscErrorCode (*setfromoptions)(FSBoundary, PetscOptionItems *);
  /* from the geometry the case gave: elements of about dx, static search structures, the view's layout */
  PetscErrorCode (*setup)(FSBoundary);
  /* this rank's part of the domain (FSBoundarySetPartition), before the wall pressure's exchange is set up: an
     implementation that holds only the elements near the part makes them here and sets elgid (may be NULL) */
  PetscErrorCode (*partition)(FSBoundary, const PetscReal lo[], const PetscReal hi[], const PetscBool periodic[]);
  /* an implementation that holds only some elements (elgid set): get (PETSC_TRUE) makes every element in b->full, in
     the order of their numbers, until called again with PETSC_FALSE (FSBoundaryGetFullView); its shepard op then
     answers at any point */
  PetscErrorCode (*fullview)(FSBoundary, PetscBool get);
  /* once per step, after the fluid candidates are built (FSBoundaryUpdate) */
  PetscErrorCode (*update)(FSBoundary, PetscInt nowned, const PetscReal rec[], PetscInt stride, FSNeighbours *,
                           FSBoundaryLeak *);
  /* at every right-hand side (FSBoundaryPrepare): gamma of the owned particles, the share of their
     support behind no-slip walls (when not NULL), the wall lists, and this rank's sums of the wall pressure, ending
     with FSBoundaryWallPressureBegin (FSBoundaryPrepareExchange and End finish the pressure and make the loads);
     collective */
  PetscErrorCode (*prepare)(FSBoundary, const FSBoundaryParticles *, PetscReal gamma[], PetscReal noslip[]);
  /* after each step (FSBoundaryBounce); not collective */
  PetscErrorCode (*bounce)(FSBoundary, PetscInt n, PetscReal x[], PetscReal v[], const PetscReal m[],
                           FSParticleEnergyFn, void *, PetscReal de[2]);
  PetscErrorCode (*boundingbox)(FSBoundary, PetscReal lo[], PetscReal hi[]);
  /* the walls' Shepard factor gamma at a point, from every element (FSBoundaryShepardAt); not collective */
  PetscErrorCode (*shepard)(FSBoundary, const PetscReal x[], PetscReal *gamma);
  /* where a point lies (FSBoundaryLocate): in the liquid region or not, the nearest wall and the distance to it;
     not collective */
  PetscErrorCode (*locate)(FSBoundary, const PetscReal x[], PetscBool *inliquid, PetscInt *wall, PetscReal *distance);
  /* rank 0: the walls into the geometry picture */
  PetscErrorCode (*draw)(FSBoundary, FSImage *, const FSImageMap *);
  /* the walls as files for ParaView (collective) */
  PetscErrorCode (*writegeometry)(FSBoundary, const char dir[]);
  PetscErrorCode (*view)(FSBoundary, PetscViewer);
  /* the geometry as the case gave it (vertices, polygons or triangles, their walls) into the hash, with
     FSBoundaryHashAdd_Private(); not collective */
  PetscErrorCode (*hash)(FSBoundary, uint64_t *);
  /* the bytes this rank's walls hold: the particles' candidate elements and wall lists (lists), the
     elements and their search grid (elements); not collective */
  PetscErrorCode (*memory)(FSBoundary, PetscInt64 *lists, PetscInt64 *elements);
  /* adds each owned particle's cost of a right-hand side's wall work, in fluid candidate pairs, from the candidate
     elements of the last update (FSBoundaryAddWork); not collective */
  PetscErrorCode (*work)(FSBoundary, PetscInt nowned, PetscInt64 work[]);
  PetscErrorCode (*destroy)(FSBoundary);
};

struct _p_FSBoundary {
  PETSCHEADER(struct _FSBoundaryOps);
  PetscBool setupcalled;
  PetscInt  dim;
  PetscReal dx, h, radius; /* particle spacing, smoothing length, candidate radius (support + halo skin) */
  /* the candidate elements kept for the right-hand sides: within the support 2h plus half the skin. The walls stay
     put and the lists are rebuilt before a particle moves more than half the skin from where they were built
     (src/solver/rebuild.c; a run that breaks this stops), so a farther element cannot enter the support before. */
  PetscReal reach;
  /* the walls: names, conditions, loads (set up by the implementation) */
  PetscInt     nwalls;
  const char **wallname;                          /* nwalls names, owned by the implementation */
  PetscBool   *noslip;                            /* per wall (-fs_walls_noslip) */
  PetscBool    anynoslip;                         /* some wall is no-slip */
  char        *noslipname[FS_BOUNDARY_MAX_NAMES]; /* -fs_walls_noslip as read, checked against the walls at set-up */
  PetscInt     nnoslipname;
  PetscReal    loadpoint[3]; /* -fs_walls_load_point */
  PetscReal *load, *loadsum; /* per wall 6: this rank's share of the last right-hand side, and the sum over the ranks */
  char      *momentname[FS_BOUNDARY_MAX_NAMES]; /* -fs_walls_moment_walls as read */
  PetscInt   nmomentname;
  PetscReal  momentpoint[3 * FS_BOUNDARY_MAX_NAMES]; /* -fs_walls_moment_points, dim values a named wall */
  PetscInt   nmomentpoint;
  PetscReal *wallpoint; /* per wall 3: the point its reported moment is about (FSBoundaryGetWallLoads) */
  PetscReal *loadwall;  /* per wall 6: loadsum with each moment moved to the wall's point */
  /* the wall pressure's sums over the ranks (FSBoundarySetPartition): without a partition one MPI_Allreduce of
     every element's sums; with one a PetscSF from the ranks whose particles can reach an element to the rank that
     owns it (its centroid's) and back */
  PetscSF   wpsf;
  PetscInt  nelglobal;       /* the elements of all the walls (set by the implementation's setup) */
  PetscReal elradius;        /* the largest distance from an element's centroid to its vertices, over all the walls
                                (the implementation's setup, or FSBoundarySetUp from the view) */
  const PetscInt *elgid;     /* per element of the view, its number among all nelglobal, when this rank holds only
                                some (set by ops->partition); NULL: the view holds them all, in order */
  FSWallView   full;         /* every element, between FSBoundaryGetFullView and FSBoundaryRestoreFullView */
  PetscMPIInt *owner;        /* per element, with a partition: the owning rank */
  PetscReal   *wproot;       /* 2 nel, with a partition: the owners' sums */
  PetscInt     wp_leaves;    /* elements this rank's particles can reach (2 values each through the SF) */
  PetscInt     wp_exchanged; /* values this rank sent to others in the last right-hand side through the SF */
  PetscInt     wp_reductions, wp_values; /* the wall pressure's sums over the ranks in the last right-hand side: calls,
                                            values (summary.json; the scaling model's cost of a stage) */
  PetscReal  bounce_distance, restitution; /* -fs_walls_bounce_distance (in dx), -fs_walls_bounce_restitution */
  PetscBool  visall;                       /* -fs_walls_visibility all: no pair cut, no facing filter, no occlusion */
  PetscInt64 nbounce;
  PetscBool  geometry_verbose; /* FSBoundaryWriteGeometry: say where the walls' files are */
  /* the wall terms' view and each owned particle's wall elements (CSR), filled by ops->prepare */
  FSWallView view;
  PetscInt  *wstart, *wk;
  PetscReal *wW;
  struct { /* the wall pressure between FSBoundaryWallPressureBegin and FSBoundaryPrepareEnd */
    PetscInt         nel;
    const PetscReal *wetfull;
    PetscReal        pamb, *wp;
  } wpx;
  PetscInt wcap; /* room in wk and wW (FSBoundaryWallListsRoom_Private) */
  void    *data;
};

/* for the implementations' writegeometry (interface/wallsxdmf.c): the wall names comma separated, and
   <dir>/walls.xdmf for the walls.h5 they wrote, with the message saying where the files are */
PETSC_INTERN PetscErrorCode FSBoundaryJoinWallNames_Private(FSBoundary, char **names);
PETSC_INTERN PetscErrorCode FSBoundaryWriteWallsH5_Private(FSBoundary, const char dir[], PetscInt dim, PetscInt n,
                                                           PetscInt nel, PetscReal pts[], PetscInt conn[],
                                                           PetscReal wall[], PetscReal nrm[], const char measure[],
                                                           PetscReal meas[], const char countname[]);
PETSC_INTERN PetscErrorCode FSBoundaryWriteWallsXDMF_Private(FSBoundary, const char dir[], const char topology[],
                                                             PetscInt nodes, PetscInt nel, const char measure[],
                                                             const char what[]);

/* The per-particle lists (the candidate elements of an implementation, the wall lists wk and wW): grown by a
   quarter when full, at least to 4096 entries (ListRoom: room for entry n); after a fill of n entries trimmed to
   n + n/16 when more than an eighth of n is unused (ListFit), so that a list holds about what it holds and one
   that shrinks gives its memory back. *array has entries of size bytes and capacity *cap. (interface/boundary.c) */
PETSC_INTERN PetscErrorCode FSBoundaryListRoom_Private(size_t size, PetscInt n, PetscInt *cap, void *array);
PETSC_INTERN PetscErrorCode FSBoundaryListFit_Private(size_t size, PetscInt n, PetscInt *cap, void *array);
/* the same for the wall lists wk and wW together (capacity b->wcap) */
PETSC_INTERN PetscErrorCode FSBoundaryWallListsRoom_Private(FSBoundary, PetscInt n);
PETSC_INTERN PetscErrorCode FSBoundaryWallListsFit_Private(FSBoundary, PetscInt n);

/* adds n bytes to a 64-bit FNV-1a hash (interface/boundary.c) */
PETSC_INTERN void FSBoundaryHashAdd_Private(uint64_t *hash, const void *data, size_t n);

/* the wall pressure's start from the implementations' per-element sums, and the pressure loads (interface/boundary.c)
 */
PETSC_INTERN PetscErrorCode FSBoundaryWallPressureBegin(FSBoundary, PetscInt nel, const PetscReal wetfull[],
                                                        PetscReal pamb, PetscReal wp[]);
PETSC_INTERN PetscErrorCode FSBoundaryPressureLoads(FSBoundary, const PetscReal wp[]);
/* one particle's bounce off an element (interface/boundary.c) */
PETSC_INTERN void FSBoundaryBounceParticle(FSBoundary, const PetscReal n[], PetscReal d, PetscReal un, PetscReal x[],
                                           PetscReal v[], PetscReal m, FSParticleEnergyFn, void *, PetscReal de[2]);
