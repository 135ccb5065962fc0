/*
   Unit tests of the 3-D wall meshes (src/boundary/impls/trimesh/mesh.h):
   - the extruded built-in tanks: a rectangular tank (12 triangles, 8 vertices, volume L H W), the
     baffled tank with baffles on the floor (part of the outline) and with free-standing baffles (the
     obstacle polygons make tunnels: a surface of genus 6) pass FSMeshCheck, enclose the 2-D area times
     the width, have the surface area of the outline and the Euler characteristic 2 - 2 genus;
   - FSMeshRefine: every element's edges at most hmax, at most m^2 elements per triangle (far fewer on a thin box's
     sliver faces), the areas add up, the elements are oriented as their triangle, sum n dS = 0 and sum (x.n) dS / 3 =
     the volume;
   - the geometry of one triangle: solid angles of a cube's faces (4 pi from inside, 0 from outside,
     2 pi on a face, 4 pi / 6 one face from the centre), the distance against brute-force sampling in
     the vertex, edge and face regions, the segment crossings;
   - FSMeshInLiquid and FSMeshDistance in the tanks (inside a baffle is not liquid, the gap under it is);
   - STL files (written by rank 0, read by all ranks: the reader broadcasts): ASCII with two named
     solids (the inner one, with outward normals, is turned inside out by FSMeshCheck), an unnamed
     solid, binary with a header starting with "solid", a 50k-triangle rotated mesh (timed);
   - bad input, each an error whose message names the file and the triangle, line or size: an open
     mesh, an inside-out cube, a reversed triangle, two intersecting cubes, a baffle standing on the
     floor (coplanar faces overlapping), a degenerate triangle, an obstacle outside the container, a
     binary file of the wrong size, a truncated ASCII file, an unparsable number, a missing file; an
     extrusion of a slanted edge, a width of 0.
   -verbose_errors prints the message of each expected error; -n <64> sets the squares per side of each
   face of the large mesh's box (12 n^2 triangles).
*/
#include <stdint.h>
#include <string.h>
#include "boundary/impls/trimesh/mesh.h"
#include "../tempdir.h"

#define TCHECK(cond, ...) PetscCheck(cond, PETSC_COMM_SELF, PETSC_ERR_PLIB, "test_mesh: " __VA_ARGS__)

static PetscBool verbose_errors_ = PETSC_FALSE;

/* the message of error ierr (from `what`) must contain every string of must[] (NULL-terminated) */
static PetscErrorCode CheckMessage(PetscErrorCode ierr, const char what[], const char *must[])
{
  char *msg = NULL;

  PetscFunctionBegin;
  TCHECK(ierr != 0, "%s must fail", what);
  PetscCall(PetscErrorMessage(ierr, NULL, &msg));
  if (verbose_errors_) PetscCall(PetscPrintf(PETSC_COMM_WORLD, "expected error %d: %s\n", (int)ierr, msg ? msg : ""));
  for (PetscInt k = 0; must[k]; k++)
    TCHECK(msg && strstr(msg, must[k]), "the error of %s must name \"%s\": \"%s\"", what, must[k],
           msg ? msg : "(none)");
  PetscFunctionReturn(0);
}

/* calls `call`, which must fail with a message containing each of the strings that follow */
#define EXPECT_ERROR(call, ...)                                      \
  do {                                                               \
    const char    *must_[] = {__VA_ARGS__, NULL};                    \
    PetscErrorCode ierr_;                                            \
    PetscCall(PetscPushErrorHandler(PetscReturnErrorHandler, NULL)); \
    ierr_ = (call);                                                  \
    PetscCall(PetscPopErrorHandler());                               \
    PetscCall(CheckMessage(ierr_, #call, must_));                    \
  } while (0)

static PetscReal Rel(PetscReal a, PetscReal b) { return PetscAbsReal(a - b) / PetscAbsReal(b); }

static void TriangleNormal(const PetscReal a[], const PetscReal b[], const PetscReal c[], PetscReal n[])
{
  const PetscReal u[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]}, v[3] = {c[0] - a[0], c[1] - a[1], c[2] - a[2]};
  n[0] = u[1] * v[2] - u[2] * v[1];
  n[1] = u[2] * v[0] - u[0] * v[2];
  n[2] = u[0] * v[1] - u[1] * v[0];
}

static PetscReal Norm(const PetscReal n[]) { return PetscSqrtReal(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]); }

/* the area of input triangle t, and the signed volume a.(b x c)/6 of the triangles of wall w (all: w < 0) */
static PetscReal TriangleArea(const FSMesh *m, PetscInt t)
{
  PetscReal n[3];
  TriangleNormal(&m->vert[3 * m->tri[3 * t]], &m->vert[3 * m->tri[3 * t + 1]], &m->vert[3 * m->tri[3 * t + 2]], n);
  return 0.5 * Norm(n);
}

static PetscReal WallVolume(const FSMesh *m, PetscInt w)
{
  PetscReal v = 0;
  for (PetscInt t = 0; t < m->ntri; t++) {
    const PetscReal *a = &m->vert[3 * m->tri[3 * t]], *b = &m->vert[3 * m->tri[3 * t + 1]];
    const PetscReal *c = &m->vert[3 * m->tri[3 * t + 2]];
    if (w >= 0 && m->triwall[t] != w) continue;
    v += (a[0] * (b[1] * c[2] - b[2] * c[1]) - a[1] * (b[0] * c[2] - b[2] * c[0]) +
          a[2] * (b[0] * c[1] - b[1] * c[0])) /
         6;
  }
  return v;
}

static PetscInt WallIndex(const FSMesh *m, const char name[])
{
  for (PetscInt w = 0; w < m->nwalls; w++)
    if (!strcmp(m->name[w], name)) return w;
  return -1;
}

/* ---------------------------------------------------------------------------------------------- */
/* extruded tanks                                                                                  */

/* the baffled tank of the seed (7 compartments of 0.1, 5 mm baffles, H 0.06) extruded over width W */
static PetscErrorCode BaffledMesh(MPI_Comm comm, PetscReal gap, PetscReal hb, PetscReal W, FSMesh *m, PetscReal *area2d,
                                  PetscReal *perimeter)
{
  FSWalls w;

  PetscFunctionBegin;
  PetscCall(FSWallsCreate(&w));
  PetscCall(FSWallsBaffledTank(&w, comm, 7, 0.1, 0.005, 0.06, gap, hb));
  PetscCall(FSWallsCheck(&w, comm));
  *area2d = *perimeter = 0;
  for (PetscInt p = 0; p < w.npoly; p++) {
    *area2d += w.area[p];
    for (PetscInt v = w.pstart[p]; v < w.pstart[p + 1]; v++) {
      const PetscInt v1 = v + 1 < w.pstart[p + 1] ? v + 1 : w.pstart[p];
      *perimeter += PetscSqrtReal(PetscSqr(w.vert[2 * v1] - w.vert[2 * v]) +
                                  PetscSqr(w.vert[2 * v1 + 1] - w.vert[2 * v + 1]));
    }
  }
  PetscCall(FSMeshCreate(m));
  PetscCall(FSMeshExtrude(m, comm, &w, W));
  PetscCall(FSWallsDestroy(&w));
  PetscFunctionReturn(0);
}

/* the rectangular tank L x H (FSWallsRectangularTank) extruded W wide, checked */
static PetscErrorCode BoxMesh(MPI_Comm comm, PetscReal L, PetscReal H, PetscReal W, FSMesh *m)
{
  FSWalls w;

  PetscFunctionBegin;
  PetscCall(FSWallsCreate(&w));
  PetscCall(FSWallsRectangularTank(&w, comm, L, H));
  PetscCall(FSWallsCheck(&w, comm));
  PetscCall(FSMeshCreate(m));
  PetscCall(FSMeshExtrude(m, comm, &w, W));
  PetscCall(FSWallsDestroy(&w));
  PetscCall(FSMeshCheck(m, comm));
  PetscFunctionReturn(0);
}

/* FSMeshLiquidBelow against the volumes and moments by hand: the box tank whole and in a column, and the baffled
   tank with free-standing baffles (obstacles) */
static PetscErrorCode TestLiquidBelow(MPI_Comm comm)
{
  FSMesh          m;
  const PetscReal all[2][3] = {{-1, 0, -1}, {1, 0, 1}}, col[2][3] = {{0.1, 0, 0.02}, {0.3, 0, 0.05}};
  PetscReal       v, q, area2d, perimeter;

  PetscFunctionBegin;
  PetscCall(BoxMesh(comm, 0.7, 0.06, 0.1, &m));
  FSMeshLiquidBelow(&m, all[0], all[1], 0.03, &v, &q);
  TCHECK(Rel(v, 0.7 * 0.1 * 0.03) < 1e-14 && Rel(q, 0.7 * 0.1 * 0.03 * 0.015) < 1e-14, "box below 0.03: %g, %g",
         (double)v, (double)q);
  FSMeshLiquidBelow(&m, col[0], col[1], 0.03, &v, &q);
  TCHECK(Rel(v, 0.2 * 0.03 * 0.03) < 1e-14 && Rel(q, 0.2 * 0.03 * 0.03 * 0.015) < 1e-14, "box's column: %g, %g",
         (double)v, (double)q);
  PetscCall(FSMeshDestroy(&m));
  PetscCall(BaffledMesh(comm, 0.01, 0.04, 0.1, &m, &area2d, &perimeter));
  PetscCall(FSMeshCheck(&m, comm));
  FSMeshLiquidBelow(&m, all[0], all[1], 0.03, &v, &q);
  TCHECK(Rel(v, 0.1 * (0.73 * 0.03 - 6 * 0.005 * 0.02)) < 1e-14 &&
             Rel(q, 0.1 * (0.73 * 0.03 * 0.015 - 6 * 0.005 * 0.02 * 0.01)) < 1e-14,
         "baffled tank below 0.03: %g, %g", (double)v, (double)q);
  PetscCall(FSMeshDestroy(&m));
  PetscFunctionReturn(0);
}

static PetscErrorCode TestExtrude(MPI_Comm comm)
{
  const PetscReal L = 0.7, H = 0.06, W = 0.1;
  FSWalls         w;
  FSMesh          m;
  PetscReal       area2d, perim, area;

  PetscFunctionBegin;
  /* the rectangular tank: a box of 12 triangles on 8 shared vertices */
  PetscCall(BoxMesh(comm, L, H, W, &m));
  TCHECK(m.ntri == 12 && m.nvert == 8 && m.nwalls == 1 && !strcmp(m.name[0], "tank"),
         "rectangular tank: %" PetscInt_FMT " triangles, %" PetscInt_FMT " vertices, %" PetscInt_FMT
         " walls; expected 12, 8, 1 (\"tank\")",
         m.ntri, m.nvert, m.nwalls);
  TCHECK(Rel(m.volume, L * H * W) < 1e-12, "rectangular tank: volume %.15g, expected L H W = %.15g", (double)m.volume,
         (double)(L * H * W));
  TCHECK(m.lo[0] == 0 && m.lo[1] == 0 && m.lo[2] == 0 && m.hi[0] == L && m.hi[1] == H && m.hi[2] == W,
         "rectangular tank: bounding box (%g %g %g)-(%g %g %g)", (double)m.lo[0], (double)m.lo[1], (double)m.lo[2],
         (double)m.hi[0], (double)m.hi[1], (double)m.hi[2]);
  for (PetscInt t = 0; t < m.ntri; t++)
    TCHECK(m.trisrc[t] == t, "triangle %" PetscInt_FMT ": source number %" PetscInt_FMT, t, m.trisrc[t]);
  PetscCall(FSMeshDestroy(&m));
  /* errors: a width of 0, a slanted edge */
  PetscCall(FSWallsCreate(&w));
  PetscCall(FSWallsRectangularTank(&w, comm, L, H));
  PetscCall(FSWallsCheck(&w, comm));
  PetscCall(FSMeshCreate(&m));
  EXPECT_ERROR(FSMeshExtrude(&m, comm, &w, 0.0), "-fs_tank_width");
  PetscCall(FSMeshDestroy(&m));
  PetscCall(FSWallsDestroy(&w));
  {
    const PetscReal xy[8] = {0, 0, 1, 0, 1, 0.5, 0, 1}; /* a slanted lid */
    PetscCall(FSWallsCreate(&w));
    PetscCall(FSWallsAddPolygon(&w, comm, "tank", 4, xy, "test"));
    PetscCall(FSMeshCreate(&m));
    EXPECT_ERROR(FSMeshExtrude(&m, comm, &w, W), "neither horizontal nor vertical", "STL");
    PetscCall(FSMeshDestroy(&m));
    PetscCall(FSWallsDestroy(&w));
  }

  /* baffles on the floor (part of the outline: genus 0), then free-standing (obstacles: 6 tunnels) */
  for (PetscInt k = 0; k < 2; k++) {
    const PetscReal gap = k ? 0.01 : 0, hb = k ? 0.04 : 0.03;
    const PetscInt  genus = k ? 6 : 0;
    PetscCall(BaffledMesh(comm, gap, hb, W, &m, &area2d, &perim));
    PetscCall(FSMeshCheck(&m, comm));
    TCHECK(Rel(m.volume, area2d * W) < 1e-12, "baffled tank (gap %g): volume %.15g, expected the area %.15g times W",
           (double)gap, (double)m.volume, (double)area2d);
    TCHECK(2 * m.nvert - m.ntri == 2 * (2 - 2 * genus),
           "baffled tank (gap %g): V - E + F = %" PetscInt_FMT " - %" PetscInt_FMT " + %" PetscInt_FMT
           ", expected 2 - 2 x %" PetscInt_FMT,
           (double)gap, m.nvert, 3 * m.ntri / 2, m.ntri, genus);
    area = 0;
    for (PetscInt t = 0; t < m.ntri; t++) area += TriangleArea(&m, t);
    TCHECK(Rel(area, 2 * area2d + perim * W) < 1e-12, "baffled tank (gap %g): surface area %.15g, expected %.15g",
           (double)gap, (double)area, (double)(2 * area2d + perim * W));
    if (k) {
      const PetscInt b  = WallIndex(&m, "baffles");
      PetscReal      ab = 0;
      TCHECK(m.nwalls == 2 && b == 1, "free-standing baffles: %" PetscInt_FMT " walls, \"baffles\" %" PetscInt_FMT,
             m.nwalls, b);
      for (PetscInt t = 0; t < m.ntri; t++)
        if (m.triwall[t] == b) ab += TriangleArea(&m, t);
      TCHECK(Rel(ab, 6 * 2 * (0.005 + 0.04) * W) < 1e-12, "the baffles' side area %.15g, expected %.15g", (double)ab,
             (double)(6 * 2 * (0.005 + 0.04) * W));
    }
    PetscCall(FSMeshDestroy(&m));
  }
  PetscFunctionReturn(0);
}

/* the elements of a checked mesh against its triangles: at most m^2 for each (m = ceil(longest edge / hmax): its
   similar split), the split's element count returned in *similar */
static PetscErrorCode CheckElements(const FSMesh *m, PetscReal hmax, PetscInt *similar)
{
  PetscInt  expect = 0, *count;
  PetscReal area = 0, elarea = 0, vecarea[3] = {0, 0, 0}, vol = 0, *tarea;

  PetscFunctionBegin;
  PetscCall(PetscCalloc2(m->ntri, &count, m->ntri, &tarea));
  for (PetscInt e = 0; e < m->nel; e++) {
    count[m->eltri[e]]++;
    tarea[m->eltri[e]] += m->el[e * FS_TRI_STRIDE + FS_TRI_AREA];
  }
  for (PetscInt t = 0; t < m->ntri; t++) {
    PetscReal L = 0;
    PetscInt  ms;
    for (PetscInt k = 0; k < 3; k++) {
      const PetscReal *a = &m->vert[3 * m->tri[3 * t + k]], *b = &m->vert[3 * m->tri[3 * t + (k + 1) % 3]];
      L = PetscMax(L, PetscSqrtReal(PetscSqr(b[0] - a[0]) + PetscSqr(b[1] - a[1]) + PetscSqr(b[2] - a[2])));
    }
    ms = (PetscInt)PetscMax(1, PetscCeilReal(L / hmax));
    expect += ms * ms;
    area += TriangleArea(m, t);
    TCHECK(count[t] >= 1 && count[t] <= ms * ms,
           "hmax %g: triangle %" PetscInt_FMT " has %" PetscInt_FMT " elements, at most m^2 = %" PetscInt_FMT
           " expected",
           (double)hmax, t, count[t], ms * ms);
    TCHECK(Rel(tarea[t], TriangleArea(m, t)) < 1e-12,
           "hmax %g: triangle %" PetscInt_FMT "'s elements cover %.15g of %.15g", (double)hmax, t, (double)tarea[t],
           (double)TriangleArea(m, t));
  }
  PetscCall(PetscFree2(count, tarea));
  *similar = expect;
  for (PetscInt e = 0; e < m->nel; e++) {
    const PetscReal *r = &m->el[e * FS_TRI_STRIDE], *n = &r[FS_TRI_NORMAL];
    const PetscInt   t = m->eltri[e];
    PetscReal        ne[3], nt[3];
    for (PetscInt k = 0; k < 3; k++) {
      const PetscReal *a = &r[3 * k], *b = &r[3 * ((k + 1) % 3)];
      const PetscReal  l = PetscSqrtReal(PetscSqr(b[0] - a[0]) + PetscSqr(b[1] - a[1]) + PetscSqr(b[2] - a[2]));
      TCHECK(l <= hmax * (1 + 1e-12), "element %" PetscInt_FMT ": an edge of %g, longer than hmax %g", e, (double)l,
             (double)hmax);
    }
    TriangleNormal(&r[FS_TRI_P0], &r[FS_TRI_P1], &r[FS_TRI_P2], ne);
    TriangleNormal(&m->vert[3 * m->tri[3 * t]], &m->vert[3 * m->tri[3 * t + 1]], &m->vert[3 * m->tri[3 * t + 2]], nt);
    TCHECK(PetscAbsReal(Norm(n) - 1) < 1e-14 && PetscAbsReal(0.5 * Norm(ne) - r[FS_TRI_AREA]) < 1e-14 * r[FS_TRI_AREA],
           "element %" PetscInt_FMT ": |n| = %.17g, area %g for %g", e, (double)Norm(n), (double)r[FS_TRI_AREA],
           (double)(0.5 * Norm(ne)));
    for (PetscInt d = 0; d < 3; d++) {
      TCHECK(PetscAbsReal(ne[d] / Norm(ne) - n[d]) < 1e-12 && PetscAbsReal(nt[d] / Norm(nt) - n[d]) < 1e-12,
             "element %" PetscInt_FMT " is not oriented as its triangle %" PetscInt_FMT, e, t);
      TCHECK(PetscAbsReal(r[FS_TRI_CENTROID + d] - (r[d] + r[3 + d] + r[6 + d]) / 3) < 1e-15,
             "element %" PetscInt_FMT ": centroid", e);
      vecarea[d] += n[d] * r[FS_TRI_AREA];
      vol += r[FS_TRI_CENTROID + d] * n[d] * r[FS_TRI_AREA] / 3;
    }
    TCHECK(m->elwall[e] == m->triwall[t],
           "element %" PetscInt_FMT ": wall %" PetscInt_FMT " of triangle wall %" PetscInt_FMT, e, m->elwall[e],
           m->triwall[t]);
    elarea += r[FS_TRI_AREA];
  }
  TCHECK(Rel(elarea, area) < 1e-12, "hmax %g: the elements' area %.15g, the triangles' %.15g", (double)hmax,
         (double)elarea, (double)area);
  TCHECK(Norm(vecarea) < 1e-13 * area, "hmax %g: sum n dS = (%g, %g, %g) of a closed surface", (double)hmax,
         (double)vecarea[0], (double)vecarea[1], (double)vecarea[2]);
  TCHECK(Rel(vol, m->volume) < 1e-12, "hmax %g: sum (x.n) dS / 3 = %.15g, the volume %.15g", (double)hmax, (double)vol,
         (double)m->volume);
  PetscFunctionReturn(0);
}

static PetscErrorCode TestRefine(MPI_Comm comm)
{
  FSMesh    m;
  PetscReal a, p;
  PetscInt  similar;

  PetscFunctionBegin;
  /* a long, low, narrow box (the seed's rectangular tank 0.05 m wide): its faces' halves are slivers, split on a
     grid along their short edges; measured 7,768 elements where similar triangles would make 40,584 */
  {
    PetscCall(BoxMesh(comm, 0.7, 0.06, 0.05, &m));
    PetscCall(FSMeshRefine(&m, 0.01));
    PetscCall(CheckElements(&m, 0.01, &similar));
    TCHECK(similar == 40584 && m.nel < similar / 5,
           "the thin box: %" PetscInt_FMT " elements, %" PetscInt_FMT " similar", m.nel, similar);
    PetscCall(PetscPrintf(comm,
                          "  thin box 0.7 x 0.06 x 0.05 at hmax 0.01: %" PetscInt_FMT
                          " elements (similar split %" PetscInt_FMT ")\n",
                          m.nel, similar));
    PetscCall(FSMeshDestroy(&m));
  }
  PetscCall(BaffledMesh(comm, 0.01, 0.04, 0.1, &m, &a, &p));
  PetscCall(FSMeshCheck(&m, comm));
  PetscCall(FSMeshRefine(&m, 0.02));
  PetscCall(CheckElements(&m, 0.02, &similar));
  PetscCall(FSMeshRefine(&m, 0.013)); /* again: the elements replaced */
  PetscCall(CheckElements(&m, 0.013, &similar));
  PetscCall(FSMeshRefine(&m, 1.0)); /* one element per triangle */
  PetscCall(CheckElements(&m, 1.0, &similar));
  TCHECK(m.nel == m.ntri, "hmax 1: %" PetscInt_FMT " elements for %" PetscInt_FMT " triangles", m.nel, m.ntri);
  /* the end faces: -z at z = 0, +z at z = W */
  {
    PetscInt ends = 0;
    for (PetscInt e = 0; e < m.nel; e++) {
      const PetscReal *r = &m.el[e * FS_TRI_STRIDE];
      if (r[2] == 0 && r[5] == 0 && r[8] == 0) {
        TCHECK(r[FS_TRI_NORMAL + 2] == -1, "an element at z = 0 with normal z %g", (double)r[FS_TRI_NORMAL + 2]);
        ends++;
      }
      if (PetscAbsReal(r[2] - 0.1) < 1e-15 && PetscAbsReal(r[5] - 0.1) < 1e-15 && PetscAbsReal(r[8] - 0.1) < 1e-15) {
        TCHECK(r[FS_TRI_NORMAL + 2] == 1, "an element at z = W with normal z %g", (double)r[FS_TRI_NORMAL + 2]);
        ends++;
      }
    }
    TCHECK(ends > 0 && ends % 2 == 0, "%" PetscInt_FMT " elements on the end faces", ends);
  }
  PetscCall(FSMeshDestroy(&m));
  PetscFunctionReturn(0);
}

/* ---------------------------------------------------------------------------------------------- */
/* one triangle's geometry                                                                         */

/* the 12 triangles (9 coordinates each) of the box [lo, hi], normals outwards (inwards if !outward) */
static void BoxTriangles(const PetscReal lo[3], const PetscReal hi[3], PetscBool outward, PetscReal t[12][9])
{
  /* the corners: bit 0 x, bit 1 y, bit 2 z; the faces counter-clockwise seen from outside */
  static const int face[6][4] = {{0, 4, 6, 2}, {1, 3, 7, 5}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 2, 3, 1}, {4, 5, 7, 6}};
  for (PetscInt f = 0; f < 6; f++)
    for (PetscInt h = 0; h < 2; h++) {
      const int c[3] = {face[f][0], face[f][1 + h], face[f][2 + h]};
      for (PetscInt k = 0; k < 3; k++) {
        const int corner = c[outward ? k : (3 - k) % 3];
        for (PetscInt d = 0; d < 3; d++) t[2 * f + h][3 * k + d] = (corner >> d) & 1 ? hi[d] : lo[d];
      }
    }
}

static PetscReal BoxAngle(PetscReal t[][9], PetscInt n, const PetscReal x[])
{
  PetscReal s = 0;
  for (PetscInt k = 0; k < n; k++) s += FSTriangleSolidAngle(&t[k][0], &t[k][3], &t[k][6], x);
  return s;
}

static PetscErrorCode TestSolidAngle(void)
{
  const PetscReal lo[3] = {0, 0, 0}, hi[3] = {1, 1, 1}, in[3] = {0.3, 0.4, 0.6}, out[3] = {2, 0.5, 0.5};
  const PetscReal centre[3] = {0.5, 0.5, 0.5}, face[3] = {0.5, 0.5, 0}, above[3] = {0.5, 0.5, 1e-9},
                  below[3] = {0.5, 0.5, -1e-9};
  PetscReal t[12][9], s;

  PetscFunctionBegin;
  BoxTriangles(lo, hi, PETSC_TRUE, t);
  s = BoxAngle(t, 12, in);
  TCHECK(PetscAbsReal(s - 4 * PETSC_PI) < 1e-12, "cube from inside: %.15g, expected 4 pi", (double)s);
  s = BoxAngle(t, 12, out);
  TCHECK(PetscAbsReal(s) < 1e-12, "cube from outside: %.15g, expected 0", (double)s);
  s = BoxAngle(t, 2, centre); /* face 0 (x = 0) */
  TCHECK(PetscAbsReal(s - 4 * PETSC_PI / 6) < 1e-12, "one face from the centre: %.15g, expected 4 pi / 6", (double)s);
  { /* the faces but z = 0 (triangles 8, 9) from the centre of z = 0 */
    PetscReal rest = 0;
    for (PetscInt k = 0; k < 12; k++)
      if (k != 8 && k != 9) rest += FSTriangleSolidAngle(&t[k][0], &t[k][3], &t[k][6], face);
    TCHECK(PetscAbsReal(rest - 2 * PETSC_PI) < 1e-12, "the other faces from a face's centre: %.15g, expected 2 pi",
           (double)rest);
  }
  s = BoxAngle(&t[8], 2, above);
  TCHECK(PetscAbsReal(s - 2 * PETSC_PI) < 1e-6, "a face from just inside its centre: %.15g, expected 2 pi", (double)s);
  s = BoxAngle(&t[8], 2, below);
  TCHECK(PetscAbsReal(s + 2 * PETSC_PI) < 1e-6, "a face from just outside its centre: %.15g, expected -2 pi",
         (double)s);
  s = BoxAngle(t, 12, below);
  TCHECK(PetscAbsReal(s) < 1e-6, "cube from just outside a face: %.15g, expected 0", (double)s);
  BoxTriangles(lo, hi, PETSC_FALSE, t);
  s = BoxAngle(t, 12, in);
  TCHECK(PetscAbsReal(s + 4 * PETSC_PI) < 1e-12, "inside-out cube from inside: %.15g, expected -4 pi", (double)s);
  PetscFunctionReturn(0);
}

static PetscErrorCode TestDistance(void)
{
  const PetscReal a[3] = {0.1, 0.2, 0.3}, b[3] = {1.3, 0.1, -0.2}, c[3] = {0.4, 1.1, 0.5};
  const PetscInt  N = 500;
  PetscReal       n[3], nn, x[12][3], perim = 0;
  PetscInt        np   = 0;
  unsigned int    seed = 12345;

  PetscFunctionBegin;
  TriangleNormal(a, b, c, n);
  nn = Norm(n);
  for (PetscInt d = 0; d < 3; d++) {
    x[np][d]     = a[d] - 0.3 * (b[d] - a[d]) - 0.3 * (c[d] - a[d]) + 0.2 * n[d] / nn;         /* vertex a */
    x[np + 1][d] = b[d] + 0.4 * (b[d] - a[d]) + 0.1 * (b[d] - c[d]);                           /* vertex b */
    x[np + 2][d] = c[d] + 0.2 * (c[d] - a[d]) + 0.2 * (c[d] - b[d]) - 0.3 * n[d] / nn;         /* vertex c */
    x[np + 3][d] = 0.5 * (a[d] + b[d]) - 0.3 * (c[d] - 0.5 * (a[d] + b[d])) + 0.1 * n[d] / nn; /* edge ab */
    x[np + 4][d] = 0.5 * (b[d] + c[d]) + 0.5 * (0.5 * (b[d] + c[d]) - a[d]) - 0.2 * n[d] / nn; /* edge bc */
    x[np + 5][d] = 0.3 * a[d] + 0.7 * c[d] - 0.4 * (b[d] - 0.3 * a[d] - 0.7 * c[d]);           /* edge ca */
    x[np + 6][d] = (a[d] + b[d] + c[d]) / 3 + 0.25 * n[d] / nn;                                /* the face */
  }
  np += 7;
  {
    const PetscReal ab[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]}, bc[3] = {c[0] - b[0], c[1] - b[1], c[2] - b[2]};
    const PetscReal ca[3] = {a[0] - c[0], a[1] - c[1], a[2] - c[2]};
    perim                 = Norm(ab) + Norm(bc) + Norm(ca);
  }
  for (; np < 12; np++)
    for (PetscInt d = 0; d < 3; d++) {
      seed     = 1103515245u * seed + 12345u;
      x[np][d] = -0.5 + 2.0 * (seed >> 8) / 16777216.0;
    }
  /* exact in the face region (the height) and at a vertex */
  {
    PetscReal d2 = FSTriangleDistance2(a, b, c, x[6]), da[3];
    TCHECK(PetscAbsReal(d2 - 0.0625) < 1e-14, "above the face: %.17g, expected 0.25^2", (double)d2);
    d2 = FSTriangleDistance2(a, b, c, x[0]);
    for (PetscInt d = 0; d < 3; d++) da[d] = x[0][d] - a[d];
    TCHECK(PetscAbsReal(d2 - PetscSqr(Norm(da))) < 1e-14, "the vertex region of a: %.17g, expected %.17g", (double)d2,
           (double)PetscSqr(Norm(da)));
  }
  for (PetscInt k = 0; k < np; k++) {
    const PetscReal d2 = FSTriangleDistance2(a, b, c, x[k]),
                    h  = perim / N; /* no point of the triangle farther from the samples */
    PetscReal best     = PETSC_MAX_REAL;
    for (PetscInt i = 0; i <= N; i++)
      for (PetscInt j = 0; i + j <= N; j++) {
        PetscReal y[3], r = 0;
        for (PetscInt d = 0; d < 3; d++) {
          y[d] = a[d] + (b[d] - a[d]) * i / N + (c[d] - a[d]) * j / N;
          r += PetscSqr(x[k][d] - y[d]);
        }
        best = PetscMin(best, r);
      }
    TCHECK(d2 <= best + 1e-14 && best <= PetscSqr(PetscSqrtReal(d2) + h) + 1e-14,
           "point %" PetscInt_FMT ": squared distance %.12g, brute force %.12g", k, (double)d2, (double)best);
  }
  /* segment crossings */
  {
    const PetscReal p[3] = {0, 0, 0}, q[3] = {1, 0, 0}, r[3] = {0, 1, 0};
    const PetscReal s[][6] = {
        {0.2, 0.2, -1, 0.2, 0.2, 1},   /* through: crosses */
        {0.2, 0.2, 1, 0.3, 0.1, -1},   /* through, the other way */
        {0.8, 0.8, -1, 0.8, 0.8, 1},   /* beside */
        {0.2, 0.2, 0, 0.2, 0.2, 1},    /* an end on the triangle: touches */
        {0.5, 0, -1, 0.5, 0, 1},       /* through an edge: touches */
        {0, 0, -1, 0, 0, 1},           /* through a vertex */
        {0.2, 0.2, 0.1, 0.3, 0.3, 1},  /* on one side */
        {-1, 0.2, 0, 2, 0.2, 0},       /* in the plane */
        {0.2, 0.2, -1, 0.2, 0.2, -0.5} /* short of it */
    };
    const PetscBool expect[] = {PETSC_TRUE,  PETSC_TRUE,  PETSC_FALSE, PETSC_FALSE, PETSC_FALSE,
                                PETSC_FALSE, PETSC_FALSE, PETSC_FALSE, PETSC_FALSE};
    for (PetscInt k = 0; k < 9; k++)
      TCHECK(FSTriangleCrossesSegment(p, q, r, &s[k][0], &s[k][3]) == expect[k],
             "segment %" PetscInt_FMT ": crossing %d, expected %d", k, (int)!expect[k], (int)expect[k]);
  }
  PetscFunctionReturn(0);
}

static PetscErrorCode TestInLiquid(MPI_Comm comm)
{
  FSMesh    m;
  PetscReal a, p;

  PetscFunctionBegin;
  /* free-standing baffles: x in [0.1, 0.105], y in [0.01, 0.05] */
  PetscCall(BaffledMesh(comm, 0.01, 0.04, 0.1, &m, &a, &p));
  PetscCall(FSMeshCheck(&m, comm));
  {
    const PetscReal inside[3] = {0.05, 0.03, 0.05}, baffle[3] = {0.1025, 0.03, 0.05}, gap[3] = {0.1025, 0.005, 0.05};
    const PetscReal front[3] = {0.05, 0.03, -0.01}, right[3] = {0.75, 0.03, 0.05}, near[3] = {0.099, 0.03, 0.05};
    const PetscReal low[3] = {0.3, 0.01, 0.05};
    TCHECK(FSMeshInLiquid(&m, inside, 0), "a point in a compartment must be in the liquid");
    TCHECK(!FSMeshInLiquid(&m, baffle, 0), "a point inside a baffle must not be in the liquid");
    TCHECK(FSMeshInLiquid(&m, gap, 0), "a point in the gap under a baffle must be in the liquid");
    TCHECK(!FSMeshInLiquid(&m, front, 0) && !FSMeshInLiquid(&m, right, 0), "points outside the tank are not liquid");
    TCHECK(PetscAbsReal(FSMeshDistance(&m, near) - 0.001) < 1e-15, "distance to the baffle %.17g, expected 0.001",
           (double)FSMeshDistance(&m, near));
    TCHECK(PetscAbsReal(FSMeshDistance(&m, low) - 0.01) < 1e-15, "distance to the floor %.17g, expected 0.01",
           (double)FSMeshDistance(&m, low));
    TCHECK(!FSMeshInLiquid(&m, low, 0.02) && FSMeshInLiquid(&m, low, 0.005), "the margin: 0.01 from the floor");
  }
  PetscCall(FSMeshDestroy(&m));
  /* baffles on the floor, 0.03 high */
  PetscCall(BaffledMesh(comm, 0, 0.03, 0.1, &m, &a, &p));
  PetscCall(FSMeshCheck(&m, comm));
  {
    const PetscReal baffle[3] = {0.1025, 0.01, 0.05}, over[3] = {0.1025, 0.045, 0.05};
    TCHECK(!FSMeshInLiquid(&m, baffle, 0), "a point inside a floor baffle must not be in the liquid");
    TCHECK(FSMeshInLiquid(&m, over, 0), "a point over a floor baffle must be in the liquid");
  }
  PetscCall(FSMeshDestroy(&m));
  PetscFunctionReturn(0);
}

/* ---------------------------------------------------------------------------------------------- */
/* STL files                                                                                       */

static void WriteASCIISolid(FILE *fp, const char name[], PetscInt n, PetscReal t[][9])
{
  fprintf(fp, "solid %s\n", name);
  for (PetscInt k = 0; k < n; k++) {
    PetscReal nr[3];
    TriangleNormal(&t[k][0], &t[k][3], &t[k][6], nr);
    fprintf(fp, "  facet normal %g %g %g\n    outer loop\n", (double)(nr[0] / Norm(nr)), (double)(nr[1] / Norm(nr)),
            (double)(nr[2] / Norm(nr)));
    for (PetscInt v = 0; v < 3; v++)
      fprintf(fp, "      vertex %.17g %.17g %.17g\n", (double)t[k][3 * v], (double)t[k][3 * v + 1],
              (double)t[k][3 * v + 2]);
    fprintf(fp, "    endloop\n  endfacet\n");
  }
  fprintf(fp, "endsolid %s\n", name);
}

static void PutU32(FILE *fp, uint32_t u)
{
  const unsigned char b[4] = {(unsigned char)(u & 255), (unsigned char)((u >> 8) & 255),
                              (unsigned char)((u >> 16) & 255), (unsigned char)(u >> 24)};
  fwrite(b, 1, 4, fp);
}

static void PutFloat(FILE *fp, PetscReal x)
{
  float    f = (float)x;
  uint32_t u;
  memcpy(&u, &f, 4);
  PutU32(fp, u);
}

/* a binary STL of n triangles whose header says count facets (header text starting with "solid") */
static void WriteBinary(const char path[], PetscInt n, PetscReal t[][9], uint32_t count)
{
  FILE *fp = fopen(path, "wb");
  char  header[80];
  memset(header, ' ', sizeof(header));
  memcpy(header, "solid a binary file whose header starts with solid", 50);
  fwrite(header, 1, 80, fp);
  PutU32(fp, count);
  for (PetscInt k = 0; k < n; k++) {
    PetscReal nr[3];
    TriangleNormal(&t[k][0], &t[k][3], &t[k][6], nr);
    for (PetscInt d = 0; d < 3; d++) PutFloat(fp, nr[d] / Norm(nr));
    for (PetscInt d = 0; d < 9; d++) PutFloat(fp, t[k][d]);
    fputc(0, fp);
    fputc(0, fp);
  }
  fclose(fp);
}

static PetscErrorCode Path(const char dir[], const char name[], char path[])
{
  PetscFunctionBegin;
  PetscCall(PetscSNPrintf(path, PETSC_MAX_PATH_LEN, "%s/%s", dir, name));
  PetscFunctionReturn(0);
}

/* the files of the STL tests, written by rank 0 */
static PetscErrorCode WriteFiles(const char dir[])
{
  const PetscReal lo[3] = {0, 0, 0}, tank[3] = {1, 0.5, 0.4}, blo[3] = {0.4, 0.1, 0.1}, bhi[3] = {0.6, 0.3, 0.3};
  const PetscReal one[3] = {1, 1, 1}, olo[3] = {0.5, 0.25, 0.25}, ohi[3] = {1.5, 0.75, 0.75}, flat[3] = {1, 0.5, 0.25};
  const PetscReal far[3] = {2, 0, 0}, farhi[3] = {2.5, 0.5, 0.4};
  PetscReal       t[13][9], u[12][9];
  char            path[PETSC_MAX_PATH_LEN];
  FILE           *fp;

  PetscFunctionBegin;
  /* two named solids: a tank and a baffle inside it, both with outward normals */
  PetscCall(Path(dir, "two.stl", path));
  fp = fopen(path, "w");
  BoxTriangles(lo, tank, PETSC_TRUE, t);
  WriteASCIISolid(fp, "tank", 12, t);
  BoxTriangles(blo, bhi, PETSC_TRUE, t);
  WriteASCIISolid(fp, "baffle", 12, t);
  fclose(fp);
  /* an unnamed solid */
  PetscCall(Path(dir, "unnamed.stl", path));
  fp = fopen(path, "w");
  BoxTriangles(lo, tank, PETSC_TRUE, t);
  WriteASCIISolid(fp, "", 12, t);
  fclose(fp);
  /* binary */
  PetscCall(Path(dir, "bin.stl", path));
  BoxTriangles(lo, flat, PETSC_TRUE, t);
  WriteBinary(path, 12, t, 12);
  PetscCall(Path(dir, "badcount.stl", path));
  WriteBinary(path, 11, t, 12);
  /* an open cube (a face missing), an inside-out cube, a reversed triangle, a degenerate triangle */
  BoxTriangles(lo, one, PETSC_TRUE, t);
  PetscCall(Path(dir, "open.stl", path));
  fp = fopen(path, "w");
  WriteASCIISolid(fp, "cube", 10, t);
  fclose(fp);
  PetscCall(Path(dir, "degenerate.stl", path));
  fp = fopen(path, "w");
  for (PetscInt d = 0; d < 9; d++) t[12][d] = d % 3 ? 0 : 0.5 * (d / 3); /* (0,0,0), (0.5,0,0), (1,0,0) */
  WriteASCIISolid(fp, "cube", 13, t);
  fclose(fp);
  PetscCall(Path(dir, "reversed.stl", path));
  fp = fopen(path, "w");
  for (PetscInt d = 0; d < 3; d++) {
    const PetscReal s = t[5][3 + d];
    t[5][3 + d]       = t[5][6 + d];
    t[5][6 + d]       = s;
  }
  WriteASCIISolid(fp, "cube", 12, t);
  fclose(fp);
  PetscCall(Path(dir, "insideout.stl", path));
  fp = fopen(path, "w");
  BoxTriangles(lo, one, PETSC_FALSE, t);
  WriteASCIISolid(fp, "cube", 12, t);
  fclose(fp);
  /* two cubes crossing each other, as two solids */
  PetscCall(Path(dir, "overlap.stl", path));
  fp = fopen(path, "w");
  BoxTriangles(lo, one, PETSC_TRUE, t);
  WriteASCIISolid(fp, "a", 12, t);
  BoxTriangles(olo, ohi, PETSC_TRUE, u);
  WriteASCIISolid(fp, "b", 12, u);
  fclose(fp);
  /* a baffle standing on the tank's floor: its bottom face lies on the floor */
  PetscCall(Path(dir, "touch.stl", path));
  fp = fopen(path, "w");
  BoxTriangles(lo, tank, PETSC_TRUE, t);
  WriteASCIISolid(fp, "tank", 12, t);
  {
    const PetscReal flo[3] = {0.4, 0, 0.1};
    BoxTriangles(flo, bhi, PETSC_TRUE, t);
  }
  WriteASCIISolid(fp, "baffle", 12, t);
  fclose(fp);
  /* an obstacle outside the tank */
  PetscCall(Path(dir, "outside.stl", path));
  fp = fopen(path, "w");
  BoxTriangles(lo, tank, PETSC_TRUE, t);
  WriteASCIISolid(fp, "tank", 12, t);
  BoxTriangles(far, farhi, PETSC_TRUE, t);
  WriteASCIISolid(fp, "post", 12, t);
  fclose(fp);
  /* truncated after line 26 (the second vertex of facet 3), and a number that does not parse on line 12 */
  {
    char    *text;
    size_t   len;
    PetscInt line = 0;
    PetscCall(Path(dir, "full.stl", path));
    fp = fopen(path, "w+");
    BoxTriangles(lo, one, PETSC_TRUE, t);
    WriteASCIISolid(fp, "cube", 12, t);
    len = (size_t)ftell(fp);
    rewind(fp);
    PetscCall(PetscMalloc1(len + 1, &text));
    TCHECK(fread(text, 1, len, fp) == len, "cannot read back %s", path);
    text[len] = 0;
    fclose(fp);
    remove(path);
    PetscCall(Path(dir, "truncated.stl", path));
    fp = fopen(path, "w");
    for (size_t k = 0; k < len && line < 26; k++) {
      fputc(text[k], fp);
      if (text[k] == '\n') line++;
    }
    fclose(fp);
    PetscCall(Path(dir, "badnumber.stl", path));
    fp   = fopen(path, "w");
    line = 0;
    for (size_t k = 0; k < len; k++) {
      if (text[k] == '\n' && ++line == 11) {
        fputs("\n      vertex 1 zero 0", fp); /* line 12 */
        while (text[k + 1] != '\n') k++;
        continue;
      }
      fputc(text[k], fp);
    }
    fclose(fp);
    PetscCall(PetscFree(text));
  }
  PetscFunctionReturn(0);
}

static PetscErrorCode Load(MPI_Comm comm, const char dir[], const char file[], const char name[], FSMesh *m)
{
  char path[PETSC_MAX_PATH_LEN];

  PetscFunctionBegin;
  PetscCall(Path(dir, file, path));
  PetscCall(FSMeshCreate(m));
  PetscCall(FSMeshLoadSTL(m, comm, path, name));
  PetscFunctionReturn(0);
}

static PetscErrorCode TestSTL(MPI_Comm comm, const char dir[])
{
  FSMesh    m;
  char      path[PETSC_MAX_PATH_LEN];
  PetscInt  b;
  PetscReal vb;

  PetscFunctionBegin;
  /* two named solids: the baffle, given with outward normals, turned inside out */
  PetscCall(Load(comm, dir, "two.stl", "walls", &m));
  PetscCall(Path(dir, "two.stl", path));
  TCHECK(m.ntri == 24 && m.nvert == 16 && m.nwalls == 2 && !strcmp(m.name[0], "tank") && !strcmp(m.name[1], "baffle"),
         "two.stl: %" PetscInt_FMT " triangles, %" PetscInt_FMT " vertices, %" PetscInt_FMT " walls (%s, %s)", m.ntri,
         m.nvert, m.nwalls, m.nwalls > 0 ? m.name[0] : "", m.nwalls > 1 ? m.name[1] : "");
  TCHECK(!strcmp(m.source[0], path) && !strcmp(m.source[1], path), "two.stl: the walls' source %s", m.source[0]);
  for (PetscInt t = 0; t < m.ntri; t++)
    TCHECK(m.trisrc[t] == t && m.triwall[t] == t / 12,
           "two.stl: triangle %" PetscInt_FMT ": facet %" PetscInt_FMT " of wall %" PetscInt_FMT, t, m.trisrc[t],
           m.triwall[t]);
  b  = WallIndex(&m, "baffle");
  vb = WallVolume(&m, b);
  TCHECK(Rel(vb, 0.008) < 1e-12, "two.stl: the baffle as given encloses %g, expected +0.008", (double)vb);
  PetscCall(FSMeshCheck(&m, comm));
  vb = WallVolume(&m, b);
  TCHECK(Rel(vb, -0.008) < 1e-12, "two.stl: the baffle after FSMeshCheck encloses %g, expected -0.008 (inside out)",
         (double)vb);
  TCHECK(Rel(m.volume, 0.2 - 0.008) < 1e-12, "two.stl: volume %.15g, expected 0.192", (double)m.volume);
  {
    const PetscReal in[3] = {0.2, 0.2, 0.2}, inbaffle[3] = {0.5, 0.2, 0.2};
    TCHECK(FSMeshInLiquid(&m, in, 0) && !FSMeshInLiquid(&m, inbaffle, 0), "two.stl: in the liquid, in the baffle");
  }
  PetscCall(FSMeshCheck(&m, comm)); /* again: nothing more to turn */
  TCHECK(Rel(WallVolume(&m, b), -0.008) < 1e-12 && Rel(m.volume, 0.192) < 1e-12,
         "two.stl: a second FSMeshCheck changed the mesh");
  PetscCall(FSMeshDestroy(&m));
  /* an unnamed solid takes the name given */
  PetscCall(Load(comm, dir, "unnamed.stl", "hull", &m));
  TCHECK(m.nwalls == 1 && !strcmp(m.name[0], "hull") && m.ntri == 12, "unnamed.stl: wall \"%s\"",
         m.nwalls ? m.name[0] : "");
  PetscCall(FSMeshDestroy(&m));
  /* binary, its header starting with "solid": named by name, or by the file */
  PetscCall(Load(comm, dir, "bin.stl", "hull", &m));
  TCHECK(m.ntri == 12 && m.nvert == 8 && m.nwalls == 1 && !strcmp(m.name[0], "hull"),
         "bin.stl: %" PetscInt_FMT " triangles, %" PetscInt_FMT " vertices, wall \"%s\"", m.ntri, m.nvert,
         m.nwalls ? m.name[0] : "");
  PetscCall(FSMeshCheck(&m, comm));
  TCHECK(m.volume == 0.125, "bin.stl: volume %.17g, expected 0.125", (double)m.volume);
  PetscCall(Path(dir, "bin.stl", path));
  PetscCall(FSMeshLoadSTL(&m, comm, path, NULL)); /* the same file again, into the same mesh: no new vertex */
  TCHECK(m.ntri == 24 && m.nvert == 8 && m.nwalls == 2 && !strcmp(m.name[1], "bin"),
         "bin.stl twice: %" PetscInt_FMT " triangles, %" PetscInt_FMT " vertices, second wall \"%s\"", m.ntri, m.nvert,
         m.nwalls > 1 ? m.name[1] : "");
  PetscCall(FSMeshDestroy(&m));
  PetscFunctionReturn(0);
}

static PetscErrorCode TestBadSTL(MPI_Comm comm, const char dir[])
{
  FSMesh m;
  char   path[PETSC_MAX_PATH_LEN], where[PETSC_MAX_PATH_LEN + 16];

  PetscFunctionBegin;
  /* files that read, meshes that fail the checks */
  PetscCall(Load(comm, dir, "open.stl", "", &m));
  PetscCall(Path(dir, "open.stl", path));
  EXPECT_ERROR(FSMeshCheck(&m, comm), path, ": triangle ", "shared by 1 triangle", "open");
  PetscCall(FSMeshDestroy(&m));
  PetscCall(Load(comm, dir, "insideout.stl", "", &m));
  PetscCall(Path(dir, "insideout.stl", path));
  EXPECT_ERROR(FSMeshCheck(&m, comm), path, "inside out", "encloses volume -1", "triangle 0");
  PetscCall(FSMeshDestroy(&m));
  PetscCall(Load(comm, dir, "reversed.stl", "", &m));
  PetscCall(Path(dir, "reversed.stl", path));
  EXPECT_ERROR(FSMeshCheck(&m, comm), path, "triangle 5", "same direction", "inconsistent orientation");
  PetscCall(FSMeshDestroy(&m));
  PetscCall(Load(comm, dir, "degenerate.stl", "", &m));
  PetscCall(Path(dir, "degenerate.stl", path));
  PetscCall(PetscSNPrintf(where, sizeof(where), "%s: triangle 12 is degenerate", path));
  EXPECT_ERROR(FSMeshCheck(&m, comm), where);
  PetscCall(FSMeshDestroy(&m));
  PetscCall(Load(comm, dir, "overlap.stl", "", &m));
  PetscCall(Path(dir, "overlap.stl", path));
  EXPECT_ERROR(FSMeshCheck(&m, comm), path, ": triangle ", "intersect", "(wall \"a\")", "(wall \"b\")");
  PetscCall(FSMeshDestroy(&m));
  PetscCall(Load(comm, dir, "touch.stl", "", &m));
  PetscCall(Path(dir, "touch.stl", path));
  EXPECT_ERROR(FSMeshCheck(&m, comm), path, ": triangle ", "intersect", "(wall \"tank\")", "(wall \"baffle\")");
  PetscCall(FSMeshDestroy(&m));
  PetscCall(Load(comm, dir, "outside.stl", "", &m));
  PetscCall(Path(dir, "outside.stl", path));
  EXPECT_ERROR(FSMeshCheck(&m, comm), path, "triangle 12", "outside the container");
  PetscCall(FSMeshDestroy(&m));
  /* files that do not read */
  PetscCall(FSMeshCreate(&m));
  PetscCall(Path(dir, "badcount.stl", path));
  EXPECT_ERROR(FSMeshLoadSTL(&m, comm, path, "x"), path, "12 triangles", "684 bytes", "has 634 bytes");
  PetscCall(Path(dir, "truncated.stl", path));
  PetscCall(PetscSNPrintf(where, sizeof(where), "%s:26:", path));
  EXPECT_ERROR(FSMeshLoadSTL(&m, comm, path, "x"), where, "facet 3", "\"vertex\"");
  PetscCall(Path(dir, "badnumber.stl", path));
  PetscCall(PetscSNPrintf(where, sizeof(where), "%s:12:", path));
  EXPECT_ERROR(FSMeshLoadSTL(&m, comm, path, "x"), where, "\"zero\"");
  PetscCall(Path(dir, "missing.stl", path));
  EXPECT_ERROR(FSMeshLoadSTL(&m, comm, path, "x"), path);
  TCHECK(m.ntri == 0 && m.nwalls == 0, "failed loads added %" PetscInt_FMT " triangles", m.ntri);
  PetscCall(FSMeshDestroy(&m));
  PetscFunctionReturn(0);
}

/* ---------------------------------------------------------------------------------------------- */
/* a larger mesh: a box of n x n squares per face around a sphere (an octahedron refined 4 times),
   rotated, written as a binary STL (single precision: the faces no longer exactly plane), loaded and
   checked, timed */

static void Rotate(PetscReal x[3])
{
  const PetscReal a = 0.3, b = 0.7; /* about z, then about x */
  PetscReal y[3] = {PetscCosReal(a) * x[0] - PetscSinReal(a) * x[1], PetscSinReal(a) * x[0] + PetscCosReal(a) * x[1],
                    x[2]};
  x[0]           = y[0];
  x[1]           = PetscCosReal(b) * y[1] - PetscSinReal(b) * y[2];
  x[2]           = PetscSinReal(b) * y[1] + PetscCosReal(b) * y[2];
}

static PetscErrorCode TestLarge(MPI_Comm comm, const char dir[], PetscInt n)
{
  const PetscReal hi[3] = {1, 0.5, 0.4}, centre[3] = {0.5, 0.25, 0.2}, radius = 0.15;
  const PetscInt  levels = 4, nsphere = 8 << (2 * levels), nbox = 12 * n * n;
  PetscReal(*t)[9], vsphere = 0, vbox = hi[0] * hi[1] * hi[2];
  char           path[PETSC_MAX_PATH_LEN];
  PetscMPIInt    rank;
  FSMesh         m;
  PetscLogDouble t0, t1, t2;

  PetscFunctionBegin;
  PetscCallMPI(MPI_Comm_rank(comm, &rank));
  PetscCall(Path(dir, "large.stl", path));
  PetscCall(PetscMalloc1(nbox + nsphere, &t));
  {
    /* the box: on face f (axis d, side s) the squares (i, j) of the two other axes, outward */
    PetscInt k = 0;
    for (PetscInt d = 0; d < 3; d++)
      for (PetscInt s = 0; s < 2; s++)
        for (PetscInt i = 0; i < n; i++)
          for (PetscInt j = 0; j < n; j++) {
            const PetscInt d1 = (d + 1) % 3, d2 = (d + 2) % 3,
                           q[4][2] = {{i, j}, {i + 1, j}, {i + 1, j + 1}, {i, j + 1}};
            PetscReal c[4][3];
            for (PetscInt v = 0; v < 4; v++) {
              c[v][d]  = s ? hi[d] : 0;
              c[v][d1] = q[v][0] == n ? hi[d1] : hi[d1] * q[v][0] / n; /* the same double from every face */
              c[v][d2] = q[v][1] == n ? hi[d2] : hi[d2] * q[v][1] / n;
              Rotate(c[v]);
            }
            /* (d1, d2, d) is right-handed: counter-clockwise in (d1, d2) points along +d */
            for (PetscInt h = 0; h < 2; h++) {
              const PetscInt o[3] = {0, s ? 1 + h : 2 + h, s ? 2 + h : 1 + h};
              for (PetscInt v = 0; v < 3; v++)
                for (PetscInt e = 0; e < 3; e++) t[k][3 * v + e] = c[o[v]][e];
              k++;
            }
          }
  }
  {
    /* the sphere: the octahedron's faces (outward) split into 4, levels times, the new vertices on the sphere */
    const PetscReal oct[8][9] = {{1, 0, 0, 0, 1, 0, 0, 0, 1},    {0, 1, 0, -1, 0, 0, 0, 0, 1},
                                 {-1, 0, 0, 0, -1, 0, 0, 0, 1},  {0, -1, 0, 1, 0, 0, 0, 0, 1},
                                 {0, 1, 0, 1, 0, 0, 0, 0, -1},   {-1, 0, 0, 0, 1, 0, 0, 0, -1},
                                 {0, -1, 0, -1, 0, 0, 0, 0, -1}, {1, 0, 0, 0, -1, 0, 0, 0, -1}};
    PetscReal(*s)[9]          = &t[nbox];
    PetscInt ns               = 8;
    PetscCall(PetscArraycpy(&s[0][0], &oct[0][0], 72));
    for (PetscInt l = 0; l < levels; l++) {
      for (PetscInt k = ns - 1; k >= 0; k--) {
        PetscReal mid[3][3], tri[9];
        PetscCall(PetscArraycpy(tri, s[k], 9));
        for (PetscInt e = 0; e < 3; e++) {
          PetscReal r = 0;
          for (PetscInt d = 0; d < 3; d++) {
            mid[e][d] = (tri[3 * e + d] + tri[3 * ((e + 1) % 3) + d]) / 2;
            r += mid[e][d] * mid[e][d];
          }
          for (PetscInt d = 0; d < 3; d++) mid[e][d] /= PetscSqrtReal(r);
        }
        /* (a, ab, ca), (ab, b, bc), (ca, bc, c), (ab, bc, ca) */
        for (PetscInt d = 0; d < 3; d++) {
          s[4 * k][d] = tri[d], s[4 * k][3 + d] = mid[0][d], s[4 * k][6 + d] = mid[2][d];
          s[4 * k + 1][d] = mid[0][d], s[4 * k + 1][3 + d] = tri[3 + d], s[4 * k + 1][6 + d] = mid[1][d];
          s[4 * k + 2][d] = mid[2][d], s[4 * k + 2][3 + d] = mid[1][d], s[4 * k + 2][6 + d] = tri[6 + d];
          s[4 * k + 3][d] = mid[0][d], s[4 * k + 3][3 + d] = mid[1][d], s[4 * k + 3][6 + d] = mid[2][d];
        }
      }
      ns *= 4;
    }
    for (PetscInt k = 0; k < ns; k++) {
      for (PetscInt v = 0; v < 3; v++) {
        PetscReal *x = &s[k][3 * v];
        for (PetscInt d = 0; d < 3; d++) x[d] = centre[d] + radius * x[d];
      }
      {
        const PetscReal *a = &s[k][0], *b = &s[k][3], *c = &s[k][6];
        vsphere += (a[0] * (b[1] * c[2] - b[2] * c[1]) - a[1] * (b[0] * c[2] - b[2] * c[0]) +
                    a[2] * (b[0] * c[1] - b[1] * c[0])) /
                   6;
      }
      for (PetscInt v = 0; v < 3; v++) Rotate(&s[k][3 * v]);
    }
  }
  if (!rank) WriteBinary(path, nbox + nsphere, t, (uint32_t)(nbox + nsphere));
  PetscCall(PetscFree(t));
  PetscCallMPI(MPI_Barrier(comm));
  PetscCall(FSMeshCreate(&m));
  PetscCall(PetscTime(&t0));
  PetscCall(FSMeshLoadSTL(&m, comm, path, "large"));
  PetscCall(PetscTime(&t1));
  PetscCall(FSMeshCheck(&m, comm));
  PetscCall(PetscTime(&t2));
  TCHECK(m.ntri == nbox + nsphere && m.nvert == (6 * n * n + 2) + (4 * (nsphere / 8) + 2),
         "large: %" PetscInt_FMT " triangles, %" PetscInt_FMT " vertices", m.ntri, m.nvert);
  TCHECK(Rel(m.volume, vbox - vsphere) < 1e-5, "large: volume %.9g, expected %.9g", (double)m.volume,
         (double)(vbox - vsphere));
  PetscCall(PetscPrintf(comm, "test_mesh: %" PetscInt_FMT " triangles: FSMeshLoadSTL %.3f s, FSMeshCheck %.3f s\n",
                        m.ntri, t1 - t0, t2 - t1));
  PetscCall(FSMeshDestroy(&m));
  if (!rank) remove(path);
  PetscFunctionReturn(0);
}

int main(int argc, char **argv)
{
  MPI_Comm    comm;
  PetscMPIInt rank;
  char        dir[PETSC_MAX_PATH_LEN] = "/tmp/fsmeshXXXXXX";
  PetscInt    n                       = 64;

  PetscFunctionBeginUser;
  PetscCall(PetscInitialize(&argc, &argv, NULL, NULL));
  comm = PETSC_COMM_WORLD;
  PetscCall(PetscOptionsGetBool(NULL, NULL, "-verbose_errors", &verbose_errors_, NULL));
  PetscCall(PetscOptionsGetInt(NULL, NULL, "-n", &n, NULL));
  PetscCallMPI(MPI_Comm_rank(comm, &rank));
  if (!rank) {
    PetscCheck(mkdtemp(dir), PETSC_COMM_SELF, PETSC_ERR_FILE_OPEN, "mkdtemp failed");
    PetscCall(WriteFiles(dir));
  }
  PetscCallMPI(MPI_Bcast(dir, sizeof(dir), MPI_CHAR, 0, comm));
  PetscCall(TestExtrude(comm));
  PetscCall(TestLiquidBelow(comm));
  PetscCall(TestRefine(comm));
  PetscCall(TestSolidAngle());
  PetscCall(TestDistance());
  PetscCall(TestInLiquid(comm));
  PetscCall(TestSTL(comm, dir));
  PetscCall(TestBadSTL(comm, dir));
  PetscCall(TestLarge(comm, dir, n));
  PetscCallMPI(MPI_Barrier(comm));
  if (!rank) PetscCall(FSTestRemoveTree(dir));
  PetscCall(PetscPrintf(comm, "test_mesh: OK\n"));
  PetscCall(PetscFinalize());
  return 0;
}
