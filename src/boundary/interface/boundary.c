/*
   FSBoundary: the walls of a run, as an object with an ops table (boundaryimpl.h) and a registry of
   implementations (-fs_boundary <name>). This file dispatches to the implementation and holds what
   every boundary method shares: the wall names, the conditions and loads per wall, the bounce
   settings, and the view handed to the wall terms.
*/
#include "boundary/boundaryimpl.h"
#include "sys/fssys.h"

PetscClassId FSBOUNDARY_CLASSID;

static FSRegistry FSBoundaries; /* src/sys/registry.c */

PETSC_EXTERN PetscErrorCode FSBoundaryCreate_Polygon(FSBoundary);
PETSC_EXTERN PetscErrorCode FSBoundaryCreate_Trimesh(FSBoundary);

/*
   FSBoundaryRegister - adds a boundary method to the registry.

   Not collective

   Input Parameters:
+  name        - the name used in -fs_boundary
.  description - one line
-  create      - fills the boundary's ops and data (FSBoundaryCreate_<Name>)
*/
PetscErrorCode FSBoundaryRegister(const char name[], const char description[], FSBoundaryCreateFn create)
{
  PetscFunctionBegin;
  PetscCall(FSRegistryAdd(&FSBoundaries, name, description, (void (*)(void))create));
  PetscFunctionReturn(0);
}

/* FSBoundaryRegisterAll - registers the built-in boundary methods and the class (idempotent). */
PetscErrorCode FSBoundaryRegisterAll(void)
{
  static PetscBool done = PETSC_FALSE;

  PetscFunctionBegin;
  if (done) PetscFunctionReturn(0);
  done = PETSC_TRUE;
  PetscCall(PetscClassIdRegister("FSBoundary", &FSBOUNDARY_CLASSID));
  PetscCall(FSBoundaryRegister(
      FSBOUNDARYPOLYGON,
      "2-D boundary integrals on closed polygons of named walls (Calderon-Sanchez et al. 2019), options -fs_walls_*",
      FSBoundaryCreate_Polygon));
  PetscCall(FSBoundaryRegister(FSBOUNDARYTRIMESH,
                               "3-D boundary integrals on closed triangle meshes of named walls (built-in tanks, STL), "
                               "options -fs_walls_*",
                               FSBoundaryCreate_Trimesh));
  PetscFunctionReturn(0);
}

/* FSBoundaryListView - prints every registered boundary method with its description. */
PetscErrorCode FSBoundaryListView(PetscViewer viewer)
{
  PetscFunctionBegin;
  PetscCall(FSBoundaryRegisterAll());
  PetscCall(FSRegistryView(&FSBoundaries, viewer, "boundary methods", "select with -fs_boundary name"));
  PetscFunctionReturn(0);
}

/*
   FSBoundaryCreate - creates a boundary without a type; a case gives it its type and geometry
   (e.g. FSBoundaryPolygonSetWalls()).

   Collective
*/
PetscErrorCode FSBoundaryCreate(MPI_Comm comm, FSBoundary *boundary)
{
  FSBoundary b;

  PetscFunctionBegin;
  PetscCall(FSBoundaryRegisterAll());
  PetscCall(
      PetscHeaderCreate(b, FSBOUNDARY_CLASSID, "FSBoundary", "walls", "FS", comm, FSBoundaryDestroy, FSBoundaryView));
  b->bounce_distance = 0.1;
  b->restitution     = 1.0;
  *boundary          = b;
  PetscFunctionReturn(0);
}

/*
   FSBoundarySetType - chooses the boundary method by its registered name (destroying what an earlier
   type held).

   Collective
*/
PetscErrorCode FSBoundarySetType(FSBoundary b, const char type[])
{
  FSBoundaryCreateFn create;
  PetscBool          same;

  PetscFunctionBegin;
  PetscCall(PetscObjectTypeCompare((PetscObject)b, type, &same));
  if (same) PetscFunctionReturn(0);
  PetscCall(FSRegistryFind(&FSBoundaries, type, (void (**)(void)) & create));
  if (!create) {
    char known[1024];
    PetscCall(FSRegistryNames(&FSBoundaries, known, sizeof(known)));
    SETERRQ(PetscObjectComm((PetscObject)b), PETSC_ERR_ARG_UNKNOWN_TYPE,
            "Unknown boundary method \"%s\" given to -fs_boundary: the registered methods are%s", type, known);
  }
  if (b->ops->destroy) PetscCall((*b->ops->destroy)(b));
  PetscCall(PetscMemzero(b->ops, sizeof(*b->ops)));
  b->data = NULL;
  PetscCall(PetscObjectChangeTypeName((PetscObject)b, type));
  PetscCall((*create)(b));
  PetscFunctionReturn(0);
}

/* -fs_walls_visibility's values, in the order of b->visall */
static const char *const FSBoundaryVisibilities[] = {"cut", "all"};

/* the options every boundary method shares (FSBoundarySetFromOptions, FSBoundaryHelpAll) */
static PetscErrorCode FSBoundaryOptions(FSBoundary b, PetscOptionItems *PetscOptionsObject)
{
  const char *const *visnames = FSBoundaryVisibilities;
  PetscInt           vis      = b->visall ? 1 : 0;
  PetscInt           np       = 4;
  PetscReal          lp[4]    = {b->loadpoint[0], b->loadpoint[1], b->loadpoint[2], 0};
  PetscBool          set;

  PetscFunctionBegin;
  for (PetscInt k = 0; k < b->nnoslipname; k++) PetscCall(PetscFree(b->noslipname[k]));
  b->nnoslipname = FS_BOUNDARY_MAX_NAMES;
  PetscCall(PetscOptionsStringArray("-fs_walls_noslip",
                                    "Walls with no-slip conditions, by name (the others are free-slip)",
                                    "FSBoundarySetUp", b->noslipname, &b->nnoslipname, NULL));
  PetscCall(FSOptionsReal(PetscOptionsObject, "-fs_walls_bounce_distance",
                          "Particles closer to a wall than this (in dx) and moving towards it bounce back (0: never)",
                          "FSBoundaryBounce", &b->bounce_distance, NULL, 0, 0.5, FS_RANGE_OPEN_UPPER));
  PetscCall(FSOptionsReal(PetscOptionsObject, "-fs_walls_bounce_restitution",
                          "Fraction of the normal velocity kept by a bounce (1: elastic)", "FSBoundaryBounce",
                          &b->restitution, NULL, 0, 1, FS_RANGE_CLOSED));
  PetscCall(FSOptionsRealArray(PetscOptionsObject, "-fs_walls_load_point",
                               "Point about which the moments of the wall loads are taken", "FSBoundarySetUp", lp, &np,
                               &set, PETSC_NINFINITY, PETSC_INFINITY, FS_RANGE_CLOSED));
  for (PetscInt k = 0; k < b->nmomentname; k++) PetscCall(PetscFree(b->momentname[k]));
  b->nmomentname = FS_BOUNDARY_MAX_NAMES;
  PetscCall(PetscOptionsStringArray(
      "-fs_walls_moment_walls", "Walls whose moment is reported about a point of their own (-fs_walls_moment_points)",
      "FSBoundarySetUp", b->momentname, &b->nmomentname, NULL));
  b->nmomentpoint = 3 * FS_BOUNDARY_MAX_NAMES;
  PetscCall(FSOptionsRealArray(PetscOptionsObject, "-fs_walls_moment_points",
                               "The points of -fs_walls_moment_walls, x,y[,z] each in the same order",
                               "FSBoundarySetUp", b->momentpoint, &b->nmomentpoint, NULL, PETSC_NINFINITY,
                               PETSC_INFINITY, FS_RANGE_CLOSED));
  PetscCall(PetscOptionsEList(
      "-fs_walls_visibility",
      "Fluid pairs and wall elements near walls: cut (pairs through walls cut, only facing and unhidden elements) or "
      "all (every pair and element within the support; wall pressure from the facing side)",
      "FSBoundarySetFromOptions", visnames, 2, visnames[vis], &vis, NULL));
  b->visall = (PetscBool)(vis == 1);
  if (set) {
    PetscCheck(np == 2 || np == 3, PetscObjectComm((PetscObject)b), PETSC_ERR_ARG_SIZ,
               "-fs_walls_load_point takes 2 or 3 values (x,y[,z]); got %" PetscInt_FMT, np);
    for (PetscInt d = 0; d < 3; d++) b->loadpoint[d] = d < np ? lp[d] : 0;
  }
  PetscFunctionReturn(0);
}

/*
   FSBoundarySetFromOptions - reads -fs_boundary, the options every method shares and the method's own.

   Collective

   Options Database Keys:
+  -fs_boundary <name>                  - the boundary method (the case's choice by default; polygon in 2-D)
.  -fs_walls_noslip <names>             - the walls with no-slip conditions (the others are free-slip)
.  -fs_walls_bounce_distance <0.1>      - particles closer to a wall than this (in dx) and moving towards it bounce back
.  -fs_walls_bounce_restitution <1>     - the fraction of the normal velocity a bounce keeps
.  -fs_walls_load_point <x,y[,z]>       - the point about which the wall moments are taken (the origin)
.  -fs_walls_moment_walls <names>       - walls whose moment is reported about a point of their own
.  -fs_walls_moment_points <x,y[,z],..> - those points, in the same order (dim values each)
-  -fs_walls_visibility <cut|all>       - what a particle near the walls interacts with. cut (default): fluid pairs
   whose connecting line crosses a wall are cut, and gamma and the wall terms count only the elements that face the
   particle and are not hidden behind others. all: every fluid pair and every element within the support, far faces
   and faces turned away included (the exact boundary-integral identity for any shape: no ray through a convex corner
   bounds the region a particle sees); the wall pressure p_k still comes only from the liquid on the side element k
   faces, so each face of a thin baffle carries its own side's pressure, and the leak check and bounce are the same.
*/
PetscErrorCode FSBoundarySetFromOptions(FSBoundary b)
{
  char      type[64];
  PetscBool set;

  PetscFunctionBegin;
  PetscCall(
      PetscStrncpy(type, ((PetscObject)b)->type_name ? ((PetscObject)b)->type_name : FSBOUNDARYPOLYGON, sizeof(type)));
  PetscObjectOptionsBegin((PetscObject)b);
  PetscCall(PetscOptionsString("-fs_boundary", "Boundary method of the walls (the case's by default)",
                               "FSBoundarySetType", type, type, sizeof(type), &set));
  if (set || !((PetscObject)b)->type_name) PetscCall(FSBoundarySetType(b, type));
  PetscCall(FSBoundaryOptions(b, PetscOptionsObject));
  if (b->ops->setfromoptions) PetscCall((*b->ops->setfromoptions)(b, PetscOptionsObject));
  PetscOptionsEnd();
  PetscFunctionReturn(0);
}

/*
   FSBoundaryHelpAll - with -help, lists the options of the walls: those every method shares, then each
   registered method's own (on a scratch boundary, since a run's boundary exists only in wall cases and
   reads its options at set-up).

   Collective
*/
PetscErrorCode FSBoundaryHelpAll(MPI_Comm comm)
{
  FSBoundary b;

  PetscFunctionBegin;
  PetscCall(FSBoundaryCreate(comm, &b));
  PetscOptionsBegin(comm, NULL, "Walls (boundary integrals): every method", "FSBoundary");
  PetscCall(FSOptionsSurveyBlock(PetscOptionsObject));
  PetscCall(FSOptionsSurveyOwner("walls", NULL));
  {
    char type[64] = FSBOUNDARYPOLYGON;
    PetscCall(PetscOptionsString("-fs_boundary", "Boundary method of the walls (the case's by default)",
                                 "FSBoundarySetType", type, type, sizeof(type), NULL));
  }
  PetscCall(FSBoundaryOptions(b, PetscOptionsObject));
  PetscOptionsEnd();
  for (FSRegistryEntry *info = FSBoundaries.first; info; info = info->next) {
    char title[128];
    PetscCall(FSBoundarySetType(b, info->name));
    PetscCall(PetscSNPrintf(title, sizeof(title), "Walls: boundary method %s", info->name));
    PetscOptionsBegin(comm, NULL, title, "FSBoundary");
    PetscCall(FSOptionsSurveyBlock(PetscOptionsObject));
    PetscCall(FSOptionsSurveyOwner("boundary method", info->name));
    if (b->ops->setfromoptions) PetscCall((*b->ops->setfromoptions)(b, PetscOptionsObject));
    PetscOptionsEnd();
  }
  PetscCall(FSOptionsSurveyOwner(NULL, NULL));
  PetscCall(FSBoundaryDestroy(&b));
  PetscFunctionReturn(0);
}

/*
   FSBoundarySetUp - builds the wall elements from the case's geometry for particles of spacing dx and
   smoothing length h, whose candidate neighbours lie within radius; then sets the wall conditions
   (FSBoundarySetFromOptions read them).

   Collective
*/
PetscErrorCode FSBoundarySetUp(FSBoundary b, PetscInt dim, PetscReal dx, PetscReal h, PetscReal radius)
{
  MPI_Comm comm = PetscObjectComm((PetscObject)b);

  PetscFunctionBegin;
  if (b->setupcalled) PetscFunctionReturn(0);
  PetscCheck(((PetscObject)b)->type_name, comm, PETSC_ERR_ARG_WRONGSTATE,
             "The boundary has no method: the case sets one with its geometry");
  b->dim    = dim;
  b->dx     = dx;
  b->h      = h;
  b->radius = radius;
  b->reach  = 2 * h + 0.5 * (radius - 2 * h);
  PetscCall((*b->ops->setup)(b));
  if (!b->nelglobal) b->nelglobal = b->view.nelements;
  if (!b->elradius)
    for (PetscInt k = 0; k < b->view.nelements; k++) {
      const PetscReal *el = &b->view.element[k * b->view.stride], *c = el + b->view.centroid;
      for (PetscInt v = 0; v < dim; v++) {
        PetscReal d2 = 0;
        for (PetscInt d = 0; d < dim; d++) d2 += PetscSqr(el[b->view.vertex + v * dim + d] - c[d]);
        b->elradius = PetscMax(b->elradius, PetscSqrtReal(d2));
      }
    }
  PetscCall(PetscCalloc1(b->nwalls, &b->noslip));
  PetscCall(PetscCalloc2(FS_WALL_LOAD_STRIDE * b->nwalls, &b->load, FS_WALL_LOAD_STRIDE * b->nwalls, &b->loadsum));
  for (PetscInt k = 0; k < b->nnoslipname; k++) {
    PetscBool found = PETSC_FALSE;
    for (PetscInt q = 0; q < b->nwalls; q++)
      if (!strcmp(b->noslipname[k], b->wallname[q])) {
        b->noslip[q] = PETSC_TRUE;
        b->anynoslip = PETSC_TRUE;
        found        = PETSC_TRUE;
      }
    PetscCheck(found, comm, PETSC_ERR_ARG_WRONG, "-fs_walls_noslip names wall \"%s\", which this case does not have",
               b->noslipname[k]);
  }
  /* the walls' own moment points: -fs_walls_load_point unless named in -fs_walls_moment_walls */
  PetscCall(PetscCalloc2(3 * b->nwalls, &b->wallpoint, FS_WALL_LOAD_STRIDE * b->nwalls, &b->loadwall));
  for (PetscInt q = 0; q < b->nwalls; q++)
    for (PetscInt d = 0; d < 3; d++) b->wallpoint[3 * q + d] = b->loadpoint[d];
  PetscCheck(b->nmomentpoint == dim * b->nmomentname, comm, PETSC_ERR_ARG_SIZ,
             "-fs_walls_moment_points gives %" PetscInt_FMT " numbers for the %" PetscInt_FMT
             " walls of -fs_walls_moment_walls: expected %" PetscInt_FMT " (%s for each, in the same order)",
             b->nmomentpoint, b->nmomentname, dim * b->nmomentname, dim == 3 ? "x,y,z" : "x,y");
  for (PetscInt k = 0; k < b->nmomentname; k++) {
    PetscBool found = PETSC_FALSE;
    for (PetscInt q = 0; q < b->nwalls; q++)
      if (!strcmp(b->momentname[k], b->wallname[q])) {
        for (PetscInt d = 0; d < dim; d++) b->wallpoint[3 * q + d] = b->momentpoint[dim * k + d];
        found = PETSC_TRUE;
      }
    if (!found) {
      char known[512] = "";
      for (PetscInt q = 0; q < b->nwalls; q++) {
        PetscCall(PetscStrlcat(known, q ? ", " : "", sizeof(known)));
        PetscCall(PetscStrlcat(known, b->wallname[q], sizeof(known)));
      }
      SETERRQ(comm, PETSC_ERR_ARG_WRONG,
              "-fs_walls_moment_walls names wall \"%s\", which this case does not have: its walls are %s",
              b->momentname[k], known);
    }
  }
  b->view.dim    = dim;
  b->view.nwalls = b->nwalls;
  b->view.noslip = b->noslip;
  b->view.load   = b->load;
  for (PetscInt d = 0; d < 3; d++) b->view.loadpoint[d] = b->loadpoint[d];
  b->setupcalled = PETSC_TRUE;
  PetscFunctionReturn(0);
}

/*
   FSBoundaryUpdate - once per step, after the candidate fluid neighbours (nb) of the nowned particles
   are built: the candidate wall elements of each particle, the fluid candidates that see each other
   through a wall removed from nb, and the leak check: leak->particle is the first particle of this rank
   outside the liquid region (-1 if none), leak->wall the wall nearest to it.

   Not collective
*/
PetscErrorCode FSBoundaryUpdate(FSBoundary b, PetscInt nowned, const PetscReal rec[], PetscInt stride, FSNeighbours *nb,
                                FSBoundaryLeak *leak)
{
  PetscFunctionBegin;
  leak->particle = leak->wall = leak->element = -1;
  PetscCall((*b->ops->update)(b, nowned, rec, stride, nb, leak));
  PetscFunctionReturn(0);
}

/*
   FSBoundaryPrepare - at every right-hand side: gamma of the owned particles into gamma[0..nowned-1],
   their wall elements within the support (FSBoundaryGetView), the wall pressure interpolated from the
   liquid, and the pressure loads on the walls (the wall terms add the shear). With noslip not NULL,
   also the share of each particle's kernel support that lies behind no-slip walls (the sum of -gamma_k
   over their elements), which the no-slip wall term fills with the wall's velocity field (wall.c).
   FSBoundaryPrepareBegin, FSBoundaryPrepareExchange and FSBoundaryPrepareEnd in one call.

   Collective
*/
PetscErrorCode FSBoundaryPrepare(FSBoundary b, const FSBoundaryParticles *P, PetscReal gamma[], PetscReal noslip[])
{
  PetscFunctionBegin;
  PetscCall(FSBoundaryPrepareBegin(b, P, gamma, noslip));
  PetscCall(FSBoundaryPrepareExchange(b));
  PetscCall(FSBoundaryPrepareEnd(b));
  PetscFunctionReturn(0);
}

/*
   FSBoundaryPrepareBegin - FSBoundaryPrepare in three parts, so that a rank's other work can go on while the wall
   pressure's sums travel between the ranks: Begin computes gamma, noslip and the wall lists of the owned particles
   (the owned records only) and sends this rank's sums of the wall pressure; FSBoundaryPrepareExchange, once the
   other ranks have sent theirs (later is better), sends the sums back from the elements' owners;
   FSBoundaryPrepareEnd makes the wall pressure and the loads. The wall view's pressure and the loads are ready
   after End only.

   Collective (each of the three)
*/
PetscErrorCode FSBoundaryPrepareBegin(FSBoundary b, const FSBoundaryParticles *P, PetscReal gamma[], PetscReal noslip[])
{
  PetscFunctionBegin;
  PetscCall(PetscArrayzero(b->load, FS_WALL_LOAD_STRIDE * b->nwalls));
  b->wp_reductions = 0;
  b->wp_values     = 0;
  b->wp_exchanged  = 0;
  b->wpx.wp        = NULL;
  PetscCall((*b->ops->prepare)(b, P, gamma, noslip));
  PetscCheck(b->wpx.wp, PetscObjectComm((PetscObject)b), PETSC_ERR_PLIB,
             "Boundary %s: prepare must start the wall pressure (FSBoundaryWallPressureBegin)",
             ((PetscObject)b)->type_name);
  PetscFunctionReturn(0);
}

/* FSBoundaryPrepareExchange - the second part of FSBoundaryPrepare (FSBoundaryPrepareBegin). Collective */
PetscErrorCode FSBoundaryPrepareExchange(FSBoundary b)
{
  const PetscInt nel = b->wpx.nel;
  PetscReal     *num = b->wpx.wp + nel;

  PetscFunctionBegin;
  if (b->wpsf) {
    PetscCall(PetscSFReduceEnd(b->wpsf, MPIU_REAL, num, b->wproot, MPI_SUM));
    PetscCall(PetscSFBcastBegin(b->wpsf, MPIU_REAL, b->wproot, num, MPI_REPLACE));
  } else {
    b->wp_reductions++;
    b->wp_values += 2 * nel;
    PetscCallMPI(
        MPI_Allreduce(MPI_IN_PLACE, num, (PetscMPIInt)(2 * nel), MPIU_REAL, MPI_SUM, PetscObjectComm((PetscObject)b)));
  }
  PetscFunctionReturn(0);
}

/* FSBoundaryPrepareEnd - the last part of FSBoundaryPrepare (FSBoundaryPrepareBegin). Collective */
PetscErrorCode FSBoundaryPrepareEnd(FSBoundary b)
{
  const PetscInt  nel  = b->wpx.nel;
  const PetscReal pamb = b->wpx.pamb, *wetfull = b->wpx.wetfull;
  PetscReal      *wp = b->wpx.wp, *num = wp + nel, *den = num + nel;

  PetscFunctionBegin;
  if (b->wpsf) {
    PetscCall(PetscSFBcastEnd(b->wpsf, MPIU_REAL, b->wproot, num, MPI_REPLACE));
    b->wp_exchanged += 2 * b->wp_leaves;
  }
  for (PetscInt k = 0; k < nel; k++) {
    PetscReal pk = den[k] > 0 ? num[k] / den[k] : pamb;
    if (pk < pamb) {
      const PetscReal c = PetscMin(1.0, den[k] / wetfull[k]);
      pk                = pamb + (pk - pamb) * c * c;
    }
    wp[k] = pk;
  }
  PetscCall(FSBoundaryPressureLoads(b, wp));
  b->view.pressure = wp;
  PetscFunctionReturn(0);
}

/* FSBoundaryHasNoSlip - whether some wall is no-slip (-fs_walls_noslip); after FSBoundarySetUp. Not collective */
PetscErrorCode FSBoundaryHasNoSlip(FSBoundary b, PetscBool *has)
{
  PetscFunctionBegin;
  *has = b->anynoslip;
  PetscFunctionReturn(0);
}

/*
   FSBoundaryWallPressureBegin - for the implementations' prepare, at its end: the wall pressure of the nel elements
   from the sums over this rank's particles near each, num[k] = sum_i (p_i + rho_i g.(x_k - x_i)) W_ik V_i and
   den[k] = sum_i W_ik V_i, held in wp[nel .. 3 nel): summed over the ranks, p_k = num/den (the ambient
   pressure p_b where no liquid is near). Below p_b, p_k counts with the square of the element's wetted
   share c_k = min(1, den_k / wetfull_k) (wetfull: the container's Shepard factor at the element), so
   that the hydrostatic correction does not extrapolate suction onto a dry wall above a free surface
   (docs/decisions.md), while a covered wall keeps its tension. Into wp[0 .. nel) by FSBoundaryPrepareEnd, which
   also makes the pressure loads (FSBoundaryPressureLoads) and sets the view's pressure to wp: with a partition
   (FSBoundarySetPartition) valid at the elements this rank's particles can reach and at those it owns, the
   sums going from the ranks that reach an element to its owner and back (neighbour messages, started here);
   without one at every element, through one MPI_Allreduce of all the sums (FSBoundaryPrepareExchange).

   Collective
*/
PetscErrorCode FSBoundaryWallPressureBegin(FSBoundary b, PetscInt nel, const PetscReal wetfull[], PetscReal pamb,
                                           PetscReal wp[])
{
  PetscFunctionBegin;
  b->wpx.nel     = nel;
  b->wpx.wetfull = wetfull;
  b->wpx.pamb    = pamb;
  b->wpx.wp      = wp;
  if (b->wpsf) {
    PetscCall(PetscArrayzero(b->wproot, 2 * nel));
    PetscCall(PetscSFReduceBegin(b->wpsf, MPIU_REAL, wp + nel, b->wproot, MPI_SUM));
  }
  PetscFunctionReturn(0);
}

/*
   FSBoundaryPressureLoads - after the wall pressure (FSBoundaryPrepareEnd): this rank's share of
   the pressure loads on the walls, sum_k p_k A_k n_k and its moment about the load point, over the elements it
   owns (with a partition; rank 0 all of them without one), into b->load (FSBoundaryGetLoads sums the ranks').

   Not collective
*/
PetscErrorCode FSBoundaryPressureLoads(FSBoundary b, const PetscReal wp[])
{
  const FSWallView *V = &b->view;
  const PetscInt    D = b->dim;
  PetscMPIInt       rank;

  PetscFunctionBegin;
  PetscCallMPI(MPI_Comm_rank(PetscObjectComm((PetscObject)b), &rank));
  if (!b->owner && rank) PetscFunctionReturn(0);
  for (PetscInt k = 0; k < V->nelements; k++) {
    const PetscReal *el = &V->element[k * V->stride], *c = el + V->centroid, *nn = el + V->normal;
    const PetscReal  a    = wp[k] * el[V->measure];
    PetscReal        f[3] = {0, 0, 0}, r[3] = {0, 0, 0}, *L = &b->load[FS_WALL_LOAD_STRIDE * V->elementwall[k]];
    if (b->owner && b->owner[k] != rank) continue;
    for (PetscInt d = 0; d < D; d++) {
      f[d] = a * nn[d];
      r[d] = c[d] - b->loadpoint[d];
    }
    L[0] += f[0];
    L[1] += f[1];
    L[2] += f[2];
    L[3] += r[1] * f[2] - r[2] * f[1];
    L[4] += r[2] * f[0] - r[0] * f[2];
    L[5] += r[0] * f[1] - r[1] * f[0];
  }
  PetscFunctionReturn(0);
}

/*
   for each of the nq elements q[] of this rank's view (elgid numbering) that other ranks own, where their owner holds
   it: its rank (given) and its index in the owner's view (found), through PetscSFCreateByMatchingIndices on the
   owners' own elements
*/
static PetscErrorCode FSBoundaryFindOwnersIndex(FSBoundary b, PetscInt nq, const PetscInt q[], PetscSFNode remote[])
{
  MPI_Comm           comm = PetscObjectComm((PetscObject)b);
  PetscMPIInt        rank;
  PetscInt           nown = 0, *gown, *kown, *gq, nroots, nleaves, found = 0;
  PetscLayout        layout;
  PetscSF            sf;
  const PetscInt    *ilocal;
  const PetscSFNode *iremote;

  PetscFunctionBegin;
  PetscCallMPI(MPI_Comm_rank(comm, &rank));
  for (PetscInt k = 0; k < b->view.nelements; k++) nown += b->owner[k] == rank;
  PetscCall(PetscMalloc3(nown + 1, &gown, nown + 1, &kown, nq + 1, &gq));
  nown = 0;
  for (PetscInt k = 0; k < b->view.nelements; k++)
    if (b->owner[k] == rank) {
      gown[nown]   = b->elgid[k];
      kown[nown++] = k;
    }
  for (PetscInt i = 0; i < nq; i++) gq[i] = b->elgid[q[i]];
  PetscCall(PetscLayoutCreateFromSizes(comm, PETSC_DECIDE, b->nelglobal, 1, &layout));
  PetscCall(PetscSFCreateByMatchingIndices(layout, nown, gown, kown, 0, nq, gq, NULL, 0, NULL, &sf));
  PetscCall(PetscSFGetGraph(sf, &nroots, &nleaves, &ilocal, &iremote));
  for (PetscInt i = 0; i < nq; i++) remote[i].rank = -1;
  for (PetscInt l = 0; l < nleaves; l++) {
    const PetscInt i = ilocal ? ilocal[l] : l;
    remote[i]        = iremote[l];
  }
  for (PetscInt i = 0; i < nq; i++) found += remote[i].rank >= 0;
  PetscCheck(found == nq, PETSC_COMM_SELF, PETSC_ERR_PLIB,
             "The walls' elements: %" PetscInt_FMT " of the %" PetscInt_FMT
             " near this rank's part not held by their owner",
             nq - found, nq);
  PetscCall(PetscSFDestroy(&sf));
  PetscCall(PetscLayoutDestroy(&layout));
  PetscCall(PetscFree3(gown, kown, gq));
  PetscFunctionReturn(0);
}

/*
   FSBoundarySetPartition - tells the walls how the particles are split over the ranks, so that the wall pressure's
   sums go only between the ranks that share an element (FSBoundaryWallPressure): rankof gives the rank owning a
   point (an element is owned by its centroid's rank), [lo, hi] is this rank's part of the domain (periodic
   directions: the whole). After FSBoundarySetUp; again whenever the split changes. With one rank nothing changes.
   An implementation that holds only the elements near the part (-fs_walls_distribute) makes them first; the sums
   then go to the owner's own index of each element, found through their numbers among all elements.

   Collective
*/
PetscErrorCode FSBoundarySetPartition(FSBoundary b, FSBoundaryRankOfFn rankof, void *ctx, const PetscReal lo[],
                                      const PetscReal hi[], const PetscBool periodic[])
{
  const FSWallView *V = &b->view;
  const PetscInt    D = b->dim;
  PetscMPIInt       size, rank;
  PetscInt          nel, nl = 0, *ilocal, nq = 0, *q;
  PetscSFNode      *iremote, *found;
  /* an element is within reach of this rank's particles when its centroid is within the candidate radius plus
     the element's own size (its farthest vertex) of this rank's part */
  const PetscReal reach = b->radius + b->elradius;

  PetscFunctionBegin;
  PetscCallMPI(MPI_Comm_size(PetscObjectComm((PetscObject)b), &size));
  PetscCallMPI(MPI_Comm_rank(PetscObjectComm((PetscObject)b), &rank));
  if (size == 1) PetscFunctionReturn(0);
  if (b->ops->partition) PetscCall((*b->ops->partition)(b, lo, hi, periodic));
  nel = V->nelements;
  PetscCall(PetscSFDestroy(&b->wpsf));
  PetscCall(PetscFree2(b->owner, b->wproot));
  if (!b->nelglobal) PetscFunctionReturn(0);
  PetscCall(PetscMalloc2(nel + 1, &b->owner, 2 * nel + 1, &b->wproot));
  PetscCall(PetscMalloc1(2 * nel + 1, &ilocal));
  PetscCall(PetscMalloc1(2 * nel + 1, &iremote));
  PetscCall(PetscMalloc2(nel + 1, &q, nel + 1, &found));
  for (PetscInt k = 0; k < nel; k++) {
    const PetscReal *c    = &V->element[k * V->stride + V->centroid];
    PetscBool        near = PETSC_TRUE;
    b->owner[k]           = rankof(ctx, c);
    for (PetscInt d = 0; d < D; d++)
      if (!periodic[d] && (c[d] < lo[d] - reach || c[d] > hi[d] + reach)) near = PETSC_FALSE;
    if (!near) continue;
    ilocal[nl]          = k; /* num[k] and den[k] (nel further) to the owner's */
    iremote[nl].rank    = b->owner[k];
    iremote[nl++].index = k;
    if (b->elgid && b->owner[k] != rank) q[nq++] = k;
  }
  if (b->elgid) { /* the owner's own index of each element, its num and den side by side there */
    PetscCall(FSBoundaryFindOwnersIndex(b, nq, q, found));
    for (PetscInt l = 0, i = 0; l < nl; l++) {
      if (iremote[l].rank != rank) {
        PetscCheck(found[i].rank == iremote[l].rank, PETSC_COMM_SELF, PETSC_ERR_PLIB,
                   "The walls' element owners disagree");
        iremote[l].index = found[i++].index;
      }
      iremote[l].index *= 2;
      iremote[nl + l].rank  = iremote[l].rank;
      iremote[nl + l].index = iremote[l].index + 1;
      ilocal[nl + l]        = nel + ilocal[l];
    }
  } else
    for (PetscInt l = 0; l < nl; l++) {
      iremote[nl + l].rank  = iremote[l].rank;
      iremote[nl + l].index = nel + iremote[l].index;
      ilocal[nl + l]        = nel + ilocal[l];
    }
  PetscCall(PetscFree2(q, found));
  b->wp_leaves = nl;
  PetscCall(PetscSFCreate(PetscObjectComm((PetscObject)b), &b->wpsf));
  PetscCall(PetscSFSetGraph(b->wpsf, 2 * nel, 2 * nl, ilocal, PETSC_OWN_POINTER, iremote, PETSC_OWN_POINTER));
  PetscCall(PetscSFSetUp(b->wpsf));
  PetscFunctionReturn(0);
}

/*
   FSBoundaryGetElementCounts - the elements this rank's view holds, those of all the walls, and whether the view
   holds them all (false with -fs_walls_distribute on more than one rank, after FSBoundarySetPartition). Any
   argument may be NULL. Not collective
*/
PetscErrorCode FSBoundaryGetElementCounts(FSBoundary b, PetscInt *nlocal, PetscInt *nglobal, PetscBool *all)
{
  PetscFunctionBegin;
  if (nlocal) *nlocal = b->view.nelements;
  if (nglobal) *nglobal = b->nelglobal;
  if (all) *all = (PetscBool)!b->elgid;
  PetscFunctionReturn(0);
}

/*
   FSBoundaryGetFullView - a view of every wall element, numbered among all of them (FSBoundaryLocalElement finds
   one's index in this rank's view), for set-up work that must see any element: this rank's own view when it holds
   them all; with -fs_walls_distribute every element made again for the while, and FSBoundaryShepardAt answering at
   any point (from all of them, in another order than a run's, so to round-off), until FSBoundaryRestoreFullView.
   Its pressure is NULL.

   Not collective
*/
PetscErrorCode FSBoundaryGetFullView(FSBoundary b, const FSWallView **full)
{
  PetscFunctionBegin;
  if (!b->elgid) {
    *full = &b->view;
    PetscFunctionReturn(0);
  }
  PetscCheck(b->ops->fullview, PetscObjectComm((PetscObject)b), PETSC_ERR_PLIB,
             "Boundary %s holds some elements but cannot make them all", ((PetscObject)b)->type_name);
  b->full          = b->view;
  b->full.pressure = NULL;
  PetscCall((*b->ops->fullview)(b, PETSC_TRUE));
  *full = &b->full;
  PetscFunctionReturn(0);
}

/* FSBoundaryRestoreFullView - the end of FSBoundaryGetFullView: the elements it made are freed. Not collective */
PetscErrorCode FSBoundaryRestoreFullView(FSBoundary b, const FSWallView **full)
{
  PetscFunctionBegin;
  *full = NULL;
  if (!b->elgid) PetscFunctionReturn(0);
  PetscCall((*b->ops->fullview)(b, PETSC_FALSE));
  PetscCall(PetscMemzero(&b->full, sizeof(b->full)));
  PetscFunctionReturn(0);
}

/*
   FSBoundaryLocalElement - the index k in this rank's view of the element numbered `number` among all of them (the
   index in FSBoundaryGetFullView's view), -1 when this rank does not hold it. Not collective
*/
PetscErrorCode FSBoundaryLocalElement(FSBoundary b, PetscInt number, PetscInt *k)
{
  PetscFunctionBegin;
  if (!b->elgid) *k = number < b->view.nelements ? number : -1;
  else {
    PetscCall(PetscFindInt(number, b->view.nelements, b->elgid, k));
    if (*k < 0) *k = -1;
  }
  PetscFunctionReturn(0);
}

/* FSBoundaryOwnsElement - whether this rank owns element k: with a partition its owner, else rank 0. Not collective */
PetscErrorCode FSBoundaryOwnsElement(FSBoundary b, PetscInt k, PetscBool *owns)
{
  PetscMPIInt rank;

  PetscFunctionBegin;
  PetscCallMPI(MPI_Comm_rank(PetscObjectComm((PetscObject)b), &rank));
  *owns = (PetscBool)(b->owner ? b->owner[k] == rank : rank == 0);
  PetscFunctionReturn(0);
}

/*
   FSBoundaryGetView - the wall terms' view (elements, wall pressure, conditions, loads) and the wall
   elements of every owned particle as the last FSBoundaryPrepare left them: particle i's are
   wk[wstart[i] .. wstart[i+1]-1] with the mean kernel values wW[...].

   Not collective
*/
PetscErrorCode FSBoundaryGetView(FSBoundary b, const FSWallView **view, const PetscInt **wstart, const PetscInt **wk,
                                 const PetscReal **wW)
{
  PetscFunctionBegin;
  *view   = &b->view;
  *wstart = b->wstart;
  *wk     = b->wk;
  *wW     = b->wW;
  PetscFunctionReturn(0);
}

/*
   FSBoundaryBounce - after each step, a particle closer to a wall than -fs_walls_bounce_distance (in
   units of dx) and moving towards it is put back at that distance and its normal velocity reversed,
   scaled by -fs_walls_bounce_restitution. x, v: the n particles' positions and velocities (the boundary's dimension
   each), changed in place; energy(ctx, x, v, m, e) measures a particle's energy so that de returns this rank's change
   of the liquid's energy by the bounces.

   Not collective
*/
PetscErrorCode FSBoundaryBounce(FSBoundary b, PetscInt n, PetscReal x[], PetscReal v[], const PetscReal m[],
                                FSParticleEnergyFn energy, void *ctx, PetscReal de[2])
{
  PetscFunctionBegin;
  de[0] = de[1] = 0;
  if (b->bounce_distance > 0) PetscCall((*b->ops->bounce)(b, n, x, v, m, energy, ctx, de));
  PetscFunctionReturn(0);
}

/*
   FSBoundaryBounceParticle - for the implementations' bounce: the rule of FSBoundaryBounce for one
   particle (x, v, mass m) found at the distance d (< the bounce distance) from an element's plane and
   moving towards it at the normal speed un > 0, n the element's unit normal (out of the liquid): put
   back at the bounce distance, its normal velocity reversed and scaled by the restitution; the change
   of its energy (energy callback) added to de.

   Not collective
*/
void FSBoundaryBounceParticle(FSBoundary b, const PetscReal n[], PetscReal d, PetscReal un, PetscReal x[],
                              PetscReal v[], PetscReal m, FSParticleEnergyFn energy, void *ctx, PetscReal de[2])
{
  const PetscReal dmin = b->bounce_distance * b->dx;
  PetscReal       e0[2], e1[2];

  energy(ctx, x, v, m, e0);
  for (PetscInt a = 0; a < b->dim; a++) {
    x[a] -= (dmin - d) * n[a];
    v[a] -= (1 + b->restitution) * un * n[a];
  }
  energy(ctx, x, v, m, e1);
  de[0] += e1[0] - e0[0];
  de[1] += e1[1] - e0[1];
  b->nbounce++;
}

/*
   FSBoundaryGetVisibilityOption - whether -fs_walls_visibility is all in the options database of obj (with its
   prefix), before a boundary reads it at set-up (FSBoundarySetFromOptions): the relaxed packing, which a case builds
   before that, balances the wall elements that the run's wall terms will count (src/cases/impls/packing.c).

   Not collective
*/
PetscErrorCode FSBoundaryGetVisibilityOption(PetscObject obj, PetscBool *all)
{
  PetscInt vis = 0;

  PetscFunctionBegin;
  PetscCall(
      PetscOptionsGetEList(obj->options, obj->prefix, "-fs_walls_visibility", FSBoundaryVisibilities, 2, &vis, NULL));
  *all = (PetscBool)(vis == 1);
  PetscFunctionReturn(0);
}

/* FSBoundaryGetBounce - whether particles bounce off the walls (-fs_walls_bounce_distance > 0). Not collective. */
PetscErrorCode FSBoundaryGetBounce(FSBoundary b, PetscBool *bounce)
{
  PetscFunctionBegin;
  *bounce = (PetscBool)(b->bounce_distance > 0);
  PetscFunctionReturn(0);
}

/*
   FSBoundaryGetLoads - the liquid's load on each wall from the last right-hand side, summed over the
   ranks: per wall the force (3) and the moment (3) about -fs_walls_load_point, in the order of
   FSBoundaryGetWallNames().

   Collective
*/
PetscErrorCode FSBoundaryGetLoads(FSBoundary b, PetscInt *nwalls, const PetscReal **loads)
{
  PetscFunctionBegin;
  *nwalls = b->nwalls;
  PetscCallMPI(MPI_Allreduce(b->load, b->loadsum, (PetscMPIInt)(FS_WALL_LOAD_STRIDE * b->nwalls), MPIU_REAL, MPI_SUM,
                             PetscObjectComm((PetscObject)b)));
  *loads = b->loadsum;
  PetscFunctionReturn(0);
}

/*
   FSBoundaryGetLoadsLocal - this rank's share of the loads of FSBoundaryGetLoads() (6 per wall), for a caller that
   sums them over the ranks in a reduction of its own (FSBoundaryGetWallLoadsSummed()).

   Not collective
*/
PetscErrorCode FSBoundaryGetLoadsLocal(FSBoundary b, PetscInt *nwalls, const PetscReal **local)
{
  PetscFunctionBegin;
  *nwalls = b->nwalls;
  *local  = b->load;
  PetscFunctionReturn(0);
}

/* each wall's moment moved from the load point o to the wall's own point p exactly, M_p = M_o + (o - p) x F: loadsum
   into loadwall */
static void FSBoundaryMoveMoments(FSBoundary b)
{
  for (PetscInt q = 0; q < b->nwalls; q++) {
    const PetscReal *F = &b->loadsum[FS_WALL_LOAD_STRIDE * q], *p = &b->wallpoint[3 * q];
    PetscReal       *out = &b->loadwall[FS_WALL_LOAD_STRIDE * q];
    PetscReal        r[3];
    for (PetscInt c = 0; c < FS_WALL_LOAD_STRIDE; c++) out[c] = F[c];
    for (PetscInt d = 0; d < 3; d++) r[d] = b->loadpoint[d] - p[d];
    if (r[0] == 0 && r[1] == 0 && r[2] == 0) continue; /* about the load point: as summed */
    out[3] += r[1] * F[2] - r[2] * F[1];
    out[4] += r[2] * F[0] - r[0] * F[2];
    out[5] += r[0] * F[1] - r[1] * F[0];
  }
}

/*
   FSBoundaryGetWallLoads - the loads of FSBoundaryGetLoads() as reported (time series, FSSolverGetWallLoads): each
   wall's moment about its own point (-fs_walls_moment_walls, -fs_walls_moment_points; -fs_walls_load_point for the
   others), moved from the load point o to the wall's p exactly, M_p = M_o + (o - p) x F.

   Collective
*/
PetscErrorCode FSBoundaryGetWallLoads(FSBoundary b, PetscInt *nwalls, const PetscReal **loads)
{
  const PetscReal *L;

  PetscFunctionBegin;
  PetscCall(FSBoundaryGetLoads(b, nwalls, &L));
  FSBoundaryMoveMoments(b);
  *loads = b->loadwall;
  PetscFunctionReturn(0);
}

/*
   FSBoundaryGetWallLoadsSummed - FSBoundaryGetWallLoads() from sums over the ranks of FSBoundaryGetLoadsLocal()'s
   values that the caller reduced with its own (the time series' row reduces them with its other sums).

   Not collective
*/
PetscErrorCode FSBoundaryGetWallLoadsSummed(FSBoundary b, const PetscReal summed[], PetscInt *nwalls,
                                            const PetscReal **loads)
{
  PetscFunctionBegin;
  *nwalls = b->nwalls;
  PetscCall(PetscArraycpy(b->loadsum, summed, FS_WALL_LOAD_STRIDE * b->nwalls));
  FSBoundaryMoveMoments(b);
  *loads = b->loadwall;
  PetscFunctionReturn(0);
}

/* FSBoundaryGetWallLoadPoints - per wall the point (3) its reported moment is about. Not collective. */
PetscErrorCode FSBoundaryGetWallLoadPoints(FSBoundary b, PetscInt *nwalls, const PetscReal **points)
{
  PetscFunctionBegin;
  *nwalls = b->nwalls;
  *points = b->wallpoint;
  PetscFunctionReturn(0);
}

/* FSBoundaryGetWallNames - the walls' names, in the order of the loads. Not collective. */
PetscErrorCode FSBoundaryGetWallNames(FSBoundary b, PetscInt *nwalls, const char *const **names)
{
  PetscFunctionBegin;
  *nwalls = b->nwalls;
  *names  = b->wallname;
  PetscFunctionReturn(0);
}

/*
   FSBoundaryShepardAt - the walls' Shepard factor gamma(x), the share of the kernel support of a point x
   that lies inside the liquid region, from the wall elements within its support (as the particles'
   gamma, with the visibility rule of -fs_walls_visibility, found through the method's static grid of
   elements); 1 far from the walls.

   Not collective
*/
PetscErrorCode FSBoundaryShepardAt(FSBoundary b, const PetscReal x[], PetscReal *gamma)
{
  PetscFunctionBegin;
  PetscCheck(b->setupcalled, PetscObjectComm((PetscObject)b), PETSC_ERR_ARG_WRONGSTATE,
             "FSBoundaryShepardAt(): call FSBoundarySetUp() first");
  PetscCheck(b->ops->shepard, PetscObjectComm((PetscObject)b), PETSC_ERR_SUP,
             "Boundary type %s gives no Shepard factor at a point", ((PetscObject)b)->type_name);
  PetscCall((*b->ops->shepard)(b, x, gamma));
  PetscFunctionReturn(0);
}

/*
   FSBoundaryLocate - where the point x lies with respect to the walls: inliquid, whether it is in the
   liquid region (inside the container's closed walls and outside every wall's solid: an obstacle, a
   baffle's thickness; the test of the leak check), the nearest wall (-1: none) and the distance to it.

   Not collective

   Notes:
   A method without the op says every point is in the liquid (wall -1, distance PETSC_MAX_REAL).
*/
PetscErrorCode FSBoundaryLocate(FSBoundary b, const PetscReal x[], PetscBool *inliquid, PetscInt *wall,
                                PetscReal *distance)
{
  PetscFunctionBegin;
  PetscCheck(b->setupcalled, PetscObjectComm((PetscObject)b), PETSC_ERR_ARG_WRONGSTATE,
             "FSBoundaryLocate(): call FSBoundarySetUp() first");
  *inliquid = PETSC_TRUE;
  *wall     = -1;
  *distance = PETSC_MAX_REAL;
  if (b->ops->locate) PetscCall((*b->ops->locate)(b, x, inliquid, wall, distance));
  PetscFunctionReturn(0);
}

/* FSBoundaryGetBoundingBox - the box around every wall (dim values each). Not collective. */
PetscErrorCode FSBoundaryGetBoundingBox(FSBoundary b, PetscReal lo[], PetscReal hi[])
{
  PetscFunctionBegin;
  PetscCall((*b->ops->boundingbox)(b, lo, hi));
  PetscFunctionReturn(0);
}

/* FSBoundaryGetLoadPoint - the point about which the wall moments are taken. Not collective. */
PetscErrorCode FSBoundaryGetLoadPoint(FSBoundary b, PetscReal point[3])
{
  PetscFunctionBegin;
  for (PetscInt d = 0; d < 3; d++) point[d] = b->loadpoint[d];
  PetscFunctionReturn(0);
}

/* FSBoundaryDraw - rank 0: the walls into the geometry picture, placed by map. */
PetscErrorCode FSBoundaryDraw(FSBoundary b, FSImage *img, const FSImageMap *map)
{
  PetscFunctionBegin;
  if (b->ops->draw) PetscCall((*b->ops->draw)(b, img, map));
  PetscFunctionReturn(0);
}

/* FSBoundaryWriteGeometry - the walls as files for ParaView in dir (collective); verbose: print where. */
PetscErrorCode FSBoundaryWriteGeometry(FSBoundary b, const char dir[], PetscBool verbose)
{
  PetscFunctionBegin;
  b->geometry_verbose = verbose;
  if (b->ops->writegeometry) PetscCall((*b->ops->writegeometry)(b, dir));
  PetscFunctionReturn(0);
}

/* FSBoundaryHashAdd_Private - adds n bytes of data to the 64-bit FNV-1a hash *hash */
void FSBoundaryHashAdd_Private(uint64_t *hash, const void *data, size_t n)
{
  const unsigned char *c = (const unsigned char *)data;

  for (size_t i = 0; i < n; i++) *hash = (*hash ^ c[i]) * 1099511628211ULL;
}

/* *array with room for cap entries of size bytes, its content kept: a reallocation, which the system does for a
   large block without copying it (no second block while it grows) */
static PetscErrorCode FSBoundaryResize(size_t size, PetscInt cap, void *array)
{
  void **a = (void **)array;

  PetscFunctionBegin;
  if (*a) PetscCall(PetscRealloc(size * (size_t)cap, a));
  else PetscCall(PetscMalloc(size * (size_t)cap, a));
  PetscFunctionReturn(0);
}

/* the capacity a list of capacity cap takes for entry n (ListRoom), or after a fill of n entries (ListFit) */
static inline PetscInt FSBoundaryListRoomCap(PetscInt n, PetscInt cap)
{
  return n < cap ? cap : PetscMax(4096, cap + cap / 4);
}
static inline PetscInt FSBoundaryListFitCap(PetscInt n, PetscInt cap)
{
  return cap > PetscMax(4096, n + n / 8) ? PetscMax(4096, n + n / 16) : cap;
}

/* *array (capacity *cap) with capacity c */
static PetscErrorCode FSBoundaryListResize(size_t size, PetscInt c, PetscInt *cap, void *array)
{
  PetscFunctionBegin;
  if (c != *cap) PetscCall(FSBoundaryResize(size, c, array));
  *cap = c;
  PetscFunctionReturn(0);
}

/* FSBoundaryListRoom_Private - room for entry n of *array (boundaryimpl.h) */
PetscErrorCode FSBoundaryListRoom_Private(size_t size, PetscInt n, PetscInt *cap, void *array)
{
  PetscFunctionBegin;
  PetscCall(FSBoundaryListResize(size, FSBoundaryListRoomCap(n, *cap), cap, array));
  PetscFunctionReturn(0);
}

/* FSBoundaryListFit_Private - *array trimmed to about its n entries (boundaryimpl.h) */
PetscErrorCode FSBoundaryListFit_Private(size_t size, PetscInt n, PetscInt *cap, void *array)
{
  PetscFunctionBegin;
  PetscCall(FSBoundaryListResize(size, FSBoundaryListFitCap(n, *cap), cap, array));
  PetscFunctionReturn(0);
}

/* the wall lists wk and wW with capacity c */
static PetscErrorCode FSBoundaryWallListsResize(FSBoundary b, PetscInt c)
{
  PetscFunctionBegin;
  if (c != b->wcap) {
    PetscCall(FSBoundaryResize(sizeof(PetscInt), c, &b->wk));
    PetscCall(FSBoundaryResize(sizeof(PetscReal), c, &b->wW));
  }
  b->wcap = c;
  PetscFunctionReturn(0);
}

/* FSBoundaryWallListsRoom_Private - room for entry n of the wall lists wk and wW */
PetscErrorCode FSBoundaryWallListsRoom_Private(FSBoundary b, PetscInt n)
{
  PetscFunctionBegin;
  PetscCall(FSBoundaryWallListsResize(b, FSBoundaryListRoomCap(n, b->wcap)));
  PetscFunctionReturn(0);
}

/* FSBoundaryWallListsFit_Private - the wall lists trimmed to about their n entries */
PetscErrorCode FSBoundaryWallListsFit_Private(FSBoundary b, PetscInt n)
{
  PetscFunctionBegin;
  PetscCall(FSBoundaryWallListsResize(b, FSBoundaryListFitCap(n, b->wcap)));
  PetscFunctionReturn(0);
}

/*@C
   FSBoundaryGetGeometryHash - a fingerprint of the walls as the case gave them: a 64-bit FNV-1a hash
   of the method, the wall names and the method's geometry (the polygons' vertices or the triangles, and
   the wall of each edge or triangle), before they are cut into elements of about dx. Two runs whose
   walls differ in any bit of a vertex have different hashes.

   Not collective (the geometry is the same on every rank)

   Input Parameters:
+  b   - the boundary, set up
-  len - the size of hash, at least 17

   Output Parameter:
.  hash - 16 hexadecimal digits

.seealso: FSBoundarySetUp()
@*/
PetscErrorCode FSBoundaryGetGeometryHash(FSBoundary b, char hash[], size_t len)
{
  uint64_t    h    = 14695981039346656037ULL;
  const char *type = ((PetscObject)b)->type_name ? ((PetscObject)b)->type_name : "";

  PetscFunctionBegin;
  PetscCheck(len >= 17, PETSC_COMM_SELF, PETSC_ERR_ARG_SIZ, "FSBoundaryGetGeometryHash(): 17 characters needed");
  PetscCheck(b->ops->hash, PETSC_COMM_SELF, PETSC_ERR_SUP, "Boundary method %s cannot hash its geometry", type);
  FSBoundaryHashAdd_Private(&h, type, strlen(type) + 1);
  for (PetscInt w = 0; w < b->nwalls; w++) FSBoundaryHashAdd_Private(&h, b->wallname[w], strlen(b->wallname[w]) + 1);
  PetscCall((*b->ops->hash)(b, &h));
  PetscCall(PetscSNPrintf(hash, len, "%016llx", (unsigned long long)h));
  PetscFunctionReturn(0);
}

/* FSBoundarySummary - the boundary's members of summary.json (collective). */
PetscErrorCode FSBoundarySummary(FSBoundary b, FSJSON js)
{
  PetscInt64 nb = b->nbounce;

  PetscFunctionBegin;
  /* particles bounced off walls: a measure of how hard the walls are pressed */
  PetscCallMPI(MPI_Allreduce(MPI_IN_PLACE, &nb, 1, MPIU_INT64, MPI_SUM, PetscObjectComm((PetscObject)b)));
  PetscCall(FSJSONWriteInt(js, "wall_bounces", nb));
  /* the wall pressure's sums over all ranks in a right-hand side: reductions and the values they carry */
  PetscCall(FSJSONWriteInt(js, "wall_pressure_reductions", b->wp_reductions));
  PetscCall(FSJSONWriteInt(js, "wall_pressure_reduced_values", b->wp_values));
  /* with a partition, the values this rank sent to the elements' owners and back in a right-hand side instead */
  PetscCall(FSJSONWriteInt(js, "wall_pressure_exchanged_values", b->wp_exchanged));
  /* the elements of all the walls, and whether each rank held only those near its part (-fs_walls_distribute) */
  PetscCall(FSJSONWriteInt(js, "wall_elements", b->nelglobal));
  PetscCall(FSJSONWriteBool(js, "wall_elements_distributed", (PetscBool)(b->elgid != NULL)));
  PetscFunctionReturn(0);
}

/* FSBoundaryGetMemory - the bytes this rank's walls hold (allocated, not used): the particles' candidate
   elements and wall lists, and the elements with their search grid and per-element arrays. Not collective. */
PetscErrorCode FSBoundaryGetMemory(FSBoundary b, PetscInt64 *lists, PetscInt64 *elements)
{
  PetscFunctionBegin;
  *lists = *elements = 0;
  if (b->ops->memory) PetscCall((*b->ops->memory)(b, lists, elements));
  PetscFunctionReturn(0);
}

/*
   FSBoundaryAddWork - adds to work[i] the cost of owned particle i's wall work in a right-hand side (its
   wall Shepard factor, wall lists and wall terms), counted in fluid candidate pairs (the cost of a pair
   in the passes over the pairs), from its candidate elements of the last FSBoundaryUpdate(). The
   decomposition balances the ranks' summed work (-fs_balance work).

   Not collective
*/
PetscErrorCode FSBoundaryAddWork(FSBoundary b, PetscInt nowned, PetscInt64 work[])
{
  PetscFunctionBegin;
  if (b->ops->work) PetscCall((*b->ops->work)(b, nowned, work));
  PetscFunctionReturn(0);
}

/* FSBoundaryView - the method, the walls and their conditions. */
PetscErrorCode FSBoundaryView(FSBoundary b, PetscViewer viewer)
{
  PetscBool isascii;

  PetscFunctionBegin;
  PetscCall(PetscObjectTypeCompare((PetscObject)viewer, PETSCVIEWERASCII, &isascii));
  if (!isascii) PetscFunctionReturn(0);
  PetscCall(PetscViewerASCIIPrintf(viewer, "Boundary: %s, %" PetscInt_FMT " wall(s):",
                                   ((PetscObject)b)->type_name ? ((PetscObject)b)->type_name : "(no type)", b->nwalls));
  PetscCall(PetscViewerASCIIUseTabs(viewer, PETSC_FALSE));
  for (PetscInt w = 0; w < b->nwalls; w++)
    PetscCall(PetscViewerASCIIPrintf(viewer, " %s (%s)", b->wallname[w],
                                     b->noslip && b->noslip[w] ? "no-slip" : "free-slip"));
  PetscCall(PetscViewerASCIIPrintf(viewer, "\n"));
  PetscCall(PetscViewerASCIIUseTabs(viewer, PETSC_TRUE));
  if (b->ops->view) {
    PetscCall(PetscViewerASCIIPushTab(viewer));
    PetscCall((*b->ops->view)(b, viewer));
    PetscCall(PetscViewerASCIIPopTab(viewer));
  }
  PetscFunctionReturn(0);
}

PetscErrorCode FSBoundaryDestroy(FSBoundary *boundary)
{
  FSBoundary b = *boundary;

  PetscFunctionBegin;
  if (!b) PetscFunctionReturn(0);
  if (--((PetscObject)b)->refct > 0) {
    *boundary = NULL;
    PetscFunctionReturn(0);
  }
  if (b->ops->destroy) PetscCall((*b->ops->destroy)(b));
  PetscCall(PetscFree(b->noslip));
  for (PetscInt k = 0; k < b->nnoslipname; k++) PetscCall(PetscFree(b->noslipname[k]));
  for (PetscInt k = 0; k < b->nmomentname; k++) PetscCall(PetscFree(b->momentname[k]));
  PetscCall(PetscFree2(b->load, b->loadsum));
  PetscCall(PetscFree2(b->wallpoint, b->loadwall));
  PetscCall(PetscSFDestroy(&b->wpsf));
  PetscCall(PetscFree2(b->owner, b->wproot));
  PetscCall(PetscHeaderDestroy(boundary));
  PetscFunctionReturn(0);
}
