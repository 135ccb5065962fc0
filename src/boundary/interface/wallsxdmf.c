/*
   What the boundary implementations share for the walls' files of the geometry view
   (FSBoundaryWriteGeometry): the wall names as one string, and <dir>/walls.xdmf, the index that lets
   ParaView open the walls.h5 the implementation wrote (segments in 2-D, triangles in 3-D).

   walls.h5 is expected to hold, in the group /walls, with nel elements of nodes points each:
     points       (nodes nel, dim) reals, the points of element k at nodes k .. nodes k + nodes - 1
     connectivity (nel, nodes) integers
     wall         (nel,) reals, the wall index
     normal       (nel, dim) reals
     <measure>    (nel,) reals, the element's length or area
*/
#define _POSIX_C_SOURCE 200809L
#include <errno.h>
#include <stdio.h>
#include <string.h>
#include <petscviewerhdf5.h>
#include "boundary/boundaryimpl.h"

/*
   FSBoundaryJoinWallNames_Private - the wall names, comma separated, in wall-index order (to free with
   PetscFree()).

   Not collective

   Note: copied by length, not with PetscStrlcat(): PETSc 3.18's PetscStrlcat() limits what it appends
   by the length of the appended string instead of the room left, and cut a single wall "tank" to "ta".
*/
PetscErrorCode FSBoundaryJoinWallNames_Private(FSBoundary b, char **names)
{
  size_t len = 1, at = 0;

  PetscFunctionBegin;
  for (PetscInt q = 0; q < b->nwalls; q++) len += strlen(b->wallname[q]) + 1;
  PetscCall(PetscCalloc1(len, names));
  for (PetscInt q = 0; q < b->nwalls; q++) {
    const size_t n = strlen(b->wallname[q]);

    if (q) (*names)[at++] = ',';
    PetscCall(PetscArraycpy(*names + at, b->wallname[q], n));
    at += n;
  }
  PetscFunctionReturn(0);
}

/* Rank 0: walls.xdmf to tmp, created as id; returns an errno value */
static int FSWriteWallsXDMF(const char tmp[], FSFileId *id, const char names[], PetscInt dim, const char topology[],
                            PetscInt nodes, PetscInt nel, const char measure[])
{
  const int psize = (int)sizeof(PetscReal);
  FILE     *fp;
  int       st = 0, err = 0;

  if ((err = FSFileCreate_Private(tmp, &fp, id))) return err; /* not through a link under the name */
  st |= fprintf(fp, "<?xml version=\"1.0\" ?>\n<Xdmf Version=\"3.0\">\n  <Domain>\n    <Grid Name=\"walls\" "
                    "GridType=\"Uniform\">\n") < 0;
  st |= fprintf(fp, "      <Information Name=\"walls\" Value=\"%s\"/>\n", names) < 0;
  st |= fprintf(fp,
                "      <Topology TopologyType=\"%s\" NumberOfElements=\"%" PetscInt_FMT
                "\" NodesPerElement=\"%" PetscInt_FMT "\">\n",
                topology, nel, nodes) < 0;
  st |= fprintf(fp,
                "        <DataItem Dimensions=\"%" PetscInt_FMT " %" PetscInt_FMT
                "\" NumberType=\"Int\" Precision=\"%d\" Format=\"HDF\">walls.h5:/walls/connectivity</DataItem>\n",
                nel, nodes, (int)sizeof(PetscInt)) < 0;
  st |= fprintf(fp, "      </Topology>\n      <Geometry GeometryType=\"%s\">\n", dim == 3 ? "XYZ" : "XY") < 0;
  st |= fprintf(fp,
                "        <DataItem Dimensions=\"%" PetscInt_FMT " %" PetscInt_FMT
                "\" NumberType=\"Float\" Precision=\"%d\" Format=\"HDF\">walls.h5:/walls/points</DataItem>\n",
                nodes * nel, dim, psize) < 0;
  st |= fprintf(fp, "      </Geometry>\n") < 0;
  st |= fprintf(fp, "      <Attribute Name=\"wall\" AttributeType=\"Scalar\" Center=\"Cell\">\n") < 0;
  st |= fprintf(fp,
                "        <DataItem Dimensions=\"%" PetscInt_FMT
                "\" NumberType=\"Float\" Precision=\"%d\" Format=\"HDF\">walls.h5:/walls/wall</DataItem>\n      "
                "</Attribute>\n",
                nel, psize) < 0;
  st |= fprintf(fp, "      <Attribute Name=\"normal\" AttributeType=\"Vector\" Center=\"Cell\">\n") < 0;
  st |= fprintf(fp,
                "        <DataItem Dimensions=\"%" PetscInt_FMT " %" PetscInt_FMT
                "\" NumberType=\"Float\" Precision=\"%d\" Format=\"HDF\">walls.h5:/walls/normal</DataItem>\n      "
                "</Attribute>\n",
                nel, dim, psize) < 0;
  st |= fprintf(fp, "      <Attribute Name=\"%s\" AttributeType=\"Scalar\" Center=\"Cell\">\n", measure) < 0;
  st |= fprintf(fp,
                "        <DataItem Dimensions=\"%" PetscInt_FMT
                "\" NumberType=\"Float\" Precision=\"%d\" Format=\"HDF\">walls.h5:/walls/%s</DataItem>\n      "
                "</Attribute>\n",
                nel, psize, measure) < 0;
  st |= fprintf(fp, "    </Grid>\n  </Domain>\n</Xdmf>\n") < 0;
  if (st) err = errno ? errno : EIO;
  if (fclose(fp) != 0 && !err) err = errno ? errno : EIO;
  return err;
}

/*
   FSBoundaryWriteWallsXDMF_Private - writes <dir>/walls.xdmf (rank 0, to a temporary name renamed
   when complete) for the walls.h5 the implementation has written, then says where they are (when
   FSBoundaryWriteGeometry was asked to).

   Collective

   Input Parameters:
+  b        - the boundary (its dimension and wall names are used)
.  dir      - the directory of walls.h5
.  topology - the XDMF topology of the elements: "Polyline" (segments) or "Triangle"
.  nodes    - points per element: 2 or 3
.  nel      - the number of elements
.  measure  - the name of the elements' length or area dataset: "length" or "area"
-  what     - the elements in words for the message, e.g. "564 segments"
*/
PetscErrorCode FSBoundaryWriteWallsXDMF_Private(FSBoundary b, const char dir[], const char topology[], PetscInt nodes,
                                                PetscInt nel, const char measure[], const char what[])
{
  MPI_Comm    comm = PetscObjectComm((PetscObject)b);
  PetscMPIInt rank;
  char        path[PETSC_MAX_PATH_LEN], tmp[PETSC_MAX_PATH_LEN], *names;
  int         err = 0;
  FSFileId    id;

  PetscFunctionBegin;
  PetscCallMPI(MPI_Comm_rank(comm, &rank));
  PetscCall(FSBoundaryJoinWallNames_Private(b, &names));
  PetscCall(PetscSNPrintf(path, sizeof(path), "%s/walls.xdmf", dir));
  PetscCall(PetscSNPrintf(tmp, sizeof(tmp), "%s.tmp", path));
  if (rank == 0) err = FSWriteWallsXDMF(tmp, &id, names, b->dim, topology, nodes, nel, measure);
  PetscCallMPI(MPI_Bcast(&err, 1, MPI_INT, 0, comm));
  PetscCheck(!err, comm, PETSC_ERR_FILE_WRITE, "Cannot write \"%s\": %s", tmp, strerror(err));
  PetscCall(FSRenameFile_Private(comm, tmp, path, &id));
  PetscCall(PetscFree(names));
  if (!b->geometry_verbose) PetscFunctionReturn(0);
  PetscCall(PetscPrintf(comm, "Geometry view: %s/walls.xdmf (+ walls.h5): %s of %" PetscInt_FMT " wall(s) (", dir, what,
                        b->nwalls));
  for (PetscInt q = 0; q < b->nwalls; q++)
    PetscCall(PetscPrintf(comm, "%s%" PetscInt_FMT " %s", q ? ", " : "", q, b->wallname[q]));
  PetscCall(PetscPrintf(comm, "), to open in ParaView with the XDMF Reader next to particles.xdmf\n"));
  PetscFunctionReturn(0);
}

/* The HDF5 file of the walls, written to tmp, created first as id (collective) */
static PetscErrorCode FSWriteWallsH5(MPI_Comm comm, const char tmp[], FSFileId *id, PetscInt dim, PetscInt n,
                                     PetscInt nel, PetscInt nw, const char names[], const FSOutputField fields[],
                                     PetscInt conn[], const char countname[])
{
  const PetscInt nodes = dim;
  IS             is;
  PetscViewer    viewer;

  PetscFunctionBegin;
  PetscCall(FSFileCreateShared_Private(comm, tmp, id)); /* HDF5 would follow a link under the name */
  PetscCall(PetscViewerHDF5Open(comm, tmp, FILE_MODE_WRITE, &viewer));
  PetscCall(PetscViewerHDF5WriteGroup(viewer, "/walls"));
  PetscCall(PetscViewerHDF5PushGroup(viewer, "/walls"));
  /* the points are nodes per element: written as a field of nodes n entries */
  PetscCall(FSViewFields_Private(viewer, comm, nodes * n, 1, &fields[0]));
  PetscCall(FSViewFields_Private(viewer, comm, n, 3, &fields[1]));
  PetscCall(ISCreateGeneral(comm, nodes * n, conn, PETSC_USE_POINTER, &is));
  PetscCall(ISSetBlockSize(is, nodes)); /* written as (nel, nodes) */
  PetscCall(PetscObjectSetName((PetscObject)is, "connectivity"));
  PetscCall(ISView(is, viewer));
  PetscCall(ISDestroy(&is));
  PetscCall(PetscViewerHDF5WriteAttribute(viewer, "/walls", countname, PETSC_INT, &nel));
  PetscCall(PetscViewerHDF5WriteAttribute(viewer, "/walls", "nwalls", PETSC_INT, &nw));
  PetscCall(PetscViewerHDF5WriteAttribute(viewer, "/walls", "names", PETSC_STRING, names));
  PetscCall(PetscViewerHDF5PopGroup(viewer));
  PetscCall(PetscViewerDestroy(&viewer));
  PetscFunctionReturn(0);
}

/*
   FSBoundaryWriteWallsH5_Private - <dir>/walls.h5 in the layout above, written to a temporary name and
   renamed: the n elements this rank gives (rank 0 gives all nel, the others none), of dim nodes
   each (segments in 2-D, triangles in 3-D): their points (nodes n x dim), connectivity (nodes n),
   wall index, normal (dim) and measure (length or area, named measure); the attributes countname
   (= nel), nwalls and names.

   Collective
*/
PetscErrorCode FSBoundaryWriteWallsH5_Private(FSBoundary b, const char dir[], PetscInt dim, PetscInt n, PetscInt nel,
                                              PetscReal pts[], PetscInt conn[], PetscReal wall[], PetscReal nrm[],
                                              const char measure[], PetscReal meas[], const char countname[])
{
  MPI_Comm       comm = PetscObjectComm((PetscObject)b);
  const PetscInt nw   = b->nwalls;
  FSOutputField  fields[4];
  char           path[PETSC_MAX_PATH_LEN], tmp[PETSC_MAX_PATH_LEN], *names;
  int            syserr;
  PetscErrorCode ierr;
  FSFileId       id;

  PetscFunctionBegin;
  PetscCall(FSBoundaryJoinWallNames_Private(b, &names));
  fields[0] = (FSOutputField){.name = "points", .bs = dim, .data = pts};
  fields[1] = (FSOutputField){.name = "wall", .bs = 1, .data = wall};
  fields[2] = (FSOutputField){.name = "normal", .bs = dim, .data = nrm};
  fields[3] = (FSOutputField){.name = measure, .bs = 1, .data = meas};
  PetscCall(PetscSNPrintf(path, sizeof(path), "%s/walls.h5", dir));
  PetscCall(PetscSNPrintf(tmp, sizeof(tmp), "%s.tmp", path));
  /* a failed write (a full disk) is an error naming the file */
  PetscCall(PetscPushErrorHandler(PetscReturnErrorHandler, NULL));
  errno  = 0;
  ierr   = FSWriteWallsH5(comm, tmp, &id, dim, n, nel, nw, names, fields, conn, countname);
  syserr = errno;
  PetscCall(PetscPopErrorHandler());
  PetscCall(FSWriteCheck_Private(ierr, syserr, path));
  PetscCallMPI(MPI_Barrier(comm)); /* every rank has closed the file before it is renamed */
  PetscCall(FSRenameFile_Private(comm, tmp, path, &id));
  PetscCall(PetscFree(names));
  PetscFunctionReturn(0);
}
