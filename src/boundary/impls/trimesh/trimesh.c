/*
   The triangle-mesh boundary ("trimesh"): 3-D boundary integrals on closed triangle meshes of named
   wall parts. The same stages as the polygon boundary: per time step, the candidate elements of every
   owned particle, the leak check, and the cut of fluid pairs that see each other through a wall; per
   right-hand side, gamma_i and the facing elements within the support with their kernel values, the
   wall pressure and the loads (force and moment vectors). The mesh (mesh.h: building, STL, checks,
   refinement) is in mesh.c and stl.c, gamma of a point in integrals.c, the walls' part of the
   geometry view in geometryview.c.
*/
#include "trimeshimpl.h"

static PetscErrorCode FSBoundaryTrimeshSetMesh_Trimesh(FSBoundary b, FSMesh *m)
{
  FSBoundary_Trimesh *tm = (FSBoundary_Trimesh *)b->data;

  PetscFunctionBegin;
  PetscCall(FSMeshDestroy(&tm->mesh));
  tm->mesh = *m;
  PetscCall(PetscMemzero(m, sizeof(*m)));
  PetscFunctionReturn(0);
}

/*
   FSBoundaryTrimeshSetMesh - gives a triangle-mesh boundary its mesh (the case builds it); the boundary
   owns it after, and m is zeroed.

   Collective
*/
PetscErrorCode FSBoundaryTrimeshSetMesh(FSBoundary b, FSMesh *m)
{
  PetscFunctionBegin;
  PetscUseMethod(b, "FSBoundaryTrimeshSetMesh_C", (FSBoundary, FSMesh *), (b, m));
  PetscFunctionReturn(0);
}

/* the grid cell of x, clamped to the grid */
static inline void GridCell(const FSBoundary_Trimesh *tm, const PetscReal x[], PetscInt c[3])
{
  for (PetscInt d = 0; d < 3; d++) {
    c[d] = (PetscInt)PetscFloorReal((x[d] - tm->glo[d]) / tm->gcell);
    c[d] = PetscMax(0, PetscMin(tm->gnc[d] - 1, c[d]));
  }
}

#define FOR_GRID_NEIGHBOURS(tm, cc, q)                                                            \
  for (PetscInt c2 = PetscMax(cc[2] - 1, 0); c2 <= PetscMin(cc[2] + 1, tm->gnc[2] - 1); c2++)     \
    for (PetscInt c1 = PetscMax(cc[1] - 1, 0); c1 <= PetscMin(cc[1] + 1, tm->gnc[1] - 1); c1++)   \
      for (PetscInt c0 = PetscMax(cc[0] - 1, 0); c0 <= PetscMin(cc[0] + 1, tm->gnc[0] - 1); c0++) \
        for (PetscInt q = tm->gstart[c0 + tm->gnc[0] * (c1 + tm->gnc[1] * c2)];                   \
             q < tm->gstart[c0 + tm->gnc[0] * (c1 + tm->gnc[1] * c2) + 1]; q++)

/* gamma at x from the elements near it (the grid), the container only or all (FSTriangleIntegrals) */
static PetscReal ShepardNear(const FSBoundary_Trimesh *tm, PetscReal h, const PetscReal x[], PetscBool all)
{
  PetscInt  cc[3];
  PetscReal g = 1;
  GridCell(tm, x, cc);
  FOR_GRID_NEIGHBOURS(tm, cc, q)
  {
    PetscReal gk, wi;
    FSTriangleIntegrals(h, x, &tm->mesh.el[tm->gel[q] * FS_TRI_STRIDE], all, &gk, &wi);
    g += gk;
  }
  return g;
}

/* is the liquid region convex (every vertex on the liquid side of every triangle's plane, one surface)? */
static PetscBool MeshConvex(const FSMesh *m)
{
  const PetscReal tol = 1e-9 * (m->hi[0] - m->lo[0] + m->hi[1] - m->lo[1] + m->hi[2] - m->lo[2]);
  if ((PetscReal)m->ntri * (PetscReal)m->nvert > 1e8) return PETSC_FALSE; /* too large to tell cheaply */
  for (PetscInt t = 0; t < m->ntri; t++) {
    const PetscReal *a = &m->vert[3 * m->tri[3 * t]], *b = &m->vert[3 * m->tri[3 * t + 1]],
                    *c    = &m->vert[3 * m->tri[3 * t + 2]];
    const PetscReal e1[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]}, e2[3] = {c[0] - a[0], c[1] - a[1], c[2] - a[2]};
    PetscReal n[3] = {e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2], e1[0] * e2[1] - e1[1] * e2[0]},
              nn   = PetscSqrtReal(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
    for (PetscInt v = 0; v < m->nvert; v++) {
      const PetscReal *p = &m->vert[3 * v];
      if (((p[0] - a[0]) * n[0] + (p[1] - a[1]) * n[1] + (p[2] - a[2]) * n[2]) / nn > tol) return PETSC_FALSE;
    }
  }
  return PETSC_TRUE;
}

/*
   SetFromOptions - the triangle-mesh boundary's options.

   Options Database Key:
.  -fs_walls_element_size <1> - the longest element edge, in units of h: the mesh's triangles are split
   until their edges are at most this (gamma to 5e-7 at 1, 3e-8 at 0.5; docs/walls.md)
-  -fs_walls_distribute <true> - on more than one rank, each rank holds only the elements near its part of the
   domain (made again when the cuts move) instead of all of them; the input triangles stay on every rank
*/
static PetscErrorCode SetFromOptions(FSBoundary b, PetscOptionItems *PetscOptionsObject)
{
  FSBoundary_Trimesh *tm = (FSBoundary_Trimesh *)b->data;

  PetscFunctionBegin;
  PetscOptionsHeadBegin(PetscOptionsObject, "Walls (boundary integrals on triangle meshes)");
  PetscCall(FSOptionsReal(PetscOptionsObject, "-fs_walls_element_size",
                          "Longest edge of the wall elements, in units of h (the mesh's triangles are split to it)",
                          "FSBoundaryCreate_Trimesh", &tm->element, NULL, 0, 4, FS_RANGE_OPEN_LOWER));
  PetscCall(PetscOptionsBool(
      "-fs_walls_distribute",
      "Each rank holds only the wall elements near its part of the domain (more than one rank; false: all)",
      "FSBoundaryCreate_Trimesh", tm->distribute, &tm->distribute, NULL));
  PetscOptionsHeadEnd();
  PetscFunctionReturn(0);
}

/*
   the elements of the whole refinement (no box) or those near the box lo..hi (FSMeshRefineRegion), binned in a
   static grid by centroid, and the container's Shepard factor at each. A box's grid is the block of the whole
   refinement's grid that holds its elements' centroids, so that every search visits the same elements in the same
   order as with the whole mesh and the sums agree to the last bit. The Shepard factor of an element whose centroid
   lies within the box shrunk by R + r (R the candidate radius, r the largest element's: the core) is the whole mesh's
   (every element within its support is held); only the core's are needed, and when the box moves those computed
   before are kept.
*/
static PetscErrorCode BuildElements(FSBoundary b, const PetscReal lo[], const PetscReal hi[])
{
  FSBoundary_Trimesh *tm  = (FSBoundary_Trimesh *)b->data;
  FSMesh             *m   = &tm->mesh;
  const PetscBool     had = tm->local;
  PetscInt            ncell, nold = m->nel, *oldgid = m->elgid, q = 0, kept = 0, made = 0;
  PetscReal          *oldwet = tm->wetfull, oldlo[3], oldhi[3];

  PetscFunctionBegin;
  for (PetscInt d = 0; d < 3; d++) {
    oldlo[d] = tm->corelo[d];
    oldhi[d] = tm->corehi[d];
  }
  m->elgid    = NULL; /* kept until the Shepard factors are */
  tm->wetfull = NULL;
  PetscCall(FSMeshRefineRegion(m, tm->element * b->h, lo, hi));
  tm->local           = (PetscBool)(lo != NULL);
  b->view.nelements   = m->nel;
  b->view.element     = m->el;
  b->view.elementwall = m->elwall;
  /* static grid of elements by centroid: an element within the candidate radius of x has its centroid
     within radius + (the largest centroid-vertex distance) of x, so within the 27 cells around x */
  tm->gcell = b->radius + m->elradius;
  ncell     = 1;
  for (PetscInt d = 0; d < 3; d++) {
    const PetscReal glo = m->lo[d] - tm->gcell;
    const PetscInt  gnc = (PetscInt)((m->hi[d] + tm->gcell - glo) / tm->gcell) + 1;
    PetscInt        c0 = 0, c1 = gnc - 1;
    if (lo) { /* the cells of the centroids within the box grown by the elements' size */
      c0 = PetscMax(0, PetscMin(gnc - 1, (PetscInt)PetscFloorReal((lo[d] - m->elradius - glo) / tm->gcell)));
      c1 = PetscMax(c0, PetscMin(gnc - 1, (PetscInt)PetscFloorReal((hi[d] + m->elradius - glo) / tm->gcell)));
    }
    tm->glo[d] = glo + c0 * tm->gcell;
    tm->gnc[d] = c1 - c0 + 1;
    ncell *= tm->gnc[d];
  }
  PetscCall(PetscFree(tm->gstart));
  PetscCall(PetscFree(tm->gel));
  PetscCall(PetscCalloc1(ncell + 1, &tm->gstart));
  PetscCall(PetscMalloc1(m->nel + 1, &tm->gel));
  for (PetscInt k = 0; k < m->nel; k++) {
    PetscInt cc[3];
    GridCell(tm, &m->el[k * FS_TRI_STRIDE + FS_TRI_CENTROID], cc);
    tm->gstart[cc[0] + tm->gnc[0] * (cc[1] + tm->gnc[1] * cc[2]) + 1]++;
  }
  for (PetscInt c = 0; c < ncell; c++) tm->gstart[c + 1] += tm->gstart[c];
  {
    PetscInt *fill;
    PetscCall(PetscMalloc1(ncell, &fill));
    PetscCall(PetscArraycpy(fill, tm->gstart, ncell));
    for (PetscInt k = 0; k < m->nel; k++) {
      PetscInt cc[3];
      GridCell(tm, &m->el[k * FS_TRI_STRIDE + FS_TRI_CENTROID], cc);
      tm->gel[fill[cc[0] + tm->gnc[0] * (cc[1] + tm->gnc[1] * cc[2])]++] = k;
    }
    PetscCall(PetscFree(fill));
  }
  /* the Shepard factor of the container just inside each element's centroid: the wall pressure's
     interpolation weights add up to it where the liquid covers the element */
  for (PetscInt d = 0; d < 3; d++) {
    tm->corelo[d] = lo ? lo[d] + (b->radius + m->elradius) : -PETSC_MAX_REAL;
    tm->corehi[d] = lo ? hi[d] - (b->radius + m->elradius) : PETSC_MAX_REAL;
  }
  /* the Shepard factors of the core's elements (those this rank's particles can reach and those it owns: the others'
     are never read, and are left NaN), kept from the core before where they were computed */
  PetscCall(PetscMalloc1(m->nel + 1, &tm->wetfull));
  for (PetscInt k = 0; k < m->nel; k++) {
    const PetscReal *el = &m->el[k * FS_TRI_STRIDE], *c = el + FS_TRI_CENTROID;
    PetscReal        x[3];
    PetscBool        core = PETSC_TRUE, before = had;
    for (PetscInt d = 0; d < 3; d++) {
      core   = (PetscBool)(core && c[d] >= tm->corelo[d] && c[d] <= tm->corehi[d]);
      before = (PetscBool)(before && c[d] >= oldlo[d] && c[d] <= oldhi[d]);
    }
    while (before && q < nold && oldgid[q] < m->elgid[k]) q++;
    if (!core) tm->wetfull[k] = (PetscReal)NAN;
    else if (before && q < nold && oldgid[q] == m->elgid[k]) {
      tm->wetfull[k] = oldwet[q];
      kept++;
    } else {
      for (PetscInt d = 0; d < 3; d++) x[d] = c[d] - 1e-3 * b->h * el[FS_TRI_NORMAL + d];
      tm->wetfull[k] = ShepardNear(tm, b->h, x, PETSC_FALSE);
      made++;
    }
  }
  PetscCall(PetscInfo(
      b, "%" PetscInt_FMT " wall elements held, Shepard factors: %" PetscInt_FMT " kept, %" PetscInt_FMT " made\n",
      m->nel, kept, made));
  PetscCall(PetscFree(oldgid));
  PetscCall(PetscFree(oldwet));
  /* what held element numbers is made again: the wall pressure at the next right-hand side, the candidate lists
     at the next update */
  PetscCall(PetscFree(tm->wp));
  PetscCall(PetscFree2(tm->cstart, b->wstart));
  tm->scap = 0;
  PetscFunctionReturn(0);
}

/*
   SetUp - checks the mesh, refines it into elements, bins the elements in a static grid and computes
   the container's Shepard factor at each. With -fs_walls_distribute on more than one rank no element is kept
   until FSBoundarySetPartition tells this rank its part (Partition).
*/
static PetscErrorCode SetUp(FSBoundary b)
{
  FSBoundary_Trimesh *tm   = (FSBoundary_Trimesh *)b->data;
  FSMesh             *m    = &tm->mesh;
  MPI_Comm            comm = PetscObjectComm((PetscObject)b);
  PetscMPIInt         size;

  PetscFunctionBegin;
  PetscCheck(b->dim == 3, comm, PETSC_ERR_SUP,
             "Triangle-mesh walls (STL tanks, 3-D built-in tanks) are three-dimensional: use -fs_dim 3");
  PetscCall(FSMeshCheck(m, comm));
  PetscCallMPI(MPI_Comm_size(comm, &size));
  PetscCall(PetscMalloc1(m->nwalls, &tm->names));
  for (PetscInt q = 0; q < m->nwalls; q++) tm->names[q] = m->name[q];
  b->nwalls        = m->nwalls;
  b->wallname      = tm->names;
  b->view.stride   = FS_TRI_STRIDE;
  b->view.vertex   = FS_TRI_P0;
  b->view.centroid = FS_TRI_CENTROID;
  b->view.normal   = FS_TRI_NORMAL;
  b->view.measure  = FS_TRI_AREA;
  tm->distribute   = (PetscBool)(tm->distribute && size > 1);
  if (tm->distribute) { /* an empty box: the count and size of the elements, none kept until the partition */
    const PetscReal none[3] = {PETSC_MAX_REAL, PETSC_MAX_REAL, PETSC_MAX_REAL},
                    nohi[3] = {-PETSC_MAX_REAL, -PETSC_MAX_REAL, -PETSC_MAX_REAL};
    PetscCall(BuildElements(b, none, nohi));
    tm->local    = PETSC_FALSE;
    tm->deferred = PETSC_TRUE;
  } else PetscCall(BuildElements(b, NULL, NULL));
  b->nelglobal  = m->nelglobal;
  b->elradius   = m->elradius;
  tm->occlusion = (PetscBool)!MeshConvex(m);
  PetscCall(PetscMalloc2(m->ntri, &tm->tmark, m->ntri, &tm->tlist));
  for (PetscInt t = 0; t < m->ntri; t++) tm->tmark[t] = -1;
  PetscFunctionReturn(0);
}

/* a boundary used before (or without) a partition: every element, as without -fs_walls_distribute */
static PetscErrorCode EnsureElements(FSBoundary b)
{
  FSBoundary_Trimesh *tm = (FSBoundary_Trimesh *)b->data;

  PetscFunctionBegin;
  if (tm->deferred) PetscCall(BuildElements(b, NULL, NULL));
  tm->deferred = PETSC_FALSE;
  PetscFunctionReturn(0);
}

/*
   Partition - with -fs_walls_distribute, this rank's elements: those whose bounding sphere comes within twice the
   candidate radius plus twice the largest element of its part lo..hi (the elements its particles can reach, and
   those within the support of these, for their Shepard factor), numbered as in the whole refinement (b->elgid)
*/
static PetscErrorCode Partition(FSBoundary b, const PetscReal lo[], const PetscReal hi[], const PetscBool periodic[])
{
  FSBoundary_Trimesh *tm   = (FSBoundary_Trimesh *)b->data;
  const FSMesh       *m    = &tm->mesh;
  const PetscReal     grow = 2 * (b->radius + m->elradius);
  PetscReal           blo[3], bhi[3];

  PetscFunctionBegin;
  if (!tm->distribute) PetscFunctionReturn(0);
  for (PetscInt d = 0; d < 3; d++) {
    blo[d] = periodic[d] ? -PETSC_MAX_REAL : lo[d] - grow;
    bhi[d] = periodic[d] ? PETSC_MAX_REAL : hi[d] + grow;
  }
  PetscCall(BuildElements(b, blo, bhi));
  tm->deferred = PETSC_FALSE;
  b->elgid     = m->elgid;
  PetscFunctionReturn(0);
}

/* does the open segment p-q cross input triangle t? */
static inline PetscBool CrossesTriangle(const FSMesh *m, PetscInt t, const PetscReal p[], const PetscReal q[])
{
  return FSTriangleCrossesSegment(&m->vert[3 * m->tri[3 * t]], &m->vert[3 * m->tri[3 * t + 1]],
                                  &m->vert[3 * m->tri[3 * t + 2]], p, q);
}

/* how near element el is to x: 0 beyond R, 1 within R, 2 within Rk <= R too. The bounding sphere decides, unless
   it straddles a radius */
static inline PetscInt Nearness(const PetscReal el[], const PetscReal x[], PetscReal R, PetscReal Rk)
{
  const PetscReal *c = el + FS_TRI_CENTROID, rad = el[FS_TRI_RADIUS];
  const PetscReal  dc = PetscSqrtReal((c[0] - x[0]) * (c[0] - x[0]) + (c[1] - x[1]) * (c[1] - x[1]) +
                                      (c[2] - x[2]) * (c[2] - x[2]));
  PetscReal        d2 = -1;
  if (dc - rad >= R) return 0;
  if (dc + rad >= R) {
    d2 = FSTriangleDistance2(el + FS_TRI_P0, el + FS_TRI_P1, el + FS_TRI_P2, x);
    if (!(d2 < R * R)) return 0;
  }
  if (dc - rad >= Rk) return 1;
  if (dc + rad < Rk) return 2;
  if (d2 < 0) d2 = FSTriangleDistance2(el + FS_TRI_P0, el + FS_TRI_P1, el + FS_TRI_P2, x);
  return d2 < Rk * Rk ? 2 : 1;
}

/* a candidate entry's element: during Update an element within the candidate radius but out of reach is listed as
   -1 - k until the particle's entries are compacted */
static inline PetscInt CandElement(PetscInt c) { return c < 0 ? -1 - c : c; }

/*
   the kept candidates of a particle, c[first..end-1], as runs: consecutive elements k0, k0 + 1, ..., k0 + L - 1
   (L >= 2) as the pair -1 - k0, L, a lone element as itself (in place: never longer than the list). The
   refinement numbers neighbouring elements closely (6 elements a run in the 3-D dam break); the order is kept.
   Returns the end of the runs.
*/
static PetscInt EncodeRuns(PetscInt c[], PetscInt first, PetscInt end)
{
  PetscInt w = first;
  for (PetscInt q = first, L; q < end; q += L) {
    const PetscInt k0 = c[q];
    for (L = 1; q + L < end && c[q + L] == k0 + L;) L++;
    if (L == 1) c[w++] = k0;
    else {
      c[w++] = -1 - k0;
      c[w++] = L;
    }
  }
  return w;
}

/* the run at c[*q] (EncodeRuns): elements k0..k1-1; *q moves past it */
static inline void DecodeRun(const PetscInt c[], PetscInt *q, PetscInt *k0, PetscInt *k1)
{
  if (c[*q] < 0) {
    *k0 = -1 - c[*q];
    *k1 = *k0 + c[*q + 1];
    *q += 2;
  } else {
    *k0 = c[*q];
    *k1 = *k0 + 1;
    *q += 1;
  }
}

/*
   Leaked - is x outside the liquid region? Only asked of particles with candidate elements. When every
   element nearest to x (ties included: an edge or corner shared by several) has x on its liquid side,
   x is inside; otherwise the winding number of the mesh decides (exact, but a sum over all triangles).
*/
static PetscBool Leaked(const FSBoundary_Trimesh *tm, const PetscReal x[], PetscInt first, PetscInt nc,
                        PetscInt *nearest)
{
  const FSMesh *m    = &tm->mesh;
  PetscReal     best = PETSC_MAX_REAL;
  PetscBool     side = PETSC_TRUE;

  /* on the liquid side of every nearby element's plane: inside (the common case, without distances) */
  for (PetscInt q = first; q < nc && side; q++) {
    const PetscReal *el = &m->el[CandElement(tm->cand[q]) * FS_TRI_STRIDE], *n = el + FS_TRI_NORMAL;
    side = (PetscBool)((el[0] - x[0]) * n[0] + (el[1] - x[1]) * n[1] + (el[2] - x[2]) * n[2] > 0);
  }
  if (side) return PETSC_FALSE;
  /* the nearest elements, ties (within a relative 1e-9) kept together, in one pass */
  for (PetscInt q = first; q < nc; q++) {
    const PetscReal *el = &m->el[CandElement(tm->cand[q]) * FS_TRI_STRIDE], *n = el + FS_TRI_NORMAL;
    const PetscReal  d2     = FSTriangleDistance2(el + FS_TRI_P0, el + FS_TRI_P1, el + FS_TRI_P2, x);
    const PetscBool  facing = (PetscBool)((el[0] - x[0]) * n[0] + (el[1] - x[1]) * n[1] + (el[2] - x[2]) * n[2] > 0);
    if (d2 > best * (1 + 1e-9) + 1e-30) continue;      /* farther than the nearest so far */
    if (d2 < best * (1 - 1e-9) - 1e-30) side = facing; /* a new nearest: the earlier ones were farther */
    else side = (PetscBool)(side && facing);           /* a tie: an edge or a corner shared by elements */
    if (d2 < best) {
      best     = d2;
      *nearest = CandElement(tm->cand[q]);
    }
  }
  return side ? PETSC_FALSE : (PetscBool)!FSMeshInLiquid(m, x, 0);
}

/*
   Update - once per step, after the candidate fluid neighbours are built: the candidate elements of
   every owned particle, the leak check, and, where the liquid region is not convex, the removal of
   fluid candidate pairs whose connecting segment crosses a wall and of the elements hidden from the
   particle behind other walls (both tested against the mesh's input triangles near the particle).
   The leak check and the cuts see every element within the candidate radius; a particle keeps those
   within reach (b->reach) that it can face before the lists are rebuilt.
*/
static PetscErrorCode Update(FSBoundary b, PetscInt n, const PetscReal rec[], PetscInt S, FSNeighbours *nb,
                             FSBoundaryLeak *lk)
{
  FSBoundary_Trimesh *tm = (FSBoundary_Trimesh *)b->data;
  const FSMesh       *m  = &tm->mesh;
  const PetscReal     R = b->radius, Rk = b->reach, slack = b->reach - 2 * b->h;
  const PetscBool     cut = (PetscBool)(tm->occlusion && !b->visall);
  PetscInt            nc = 0, leak = -1, leakel = -1;

  PetscFunctionBegin;
  PetscCall(EnsureElements(b));
  if (n + 1 > tm->scap) {
    PetscCall(PetscFree2(tm->cstart, b->wstart));
    tm->scap = PetscMax(n + 1, (PetscInt)(1.25 * tm->scap));
    PetscCall(PetscMalloc2(tm->scap, &tm->cstart, tm->scap, &b->wstart));
  }
  for (PetscInt t = 0; t < m->ntri; t++) tm->tmark[t] = -1;
  for (PetscInt i = 0; i < n; i++) {
    const PetscReal *x = &rec[i * S];
    PetscInt         cc[3], first = nc, nt = 0;
    tm->cstart[i] = nc;
    GridCell(tm, x, cc);
    FOR_GRID_NEIGHBOURS(tm, cc, q)
    {
      const PetscInt   k  = tm->gel[q];
      const PetscReal *el = &m->el[k * FS_TRI_STRIDE], *nn = el + FS_TRI_NORMAL;
      const PetscInt   near = Nearness(el, x, R, Rk);
      if (near) {
        const PetscReal d = (el[0] - x[0]) * nn[0] + (el[1] - x[1]) * nn[1] + (el[2] - x[2]) * nn[2]; /* > 0: facing */
        /* kept: within reach and, unless visibility all, not so far behind its plane that x cannot face it before
           the rebuild (FSTriangleIntegrals gives such an element 0) */
        const PetscBool keep = (PetscBool)(near == 2 && (b->visall || d > -slack));
        PetscCall(FSBoundaryListRoom_Private(sizeof(PetscInt), nc, &tm->ccap, &tm->cand));
        tm->cand[nc++] = keep ? k : -1 - k;
        if (cut && tm->tmark[m->eltri[k]] != i) { /* the input triangles near the particle */
          tm->tmark[m->eltri[k]] = i;
          tm->tlist[nt++]        = m->eltri[k];
        }
      }
    }
    if (nc > first && leak < 0) {
      PetscInt nearest = -1;
      if (Leaked(tm, x, first, nc, &nearest)) {
        leak   = i;
        leakel = nearest;
      }
    }
    if (nt) {
      /* drop the fluid candidates seen through a wall */
      FSCandidateIter it;
      PetscInt        j;
      FSNeighboursCandidateBegin(nb, i, &it);
      while (FSNeighboursCandidateNext(nb, &it, &j)) {
        const PetscReal *xj  = &rec[j * S];
        PetscBool        hit = PETSC_FALSE;
        for (PetscInt r = 0; r < nt && !hit; r++) hit = CrossesTriangle(m, tm->tlist[r], x, xj);
        if (hit) FSNeighboursCandidateDrop(nb, &it);
      }
    }
    /* keep the elements within reach, less (with cuts) the facing ones whose centroid is seen through another wall */
    {
      PetscInt keep = first;
      for (PetscInt q = first; q < nc; q++) {
        const PetscInt   k  = tm->cand[q];
        const PetscReal *el = &m->el[CandElement(k) * FS_TRI_STRIDE], *nn = el + FS_TRI_NORMAL;
        PetscBool        hidden = PETSC_FALSE;
        if (k < 0) continue;
        if (nt && (el[0] - x[0]) * nn[0] + (el[1] - x[1]) * nn[1] + (el[2] - x[2]) * nn[2] > 0)
          for (PetscInt r = 0; r < nt && !hidden; r++)
            hidden = (PetscBool)(tm->tlist[r] != m->eltri[k] &&
                                 CrossesTriangle(m, tm->tlist[r], x, el + FS_TRI_CENTROID));
        if (!hidden) tm->cand[keep++] = k;
      }
      nc = EncodeRuns(tm->cand, first, keep);
    }
  }
  tm->cstart[n] = nc;
  PetscCall(FSBoundaryListFit_Private(sizeof(PetscInt), nc, &tm->ccap, &tm->cand));
  lk->particle = leak;
  lk->wall     = leakel >= 0 ? m->elwall[leakel] : -1;
  lk->element  = leakel >= 0 ? m->trisrc[m->eltri[leakel]] : -1;
  PetscFunctionReturn(0);
}

/*
   Prepare - at every right-hand side: gamma_i of every owned particle near a wall (1 elsewhere) and its
   facing elements within the support with their mean kernel values (int_k W dS / A_k); with
   -fs_walls_visibility all every element within the support. Then this rank's sums of the wall pressure,
   sent on their way, as for polygons (polygon.c).
*/
static PetscErrorCode Prepare(FSBoundary b, const FSBoundaryParticles *P, PetscReal gamma[], PetscReal noslip[])
{
  FSBoundary_Trimesh *tm = (FSBoundary_Trimesh *)b->data;
  const FSMesh       *m  = &tm->mesh;
  const PetscInt      S = P->stride, n = P->nowned, nel = m->nel;
  PetscInt            nw = 0;

  PetscFunctionBegin;
  for (PetscInt i = 0; i < n; i++) {
    FSCommProgress(i); /* the ghosts' records travel meanwhile (FSSolverEvaluateRates) */
    const PetscReal *x = &P->rec[i * S];
    PetscReal        g = 1, gn = 0;
    b->wstart[i] = nw;
    for (PetscInt q = tm->cstart[i], k0, k1; q < tm->cstart[i + 1];) {
      DecodeRun(tm->cand, &q, &k0, &k1);
      for (PetscInt k = k0; k < k1; k++) {
        const PetscReal *el = &m->el[k * FS_TRI_STRIDE];
        PetscReal        gk, wi;
        FSTriangleIntegrals(b->h, x, el, b->visall, &gk, &wi);
        g += gk;
        if (b->noslip[b->view.elementwall[k]] && gk < 0) gn -= gk; /* the shadows the no-slip term fills */
        if (wi > 0) {
          PetscCall(FSBoundaryWallListsRoom_Private(b, nw));
          b->wk[nw] = k;
          b->wW[nw] = wi / el[FS_TRI_AREA];
          nw++;
        }
      }
    }
    gamma[i] = g;
    if (noslip) noslip[i] = gn;
  }
  b->wstart[n] = nw;
  PetscCall(FSBoundaryWallListsFit_Private(b, nw));
  /* the wall pressure: the Shepard interpolation of the liquid's pressure with the hydrostatic
     correction, and its wetted share below the ambient pressure, as for polygons (polygon.c) */
  if (!tm->wp) PetscCall(PetscMalloc1(3 * nel + 1, &tm->wp));
  PetscCall(PetscArrayzero(tm->wp, 3 * nel));
  {
    PetscReal *num = tm->wp + nel, *den = num + nel;
    for (PetscInt i = 0; i < n; i++) {
      FSCommProgress(i);
      const PetscReal *x = &P->rec[i * S], rho = x[2 * P->dim];
      for (PetscInt q = b->wstart[i]; q < b->wstart[i + 1]; q++) {
        const PetscInt   k  = b->wk[q];
        const PetscReal *el = &m->el[k * FS_TRI_STRIDE], *c = el + FS_TRI_CENTROID, *nn = el + FS_TRI_NORMAL;
        const PetscReal  wv     = b->wW[q] * P->vol[i];
        const PetscReal  mid[3] = {0.5 * (c[0] + x[0]), 0.5 * (c[1] + x[1]), 0.5 * (c[2] + x[2])};
        PetscReal        g[3];
        if (b->visall && (el[0] - x[0]) * nn[0] + (el[1] - x[1]) * nn[1] + (el[2] - x[2]) * nn[2] <= 0) continue;
        FSFrameFieldEval3(P->body, mid, g);
        num[k] += (P->pressure[i] + rho * (g[0] * (c[0] - x[0]) + g[1] * (c[1] - x[1]) + g[2] * (c[2] - x[2]))) * wv;
        den[k] += wv;
      }
    }
    PetscCall(FSBoundaryWallPressureBegin(b, nel, tm->wetfull, P->background_pressure, tm->wp));
  }
  PetscFunctionReturn(0);
}

/*
   Bounce - a particle closer to an element's plane than -fs_walls_bounce_distance (in dx), over the
   element, and moving towards it is put back at that distance with its normal velocity reversed,
   scaled by -fs_walls_bounce_restitution (as for polygons).
*/
static PetscErrorCode Bounce(FSBoundary b, PetscInt n, PetscReal x[], PetscReal v[], const PetscReal m[],
                             FSParticleEnergyFn energy, void *ctx, PetscReal de[2])
{
  FSBoundary_Trimesh *tm   = (FSBoundary_Trimesh *)b->data;
  const FSMesh       *ms   = &tm->mesh;
  const PetscReal     dmin = b->bounce_distance * b->dx;

  PetscFunctionBegin;
  PetscCall(EnsureElements(b));
  for (PetscInt i = 0; i < n; i++) {
    PetscReal *xi = &x[3 * i], *vi = &v[3 * i];
    PetscInt   cc[3];
    PetscBool  outside = PETSC_FALSE;
    for (PetscInt d = 0; d < 3; d++)
      if (xi[d] < tm->glo[d] || xi[d] >= tm->glo[d] + tm->gnc[d] * tm->gcell) outside = PETSC_TRUE;
    if (outside) continue;
    GridCell(tm, xi, cc);
    FOR_GRID_NEIGHBOURS(tm, cc, q)
    {
      const PetscReal *el = &ms->el[tm->gel[q] * FS_TRI_STRIDE], *a = el + FS_TRI_P0, *nn = el + FS_TRI_NORMAL;
      const PetscReal  dist = (a[0] - xi[0]) * nn[0] + (a[1] - xi[1]) * nn[1] + (a[2] - xi[2]) * nn[2];
      const PetscReal  un   = vi[0] * nn[0] + vi[1] * nn[1] + vi[2] * nn[2];
      if (dist < dmin && dist > -dmin && un > 0) {
        /* over the element: the barycentric coordinates of the projection */
        const PetscReal e1[3] = {el[FS_TRI_P1] - a[0], el[FS_TRI_P1 + 1] - a[1], el[FS_TRI_P1 + 2] - a[2]};
        const PetscReal e2[3] = {el[FS_TRI_P2] - a[0], el[FS_TRI_P2 + 1] - a[1], el[FS_TRI_P2 + 2] - a[2]};
        const PetscReal p[3]  = {xi[0] - a[0], xi[1] - a[1], xi[2] - a[2]};
        const PetscReal d11   = e1[0] * e1[0] + e1[1] * e1[1] + e1[2] * e1[2];
        const PetscReal d12   = e1[0] * e2[0] + e1[1] * e2[1] + e1[2] * e2[2];
        const PetscReal d22   = e2[0] * e2[0] + e2[1] * e2[1] + e2[2] * e2[2];
        const PetscReal p1    = p[0] * e1[0] + p[1] * e1[1] + p[2] * e1[2],
                        p2    = p[0] * e2[0] + p[1] * e2[1] + p[2] * e2[2];
        const PetscReal det = d11 * d22 - d12 * d12, s = (d22 * p1 - d12 * p2) / det, t = (d11 * p2 - d12 * p1) / det;
        if (s < -1e-12 || t < -1e-12 || s + t > 1 + 1e-12) continue;
        FSBoundaryBounceParticle(b, nn, dist, un, xi, vi, m[i], energy, ctx, de);
      }
    }
  }
  PetscFunctionReturn(0);
}

/* gamma at a point (FSBoundaryShepardAt) from the elements in the static grid's cells around it; with only this rank's
   elements, from every element of the full view (FSBoundaryGetFullView), which must be out */
static PetscErrorCode ShepardAt(FSBoundary b, const PetscReal x[], PetscReal *gamma)
{
  FSBoundary_Trimesh *tm = (FSBoundary_Trimesh *)b->data;
  PetscReal           grad[3];

  PetscFunctionBegin;
  PetscCall(EnsureElements(b));
  if (!tm->local) *gamma = ShepardNear(tm, b->h, x, b->visall);
  else {
    PetscCheck(tm->full.el, PetscObjectComm((PetscObject)b), PETSC_ERR_ARG_WRONGSTATE,
               "FSBoundaryShepardAt with -fs_walls_distribute: only between FSBoundaryGetFullView and "
               "FSBoundaryRestoreFullView");
    PetscCall(FSMeshShepard(&tm->full, b->h, x, b->visall, gamma, grad));
  }
  PetscFunctionReturn(0);
}

/* FullView - every element (the whole refinement) into tm->full and b->full, or freed */
static PetscErrorCode FullView(FSBoundary b, PetscBool get)
{
  FSBoundary_Trimesh *tm = (FSBoundary_Trimesh *)b->data;
  FSMesh             *f  = &tm->full;

  PetscFunctionBegin;
  PetscCall(PetscFree(f->el));
  PetscCall(PetscFree(f->elwall));
  PetscCall(PetscFree(f->eltri));
  PetscCall(PetscFree(f->elgid));
  PetscCall(PetscMemzero(f, sizeof(*f)));
  if (!get) PetscFunctionReturn(0);
  *f        = tm->mesh; /* the input triangles shared, the elements its own */
  f->el     = NULL;
  f->elwall = NULL;
  f->eltri  = NULL;
  f->elgid  = NULL;
  f->nel    = 0;
  PetscCall(FSMeshRefineRegion(f, tm->element * b->h, NULL, NULL));
  b->full.nelements   = f->nel;
  b->full.element     = f->el;
  b->full.elementwall = f->elwall;
  PetscFunctionReturn(0);
}

/* Locate - in the liquid region (the winding number of the input triangles), the nearest input triangle's wall */
static PetscErrorCode Locate(FSBoundary b, const PetscReal x[], PetscBool *inliquid, PetscInt *wall,
                             PetscReal *distance)
{
  const FSMesh *m    = &((FSBoundary_Trimesh *)b->data)->mesh;
  PetscReal     best = PETSC_MAX_REAL;

  PetscFunctionBegin;
  *inliquid = FSMeshInLiquid(m, x, 0);
  for (PetscInt t = 0; t < m->ntri; t++) {
    const PetscReal d2 = FSTriangleDistance2(&m->vert[3 * m->tri[3 * t]], &m->vert[3 * m->tri[3 * t + 1]],
                                             &m->vert[3 * m->tri[3 * t + 2]], x);
    if (d2 < best) {
      best  = d2;
      *wall = m->triwall[t];
    }
  }
  *distance = PetscSqrtReal(best);
  PetscFunctionReturn(0);
}

static PetscErrorCode BoundingBox(FSBoundary b, PetscReal lo[], PetscReal hi[])
{
  FSBoundary_Trimesh *tm = (FSBoundary_Trimesh *)b->data;

  PetscFunctionBegin;
  for (PetscInt d = 0; d < 3; d++) {
    lo[d] = tm->mesh.lo[d];
    hi[d] = tm->mesh.hi[d];
  }
  PetscFunctionReturn(0);
}

/* Hash - the triangles as given: the vertices, the triangles and their walls */
static PetscErrorCode Hash(FSBoundary b, uint64_t *h)
{
  FSMesh *m = &((FSBoundary_Trimesh *)b->data)->mesh;

  PetscFunctionBegin;
  FSBoundaryHashAdd_Private(h, &m->nvert, sizeof(m->nvert));
  FSBoundaryHashAdd_Private(h, m->vert, (size_t)(3 * m->nvert) * sizeof(PetscReal));
  FSBoundaryHashAdd_Private(h, &m->ntri, sizeof(m->ntri));
  FSBoundaryHashAdd_Private(h, m->tri, (size_t)(3 * m->ntri) * sizeof(PetscInt));
  FSBoundaryHashAdd_Private(h, m->triwall, (size_t)m->ntri * sizeof(PetscInt));
  PetscFunctionReturn(0);
}

static PetscErrorCode View(FSBoundary b, PetscViewer viewer)
{
  FSBoundary_Trimesh *tm = (FSBoundary_Trimesh *)b->data;

  PetscFunctionBegin;
  PetscCall(PetscViewerASCIIPrintf(
      viewer,
      "%" PetscInt_FMT " triangles, %" PetscInt_FMT " elements of edge <= %g h, liquid volume %g, visibility %s%s\n",
      tm->mesh.ntri, tm->mesh.nelglobal, (double)tm->element, (double)tm->mesh.volume, b->visall ? "all" : "cut",
      tm->distribute ? ", each rank holding those near its part" : ""));
  PetscFunctionReturn(0);
}

static PetscErrorCode Memory(FSBoundary b, PetscInt64 *lists, PetscInt64 *elements)
{
  FSBoundary_Trimesh *tm  = (FSBoundary_Trimesh *)b->data;
  const PetscInt64    nel = tm->mesh.nel;

  PetscFunctionBegin;
  /* cstart and wstart (scap each), the candidate elements (ccap), the wall lists' k and W (b->wcap) */
  *lists = (PetscInt64)tm->scap * 2 * sizeof(PetscInt) + (PetscInt64)tm->ccap * sizeof(PetscInt) +
           (PetscInt64)b->wcap * (sizeof(PetscInt) + sizeof(PetscReal));
  /* the elements (FS_TRI_STRIDE reals, wall, triangle and number), wetfull and wp (3 nel + 1), the grid, the marks
     of the input triangles (tmark, tlist) */
  *elements = nel * (FS_TRI_STRIDE * sizeof(PetscReal) + 3 * sizeof(PetscInt) + 4 * sizeof(PetscReal)) +
              (PetscInt64)(tm->gnc[0] * tm->gnc[1] * tm->gnc[2] + 1 + nel + 2 * tm->mesh.ntri) * sizeof(PetscInt);
  PetscFunctionReturn(0);
}

/* a candidate element's cost in a right-hand side (its integrals for gamma, and for the facing ones within
   the support the wall list entry, the wall pressure's sums and the wall terms), in fluid candidate pairs:
   measured on the 3-D dam break (docs/performance.md, "Balancing the work") */
#define FS_TRIMESH_ELEMENT_COST 3.8

static PetscErrorCode Work(FSBoundary b, PetscInt n, PetscInt64 work[])
{
  FSBoundary_Trimesh *tm = (FSBoundary_Trimesh *)b->data;

  PetscFunctionBegin;
  if (!tm->cstart) PetscFunctionReturn(0);
  for (PetscInt i = 0; i < n; i++) {
    PetscInt ne = 0;
    for (PetscInt q = tm->cstart[i], k0, k1; q < tm->cstart[i + 1];) {
      DecodeRun(tm->cand, &q, &k0, &k1);
      ne += k1 - k0;
    }
    work[i] += (PetscInt64)(FS_TRIMESH_ELEMENT_COST * ne + 0.5);
  }
  PetscFunctionReturn(0);
}

static PetscErrorCode Destroy(FSBoundary b)
{
  FSBoundary_Trimesh *tm = (FSBoundary_Trimesh *)b->data;

  PetscFunctionBegin;
  PetscCall(FullView(b, PETSC_FALSE));
  PetscCall(FSMeshDestroy(&tm->mesh));
  PetscCall(PetscFree(tm->names));
  PetscCall(PetscFree(tm->gstart));
  PetscCall(PetscFree(tm->gel));
  PetscCall(PetscFree2(tm->cstart, b->wstart));
  PetscCall(PetscFree(tm->cand));
  PetscCall(PetscFree2(tm->tmark, tm->tlist));
  PetscCall(PetscFree(b->wk));
  PetscCall(PetscFree(b->wW));
  PetscCall(PetscFree(tm->wp));
  PetscCall(PetscFree(tm->wetfull));
  PetscCall(PetscFree(b->data));
  b->wallname = NULL;
  b->nwalls   = 0;
  PetscCall(PetscObjectComposeFunction((PetscObject)b, "FSBoundaryTrimeshSetMesh_C", NULL));
  PetscFunctionReturn(0);
}

PETSC_INTERN PetscErrorCode FSBoundaryDraw_Trimesh(FSBoundary, FSImage *, const FSImageMap *);
PETSC_INTERN PetscErrorCode FSBoundaryWriteGeometry_Trimesh(FSBoundary, const char[]);

/*
   FSBoundaryCreate_Trimesh - the triangle-mesh boundary: 3-D boundary integrals on closed triangle
   meshes (mesh.h for the orientation convention), given by the case with FSBoundaryTrimeshSetMesh().
*/
PetscErrorCode FSBoundaryCreate_Trimesh(FSBoundary b)
{
  FSBoundary_Trimesh *tm;

  PetscFunctionBegin;
  PetscCall(PetscNew(&tm));
  PetscCall(FSMeshCreate(&tm->mesh));
  tm->element            = 1.0;
  tm->distribute         = PETSC_TRUE;
  b->data                = tm;
  b->ops->setfromoptions = SetFromOptions;
  b->ops->setup          = SetUp;
  b->ops->partition      = Partition;
  b->ops->fullview       = FullView;
  b->ops->update         = Update;
  b->ops->prepare        = Prepare;
  b->ops->bounce         = Bounce;
  b->ops->boundingbox    = BoundingBox;
  b->ops->shepard        = ShepardAt;
  b->ops->locate         = Locate;
  b->ops->draw           = FSBoundaryDraw_Trimesh;
  b->ops->writegeometry  = FSBoundaryWriteGeometry_Trimesh;
  b->ops->view           = View;
  b->ops->hash           = Hash;
  b->ops->destroy        = Destroy;
  b->ops->memory         = Memory;
  b->ops->work           = Work;
  PetscCall(PetscObjectComposeFunction((PetscObject)b, "FSBoundaryTrimeshSetMesh_C", FSBoundaryTrimeshSetMesh_Trimesh));
  PetscFunctionReturn(0);
}
