/*
   Triangle meshes of the 3-D walls: the growable arrays, the extruded built-in tanks, the checks
   (degenerate triangles, watertight and consistently oriented, no intersections, the container and
   its obstacles), the refinement into elements, and the geometry of one triangle (distance, solid
   angle, segment crossing). The STL reader is in stl.c.
*/
#include "mesh.h"

/*
   FSMeshCreate - an empty mesh: no vertices, triangles, walls or elements.

   Not collective

   Output Parameter:
.  m - the mesh

.seealso: FSMeshDestroy(), FSMeshExtrude(), FSMeshLoadSTL()
*/
PetscErrorCode FSMeshCreate(FSMesh *m)
{
  PetscFunctionBegin;
  PetscCall(PetscMemzero(m, sizeof(*m)));
  PetscFunctionReturn(0);
}

/*
   FSMeshDestroy - frees the arrays of a mesh and zeroes it (it may be created again).

   Not collective

.seealso: FSMeshCreate()
*/
PetscErrorCode FSMeshDestroy(FSMesh *m)
{
  PetscFunctionBegin;
  PetscCall(PetscFree(m->vert));
  PetscCall(PetscFree(m->tri));
  PetscCall(PetscFree(m->triwall));
  PetscCall(PetscFree(m->trisrc));
  PetscCall(PetscFree(m->name));
  PetscCall(PetscFree(m->source));
  PetscCall(PetscFree(m->el));
  PetscCall(PetscFree(m->elwall));
  PetscCall(PetscFree(m->eltri));
  PetscCall(PetscMemzero(m, sizeof(*m)));
  PetscFunctionReturn(0);
}

/*
   FSMeshAddWall - the index of the wall part named name, added (with the source it comes from, for
   error messages) if the mesh has none of that name yet.

   Not collective

   Input Parameters:
+  m      - the mesh
.  name   - the wall's name (at most 63 characters kept)
-  source - the file or builder its triangles come from

   Output Parameter:
.  wall - the wall's index

   Note: a wall that exists keeps its first source.
*/
PetscErrorCode FSMeshAddWall(FSMesh *m, const char name[], const char source[], PetscInt *wall)
{
  char(*names)[64];
  char(*sources)[PETSC_MAX_PATH_LEN];

  PetscFunctionBegin;
  for (PetscInt k = 0; k < m->nwalls; k++)
    if (!strncmp(m->name[k], name, sizeof(m->name[k]) - 1)) {
      *wall = k;
      PetscFunctionReturn(0);
    }
  PetscCall(PetscMalloc1(m->nwalls + 1, &names));
  PetscCall(PetscMalloc1(m->nwalls + 1, &sources));
  if (m->nwalls) {
    PetscCall(PetscArraycpy(names, m->name, m->nwalls));
    PetscCall(PetscArraycpy(sources, m->source, m->nwalls));
  }
  PetscCall(PetscStrncpy(names[m->nwalls], name, sizeof(names[0])));
  PetscCall(PetscStrncpy(sources[m->nwalls], source ? source : "", sizeof(sources[0])));
  PetscCall(PetscFree(m->name));
  PetscCall(PetscFree(m->source));
  m->name   = names;
  m->source = sources;
  *wall     = m->nwalls++;
  PetscFunctionReturn(0);
}

/*
   FSMeshAddVertex - appends the vertex x (no search for an equal one: the builders share vertices
   themselves).

   Not collective

   Output Parameter:
.  v - the vertex's index
*/
PetscErrorCode FSMeshAddVertex(FSMesh *m, const PetscReal x[3], PetscInt *v)
{
  PetscFunctionBegin;
  if (m->nvert == m->vcap) {
    PetscReal *vert;
    m->vcap = PetscMax(64, 2 * m->vcap);
    PetscCall(PetscMalloc1(3 * m->vcap, &vert));
    if (m->nvert) PetscCall(PetscArraycpy(vert, m->vert, 3 * m->nvert));
    PetscCall(PetscFree(m->vert));
    m->vert = vert;
  }
  for (PetscInt d = 0; d < 3; d++) m->vert[3 * m->nvert + d] = x[d];
  *v = m->nvert++;
  PetscFunctionReturn(0);
}

/*
   FSMeshAddTriangle - appends the triangle (a, b, c) (vertex indices; its normal (b - a) x (c - a)
   points out of the liquid) to the wall part wall; src is its number in its source (0-based), for
   error messages.

   Not collective
*/
PetscErrorCode FSMeshAddTriangle(FSMesh *m, PetscInt wall, PetscInt a, PetscInt b, PetscInt c, PetscInt src)
{
  PetscFunctionBegin;
  PetscCheck(a >= 0 && a < m->nvert && b >= 0 && b < m->nvert && c >= 0 && c < m->nvert, PETSC_COMM_SELF,
             PETSC_ERR_ARG_OUTOFRANGE,
             "Triangle (%" PetscInt_FMT ", %" PetscInt_FMT ", %" PetscInt_FMT
             ") refers to a vertex that does not exist (%" PetscInt_FMT " vertices)",
             a, b, c, m->nvert);
  PetscCheck(wall >= 0 && wall < m->nwalls, PETSC_COMM_SELF, PETSC_ERR_ARG_OUTOFRANGE,
             "Wall %" PetscInt_FMT " does not exist (%" PetscInt_FMT " walls)", wall, m->nwalls);
  if (m->ntri == m->tcap) {
    PetscInt *tri, *triwall, *trisrc;
    m->tcap = PetscMax(64, 2 * m->tcap);
    PetscCall(PetscMalloc1(3 * m->tcap, &tri));
    PetscCall(PetscMalloc1(m->tcap, &triwall));
    PetscCall(PetscMalloc1(m->tcap, &trisrc));
    if (m->ntri) {
      PetscCall(PetscArraycpy(tri, m->tri, 3 * m->ntri));
      PetscCall(PetscArraycpy(triwall, m->triwall, m->ntri));
      PetscCall(PetscArraycpy(trisrc, m->trisrc, m->ntri));
    }
    PetscCall(PetscFree(m->tri));
    PetscCall(PetscFree(m->triwall));
    PetscCall(PetscFree(m->trisrc));
    m->tri     = tri;
    m->triwall = triwall;
    m->trisrc  = trisrc;
  }
  m->tri[3 * m->ntri]     = a;
  m->tri[3 * m->ntri + 1] = b;
  m->tri[3 * m->ntri + 2] = c;
  m->triwall[m->ntri]     = wall;
  m->trisrc[m->ntri]      = src;
  m->ntri++;
  PetscFunctionReturn(0);
}

static inline void Sub(const PetscReal a[], const PetscReal b[], PetscReal d[])
{
  d[0] = a[0] - b[0];
  d[1] = a[1] - b[1];
  d[2] = a[2] - b[2];
}

static inline PetscReal Dot(const PetscReal a[], const PetscReal b[])
{
  return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

static inline void Cross(const PetscReal a[], const PetscReal b[], PetscReal c[])
{
  c[0] = a[1] * b[2] - a[2] * b[1];
  c[1] = a[2] * b[0] - a[0] * b[2];
  c[2] = a[0] * b[1] - a[1] * b[0];
}

/* u . (v x w) */
static inline PetscReal Triple(const PetscReal u[], const PetscReal v[], const PetscReal w[])
{
  PetscReal vw[3];
  Cross(v, w, vw);
  return Dot(u, vw);
}

/* (b - a) x (c - a): twice the area times the unit normal */
static inline void Normal(const PetscReal a[], const PetscReal b[], const PetscReal c[], PetscReal n[])
{
  PetscReal ab[3], ac[3];
  Sub(b, a, ab);
  Sub(c, a, ac);
  Cross(ab, ac, n);
}

/* the index of x in the sorted array s[n] (x is one of its entries) */
static PetscInt IndexOf(PetscInt n, const PetscReal s[], PetscReal x)
{
  PetscInt lo = 0, hi = n - 1;
  while (lo < hi) {
    const PetscInt mid = (lo + hi) / 2;
    if (s[mid] < x) lo = mid + 1;
    else hi = mid;
  }
  return lo;
}

/* the vertex at grid point (i, j) of the end face s (0: z = 0, 1: z = width), added on first use */
static PetscErrorCode GridVertex(FSMesh *m, PetscInt *gv, const PetscReal xs[], const PetscReal ys[], PetscInt ny,
                                 PetscReal width, PetscInt i, PetscInt j, PetscInt s, PetscInt *v)
{
  PetscInt *g = &gv[2 * (i * ny + j) + s];

  PetscFunctionBegin;
  if (*g < 0) {
    const PetscReal x[3] = {xs[i], ys[j], s ? width : 0};
    PetscCall(FSMeshAddVertex(m, x, g));
  }
  *v = *g;
  PetscFunctionReturn(0);
}

/* sorts r[n] and drops repeated values, n becomes the number of distinct ones */
static PetscErrorCode SortUnique(PetscInt *n, PetscReal r[])
{
  PetscInt k = 0;

  PetscFunctionBegin;
  PetscCall(PetscSortReal(*n, r));
  for (PetscInt i = 0; i < *n; i++)
    if (!k || r[i] != r[k - 1]) r[k++] = r[i];
  *n = k;
  PetscFunctionReturn(0);
}

/*
   FSMeshExtrude - the 3-D tank of a 2-D outline (the polygons of w: the container counter-clockwise,
   the obstacles clockwise) extruded along z over [0, width]. Only outlines of horizontal and vertical
   edges are supported. The mesh is watertight: the distinct x and y coordinates of the vertices make
   a grid, every polygon edge is split at the grid lines it crosses into side quads (two triangles
   each, of the wall of the edge), and the end faces z = 0 and z = width are the grid cells whose
   centre is in the liquid (two triangles each, of the container polygon's wall), with their normals
   -z and +z. Vertices are shared between the faces.

   Collective (errors only; every rank builds the same mesh)

   Input Parameters:
+  m     - the mesh (triangles and walls are appended)
.  comm  - the communicator of the errors
.  w     - the outline (checked by FSWallsCheck)
-  width - the tank's width, > 0

.seealso: FSWallsRectangularTank(), FSWallsBaffledTank(), FSMeshCheck()
*/
PetscErrorCode FSMeshExtrude(FSMesh *m, MPI_Comm comm, const FSWalls *w, PetscReal width)
{
  const char source[] = "extruded tank outline";
  PetscReal *xs, *ys;
  PetscInt   nx = w->nvert, ny = w->nvert, *gv, *wallmap, src = 0;

  PetscFunctionBegin;
  PetscCheck(width > 0, comm, PETSC_ERR_ARG_OUTOFRANGE,
             "The tank width %g (-fs_tank_width) must be positive for a 3-D tank", (double)width);
  PetscCheck(w->npoly > 0, comm, PETSC_ERR_ARG_WRONG, "No tank outline to extrude");
  for (PetscInt p = 0; p < w->npoly; p++) {
    PetscCheck(p == 0 ? w->area[p] > 0
               : w->area[p]<0, comm, PETSC_ERR_ARG_WRONG,
                            "Polygon %" PetscInt_FMT " (wall \"%s\") of the tank outline runs %s: the container runs "
                            "counter-clockwise, the obstacles clockwise (see FSWallsCheck)",
                            p, w->name[w->pwall[p]], w->area[p]> 0
                   ? "counter-clockwise"
                   : "clockwise");
    for (PetscInt v = w->pstart[p]; v < w->pstart[p + 1]; v++) {
      const PetscInt   v1 = v + 1 < w->pstart[p + 1] ? v + 1 : w->pstart[p];
      const PetscReal *a = &w->vert[2 * v], *b = &w->vert[2 * v1];
      PetscCheck(a[0] == b[0] || a[1] == b[1], comm, PETSC_ERR_SUP,
                 "Edge (%g, %g)-(%g, %g) of wall \"%s\" is neither horizontal nor vertical: only outlines made of "
                 "horizontal and vertical edges are extruded into a 3-D tank; give the tank as an STL file instead",
                 (double)a[0], (double)a[1], (double)b[0], (double)b[1], w->name[w->vwall[v]]);
    }
  }
  PetscCall(PetscMalloc2(nx, &xs, ny, &ys));
  for (PetscInt v = 0; v < w->nvert; v++) {
    xs[v] = w->vert[2 * v];
    ys[v] = w->vert[2 * v + 1];
  }
  PetscCall(SortUnique(&nx, xs));
  PetscCall(SortUnique(&ny, ys));
  PetscCall(PetscMalloc1(w->nwalls, &wallmap));
  for (PetscInt k = 0; k < w->nwalls; k++) PetscCall(FSMeshAddWall(m, w->name[k], source, &wallmap[k]));
  PetscCall(PetscMalloc1(2 * nx * ny, &gv));
  for (PetscInt k = 0; k < 2 * nx * ny; k++) gv[k] = -1;

  /* the side faces: each edge split at the grid lines into quads (p0, p1) x [0, width], normal
     (dy, -dx, 0) like the 2-D segments' */
  for (PetscInt p = 0; p < w->npoly; p++)
    for (PetscInt v = w->pstart[p]; v < w->pstart[p + 1]; v++) {
      const PetscInt   v1 = v + 1 < w->pstart[p + 1] ? v + 1 : w->pstart[p], wall = wallmap[w->vwall[v]];
      const PetscReal *a = &w->vert[2 * v], *b = &w->vert[2 * v1];
      const PetscBool  horizontal = (PetscBool)(a[1] == b[1]);
      PetscInt         i = IndexOf(nx, xs, a[0]), j = IndexOf(ny, ys, a[1]);
      const PetscInt   end  = horizontal ? IndexOf(nx, xs, b[0]) : IndexOf(ny, ys, b[1]);
      const PetscInt   step = horizontal ? (end > i ? 1 : -1) : (end > j ? 1 : -1);

      while (horizontal ? i != end : j != end) {
        const PetscInt i1 = horizontal ? i + step : i, j1 = horizontal ? j : j + step;
        PetscInt       a0 = -1, a1 = -1, b0 = -1, b1 = -1;
        PetscCall(GridVertex(m, gv, xs, ys, ny, width, i, j, 0, &a0));
        PetscCall(GridVertex(m, gv, xs, ys, ny, width, i1, j1, 0, &a1));
        PetscCall(GridVertex(m, gv, xs, ys, ny, width, i1, j1, 1, &b1));
        PetscCall(GridVertex(m, gv, xs, ys, ny, width, i, j, 1, &b0));
        PetscCall(FSMeshAddTriangle(m, wall, a0, a1, b1, src++));
        PetscCall(FSMeshAddTriangle(m, wall, a0, b1, b0, src++));
        i = i1;
        j = j1;
      }
    }
  /* the end faces: the liquid's grid cells, clockwise seen from +z at z = 0 (normal -z), counter-clockwise
     at z = width (normal +z) */
  for (PetscInt i = 0; i + 1 < nx; i++)
    for (PetscInt j = 0; j + 1 < ny; j++) {
      const PetscReal centre[2] = {0.5 * (xs[i] + xs[i + 1]), 0.5 * (ys[j] + ys[j + 1])};
      const PetscInt  wall      = wallmap[w->pwall[0]];
      PetscInt        q[4]      = {-1, -1, -1, -1};
      if (!FSWallsInLiquid(w, centre, 0)) continue;
      for (PetscInt s = 0; s < 2; s++) {
        PetscCall(GridVertex(m, gv, xs, ys, ny, width, i, j, s, &q[0]));
        PetscCall(GridVertex(m, gv, xs, ys, ny, width, i + 1, j, s, &q[1]));
        PetscCall(GridVertex(m, gv, xs, ys, ny, width, i + 1, j + 1, s, &q[2]));
        PetscCall(GridVertex(m, gv, xs, ys, ny, width, i, j + 1, s, &q[3]));
        if (s == 0) {
          PetscCall(FSMeshAddTriangle(m, wall, q[0], q[2], q[1], src++));
          PetscCall(FSMeshAddTriangle(m, wall, q[0], q[3], q[2], src++));
        } else {
          PetscCall(FSMeshAddTriangle(m, wall, q[0], q[1], q[2], src++));
          PetscCall(FSMeshAddTriangle(m, wall, q[0], q[2], q[3], src++));
        }
      }
    }
  PetscCall(PetscFree(gv));
  PetscCall(PetscFree(wallmap));
  PetscCall(PetscFree2(xs, ys));
  PetscFunctionReturn(0);
}

/*
   FSTriangleDistance2 - the squared distance from x to the triangle (a, b, c): the closest point is
   found from the sign of the barycentric parameters of x's projection (a vertex, an edge or the
   interior), exactly.

   Not collective
*/
PetscReal FSTriangleDistance2(const PetscReal a[], const PetscReal b[], const PetscReal c[], const PetscReal x[])
{
  PetscReal ab[3], ac[3], ax[3], bx[3], cx[3], y[3], d[3];
  PetscReal d1, d2, d3, d4, d5, d6, va, vb, vc;

  Sub(b, a, ab);
  Sub(c, a, ac);
  Sub(x, a, ax);
  d1 = Dot(ab, ax);
  d2 = Dot(ac, ax);
  if (d1 <= 0 && d2 <= 0) return Dot(ax, ax); /* vertex a */
  Sub(x, b, bx);
  d3 = Dot(ab, bx);
  d4 = Dot(ac, bx);
  if (d3 >= 0 && d4 <= d3) return Dot(bx, bx); /* vertex b */
  vc = d1 * d4 - d3 * d2;
  if (vc <= 0 && d1 >= 0 && d3 <= 0) { /* edge ab */
    const PetscReal t = d1 / (d1 - d3);
    for (PetscInt k = 0; k < 3; k++) y[k] = a[k] + t * ab[k];
    Sub(x, y, d);
    return Dot(d, d);
  }
  Sub(x, c, cx);
  d5 = Dot(ab, cx);
  d6 = Dot(ac, cx);
  if (d6 >= 0 && d5 <= d6) return Dot(cx, cx); /* vertex c */
  vb = d5 * d2 - d1 * d6;
  if (vb <= 0 && d2 >= 0 && d6 <= 0) { /* edge ac */
    const PetscReal t = d2 / (d2 - d6);
    for (PetscInt k = 0; k < 3; k++) y[k] = a[k] + t * ac[k];
    Sub(x, y, d);
    return Dot(d, d);
  }
  va = d3 * d6 - d5 * d4;
  if (va <= 0 && d4 - d3 >= 0 && d5 - d6 >= 0) { /* edge bc */
    const PetscReal t = (d4 - d3) / ((d4 - d3) + (d5 - d6));
    for (PetscInt k = 0; k < 3; k++) y[k] = b[k] + t * (c[k] - b[k]);
    Sub(x, y, d);
    return Dot(d, d);
  }
  { /* the interior: the projection of x */
    const PetscReal s = 1 / (va + vb + vc), v = vb * s, t = vc * s;
    for (PetscInt k = 0; k < 3; k++) y[k] = a[k] + v * ab[k] + t * ac[k];
    Sub(x, y, d);
    return Dot(d, d);
  }
}

/*
   FSTriangleSolidAngle - the signed solid angle of the triangle (a, b, c) seen from x (Van Oosterom
   and Strackee 1983): with A = a - x, B = b - x, C = c - x,
     tan(Omega/2) = A.(B x C) / (|A||B||C| + (A.B)|C| + (A.C)|B| + (B.C)|A|),
   positive when x is on the side opposite to the normal (b - a) x (c - a): a closed surface with its
   normals pointing outwards is seen from inside under 4 pi, from outside under 0.

   Not collective
*/
PetscReal FSTriangleSolidAngle(const PetscReal a[], const PetscReal b[], const PetscReal c[], const PetscReal x[])
{
  PetscReal A[3], B[3], C[3], la, lb, lc, num, den;

  Sub(a, x, A);
  Sub(b, x, B);
  Sub(c, x, C);
  la  = PetscSqrtReal(Dot(A, A));
  lb  = PetscSqrtReal(Dot(B, B));
  lc  = PetscSqrtReal(Dot(C, C));
  num = Triple(A, B, C);
  den = la * lb * lc + Dot(A, B) * lc + Dot(A, C) * lb + Dot(B, C) * la;
  return 2 * PetscAtan2Real(num, den);
}

/*
   FSTriangleCrossesSegment - does the open segment p-q cross the triangle (a, b, c)? p and q must lie
   strictly on opposite sides of the triangle's plane and the line pq pass strictly inside its three
   edges: a segment that only touches the triangle (an end point on it, or through an edge or a
   vertex) does not cross it.

   Not collective
*/
PetscBool FSTriangleCrossesSegment(const PetscReal a[], const PetscReal b[], const PetscReal c[], const PetscReal p[],
                                   const PetscReal q[])
{
  PetscReal n[3], ap[3], aq[3], pq[3], pa[3], pb[3], pc[3], dp, dq, s1, s2, s3;

  Normal(a, b, c, n);
  Sub(p, a, ap);
  Sub(q, a, aq);
  dp = Dot(n, ap);
  dq = Dot(n, aq);
  if (!((dp > 0 && dq < 0) || (dp < 0 && dq > 0))) return PETSC_FALSE;
  Sub(q, p, pq);
  Sub(a, p, pa);
  Sub(b, p, pb);
  Sub(c, p, pc);
  s1 = Triple(pq, pa, pb);
  s2 = Triple(pq, pb, pc);
  s3 = Triple(pq, pc, pa);
  return (PetscBool)((s1 > 0 && s2 > 0 && s3 > 0) || (s1 < 0 && s2 < 0 && s3 < 0));
}

/*
   FSMeshDistance - the distance from x to the nearest input triangle of the mesh.

   Not collective
*/
PetscReal FSMeshDistance(const FSMesh *m, const PetscReal x[])
{
  PetscReal best = PETSC_MAX_REAL;
  for (PetscInt t = 0; t < m->ntri; t++) {
    const PetscInt *v = &m->tri[3 * t];
    best = PetscMin(best, FSTriangleDistance2(&m->vert[3 * v[0]], &m->vert[3 * v[1]], &m->vert[3 * v[2]], x));
  }
  return PetscSqrtReal(best);
}

/*
   FSMeshInLiquid - is x in the liquid region: its winding number (the solid angle under which the
   input triangles are seen, over 4 pi) at least 1/2 (1 inside the container and outside the
   obstacles, 0 elsewhere, once FSMeshCheck has oriented the obstacles), and, for margin > 0, x at
   least margin from every triangle?

   Not collective
*/
PetscBool FSMeshInLiquid(const FSMesh *m, const PetscReal x[], PetscReal margin)
{
  PetscReal omega = 0;
  for (PetscInt t = 0; t < m->ntri; t++) {
    const PetscInt *v = &m->tri[3 * t];
    omega += FSTriangleSolidAngle(&m->vert[3 * v[0]], &m->vert[3 * v[1]], &m->vert[3 * v[2]], x);
  }
  if (omega / (4 * PETSC_PI) < 0.5) return PETSC_FALSE;
  return (PetscBool)(margin <= 0 || FSMeshDistance(m, x) >= margin);
}
