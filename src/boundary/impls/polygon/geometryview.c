/*
   The polygon boundary's part of the geometry view (-fs_geometry_view, src/solver/geometryview.c):
     the walls in geometry.png      each wall in its colour (FSImagePalette), with ticks along the normals
     <dir>/walls.h5, walls.xdmf     the wall segments, for ParaView next to particles.xdmf

   Layout of walls.h5 (float64 unless said):
     /walls                     group; attributes nsegments, nwalls (int), names (the wall names,
                                comma separated, in wall-index order)
     /walls/points              (2 nseg, 2): the end points p0, p1 of every segment
     /walls/connectivity        (2 nseg,) integers: 2k, 2k+1 for segment k (the XDMF topology)
     /walls/wall                (nseg,): the wall index of each segment
     /walls/normal              (nseg, 2): the unit normal, pointing out of the liquid
     /walls/length              (nseg,): the segment length
*/
#define _POSIX_C_SOURCE 200809L
#include <errno.h>
#include <stdio.h>
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

/* Rank 0: walls.xdmf to tmp; returns an errno value */
static int FSGeometryWriteWallsXDMF(const char tmp[], PetscInt nseg, const char names[])
{
  FILE *fp;
  int   st = 0, err = 0;

  fp = fopen(tmp, "w");
  if (!fp) return errno ? errno : EIO;
  st |= fprintf(fp, "<?xml version=\"1.0\" ?>\n<Xdmf Version=\"3.0\">\n  <Domain>\n    <Grid Name=\"walls\" "
                    "GridType=\"Uniform\">\n") < 0;
  st |= fprintf(fp, "      <Information Name=\"walls\" Value=\"%s\"/>\n", names) < 0;
  st |= fprintf(fp,
                "      <Topology TopologyType=\"Polyline\" NumberOfElements=\"%" PetscInt_FMT
                "\" NodesPerElement=\"2\">\n",
                nseg) < 0;
  st |= fprintf(fp,
                "        <DataItem Dimensions=\"%" PetscInt_FMT
                " 2\" NumberType=\"Int\" Precision=\"%d\" Format=\"HDF\">walls.h5:/walls/connectivity</DataItem>\n",
                nseg, (int)sizeof(PetscInt)) < 0;
  st |= fprintf(fp, "      </Topology>\n      <Geometry GeometryType=\"XY\">\n") < 0;
  st |= fprintf(fp,
                "        <DataItem Dimensions=\"%" PetscInt_FMT
                " 2\" NumberType=\"Float\" Precision=\"%d\" Format=\"HDF\">walls.h5:/walls/points</DataItem>\n",
                2 * nseg, (int)sizeof(PetscReal)) < 0;
  st |= fprintf(fp, "      </Geometry>\n") < 0;
  st |= fprintf(fp, "      <Attribute Name=\"wall\" AttributeType=\"Scalar\" Center=\"Cell\">\n") < 0;
  st |= fprintf(fp,
                "        <DataItem Dimensions=\"%" PetscInt_FMT
                "\" NumberType=\"Float\" Precision=\"%d\" Format=\"HDF\">walls.h5:/walls/wall</DataItem>\n      "
                "</Attribute>\n",
                nseg, (int)sizeof(PetscReal)) < 0;
  st |= fprintf(fp, "      <Attribute Name=\"normal\" AttributeType=\"Vector\" Center=\"Cell\">\n") < 0;
  st |= fprintf(fp,
                "        <DataItem Dimensions=\"%" PetscInt_FMT
                " 2\" NumberType=\"Float\" Precision=\"%d\" Format=\"HDF\">walls.h5:/walls/normal</DataItem>\n      "
                "</Attribute>\n",
                nseg, (int)sizeof(PetscReal)) < 0;
  st |= fprintf(fp, "      <Attribute Name=\"length\" AttributeType=\"Scalar\" Center=\"Cell\">\n") < 0;
  st |= fprintf(fp,
                "        <DataItem Dimensions=\"%" PetscInt_FMT
                "\" NumberType=\"Float\" Precision=\"%d\" Format=\"HDF\">walls.h5:/walls/length</DataItem>\n      "
                "</Attribute>\n",
                nseg, (int)sizeof(PetscReal)) < 0;
  st |= fprintf(fp, "    </Grid>\n  </Domain>\n</Xdmf>\n") < 0;
  if (st) err = errno ? errno : EIO;
  if (fclose(fp) != 0 && !err) err = errno ? errno : EIO;
  return err;
}

/*
   FSBoundaryWriteGeometry_Polygon - walls.h5 (collective: rank 0 holds every segment) and walls.xdmf
   (rank 0), each written to a temporary name and renamed; then says where they are.
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
  char           path[PETSC_MAX_PATH_LEN], tmp[PETSC_MAX_PATH_LEN], *names;
  size_t         namelen = 1;
  int            err     = 0;

  PetscFunctionBegin;
  PetscCallMPI(MPI_Comm_rank(comm, &rank));
  n = rank == 0 ? nseg : 0;
  for (PetscInt q = 0; q < nw; q++) namelen += strlen(w->name[q]) + 1;
  PetscCall(PetscCalloc1(namelen, &names));
  for (PetscInt q = 0; q < nw; q++) {
    if (q) PetscCall(PetscStrlcat(names, ",", namelen));
    PetscCall(PetscStrlcat(names, w->name[q], namelen));
  }
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

  PetscCall(PetscSNPrintf(path, sizeof(path), "%s/walls.xdmf", dir));
  PetscCall(PetscSNPrintf(tmp, sizeof(tmp), "%s.tmp", path));
  if (rank == 0) err = FSGeometryWriteWallsXDMF(tmp, nseg, names);
  PetscCallMPI(MPI_Bcast(&err, 1, MPI_INT, 0, comm));
  PetscCheck(!err, comm, PETSC_ERR_FILE_WRITE, "Cannot write \"%s\": %s", tmp, strerror(err));
  PetscCall(FSRenameFile_Private(comm, tmp, path));
  PetscCall(PetscFree(names));
  PetscCall(PetscPrintf(
      comm, "Geometry view: %s/walls.xdmf (+ walls.h5): %" PetscInt_FMT " segments of %" PetscInt_FMT " wall(s) (", dir,
      w->nseg, w->nwalls));
  for (PetscInt q = 0; q < w->nwalls; q++)
    PetscCall(PetscPrintf(comm, "%s%" PetscInt_FMT " %s", q ? ", " : "", q, w->name[q]));
  PetscCall(PetscPrintf(comm, "), to open in ParaView with the XDMF Reader next to particles.xdmf\n"));
  PetscFunctionReturn(0);
}
