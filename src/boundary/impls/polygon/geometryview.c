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
  PetscInt       n, nw = w->nwalls, nseg = w->nseg;
  PetscReal     *pts, *wall, *nrm, *len;
  PetscInt      *conn;
  FSOutputField  fields[4];
  IS             is;
  PetscViewer    viewer;
  char           path[PETSC_MAX_PATH_LEN], tmp[PETSC_MAX_PATH_LEN], what[64], *names;

  PetscFunctionBegin;
  PetscCallMPI(MPI_Comm_rank(comm, &rank));
  n = rank == 0 ? nseg : 0;
  PetscCall(FSBoundaryJoinWallNames_Private(b, &names));
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
  fields[0] = (FSOutputField){"points", 2, pts};
  fields[1] = (FSOutputField){"wall", 1, wall};
  fields[2] = (FSOutputField){"normal", 2, nrm};
  fields[3] = (FSOutputField){"length", 1, len};

  PetscCall(PetscSNPrintf(path, sizeof(path), "%s/walls.h5", dir));
  PetscCall(PetscSNPrintf(tmp, sizeof(tmp), "%s.tmp", path));
  PetscCall(PetscViewerHDF5Open(comm, tmp, FILE_MODE_WRITE, &viewer));
  PetscCall(PetscViewerHDF5WriteGroup(viewer, "/walls"));
  PetscCall(PetscViewerHDF5PushGroup(viewer, "/walls"));
  /* the points are two per segment: written as a field of 2n entries with bs 2 */
  PetscCall(FSViewFields_Private(viewer, comm, 2 * n, 1, &fields[0]));
  PetscCall(FSViewFields_Private(viewer, comm, n, 3, &fields[1]));
  PetscCall(ISCreateGeneral(comm, 2 * n, conn, PETSC_USE_POINTER, &is));
  PetscCall(ISSetBlockSize(is, 2)); /* written as (nseg, 2) */
  PetscCall(PetscObjectSetName((PetscObject)is, "connectivity"));
  PetscCall(ISView(is, viewer));
  PetscCall(ISDestroy(&is));
  PetscCall(PetscViewerHDF5WriteAttribute(viewer, "/walls", "nsegments", PETSC_INT, &nseg));
  PetscCall(PetscViewerHDF5WriteAttribute(viewer, "/walls", "nwalls", PETSC_INT, &nw));
  PetscCall(PetscViewerHDF5WriteAttribute(viewer, "/walls", "names", PETSC_STRING, names));
  PetscCall(PetscViewerHDF5PopGroup(viewer));
  PetscCall(PetscViewerDestroy(&viewer));
  PetscCallMPI(MPI_Barrier(comm)); /* every rank has closed the file before it is renamed */
  PetscCall(FSRenameFile_Private(comm, tmp, path));
  PetscCall(PetscFree5(pts, wall, nrm, len, conn));
  PetscCall(PetscFree(names));

  PetscCall(PetscSNPrintf(what, sizeof(what), "%" PetscInt_FMT " segments", nseg));
  PetscCall(FSBoundaryWriteWallsXDMF_Private(b, dir, "Polyline", 2, nseg, "length", what));
  PetscFunctionReturn(0);
}
