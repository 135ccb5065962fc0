/*
   The triangle-mesh boundary's part of the geometry view (-fs_geometry_view, src/solver/geometryview.c):
     the walls in geometry.png      in each of the three views, the edges of the walls' triangles, each
                                    wall in its colour (FSImagePalette), with a tick along the normal
                                    of every triangle seen edge-on
     <dir>/walls.h5, walls.xdmf     the walls' triangles, for ParaView next to particles.xdmf

   Both show the INPUT triangles (mesh.tri, mesh.vert: the built-in tank's or the STL files', after
   FSMeshCheck), not the elements the run integrates over (FSMeshRefine's subdivision of them): the
   walls as the user gave them, numbered as FSMeshCheck's messages number them.

   Layout of walls.h5 (float64 unless said):
     /walls                     group; attributes ntriangles, nwalls (int), names (the wall names,
                                comma separated, in wall-index order)
     /walls/points              (3 ntri, 3): the vertices a, b, c of every triangle (not shared)
     /walls/connectivity        (ntri, 3) integers: 3k, 3k+1, 3k+2 for triangle k (the XDMF topology)
     /walls/wall                (ntri,): the wall index of each triangle
     /walls/normal              (ntri, 3): the unit normal (b - a) x (c - a) / |...|, out of the liquid
     /walls/area                (ntri,): the triangle's area
*/
#include <petscviewerhdf5.h>
#include "trimeshimpl.h"

#define FS_GEOMETRY_TICK 7 /* length of a normal tick, pixels */

/* the unit normal (b - a) x (c - a) / |...| of input triangle t and its area */
static void TriangleNormal(const FSMesh *ms, PetscInt t, PetscReal n[3], PetscReal *area)
{
  const PetscReal *a = &ms->vert[3 * ms->tri[3 * t]], *b = &ms->vert[3 * ms->tri[3 * t + 1]],
                  *c    = &ms->vert[3 * ms->tri[3 * t + 2]];
  const PetscReal e1[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]}, e2[3] = {c[0] - a[0], c[1] - a[1], c[2] - a[2]};
  PetscReal       len;

  n[0] = e1[1] * e2[2] - e1[2] * e2[1];
  n[1] = e1[2] * e2[0] - e1[0] * e2[2];
  n[2] = e1[0] * e2[1] - e1[1] * e2[0];
  len  = PetscSqrtReal(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
  for (PetscInt d = 0; d < 3; d++) n[d] = len > 0 ? n[d] / len : 0;
  *area = 0.5 * len;
}

/*
   FSBoundaryDraw_Trimesh - rank 0: the edges of the input triangles projected on the map's axes, each
   wall in its colour, wall 0 first; a triangle seen edge-on, or nearly (its normal at least half in
   the view's plane), gets a tick from its centroid along the normal, out of the liquid.
*/
PetscErrorCode FSBoundaryDraw_Trimesh(FSBoundary b, FSImage *img, const FSImageMap *m)
{
  const FSMesh *ms = &((FSBoundary_Trimesh *)b->data)->mesh;

  PetscFunctionBegin;
  /* wall by wall, so that the later walls (obstacles) show over the container's edges they share */
  for (PetscInt q = 0; q < ms->nwalls; q++)
    for (PetscInt t = 0; t < ms->ntri; t++) {
      const unsigned char *col = FSImagePalette[q % FS_IMAGE_NPALETTE];
      PetscReal            px[3], py[3], n[3], area, g[3] = {0, 0, 0};

      if (ms->triwall[t] != q) continue;
      for (PetscInt i = 0; i < 3; i++) {
        const PetscReal *p = &ms->vert[3 * ms->tri[3 * t + i]];

        FSImageMapPoint(m, p, &px[i], &py[i]);
        for (PetscInt d = 0; d < 3; d++) g[d] += p[d] / 3;
      }
      /* the 2-pixel pen covers the pixel right and below the line: start half a pixel up-left */
      for (PetscInt i = 0; i < 3; i++) {
        const PetscInt j = (i + 1) % 3;

        FSImageDrawLine(img, FSImageRound(px[i] - 0.5), FSImageRound(py[i] - 0.5), FSImageRound(px[j] - 0.5),
                        FSImageRound(py[j] - 0.5), 2, col);
      }
      TriangleNormal(ms, t, n, &area);
      if (PetscSqr(n[m->ax]) + PetscSqr(n[m->ay]) >= 0.25) {
        PetscReal gx, gy, tx, ty, tip[3];

        for (PetscInt d = 0; d < 3; d++) tip[d] = g[d] + FS_GEOMETRY_TICK / m->scale * n[d];
        FSImageMapPoint(m, g, &gx, &gy);
        FSImageMapPoint(m, tip, &tx, &ty);
        FSImageDrawLine(img, FSImageRound(gx), FSImageRound(gy), FSImageRound(tx), FSImageRound(ty), 1, col);
      }
    }
  PetscFunctionReturn(0);
}

/*
   FSBoundaryWriteGeometry_Trimesh - walls.h5 (collective: rank 0 writes every input triangle) and
   walls.xdmf (rank 0, FSBoundaryWriteWallsXDMF_Private), each written to a temporary name and renamed;
   then says where they are.
*/
PetscErrorCode FSBoundaryWriteGeometry_Trimesh(FSBoundary b, const char dir[])
{
  const FSMesh *ms   = &((FSBoundary_Trimesh *)b->data)->mesh;
  MPI_Comm      comm = PetscObjectComm((PetscObject)b);
  PetscMPIInt   rank;
  PetscInt      n, ntri = ms->ntri;
  PetscReal    *pts, *wall, *nrm, *area;
  PetscInt     *conn;
  char          what[128];

  PetscFunctionBegin;
  PetscCallMPI(MPI_Comm_rank(comm, &rank));
  n = rank == 0 ? ntri : 0;
  PetscCall(PetscMalloc5(9 * n + 1, &pts, n + 1, &wall, 3 * n + 1, &nrm, n + 1, &area, 3 * n + 1, &conn));
  for (PetscInt t = 0; t < n; t++) {
    for (PetscInt i = 0; i < 3; i++) {
      for (PetscInt d = 0; d < 3; d++) pts[9 * t + 3 * i + d] = ms->vert[3 * ms->tri[3 * t + i] + d];
      conn[3 * t + i] = 3 * t + i;
    }
    TriangleNormal(ms, t, &nrm[3 * t], &area[t]);
    wall[t] = (PetscReal)ms->triwall[t];
  }
  PetscCall(FSBoundaryWriteWallsH5_Private(b, dir, 3, n, ntri, pts, conn, wall, nrm, "area", area, "ntriangles"));
  PetscCall(PetscFree5(pts, wall, nrm, area, conn));

  PetscCall(PetscSNPrintf(what, sizeof(what),
                          "%" PetscInt_FMT " triangles as given (the run integrates over %" PetscInt_FMT
                          " elements refined from them)",
                          ntri, ms->nelglobal));
  PetscCall(FSBoundaryWriteWallsXDMF_Private(b, dir, "Triangle", 3, ntri, "area", what));
  PetscFunctionReturn(0);
}
