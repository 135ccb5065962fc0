/*
   The polygon boundary's part of the geometry view (-fs_geometry_view, src/solver/geometryview.c):
     the walls in geometry.png      each wall in its colour (FSImagePalette), with ticks along the normals
     <dir>/walls.h5, walls.xdmf     the wall segments, for ParaView next to particles.xdmf

   Layout of walls.h5 (float64 unless said):
     /walls                     group; attributes nsegments, nwalls (int), names (the wall names,
                                comma separated, in wall-index order)
     /walls/points              (2 nseg, 2): the end points p0, p1 of every segment
     /walls/connectivity        (nseg, 2) integers: 2k, 2k+1 for segment k (the XDMF topology)
     /walls/wall                (nseg,): the wall index of each segment
     /walls/normal              (nseg, 2): the unit normal, pointing out of the liquid
     /walls/length              (nseg,): the segment length
*/
#include <petscviewerhdf5.h>
#include "polygonimpl.h"

#define FS_GEOMETRY_TICK  7  /* length of a normal tick, pixels */
#define FS_GEOMETRY_TICKS 24 /* pixels of wall between two ticks */

/* FSBoundaryDraw_Polygon - rank 0: the walls with their normal ticks, each wall in its colour */
PetscErrorCode FSBoundaryDraw_Polygon(FSBoundary b, FSImage *img, const FSImageMap *m)
{
  const FSWalls *w   = &((FSBoundary_Polygon *)b->data)->walls;
  PetscReal      acc = FS_GEOMETRY_TICKS;

  PetscFunctionBegin;
  for (PetscInt k = 0; k < w->nseg; k++) {
    const PetscReal     *sg = &w->seg[k * FS_SEG_STRIDE];
    const unsigned char *c  = FSImagePalette[w->segwall[k] % FS_IMAGE_NPALETTE];
    const PetscReal      mx = FSImageMapX(m, sg[FS_SEG_MID]), my = FSImageMapY(m, sg[FS_SEG_MID + 1]);

    /* the 2-pixel pen covers the pixel right and below the line: start half a pixel up-left */
    FSImageDrawLine(
        img, FSImageRound(FSImageMapX(m, sg[FS_SEG_P0]) - 0.5), FSImageRound(FSImageMapY(m, sg[FS_SEG_P0 + 1]) - 0.5),
        FSImageRound(FSImageMapX(m, sg[FS_SEG_P1]) - 0.5), FSImageRound(FSImageMapY(m, sg[FS_SEG_P1 + 1]) - 0.5), 2, c);
    /* a tick along the normal (out of the liquid, so on the wall's solid side) every few segments;
       the pixel y axis points down, hence the minus on the normal's y */
    acc += sg[FS_SEG_LENGTH] * m->scale;
    if (acc >= FS_GEOMETRY_TICKS) {
      FSImageDrawLine(img, FSImageRound(mx), FSImageRound(my), FSImageRound(mx + FS_GEOMETRY_TICK * sg[FS_SEG_NORMAL]),
                      FSImageRound(my - FS_GEOMETRY_TICK * sg[FS_SEG_NORMAL + 1]), 1, c);
      acc = 0;
    }
  }
  PetscFunctionReturn(0);
}

/*
   FSBoundaryWriteGeometry_Polygon - walls.h5 (collective: rank 0 holds every segment) and walls.xdmf
   (rank 0, FSBoundaryWriteWallsXDMF_Private), each written to a temporary name and renamed; then
   says where they are.
*/
PetscErrorCode FSBoundaryWriteGeometry_Polygon(FSBoundary b, const char dir[])
{
  const FSWalls *w    = &((FSBoundary_Polygon *)b->data)->walls;
  MPI_Comm       comm = PetscObjectComm((PetscObject)b);
  PetscMPIInt    rank;
  PetscInt       n, nseg = w->nseg;
  PetscReal     *pts, *wall, *nrm, *len;
  PetscInt      *conn;
  char           what[64];

  PetscFunctionBegin;
  PetscCallMPI(MPI_Comm_rank(comm, &rank));
  n = rank == 0 ? nseg : 0;
  PetscCall(PetscMalloc5(4 * n + 1, &pts, n + 1, &wall, 2 * n + 1, &nrm, n + 1, &len, 2 * n + 1, &conn));
  for (PetscInt k = 0; k < n; k++) {
    const PetscReal *sg = &w->seg[k * FS_SEG_STRIDE];
    for (PetscInt c = 0; c < 4; c++) pts[4 * k + c] = sg[c];
    nrm[2 * k]      = sg[FS_SEG_NORMAL];
    nrm[2 * k + 1]  = sg[FS_SEG_NORMAL + 1];
    len[k]          = sg[FS_SEG_LENGTH];
    wall[k]         = (PetscReal)w->segwall[k];
    conn[2 * k]     = 2 * k;
    conn[2 * k + 1] = 2 * k + 1;
  }
  PetscCall(FSBoundaryWriteWallsH5_Private(b, dir, 2, n, nseg, pts, conn, wall, nrm, "length", len, "nsegments"));
  PetscCall(PetscFree5(pts, wall, nrm, len, conn));

  PetscCall(PetscSNPrintf(what, sizeof(what), "%" PetscInt_FMT " segments", nseg));
  PetscCall(FSBoundaryWriteWallsXDMF_Private(b, dir, "Polyline", 2, nseg, "length", what));
  PetscFunctionReturn(0);
}
