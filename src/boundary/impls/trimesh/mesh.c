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
  PetscCall(PetscFree(m->elgid));
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
  *v         = m->nvert++;
  m->checked = PETSC_FALSE;
  PetscFunctionReturn(0);
}

/*
   FSMeshVertexBox - the bounding box lo..hi of the mesh's vertices as they are now (before FSMeshCheck,
   which sets m->lo, m->hi); zeros for a mesh without vertices.

   Not collective
*/
void FSMeshVertexBox(const FSMesh *m, PetscReal lo[3], PetscReal hi[3])
{
  for (PetscInt d = 0; d < 3; d++) lo[d] = hi[d] = m->nvert ? m->vert[d] : 0;
  for (PetscInt v = 1; v < m->nvert; v++)
    for (PetscInt d = 0; d < 3; d++) {
      lo[d] = PetscMin(lo[d], m->vert[3 * v + d]);
      hi[d] = PetscMax(hi[d], m->vert[3 * v + d]);
    }
}

/* cos and sin of deg degrees, exact at the multiples of 90 (an STL rotated by a quarter turn keeps its faces along
   the axes, which the fills and the walls' checks see exactly) */
static void CosSinDegrees(PetscReal deg, PetscReal *c, PetscReal *s)
{
  const PetscReal q = deg / 90;
  if (q == PetscFloorReal(q) && PetscAbsReal(q) < 1e9) {
    const long k = ((long)q % 4 + 4) % 4;
    *c           = k == 0 ? 1 : k == 2 ? -1 : 0;
    *s           = k == 1 ? 1 : k == 3 ? -1 : 0;
  } else {
    *c = PetscCosReal(deg * PETSC_PI / 180);
    *s = PetscSinReal(deg * PETSC_PI / 180);
  }
}

/*
   FSMeshTransform - moves every vertex x of the mesh to R (scale x) + shift, R the rotation by rot[0]
   degrees about the x axis, then rot[1] about the y axis, then rot[2] about the z axis (the axes fixed:
   R = Rz Ry Rx; right-hand rule, a positive angle counter-clockwise seen from the axis's tip). A positive
   scale and a rotation keep the triangles' orientation. The mesh must be checked again (FSMeshCheck).

   Not collective
*/
void FSMeshTransform(FSMesh *m, PetscReal scale, const PetscReal rot[3], const PetscReal shift[3])
{
  PetscReal c[3], s[3], R[9];

  for (PetscInt a = 0; a < 3; a++) CosSinDegrees(rot[a], &c[a], &s[a]);
  /* Rz Ry Rx, written out */
  R[0] = c[2] * c[1];
  R[1] = c[2] * s[1] * s[0] - s[2] * c[0];
  R[2] = c[2] * s[1] * c[0] + s[2] * s[0];
  R[3] = s[2] * c[1];
  R[4] = s[2] * s[1] * s[0] + c[2] * c[0];
  R[5] = s[2] * s[1] * c[0] - c[2] * s[0];
  R[6] = -s[1];
  R[7] = c[1] * s[0];
  R[8] = c[1] * c[0];
  for (PetscInt v = 0; v < m->nvert; v++) {
    PetscReal *x = &m->vert[3 * v], y[3];
    for (PetscInt i = 0; i < 3; i++) y[i] = scale * (R[3 * i] * x[0] + R[3 * i + 1] * x[1] + R[3 * i + 2] * x[2]);
    for (PetscInt i = 0; i < 3; i++) x[i] = y[i] + shift[i];
  }
  m->checked = PETSC_FALSE;
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
  m->checked = PETSC_FALSE;
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

/* ---------------------------------------------------------------------------------------------------
   FSMeshCheck and its parts
   --------------------------------------------------------------------------------------------------- */

/* the format and arguments naming triangle t: its source (file) and its number there */
#define TRI_FMT      "%s: triangle %" PetscInt_FMT
#define TRI_ARGS(t)  m->source[m->triwall[t]], m->trisrc[t]
#define PT_FMT       "(%g, %g, %g)"
#define PT_ARGS(v)   (double)m->vert[3 * (v)], (double)m->vert[3 * (v) + 1], (double)m->vert[3 * (v) + 2]
#define WALL_ARGS(t) m->name[m->triwall[t]]

/* (a) no repeated vertex, no triangle of area below 1e-12 diag2 */
static PetscErrorCode CheckDegenerate(const FSMesh *m, MPI_Comm comm, PetscReal diag2)
{
  PetscFunctionBegin;
  for (PetscInt t = 0; t < m->ntri; t++) {
    const PetscInt *v = &m->tri[3 * t];
    PetscReal       n[3], area;
    PetscCheck(v[0] != v[1] && v[1] != v[2] && v[2] != v[0], comm, PETSC_ERR_ARG_WRONG,
               TRI_FMT " is degenerate (area 0: a repeated vertex " PT_FMT ") (wall \"%s\")", TRI_ARGS(t),
               PT_ARGS(v[0] == v[1] || v[0] == v[2] ? v[0] : v[1]), WALL_ARGS(t));
    Normal(&m->vert[3 * v[0]], &m->vert[3 * v[1]], &m->vert[3 * v[2]], n);
    area = 0.5 * PetscSqrtReal(Dot(n, n));
    PetscCheck(area >= 1e-12 * diag2, comm, PETSC_ERR_ARG_WRONG,
               TRI_FMT
               " is degenerate (area %g, below 1e-12 times the squared diagonal %g of the mesh's bounding box): "
               "vertices " PT_FMT ", " PT_FMT ", " PT_FMT " (wall \"%s\")",
               TRI_ARGS(t), (double)area, (double)diag2, PT_ARGS(v[0]), PT_ARGS(v[1]), PT_ARGS(v[2]), WALL_ARGS(t));
  }
  PetscFunctionReturn(0);
}

typedef struct {
  PetscInt v0, v1; /* the end points, v0 < v1 */
  PetscInt t, k;   /* triangle t's edge k: from its vertex k to its vertex k + 1 */
} HalfEdge;

static int CompareHalfEdges(const void *x, const void *y)
{
  const HalfEdge *a = (const HalfEdge *)x, *b = (const HalfEdge *)y;
  if (a->v0 != b->v0) return a->v0 < b->v0 ? -1 : 1;
  if (a->v1 != b->v1) return a->v1 < b->v1 ? -1 : 1;
  if (a->t != b->t) return a->t < b->t ? -1 : 1;
  return a->k < b->k ? -1 : (a->k > b->k ? 1 : 0);
}

static PetscInt Root(PetscInt parent[], PetscInt i)
{
  while (parent[i] != i) {
    parent[i] = parent[parent[i]];
    i         = parent[i];
  }
  return i;
}

/* (b) every edge shared by exactly two triangles, in opposite directions; joins the triangles sharing an
   edge in the union-find forest parent[] */
static PetscErrorCode CheckEdges(const FSMesh *m, MPI_Comm comm, PetscInt parent[])
{
  HalfEdge      *he;
  const PetscInt n = 3 * m->ntri;

  PetscFunctionBegin;
  PetscCall(PetscMalloc1(n, &he));
  for (PetscInt t = 0; t < m->ntri; t++)
    for (PetscInt k = 0; k < 3; k++) {
      const PetscInt a = m->tri[3 * t + k], b = m->tri[3 * t + (k + 1) % 3];
      he[3 * t + k] = (HalfEdge){PetscMin(a, b), PetscMax(a, b), t, k};
    }
  qsort(he, (size_t)n, sizeof(*he), CompareHalfEdges);
  for (PetscInt i = 0, j; i < n; i = j) {
    PetscInt  t0 = he[i].t, t1;
    PetscBool f0, f1;
    for (j = i + 1; j < n && he[j].v0 == he[i].v0 && he[j].v1 == he[i].v1;) j++;
    if (j - i != 2) {
      const PetscInt cnt = j - i, v0 = he[i].v0, v1 = he[i].v1;
      PetscCall(PetscFree(he));
      PetscCheck(cnt != 1, comm, PETSC_ERR_ARG_WRONG,
                 TRI_FMT ": its edge " PT_FMT "-" PT_FMT
                         " is shared by 1 triangle: the mesh is open (a hole, a missing "
                         "face, or a vertex lying on another triangle's edge) (wall \"%s\")",
                 TRI_ARGS(t0), PT_ARGS(v0), PT_ARGS(v1), WALL_ARGS(t0));
      SETERRQ(comm, PETSC_ERR_ARG_WRONG,
              TRI_FMT ": its edge " PT_FMT "-" PT_FMT " is shared by %" PetscInt_FMT
                      " triangles: every edge of a closed surface is shared by exactly two (wall \"%s\")",
              TRI_ARGS(t0), PT_ARGS(v0), PT_ARGS(v1), cnt, WALL_ARGS(t0));
    }
    t1 = he[i + 1].t;
    f0 = (PetscBool)(m->tri[3 * t0 + he[i].k] == he[i].v0);
    f1 = (PetscBool)(m->tri[3 * t1 + he[i + 1].k] == he[i + 1].v0);
    if (f0 == f1) {
      const PetscInt v0 = f0 ? he[i].v0 : he[i].v1, v1 = f0 ? he[i].v1 : he[i].v0;
      PetscCall(PetscFree(he));
      SETERRQ(comm, PETSC_ERR_ARG_WRONG,
              TRI_FMT " (wall \"%s\") and " TRI_FMT " (wall \"%s\") run along their shared edge " PT_FMT " -> " PT_FMT
                      " in the same direction: inconsistent orientation (reverse the vertex order of one of them; "
                      "neighbours run along a shared edge in opposite directions)",
              TRI_ARGS(t0), WALL_ARGS(t0), TRI_ARGS(t1), WALL_ARGS(t1), PT_ARGS(v0), PT_ARGS(v1));
    }
    {
      const PetscInt r0 = Root(parent, t0), r1 = Root(parent, t1);
      if (r0 != r1) parent[PetscMax(r0, r1)] = PetscMin(r0, r1);
    }
  }
  PetscCall(PetscFree(he));
  PetscFunctionReturn(0);
}

/* the barycentric coordinates of the projection of x on the plane of the triangle t[] with normal n
   ((t1 - t0) x (t2 - t0)) */
static void Barycentric(const PetscReal *t[3], const PetscReal n[], const PetscReal x[], PetscReal l[3])
{
  const PetscReal nn = Dot(n, n);
  for (PetscInt k = 0; k < 3; k++) {
    PetscReal u[3], w[3], c[3];
    Sub(t[(k + 1) % 3], x, u);
    Sub(t[(k + 2) % 3], x, w);
    Cross(u, w, c);
    l[k] = Dot(n, c) / nn;
  }
}

static PetscBool InsideStrict(const PetscReal *t[3], const PetscReal n[], const PetscReal x[])
{
  PetscReal l[3];
  Barycentric(t, n, x, l);
  return (PetscBool)(l[0] > 1e-9 && l[1] > 1e-9 && l[2] > 1e-9);
}

static PetscBool InsideClosed(const PetscReal *t[3], const PetscReal n[], const PetscReal x[])
{
  PetscReal l[3];
  Barycentric(t, n, x, l);
  return (PetscBool)(l[0] >= -1e-9 && l[1] >= -1e-9 && l[2] >= -1e-9);
}

/* signed distance of x from the line through a and b, in the plane of normal n (positive on the left) */
static PetscReal LineDistance(const PetscReal n[], const PetscReal a[], const PetscReal b[], const PetscReal x[])
{
  PetscReal ab[3], ax[3], c[3];
  Sub(b, a, ab);
  Sub(x, a, ax);
  Cross(ab, ax, c);
  return Dot(n, c) / (PetscSqrtReal(Dot(n, n)) * PetscSqrtReal(Dot(ab, ab)));
}

/* do the segments ab and cd, in the plane of normal n, cross properly (each strictly through the other)? */
static PetscBool SegmentsCross(const PetscReal n[], const PetscReal a[], const PetscReal b[], const PetscReal c[],
                               const PetscReal d[], PetscReal tol)
{
  const PetscReal dc = LineDistance(n, a, b, c), dd = LineDistance(n, a, b, d);
  const PetscReal da = LineDistance(n, c, d, a), db = LineDistance(n, c, d, b);
  return (PetscBool)(((dc > tol && dd < -tol) || (dc < -tol && dd > tol)) &&
                     ((da > tol && db < -tol) || (da < -tol && db > tol)));
}

/* is x (in the plane of triangle t) strictly inside its angle at vertex j? */
static PetscBool InAngle(const PetscReal *t[3], const PetscReal n[], PetscInt j, const PetscReal x[], PetscReal tol)
{
  return (PetscBool)(LineDistance(n, t[j], t[(j + 1) % 3], x) > tol && LineDistance(n, t[(j + 2) % 3], t[j], x) > tol);
}

/* the edges of triangle P against triangle Q (normal nQ), not coplanar: dP[] the signed distances of P's
   vertices from Q's plane, sp[i] the index in Q of P's vertex i if they share it, else -1 */
static PetscBool EdgesMeetTriangle(const PetscReal *P[3], const PetscInt sp[3], const PetscReal dP[3],
                                   const PetscReal *Q[3], const PetscReal nQ[], PetscReal tol)
{
  for (PetscInt i = 0; i < 3; i++) {
    const PetscInt i1 = (i + 1) % 3;
    if (sp[i] >= 0 && sp[i1] >= 0) continue;
    if (sp[i] >= 0 || sp[i1] >= 0) {
      /* from a shared vertex (a corner of Q): meets Q beyond it only if it runs in Q's plane into its angle */
      const PetscInt v = sp[i] >= 0 ? i : i1, u = sp[i] >= 0 ? i1 : i;
      if (PetscAbsReal(dP[u]) <= tol && InAngle(Q, nQ, sp[v], P[u], tol)) return PETSC_TRUE;
      continue;
    }
    if (PetscAbsReal(dP[i]) <= tol && PetscAbsReal(dP[i1]) <= tol) { /* the edge lies in Q's plane */
      if (InsideStrict(Q, nQ, P[i]) || InsideStrict(Q, nQ, P[i1])) return PETSC_TRUE;
      for (PetscInt j = 0; j < 3; j++)
        if (SegmentsCross(nQ, P[i], P[i1], Q[j], Q[(j + 1) % 3], tol)) return PETSC_TRUE;
    } else if (PetscAbsReal(dP[i]) <= tol) { /* a vertex touches Q's plane */
      if (InsideStrict(Q, nQ, P[i])) return PETSC_TRUE;
    } else if (PetscAbsReal(dP[i1]) <= tol) {
      if (InsideStrict(Q, nQ, P[i1])) return PETSC_TRUE;
    } else if ((dP[i] > 0) != (dP[i1] > 0)) { /* through Q's plane: where? */
      const PetscReal s = dP[i] / (dP[i] - dP[i1]);
      PetscReal       x[3];
      for (PetscInt d = 0; d < 3; d++) x[d] = P[i][d] + s * (P[i1][d] - P[i][d]);
      if (InsideClosed(Q, nQ, x)) return PETSC_TRUE;
    }
  }
  return PETSC_FALSE;
}

/* do triangles t and u meet anywhere but in the vertices or the edge they share? tol: the distance below
   which points are taken as lying in a plane or on a line */
static PetscBool TrianglesIntersect(const FSMesh *m, PetscInt t, PetscInt u, PetscReal tol)
{
  const PetscInt  *vp = &m->tri[3 * t], *vq = &m->tri[3 * u];
  const PetscReal *P[3], *Q[3];
  PetscInt         sp[3] = {-1, -1, -1}, sq[3] = {-1, -1, -1}, shared = 0;
  PetscReal        nP[3], nQ[3], lP, lQ, dP[3], dQ[3];
  PetscBool        coplanar = PETSC_TRUE, above = PETSC_TRUE, below = PETSC_TRUE;

  for (PetscInt i = 0; i < 3; i++) {
    P[i] = &m->vert[3 * vp[i]];
    Q[i] = &m->vert[3 * vq[i]];
  }
  for (PetscInt i = 0; i < 3; i++)
    for (PetscInt j = 0; j < 3; j++)
      if (vp[i] == vq[j]) {
        sp[i] = j;
        sq[j] = i;
        shared++;
      }
  if (shared == 3) return PETSC_TRUE; /* the same triangle twice */
  Normal(P[0], P[1], P[2], nP);
  Normal(Q[0], Q[1], Q[2], nQ);
  lP = PetscSqrtReal(Dot(nP, nP));
  lQ = PetscSqrtReal(Dot(nQ, nQ));
  for (PetscInt i = 0; i < 3; i++) {
    PetscReal r[3];
    Sub(Q[i], P[0], r);
    dQ[i] = sq[i] >= 0 ? 0 : Dot(nP, r) / lP;
    Sub(P[i], Q[0], r);
    dP[i] = sp[i] >= 0 ? 0 : Dot(nQ, r) / lQ;
    if (PetscAbsReal(dQ[i]) > tol || PetscAbsReal(dP[i]) > tol) coplanar = PETSC_FALSE;
    if (dQ[i] <= tol) above = PETSC_FALSE;
    if (dQ[i] >= -tol) below = PETSC_FALSE;
  }
  if (shared == 2) {
    /* neighbours across an edge meet beyond it only when folded onto each other: in one plane, on the same
       side of the edge */
    PetscInt i3 = 0, j3 = 0, i0, i1;
    while (sp[i3] >= 0) i3++;
    while (sq[j3] >= 0) j3++;
    i0 = (i3 + 1) % 3;
    i1 = (i3 + 2) % 3;
    if (PetscAbsReal(dQ[j3]) > tol) return PETSC_FALSE;
    return (PetscBool)(LineDistance(nP, P[i0], P[i1], P[i3]) * LineDistance(nP, P[i0], P[i1], Q[j3]) > 0);
  }
  if (above || below) return PETSC_FALSE; /* Q on one side of P's plane */
  if (coplanar) {
    PetscReal gP[3], gQ[3];
    for (PetscInt i = 0; i < 3; i++)
      for (PetscInt j = 0; j < 3; j++) {
        const PetscInt i1 = (i + 1) % 3, j1 = (j + 1) % 3;
        if (vp[i] == vq[j] || vp[i] == vq[j1] || vp[i1] == vq[j] || vp[i1] == vq[j1]) continue;
        if (SegmentsCross(nP, P[i], P[i1], Q[j], Q[j1], tol)) return PETSC_TRUE;
      }
    for (PetscInt i = 0; i < 3; i++) {
      if (sp[i] < 0 && InsideStrict(Q, nQ, P[i])) return PETSC_TRUE;
      if (sq[i] < 0 && InsideStrict(P, nP, Q[i])) return PETSC_TRUE;
    }
    for (PetscInt d = 0; d < 3; d++) {
      gP[d] = (P[0][d] + P[1][d] + P[2][d]) / 3;
      gQ[d] = (Q[0][d] + Q[1][d] + Q[2][d]) / 3;
    }
    if (InsideStrict(Q, nQ, gP) || InsideStrict(P, nP, gQ)) return PETSC_TRUE;
    /* a shared vertex: does an edge of one run from it into the other's angle there? */
    for (PetscInt i = 0; i < 3; i++)
      if (sp[i] >= 0)
        for (PetscInt k = 1; k < 3; k++)
          if (InAngle(Q, nQ, sp[i], P[(i + k) % 3], tol) || InAngle(P, nP, i, Q[(sp[i] + k) % 3], tol))
            return PETSC_TRUE;
    return PETSC_FALSE;
  }
  return (PetscBool)(EdgesMeetTriangle(P, sp, dP, Q, nQ, tol) || EdgesMeetTriangle(Q, sq, dQ, P, nP, tol));
}

typedef struct {
  PetscInt64 cell;
  PetscInt   t;
} CellEntry;

static int CompareCellEntries(const void *x, const void *y)
{
  const CellEntry *a = (const CellEntry *)x, *b = (const CellEntry *)y;
  if (a->cell != b->cell) return a->cell < b->cell ? -1 : 1;
  return a->t < b->t ? -1 : (a->t > b->t ? 1 : 0);
}

/* (c) no two triangles meet but in a shared vertex or edge: the triangles' bounding boxes (widened by tol)
   binned in a uniform grid, each pair of overlapping boxes tested once, in the first cell they share */
static PetscErrorCode CheckIntersections(const FSMesh *m, MPI_Comm comm, PetscReal tol)
{
  const PetscInt nt = m->ntri;
  PetscReal     *box, s = 0;
  PetscInt      *range, n[3];
  PetscInt64     count;
  CellEntry     *cells;

  PetscFunctionBegin;
  PetscCall(PetscMalloc2(6 * nt, &box, 6 * nt, &range));
  for (PetscInt t = 0; t < nt; t++) {
    PetscReal ext = 0;
    for (PetscInt d = 0; d < 3; d++) {
      PetscReal lo = PETSC_MAX_REAL, hi = -PETSC_MAX_REAL;
      for (PetscInt k = 0; k < 3; k++) {
        lo = PetscMin(lo, m->vert[3 * m->tri[3 * t + k] + d]);
        hi = PetscMax(hi, m->vert[3 * m->tri[3 * t + k] + d]);
      }
      box[6 * t + d]     = lo - tol;
      box[6 * t + 3 + d] = hi + tol;
      ext                = PetscMax(ext, hi - lo);
    }
    s += ext;
  }
  /* the cell size: the triangles' mean extent, larger if the triangles would fill too many cells */
  s = PetscMax(s / nt, 1e-6 * PetscMax(m->hi[0] - m->lo[0], PetscMax(m->hi[1] - m->lo[1], m->hi[2] - m->lo[2])));
  for (;;) {
    for (PetscInt d = 0; d < 3; d++) n[d] = (PetscInt)((m->hi[d] - m->lo[d] + 2 * tol) / s) + 1;
    if ((double)n[0] * (double)n[1] * (double)n[2] > 1e18) {
      s *= 2;
      continue;
    }
    count = 0;
    for (PetscInt t = 0; t < nt; t++) {
      PetscInt64 c = 1;
      for (PetscInt d = 0; d < 3; d++) {
        const PetscInt i0    = (PetscInt)((box[6 * t + d] - (m->lo[d] - tol)) / s);
        const PetscInt i1    = (PetscInt)((box[6 * t + 3 + d] - (m->lo[d] - tol)) / s);
        range[6 * t + d]     = PetscMax(0, PetscMin(n[d] - 1, i0));
        range[6 * t + 3 + d] = PetscMax(0, PetscMin(n[d] - 1, i1));
        c *= range[6 * t + 3 + d] - range[6 * t + d] + 1;
      }
      count += c;
    }
    if (count <= 8 * (PetscInt64)nt + 1024) break;
    s *= 1.5;
  }
  PetscCall(PetscMalloc1(count, &cells));
  count = 0;
  for (PetscInt t = 0; t < nt; t++) {
    const PetscInt *r = &range[6 * t];
    for (PetscInt k = r[2]; k <= r[5]; k++)
      for (PetscInt j = r[1]; j <= r[4]; j++)
        for (PetscInt i = r[0]; i <= r[3]; i++) {
          cells[count].cell = i + n[0] * (j + (PetscInt64)n[1] * k);
          cells[count].t    = t;
          count++;
        }
  }
  qsort(cells, (size_t)count, sizeof(*cells), CompareCellEntries);
  for (PetscInt64 a = 0, b; a < count; a = b) {
    const PetscInt64 cell = cells[a].cell;
    const PetscInt   ci = (PetscInt)(cell % n[0]), cj = (PetscInt)((cell / n[0]) % n[1]),
                   ck = (PetscInt)(cell / n[0] / n[1]);
    for (b = a + 1; b < count && cells[b].cell == cell;) b++;
    for (PetscInt64 p = a; p < b; p++)
      for (PetscInt64 q = p + 1; q < b; q++) {
        const PetscInt t = cells[p].t, u = cells[q].t;
        PetscBool      overlap = PETSC_TRUE;
        /* the first cell of both: the pair is tested there only */
        if (PetscMax(range[6 * t], range[6 * u]) != ci || PetscMax(range[6 * t + 1], range[6 * u + 1]) != cj ||
            PetscMax(range[6 * t + 2], range[6 * u + 2]) != ck)
          continue;
        for (PetscInt d = 0; d < 3; d++)
          if (box[6 * t + d] > box[6 * u + 3 + d] || box[6 * u + d] > box[6 * t + 3 + d]) overlap = PETSC_FALSE;
        if (overlap && TrianglesIntersect(m, t, u, tol)) {
          PetscCall(PetscFree(cells));
          PetscCall(PetscFree2(box, range));
          SETERRQ(comm, PETSC_ERR_ARG_WRONG,
                  TRI_FMT " (wall \"%s\") and " TRI_FMT " (wall \"%s\") intersect: surfaces must not cross, overlap or "
                          "touch (other than neighbours sharing an edge or a vertex)",
                  TRI_ARGS(t), WALL_ARGS(t), TRI_ARGS(u), WALL_ARGS(u));
        }
      }
  }
  PetscCall(PetscFree(cells));
  PetscCall(PetscFree2(box, range));
  PetscFunctionReturn(0);
}

/* (d) the closed surfaces (components by shared edges, comp[t] their number, nc of them): the container
   (the largest enclosed volume) oriented out of the liquid, the others inside it and not inside each
   other, turned inside out if their normals point outwards of their solid; the liquid's volume */
static PetscErrorCode CheckSurfaces(FSMesh *m, MPI_Comm comm, PetscInt nc, const PetscInt comp[])
{
  PetscReal o[3], *vol, *wind;
  PetscInt *first, cont = 0;

  PetscFunctionBegin;
  PetscCall(PetscCalloc3(nc, &vol, nc, &wind, nc, &first));
  for (PetscInt c = 0; c < nc; c++) first[c] = -1;
  for (PetscInt d = 0; d < 3; d++) o[d] = 0.5 * (m->lo[d] + m->hi[d]);
  for (PetscInt t = 0; t < m->ntri; t++) {
    PetscReal a[3], b[3], c[3];
    Sub(&m->vert[3 * m->tri[3 * t]], o, a);
    Sub(&m->vert[3 * m->tri[3 * t + 1]], o, b);
    Sub(&m->vert[3 * m->tri[3 * t + 2]], o, c);
    vol[comp[t]] += Triple(a, b, c) / 6;
    if (first[comp[t]] < 0) first[comp[t]] = t;
  }
  for (PetscInt c = 1; c < nc; c++)
    if (PetscAbsReal(vol[c]) > PetscAbsReal(vol[cont])) cont = c;
  if (!(vol[cont] > 0)) {
    const PetscInt  t = first[cont];
    const PetscReal v = vol[cont];
    PetscCall(PetscFree3(vol, wind, first));
    SETERRQ(comm, PETSC_ERR_ARG_WRONG,
            "%s: the surface is inside out (its normals point into the liquid): encloses volume %g; flip the vertex "
            "order of its triangles (the closed surface of triangle %" PetscInt_FMT ", wall \"%s\")",
            m->source[m->triwall[t]], (double)v, m->trisrc[t], WALL_ARGS(t));
  }
  for (PetscInt c = 0; c < nc; c++) {
    const PetscInt *v = &m->tri[3 * first[c]];
    PetscReal       x[3];
    PetscInt        bad = -1;
    if (c == cont) continue;
    /* a point of surface c (its first triangle's centroid) against every other surface */
    for (PetscInt d = 0; d < 3; d++) x[d] = (m->vert[3 * v[0] + d] + m->vert[3 * v[1] + d] + m->vert[3 * v[2] + d]) / 3;
    for (PetscInt k = 0; k < nc; k++) wind[k] = 0;
    for (PetscInt t = 0; t < m->ntri; t++) {
      const PetscInt *u = &m->tri[3 * t];
      if (comp[t] != c)
        wind[comp[t]] += FSTriangleSolidAngle(&m->vert[3 * u[0]], &m->vert[3 * u[1]], &m->vert[3 * u[2]], x);
    }
    if (PetscAbsReal(wind[cont]) < 2 * PETSC_PI) bad = cont;
    for (PetscInt k = 0; k < nc && bad < 0; k++)
      if (k != c && k != cont && PetscAbsReal(wind[k]) >= 2 * PETSC_PI) bad = k;
    if (bad >= 0) {
      const PetscInt t = first[c], u = first[bad];
      PetscCall(PetscFree3(vol, wind, first));
      PetscCheck(bad != cont, comm, PETSC_ERR_ARG_WRONG,
                 "%s: the closed surface of triangle %" PetscInt_FMT " (wall \"%s\") lies outside the container (the "
                 "closed surface of " TRI_FMT ", wall \"%s\"): every other surface must lie inside the container",
                 m->source[m->triwall[t]], m->trisrc[t], WALL_ARGS(t), TRI_ARGS(u), WALL_ARGS(u));
      SETERRQ(comm, PETSC_ERR_ARG_WRONG,
              "%s: the closed surface of triangle %" PetscInt_FMT " (wall \"%s\") lies inside another obstacle (the "
              "closed surface of " TRI_FMT ", wall \"%s\"): obstacles must not nest",
              m->source[m->triwall[t]], m->trisrc[t], WALL_ARGS(t), TRI_ARGS(u), WALL_ARGS(u));
    }
  }
  /* obstacles given with their normals out of their solid (as STL files give them) are turned inside out */
  m->volume = 0;
  for (PetscInt t = 0; t < m->ntri; t++)
    if (comp[t] != cont && vol[comp[t]] > 0) {
      const PetscInt v  = m->tri[3 * t + 1];
      m->tri[3 * t + 1] = m->tri[3 * t + 2];
      m->tri[3 * t + 2] = v;
    }
  for (PetscInt c = 0; c < nc; c++) m->volume += c == cont ? vol[c] : -PetscAbsReal(vol[c]);
  PetscCall(PetscFree3(vol, wind, first));
  PetscFunctionReturn(0);
}

/*
   FSMeshCheck - checks the input triangles before a run, each failure an error naming the source (file)
   and the number there of the triangle:
   (a) no degenerate triangle (a repeated vertex, or an area below 1e-12 times the squared diagonal of
       the bounding box);
   (b) watertight and consistently oriented: every edge shared by exactly two triangles, which run
       along it in opposite directions;
   (c) no two triangles intersecting (other than neighbours sharing an edge or a vertex), candidate
       pairs from a uniform grid of cells;
   (d) the closed surfaces (the triangles connected by shared edges): the container, the one enclosing
       the largest volume, must enclose a positive volume (normals out of the liquid), the others
       (obstacles) lie inside it and not inside each other; an obstacle whose normals point out of
       its solid (the STL convention) is turned inside out (two vertices of each triangle swapped).
   Then sets the bounding box lo, hi and the volume of the liquid region (the container's minus the
   obstacles').

   Collective (every rank checks the same triangles, no communication; the errors are raised on comm)

.seealso: FSMeshExtrude(), FSMeshLoadSTL(), FSMeshRefine()
*/
PetscErrorCode FSMeshCheck(FSMesh *m, MPI_Comm comm)
{
  PetscReal      diag2 = 0;
  PetscInt      *parent, *comp, nc = 0;
  PetscErrorCode ierr;

  PetscFunctionBegin;
  if (m->checked) PetscFunctionReturn(0);
  PetscCheck(m->ntri > 0, comm, PETSC_ERR_ARG_WRONG, "The wall mesh has no triangles");
  for (PetscInt d = 0; d < 3; d++) {
    m->lo[d] = PETSC_MAX_REAL;
    m->hi[d] = -PETSC_MAX_REAL;
  }
  for (PetscInt k = 0; k < 3 * m->ntri; k++)
    for (PetscInt d = 0; d < 3; d++) {
      m->lo[d] = PetscMin(m->lo[d], m->vert[3 * m->tri[k] + d]);
      m->hi[d] = PetscMax(m->hi[d], m->vert[3 * m->tri[k] + d]);
    }
  for (PetscInt d = 0; d < 3; d++) diag2 += PetscSqr(m->hi[d] - m->lo[d]);
  PetscCheck(diag2 > 0 && diag2 < PETSC_MAX_REAL, comm, PETSC_ERR_ARG_WRONG,
             "%s: the wall mesh's bounding box " PT_FMT "-" PT_FMT " is empty or not finite", m->source[m->triwall[0]],
             (double)m->lo[0], (double)m->lo[1], (double)m->lo[2], (double)m->hi[0], (double)m->hi[1],
             (double)m->hi[2]);
  PetscCall(CheckDegenerate(m, comm, diag2));
  PetscCall(PetscMalloc2(m->ntri, &parent, m->ntri, &comp));
  for (PetscInt t = 0; t < m->ntri; t++) parent[t] = t;
  /* the failures are raised after the arrays are freed: a caller that lives on after an error (the Python
     package) loses no memory */
  ierr = CheckEdges(m, comm, parent);
  if (!ierr) ierr = CheckIntersections(m, comm, 1e-10 * PetscSqrtReal(diag2));
  if (!ierr) {
    for (PetscInt t = 0; t < m->ntri; t++) {
      const PetscInt r = Root(parent, t);
      comp[t]          = r == t ? nc++ : comp[r]; /* a root is the first triangle of its surface */
    }
    ierr = CheckSurfaces(m, comm, nc, comp);
  }
  PetscCall(PetscFree2(parent, comp));
  PetscCall(ierr);
  m->checked = PETSC_TRUE;
  PetscFunctionReturn(0);
}

/* the element p0, p1, p2 of triangle t, whose unit normal is n (mesh.h's row: vertices, centroid, normal, area, radius
   of its bounding sphere about the centroid), numbered m->nelglobal in the whole refinement: appended when its bounding
   sphere meets the box lo..hi (no box: always); only counted (m->nel) unless store */
static PetscErrorCode AddElement(FSMesh *m, PetscInt t, const PetscReal p0[], const PetscReal p1[],
                                 const PetscReal p2[], const PetscReal n[], const PetscReal lo[], const PetscReal hi[],
                                 PetscBool store)
{
  PetscReal row[FS_TRI_STRIDE], e[3];

  PetscFunctionBegin;
  for (PetscInt d = 0; d < 3; d++) {
    row[FS_TRI_P0 + d]       = p0[d];
    row[FS_TRI_P1 + d]       = p1[d];
    row[FS_TRI_P2 + d]       = p2[d];
    row[FS_TRI_CENTROID + d] = (p0[d] + p1[d] + p2[d]) / 3;
    row[FS_TRI_NORMAL + d]   = n[d];
  }
  Normal(&row[FS_TRI_P0], &row[FS_TRI_P1], &row[FS_TRI_P2], e);
  row[FS_TRI_AREA]   = 0.5 * PetscSqrtReal(Dot(e, e));
  row[FS_TRI_RADIUS] = 0;
  for (PetscInt k = 0; k < 3; k++) {
    PetscReal r[3];
    Sub(&row[3 * k], &row[FS_TRI_CENTROID], r);
    row[FS_TRI_RADIUS] = PetscMax(row[FS_TRI_RADIUS], PetscSqrtReal(Dot(r, r)));
  }
  m->elradius = PetscMax(m->elradius, row[FS_TRI_RADIUS]);
  m->nelglobal++;
  if (lo)
    for (PetscInt d = 0; d < 3; d++)
      if (row[FS_TRI_CENTROID + d] + row[FS_TRI_RADIUS] < lo[d] ||
          row[FS_TRI_CENTROID + d] - row[FS_TRI_RADIUS] > hi[d])
        PetscFunctionReturn(0);
  if (!store) { /* the counting pass */
    m->nel++;
    PetscFunctionReturn(0);
  }
  PetscCall(PetscArraycpy(&m->el[(size_t)m->nel * FS_TRI_STRIDE], row, FS_TRI_STRIDE));
  m->elwall[m->nel] = m->triwall[t];
  m->eltri[m->nel]  = t;
  m->elgid[m->nel]  = m->nelglobal - 1;
  m->nel++;
  PetscFunctionReturn(0);
}

/* A triangle's split (FSMeshRefine): m^2 similar triangles (grid = 0), or a grid of cells along the edges AB and AC
   at its widest angle (A opposite the longest edge, B and C after it in the triangle's order), m1 x m2 cells of
   sides at most s = hmax / sqrt(2 + 2 |cos A|), which bounds every segment within a cell by hmax: each cell two
   triangles cut along its shorter diagonal, those the edge BC crosses clipped to the triangle (a convex polygon of
   3 to 5 corners, fanned from its first) */
typedef struct {
  PetscInt  grid, m, m1, m2;
  PetscReal A[3], B[3], C[3], cosA;
} FSTriangleSplit;

/* the corners of cell (i, j) in (u, v), P = A + u (B - A) + v (C - A), clipped to u + v <= 1, counterclockwise;
   returns their number (0: the cell lies beyond BC) */
static PetscInt GridCell(const FSTriangleSplit *sp, PetscInt i, PetscInt j, PetscReal uv[][2])
{
  const PetscReal eps = 1e-12, c[4][2] = {{(PetscReal)i / sp->m1, (PetscReal)j / sp->m2},
                                          {(PetscReal)(i + 1) / sp->m1, (PetscReal)j / sp->m2},
                                          {(PetscReal)(i + 1) / sp->m1, (PetscReal)(j + 1) / sp->m2},
                                          {(PetscReal)i / sp->m1, (PetscReal)(j + 1) / sp->m2}};
  PetscInt        n = 0;

  for (PetscInt k = 0; k < 4; k++) { /* Sutherland-Hodgman against f = 1 - u - v >= 0 */
    const PetscReal *p = c[k], *q = c[(k + 1) % 4], fp = 1 - p[0] - p[1], fq = 1 - q[0] - q[1];
    if (fp >= -eps) {
      uv[n][0]   = p[0];
      uv[n++][1] = p[1];
    }
    if ((fp > eps && fq < -eps) || (fp < -eps && fq > eps)) {
      const PetscReal w = fp / (fp - fq);
      uv[n][0]          = p[0] + w * (q[0] - p[0]);
      uv[n++][1]        = p[1] + w * (q[1] - p[1]);
    }
  }
  return n;
}

/* the split of triangle t with edges at most hmax that makes the fewer elements; their number */
static PetscInt64 ChooseSplit(const FSMesh *m, PetscInt t, PetscReal hmax, FSTriangleSplit *sp)
{
  const PetscReal *p[3];
  PetscReal        len[3], ab[3], ac[3], s;
  PetscInt         k     = 0;
  PetscInt64       ngrid = 0;

  for (PetscInt q = 0; q < 3; q++) p[q] = &m->vert[3 * m->tri[3 * t + q]];
  for (PetscInt q = 0; q < 3; q++) {
    PetscReal e[3];
    Sub(p[(q + 2) % 3], p[(q + 1) % 3], e); /* the edge opposite corner q */
    len[q] = PetscSqrtReal(Dot(e, e));
    if (len[q] > len[k]) k = q;
  }
  sp->grid = 0;
  sp->m    = PetscMax(1, (PetscInt)PetscCeilReal(len[k] / hmax));
  for (PetscInt d = 0; d < 3; d++) {
    sp->A[d] = p[k][d];
    sp->B[d] = p[(k + 1) % 3][d];
    sp->C[d] = p[(k + 2) % 3][d];
  }
  Sub(sp->B, sp->A, ab);
  Sub(sp->C, sp->A, ac);
  sp->cosA = Dot(ab, ac) / PetscSqrtReal(Dot(ab, ab) * Dot(ac, ac));
  s        = hmax / PetscSqrtReal(2 + 2 * PetscAbsReal(sp->cosA));
  sp->m1   = PetscMax(1, (PetscInt)PetscCeilReal(PetscSqrtReal(Dot(ab, ab)) / s));
  sp->m2   = PetscMax(1, (PetscInt)PetscCeilReal(PetscSqrtReal(Dot(ac, ac)) / s));
  if ((PetscInt64)sp->m1 * sp->m2 >= (PetscInt64)sp->m * sp->m) return (PetscInt64)sp->m * sp->m; /* not fewer */
  for (PetscInt j = 0; j < sp->m2; j++)
    for (PetscInt i = 0; i < sp->m1; i++) {
      PetscReal      uv[5][2];
      const PetscInt n = GridCell(sp, i, j, uv);
      ngrid += n >= 3 ? n - 2 : 0;
    }
  if (ngrid < (PetscInt64)sp->m * sp->m) {
    sp->grid = 1;
    return ngrid;
  }
  return (PetscInt64)sp->m * sp->m;
}

/*
   FSMeshRefine - the elements: every edge at most hmax. Each input triangle is split into m^2 similar triangles
   (m = ceil(longest edge / hmax), at least 1) or, where that makes fewer (a thin triangle, e.g. half of a long
   narrow face: similar pieces of a sliver are slivers), into a grid of cells along its two edges at its widest
   angle, each cell two triangles and those its third edge crosses clipped to it. Elements are oriented as their
   triangle; each element's row holds its vertices, centroid, unit normal (its triangle's) and area. Elements made
   before are replaced.

   Not collective

.seealso: FSMeshCheck(), FSMeshRefineRegion(), FS_TRI_STRIDE
*/
PetscErrorCode FSMeshRefine(FSMesh *m, PetscReal hmax)
{
  PetscFunctionBegin;
  PetscCall(FSMeshRefineRegion(m, hmax, NULL, NULL));
  PetscFunctionReturn(0);
}

/*
   FSMeshRefineRegion - FSMeshRefine()'s elements whose bounding sphere meets the box lo..hi (NULL: all of them), in
   the same order; elgid numbers each as in the whole refinement, nelglobal counts the whole refinement's elements
   and elradius is the largest bounding sphere of them all, so that ranks holding the elements near their part of
   the domain agree on every element's number and on the search radius. Elements made before are replaced.

   Not collective
*/
PetscErrorCode FSMeshRefineRegion(FSMesh *m, PetscReal hmax, const PetscReal lo[], const PetscReal hi[])
{
  FSTriangleSplit *split;
  PetscInt64       nel = 0;
  PetscInt        *count;
  PetscBool       *inbox;

  PetscFunctionBegin;
  PetscCheck(hmax > 0, PETSC_COMM_SELF, PETSC_ERR_ARG_OUTOFRANGE, "The element size %g must be positive", (double)hmax);
  PetscCall(PetscMalloc2(m->ntri + 1, &split, m->ntri + 1, &count));
  for (PetscInt t = 0; t < m->ntri; t++) {
    PetscReal L = 0, e[3];
    for (PetscInt k = 0; k < 3; k++) {
      Sub(&m->vert[3 * m->tri[3 * t + (k + 1) % 3]], &m->vert[3 * m->tri[3 * t + k]], e);
      L = PetscMax(L, PetscSqrtReal(Dot(e, e)));
    }
    PetscCheck(L / hmax < 1e7, PETSC_COMM_SELF, PETSC_ERR_ARG_OUTOFRANGE,
               TRI_FMT ": an edge of length %g split into elements of at most %g: too many", TRI_ARGS(t), (double)L,
               (double)hmax);
    count[t] = (PetscInt)ChooseSplit(m, t, hmax, &split[t]);
    nel += count[t];
  }
  PetscCheck(nel * FS_TRI_STRIDE < PETSC_MAX_INT, PETSC_COMM_SELF, PETSC_ERR_ARG_OUTOFRANGE,
             "%" PetscInt64_FMT " elements of size at most %g: too many", nel, (double)hmax);
  PetscCall(PetscFree(m->el));
  PetscCall(PetscFree(m->elwall));
  PetscCall(PetscFree(m->eltri));
  PetscCall(PetscFree(m->elgid));
  /* with a box a first pass counts its elements and those of each triangle in it, so that the arrays are allocated
     once, to size, and the second makes the elements of those triangles only */
  PetscCall(PetscCalloc1(m->ntri + 1, &inbox));
  for (PetscInt pass = lo ? 0 : 1; pass < 2; pass++) {
    const PetscBool store = (PetscBool)(pass == 1);
    if (store) {
      const PetscInt cap = lo ? m->nel : (PetscInt)nel;
      PetscCall(PetscMalloc1((size_t)cap * FS_TRI_STRIDE + 1, &m->el));
      PetscCall(PetscMalloc1(cap + 1, &m->elwall));
      PetscCall(PetscMalloc1(cap + 1, &m->eltri));
      PetscCall(PetscMalloc1(cap + 1, &m->elgid));
    }
    if (pass == (lo ? 0 : 1)) m->elradius = 0; /* from every element: the first pass makes them all */
    m->nel       = 0;
    m->nelglobal = 0;
    for (PetscInt t = 0; t < m->ntri; t++) {
      const PetscInt before = m->nel;
      if (lo && store && !inbox[t]) { /* none of its elements is kept: only numbered */
        m->nelglobal += count[t];
        continue;
      }
      const FSTriangleSplit *sp = &split[t];
      const PetscReal       *a = sp->A, *b = sp->B, *c = sp->C;
      PetscReal              n[3], ln;
      Normal(&m->vert[3 * m->tri[3 * t]], &m->vert[3 * m->tri[3 * t + 1]], &m->vert[3 * m->tri[3 * t + 2]], n);
      ln = PetscSqrtReal(Dot(n, n));
      for (PetscInt d = 0; d < 3; d++) n[d] /= ln;
      if (!sp->grid) { /* from the triangle's first corner, as it comes */
        const PetscInt   s  = sp->m;
        const PetscReal *p0 = &m->vert[3 * m->tri[3 * t]], *p1 = &m->vert[3 * m->tri[3 * t + 1]];
        const PetscReal *p2 = &m->vert[3 * m->tri[3 * t + 2]];
        for (PetscInt j = 0; j < s; j++)
          for (PetscInt i = 0; i + j < s; i++)
            for (PetscInt up = 1; up >= 0; up--) {
              /* the corners (i, j) of the grid P(i, j) = p0 + i (p1 - p0)/s + j (p2 - p0)/s: the triangle pointing
                 up ((i,j), (i+1,j), (i,j+1)), and the one pointing down ((i+1,j), (i+1,j+1), (i,j+1)) */
              const PetscInt ij[3][2] = {{i + !up, j}, {i + 1, j + !up}, {i, j + 1}};
              PetscReal      q[3][3];
              if (!up && i + j + 2 > s) continue;
              for (PetscInt k = 0; k < 3; k++)
                for (PetscInt d = 0; d < 3; d++)
                  q[k][d] = ((s - ij[k][0] - ij[k][1]) * p0[d] + ij[k][0] * p1[d] + ij[k][1] * p2[d]) / s;
              PetscCall(AddElement(m, t, q[0], q[1], q[2], n, lo, hi, store));
            }
      } else {
        for (PetscInt j = 0; j < sp->m2; j++)
          for (PetscInt i = 0; i < sp->m1; i++) {
            PetscReal      uv[5][2], q[5][3];
            const PetscInt nc = GridCell(sp, i, j, uv);
            if (nc < 3) continue;
            for (PetscInt k = 0; k < nc; k++)
              for (PetscInt d = 0; d < 3; d++) q[k][d] = a[d] + uv[k][0] * (b[d] - a[d]) + uv[k][1] * (c[d] - a[d]);
            if (nc == 4) { /* a whole cell: cut along its shorter diagonal */
              if (sp->cosA >= 0) {
                PetscCall(AddElement(m, t, q[0], q[1], q[3], n, lo, hi, store));
                PetscCall(AddElement(m, t, q[1], q[2], q[3], n, lo, hi, store));
              } else {
                PetscCall(AddElement(m, t, q[0], q[1], q[2], n, lo, hi, store));
                PetscCall(AddElement(m, t, q[0], q[2], q[3], n, lo, hi, store));
              }
            } else
              for (PetscInt k = 1; k + 1 < nc; k++) PetscCall(AddElement(m, t, q[0], q[k], q[k + 1], n, lo, hi, store));
          }
      }
      if (!store) inbox[t] = (PetscBool)(m->nel > before);
    }
  }
  PetscCall(PetscFree(inbox));
  PetscCheck(m->nelglobal == nel && (lo || m->nel == nel), PETSC_COMM_SELF, PETSC_ERR_PLIB,
             "%" PetscInt_FMT " elements made, %" PetscInt64_FMT " counted", m->nelglobal, nel);
  PetscCall(PetscFree2(split, count));
  PetscFunctionReturn(0);
}

/*
   FSMeshLiquidBelow - the volume of the liquid region of the checked mesh m in the column lo[0] <= x <= hi[0],
   lo[2] <= z <= hi[2] (lo[1], hi[1] unused) below the level y = t, and its moment about the level, the integral
   of t - y over it: exact for any closed meshes.

   Not collective

   Notes:
   The divergence theorem with F = (0, y - t, 0) (div F = 1) for the volume and F = (0, -(y - t)^2 / 2, 0)
   (div F = t - y) for the moment: F vanishes on the plane y = t and F . n on the column's sides, so both are
   integrals over the triangles clipped to the column below t alone (no cap), their normals pointing out of the
   liquid (FSMeshCheck turns the obstacles so).

.seealso: FSMeshCheck(), FSWallsLiquidBelow()
*/
void FSMeshLiquidBelow(const FSMesh *m, const PetscReal lo[], const PetscReal hi[], PetscReal t, PetscReal *vol,
                       PetscReal *moment)
{
  *vol    = 0;
  *moment = 0;
  for (PetscInt tr = 0; tr < m->ntri; tr++) {
    PetscReal p[2][10][3]; /* the polygon, clipped by one plane after the other (3 + 5 vertices at most) */
    PetscInt  np = 3, cur = 0;
    for (PetscInt k = 0; k < 3; k++)
      for (PetscInt d = 0; d < 3; d++) p[0][k][d] = m->vert[3 * m->tri[3 * tr + k] + d];
    /* the half-spaces x >= lo[0], x <= hi[0], z >= lo[2], z <= hi[2], y <= t: f(v) = sign (v[axis] - level) >= 0 */
    for (PetscInt c = 0; c < 5 && np > 0; c++) {
      const PetscInt  axis = c < 2 ? 0 : c < 4 ? 2 : 1;
      const PetscReal sg = c % 2 || c == 4 ? -1 : 1, level = c == 4 ? t : c % 2 ? hi[axis] : lo[axis];
      PetscInt        nq = 0;
      for (PetscInt k = 0; k < np; k++) {
        const PetscReal *a = p[cur][k], *b = p[cur][(k + 1) % np];
        const PetscReal  fa = sg * (a[axis] - level), fb = sg * (b[axis] - level);
        if (fa >= 0) {
          for (PetscInt d = 0; d < 3; d++) p[1 - cur][nq][d] = a[d];
          nq++;
        }
        if ((fa >= 0) != (fb >= 0)) {
          const PetscReal s = fa / (fa - fb);
          for (PetscInt d = 0; d < 3; d++) p[1 - cur][nq][d] = a[d] + s * (b[d] - a[d]);
          p[1 - cur][nq++][axis] = level;
        }
      }
      np  = nq;
      cur = 1 - cur;
    }
    /* the fan of triangles of the clipped polygon: n_y dA is the y component of half the cross product */
    for (PetscInt k = 1; k + 1 < np; k++) {
      const PetscReal *a = p[cur][0], *b = p[cur][k], *c = p[cur][k + 1];
      const PetscReal  ay = 0.5 * ((b[2] - a[2]) * (c[0] - a[0]) - (b[0] - a[0]) * (c[2] - a[2]));
      const PetscReal  ya = a[1] - t, yb = b[1] - t, yc = c[1] - t;
      *vol += ay * (ya + yb + yc) / 3;
      *moment -= 0.5 * ay * (ya * ya + yb * yb + yc * yc + ya * yb + yb * yc + yc * ya) / 6;
    }
  }
}
