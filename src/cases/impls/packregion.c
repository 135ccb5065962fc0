/* The closed region a body of liquid is packed in (packing.h): the walls' elements clipped to the liquid's box, and
 * the box's faces that lie in the liquid (the fill level, the sides of a liquid box) as elements of their own. */
#include "packing.h"
#include "liquid.h"

static PetscErrorCode RegionAppend(FSPackRegion *g, PetscInt *cap, const PetscReal row[])
{
  PetscFunctionBegin;
  if (g->nel == *cap) {
    PetscReal *el;
    *cap = 2 * (*cap) + 64;
    PetscCall(PetscMalloc1((size_t)(*cap) * g->stride, &el));
    if (g->nel) PetscCall(PetscArraycpy(el, g->el, (size_t)g->nel * g->stride));
    PetscCall(PetscFree(g->el));
    g->el = el;
  }
  PetscCall(PetscArraycpy(&g->el[(size_t)g->nel * g->stride], row, g->stride));
  g->nel++;
  PetscFunctionReturn(0);
}

/* a segment's row from its ends and its normal (FS_SEG_*) */
static void SegmentRow(const PetscReal p[2], const PetscReal q[2], const PetscReal n[2], PetscReal row[])
{
  row[FS_SEG_P0]         = p[0];
  row[FS_SEG_P0 + 1]     = p[1];
  row[FS_SEG_P1]         = q[0];
  row[FS_SEG_P1 + 1]     = q[1];
  row[FS_SEG_MID]        = 0.5 * (p[0] + q[0]);
  row[FS_SEG_MID + 1]    = 0.5 * (p[1] + q[1]);
  row[FS_SEG_NORMAL]     = n[0];
  row[FS_SEG_NORMAL + 1] = n[1];
  row[FS_SEG_LENGTH]     = PetscSqrtReal((q[0] - p[0]) * (q[0] - p[0]) + (q[1] - p[1]) * (q[1] - p[1]));
}

/* a triangle's row from its corners and its normal (FS_TRI_*); its area */
static PetscReal TriangleRow(const PetscReal a[3], const PetscReal b[3], const PetscReal c[3], const PetscReal n[3],
                             PetscReal row[])
{
  const PetscReal u[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]}, v[3] = {c[0] - a[0], c[1] - a[1], c[2] - a[2]};
  const PetscReal cr[3] = {u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]};

  row[FS_TRI_RADIUS] = 0;
  for (PetscInt d = 0; d < 3; d++) {
    row[FS_TRI_P0 + d]       = a[d];
    row[FS_TRI_P1 + d]       = b[d];
    row[FS_TRI_P2 + d]       = c[d];
    row[FS_TRI_CENTROID + d] = (a[d] + b[d] + c[d]) / 3;
    row[FS_TRI_NORMAL + d]   = n[d];
  }
  row[FS_TRI_AREA] = 0.5 * PetscSqrtReal(cr[0] * cr[0] + cr[1] * cr[1] + cr[2] * cr[2]);
  for (PetscInt k = 0; k < 3; k++) {
    PetscReal r2 = 0;
    for (PetscInt d = 0; d < 3; d++) r2 += PetscSqr(row[3 * k + d] - row[FS_TRI_CENTROID + d]);
    row[FS_TRI_RADIUS] = PetscMax(row[FS_TRI_RADIUS], PetscSqrtReal(r2));
  }
  return row[FS_TRI_AREA];
}

/* does the face of the box on side `side` (0 low, 1 high) of axis d lie on or beyond the walls' bounding box
   wlo..whi there (no liquid can be beyond it)? */
static PetscBool FaceOnBounds(const PetscReal lo[], const PetscReal hi[], const PetscReal wlo[], const PetscReal whi[],
                              PetscInt d, PetscInt side, PetscReal eps)
{
  return side ? (PetscBool)(hi[d] >= whi[d] - eps) : (PetscBool)(lo[d] <= wlo[d] + eps);
}

/*
   FSPackRegionFromWalls - the closed region of the liquid of the 2-D walls w (discretized) in the box lo..hi: w's
   segments clipped to the box, and the box's sides inside the liquid cut into pieces of dx/8 (those whose middle
   is in the liquid), their normals out of the box.

   Not collective
*/
PetscErrorCode FSPackRegionFromWalls(FSPackRegion *g, const FSWalls *w, const PetscReal lo[], const PetscReal hi[],
                                     PetscReal dx)
{
  const PetscReal eps = 1e-9 * ((w->hi[0] - w->lo[0]) + (w->hi[1] - w->lo[1]));
  PetscInt        cap = 0;
  PetscReal       row[FS_SEG_STRIDE];

  PetscFunctionBegin;
  PetscCall(PetscMemzero(g, sizeof(*g)));
  g->dim    = 2;
  g->stride = FS_SEG_STRIDE;
  for (PetscInt d = 0; d < 2; d++) {
    g->lo[d] = lo[d];
    g->hi[d] = hi[d];
  }
  for (PetscInt k = 0; k < w->nseg; k++) { /* the part of the segment in the box (eps wider) */
    const PetscReal *s = &w->seg[k * FS_SEG_STRIDE], *p = s + FS_SEG_P0, *q = s + FS_SEG_P1;
    PetscReal        t0, t1, a[2], b[2];
    if (!FSSegmentClip(p, q, lo, hi, 2, eps, &t0, &t1)) continue;
    for (PetscInt d = 0; d < 2; d++) {
      a[d] = p[d] + t0 * (q[d] - p[d]);
      b[d] = p[d] + t1 * (q[d] - p[d]);
    }
    SegmentRow(a, b, s + FS_SEG_NORMAL, row);
    if (row[FS_SEG_LENGTH] > eps) PetscCall(RegionAppend(g, &cap, row));
  }
  for (PetscInt d = 0; d < 2; d++)
    for (PetscInt side = 0; side < 2; side++) {
      const PetscInt  o = 1 - d, np = (PetscInt)PetscCeilReal((hi[o] - lo[o]) / (dx / 8));
      const PetscReal at   = side ? hi[d] : lo[d];
      PetscReal       n[2] = {0, 0};
      if (FaceOnBounds(lo, hi, w->lo, w->hi, d, side, eps)) continue;
      n[d] = side ? 1 : -1;
      for (PetscInt i = 0; i < np; i++) {
        PetscReal a[2], b[2], mid[2];
        a[d] = b[d] = at;
        a[o]        = lo[o] + (hi[o] - lo[o]) * i / np;
        b[o]        = lo[o] + (hi[o] - lo[o]) * (i + 1) / np;
        mid[d]      = at - 1e3 * eps * n[d]; /* just inside the box */
        mid[o]      = 0.5 * (a[o] + b[o]);
        if (!FSWallsInLiquid(w, mid, 0)) continue;
        SegmentRow(a, b, n, row);
        PetscCall(RegionAppend(g, &cap, row));
        g->nlid++;
      }
    }
  PetscFunctionReturn(0);
}

/* the convex polygon v (nv corners, 3 reals each) clipped to the half-space s (x[d] - at) <= 0: Sutherland-Hodgman */
static PetscInt ClipPolygon(PetscInt nv, const PetscReal v[], PetscInt d, PetscReal at, PetscReal s, PetscReal out[])
{
  PetscInt n = 0;
  for (PetscInt k = 0; k < nv; k++) {
    const PetscReal *p = &v[3 * k], *q = &v[3 * ((k + 1) % nv)], fp = s * (p[d] - at), fq = s * (q[d] - at);
    if (fp <= 0) {
      for (PetscInt e = 0; e < 3; e++) out[3 * n + e] = p[e];
      n++;
    }
    if ((fp < 0 && fq > 0) || (fp > 0 && fq < 0)) {
      const PetscReal t = fp / (fp - fq);
      for (PetscInt e = 0; e < 3; e++) out[3 * n + e] = p[e] + t * (q[e] - p[e]);
      n++;
    }
  }
  return n;
}

/* the most halvings of a lid square that a wall crosses: pieces of dx/8, as the 2-D lid's */
#define FS_LID_LEVELS 3

/* a point of a box face (axis d): x[d] = at, x[(d + 1) % 3] = a, x[(d + 2) % 3] = b */
static void LidPoint(PetscInt d, PetscReal at, PetscReal a, PetscReal b, PetscReal x[3])
{
  x[d]           = at;
  x[(d + 1) % 3] = a;
  x[(d + 2) % 3] = b;
}

/* the part in the liquid of the square u x v of the box face x[d] = at (normal n out of the box; `inside` the plane
   just inside the box, where the points are tested) as triangles: whole where its corners, its edges' middles and
   its middle are in the liquid, else halved both ways down to FS_LID_LEVELS and the last pieces kept where their
   middle is. A wall that is not along the axes crosses the lid: whole squares of dx would reach beyond it or leave
   holes beside it, and the particles next to it would be relaxed against a lid that is not there (the box turned
   30 degrees stopped at a largest |e_i| dx of 0.016 instead of 1e-4, docs/walls.md) */
static PetscErrorCode LidTile(FSPackRegion *g, PetscInt *cap, FSMesh *m, PetscInt d, PetscReal at, PetscReal inside,
                              const PetscReal n[], const PetscReal u[2], const PetscReal v[2], PetscInt level,
                              PetscReal row[])
{
  const PetscReal um = 0.5 * (u[0] + u[1]), vm = 0.5 * (v[0] + v[1]);
  PetscReal       x[3], c[4][3];
  PetscBool       whole = PETSC_TRUE;

  PetscFunctionBegin;
  for (PetscInt a = 0; a < 3 && whole; a++) /* the corners and edges a millionth inside: a wall along the edge */
    for (PetscInt b = 0; b < 3 && whole; b++) {
      const PetscReal ua[3] = {u[0] + 1e-6 * (u[1] - u[0]), u[1] - 1e-6 * (u[1] - u[0]), um};
      const PetscReal vb[3] = {v[0] + 1e-6 * (v[1] - v[0]), v[1] - 1e-6 * (v[1] - v[0]), vm};
      LidPoint(d, inside, ua[a], vb[b], x);
      whole = FSMeshInLiquid(m, x, 0);
    }
  if (!whole && level < FS_LID_LEVELS) {
    for (PetscInt a = 0; a < 2; a++)
      for (PetscInt b = 0; b < 2; b++) {
        const PetscReal us[2] = {a ? um : u[0], a ? u[1] : um}, vs[2] = {b ? vm : v[0], b ? v[1] : vm};
        PetscCall(LidTile(g, cap, m, d, at, inside, n, us, vs, level + 1, row));
      }
    PetscFunctionReturn(0);
  }
  LidPoint(d, inside, um, vm, x);
  if (!whole && !FSMeshInLiquid(m, x, 0)) PetscFunctionReturn(0);
  for (PetscInt k = 0; k < 4; k++) LidPoint(d, at, u[k == 1 || k == 2], v[k >= 2], c[k]);
  TriangleRow(c[0], c[1], c[2], n, row);
  PetscCall(RegionAppend(g, cap, row));
  TriangleRow(c[0], c[2], c[3], n, row);
  PetscCall(RegionAppend(g, cap, row));
  g->nlid += 2;
  PetscFunctionReturn(0);
}

/*
   FSPackRegionFromMesh - the closed region of the liquid of the checked 3-D mesh m in the box lo..hi: m's elements
   (refined to edges of at most h) clipped to the box, and the box's faces inside the liquid tiled with squares of
   at most dx, two triangles each, cut where a wall crosses them (LidTile), their normals out of the box.

   Not collective
*/
PetscErrorCode FSPackRegionFromMesh(FSPackRegion *g, FSMesh *m, const PetscReal lo[], const PetscReal hi[],
                                    PetscReal dx, PetscReal h)
{
  const PetscReal eps = 1e-9 * ((m->hi[0] - m->lo[0]) + (m->hi[1] - m->lo[1]) + (m->hi[2] - m->lo[2]));
  PetscInt        cap = 0;
  PetscReal       row[FS_TRI_STRIDE];

  PetscFunctionBegin;
  PetscCall(PetscMemzero(g, sizeof(*g)));
  g->dim    = 3;
  g->stride = FS_TRI_STRIDE;
  for (PetscInt d = 0; d < 3; d++) {
    g->lo[d] = lo[d];
    g->hi[d] = hi[d];
  }
  PetscCall(FSMeshRefine(m, h));
  for (PetscInt k = 0; k < m->nel; k++) {
    const PetscReal *el = &m->el[k * FS_TRI_STRIDE];
    PetscReal        a[3 * 9], b[3 * 9];
    PetscInt         nv = 3;
    PetscCall(PetscArraycpy(a, el + FS_TRI_P0, 9));
    for (PetscInt d = 0; d < 3 && nv >= 3; d++) {
      nv = ClipPolygon(nv, a, d, lo[d] - eps, -1, b);
      nv = ClipPolygon(nv, b, d, hi[d] + eps, 1, a);
    }
    for (PetscInt t = 1; t + 1 < nv; t++)
      if (TriangleRow(&a[0], &a[3 * t], &a[3 * (t + 1)], el + FS_TRI_NORMAL, row) > eps * eps)
        PetscCall(RegionAppend(g, &cap, row));
  }
  for (PetscInt d = 0; d < 3; d++)
    for (PetscInt side = 0; side < 2; side++) {
      const PetscInt  o1 = (d + 1) % 3, o2 = (d + 2) % 3;
      const PetscInt  n1   = (PetscInt)PetscCeilReal((hi[o1] - lo[o1]) / dx);
      const PetscInt  n2   = (PetscInt)PetscCeilReal((hi[o2] - lo[o2]) / dx);
      const PetscReal at   = side ? hi[d] : lo[d];
      PetscReal       n[3] = {0, 0, 0};
      if (FaceOnBounds(lo, hi, m->lo, m->hi, d, side, eps)) continue;
      n[d] = side ? 1 : -1;
      for (PetscInt j = 0; j < n2; j++)
        for (PetscInt i = 0; i < n1; i++) {
          const PetscReal u[2] = {lo[o1] + (hi[o1] - lo[o1]) * i / n1, lo[o1] + (hi[o1] - lo[o1]) * (i + 1) / n1};
          const PetscReal v[2] = {lo[o2] + (hi[o2] - lo[o2]) * j / n2, lo[o2] + (hi[o2] - lo[o2]) * (j + 1) / n2};
          PetscCall(LidTile(g, &cap, m, d, at, at - 1e3 * eps * n[d], n, u, v, 0, row));
        }
    }
  PetscFunctionReturn(0);
}

/* FSPackRegionDestroy - frees the region's elements. */
PetscErrorCode FSPackRegionDestroy(FSPackRegion *g)
{
  PetscFunctionBegin;
  PetscCall(PetscFree(g->el));
  g->nel = g->nlid = 0;
  PetscFunctionReturn(0);
}
