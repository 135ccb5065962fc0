/*
   The geometry view (-fs_geometry_view): the set-up as files a user can look at before running:
     <dir>/geometry.png         the walls and the particles (rank 0 draws, after gathering the
                                particle positions of every rank)
     <dir>/walls.h5, walls.xdmf the wall segments, for ParaView next to particles.xdmf

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
#include "solver/solverimpl.h"
#include "io/fsimage.h"
#include "polygonimpl.h"

#define FS_GEOMETRY_SIZE   1600 /* pixels on the longer side */
#define FS_GEOMETRY_MARGIN 20   /* white pixels around the drawing */
#define FS_GEOMETRY_TICK   7    /* length of a normal tick, pixels */
#define FS_GEOMETRY_TICKS  24   /* pixels of wall between two ticks */

/* the picture's colours (tests/python/test_geometry_view.py checks them) */
static const unsigned char FSGeometryWhite[3]    = {255, 255, 255};
static const unsigned char FSGeometryParticle[3] = {30, 90, 220};
static const unsigned char FSGeometryWall[6][3]  = {
  {40, 40, 40}, {170, 30, 30}, {0, 110, 50}, {120, 50, 160}, {180, 100, 0}, {0, 100, 120},
};

typedef struct {
  PetscReal x0, y0, scale; /* world (x0, y0) is at pixel (margin, height - 1 - margin) */
  PetscInt  height;
} FSGeometryMap;

static inline PetscReal FSGeometryPX(const FSGeometryMap *m, PetscReal x) { return FS_GEOMETRY_MARGIN + (x - m->x0) * m->scale; }
static inline PetscReal FSGeometryPY(const FSGeometryMap *m, PetscReal y) { return (PetscReal)(m->height - 1 - FS_GEOMETRY_MARGIN) - (y - m->y0) * m->scale; }
static inline PetscInt  FSGeometryRound(PetscReal v) { return (PetscInt)PetscFloorReal(v + 0.5); }

/* Rank 0: draws the particles (x, y pairs), then the walls with their normal ticks */
static PetscErrorCode FSGeometryDraw(FSSolver s, const FSWalls *w, PetscInt np, const PetscReal xy[], const PetscReal lo[], const PetscReal hi[], FSImage *img)
{
  const PetscReal span = PetscMax(hi[0] - lo[0], hi[1] - lo[1]);
  FSGeometryMap   m;
  PetscInt        width, height;
  PetscReal       r, acc = FS_GEOMETRY_TICKS;

  PetscFunctionBegin;
  m.x0    = lo[0];
  m.y0    = lo[1];
  m.scale = (FS_GEOMETRY_SIZE - 1 - 2 * FS_GEOMETRY_MARGIN) / span;
  width   = FSGeometryRound((hi[0] - lo[0]) * m.scale) + 2 * FS_GEOMETRY_MARGIN + 1;
  height  = FSGeometryRound((hi[1] - lo[1]) * m.scale) + 2 * FS_GEOMETRY_MARGIN + 1;
  m.height = height;
  PetscCall(FSImageCreate(width, height, img));
  FSImageFill(img, FSGeometryWhite);
  /* particles: discs of a quarter of the spacing, at least one pixel, at most 4 pixels in radius */
  r = PetscMin(4.0, PetscMax(0.5, 0.25 * s->dx * m.scale));
  for (PetscInt k = 0; k < np; k++) FSImageDrawDisc(img, FSGeometryPX(&m, xy[2 * k]), FSGeometryPY(&m, xy[2 * k + 1]), r, FSGeometryParticle);
  if (!w) PetscFunctionReturn(0);
  for (PetscInt k = 0; k < w->nseg; k++) {
    const PetscReal     *sg = &w->seg[k * FS_SEG_STRIDE];
    const unsigned char *c  = FSGeometryWall[w->segwall[k] % 6];
    const PetscReal      mx = FSGeometryPX(&m, sg[4]), my = FSGeometryPY(&m, sg[5]);

    /* the 2-pixel pen covers the pixel right and below the line: start half a pixel up-left */
    FSImageDrawLine(img, FSGeometryRound(FSGeometryPX(&m, sg[0]) - 0.5), FSGeometryRound(FSGeometryPY(&m, sg[1]) - 0.5), FSGeometryRound(FSGeometryPX(&m, sg[2]) - 0.5), FSGeometryRound(FSGeometryPY(&m, sg[3]) - 0.5), 2, c);
    /* a tick along the normal (out of the liquid, so on the wall's solid side) every few segments;
       the pixel y axis points down, hence the minus on the normal's y */
    acc += sg[8] * m.scale;
    if (acc >= FS_GEOMETRY_TICKS) {
      FSImageDrawLine(img, FSGeometryRound(mx), FSGeometryRound(my), FSGeometryRound(mx + FS_GEOMETRY_TICK * sg[6]), FSGeometryRound(my - FS_GEOMETRY_TICK * sg[7]), 1, c);
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
  st |= fprintf(fp, "<?xml version=\"1.0\" ?>\n<Xdmf Version=\"3.0\">\n  <Domain>\n    <Grid Name=\"walls\" GridType=\"Uniform\">\n") < 0;
  st |= fprintf(fp, "      <Information Name=\"walls\" Value=\"%s\"/>\n", names) < 0;
  st |= fprintf(fp, "      <Topology TopologyType=\"Polyline\" NumberOfElements=\"%" PetscInt_FMT "\" NodesPerElement=\"2\">\n", nseg) < 0;
  st |= fprintf(fp, "        <DataItem Dimensions=\"%" PetscInt_FMT " 2\" NumberType=\"Int\" Precision=\"%d\" Format=\"HDF\">walls.h5:/walls/connectivity</DataItem>\n", nseg, (int)sizeof(PetscInt)) < 0;
  st |= fprintf(fp, "      </Topology>\n      <Geometry GeometryType=\"XY\">\n") < 0;
  st |= fprintf(fp, "        <DataItem Dimensions=\"%" PetscInt_FMT " 2\" NumberType=\"Float\" Precision=\"%d\" Format=\"HDF\">walls.h5:/walls/points</DataItem>\n", 2 * nseg, (int)sizeof(PetscReal)) < 0;
  st |= fprintf(fp, "      </Geometry>\n") < 0;
  st |= fprintf(fp, "      <Attribute Name=\"wall\" AttributeType=\"Scalar\" Center=\"Cell\">\n") < 0;
  st |= fprintf(fp, "        <DataItem Dimensions=\"%" PetscInt_FMT "\" NumberType=\"Float\" Precision=\"%d\" Format=\"HDF\">walls.h5:/walls/wall</DataItem>\n      </Attribute>\n", nseg, (int)sizeof(PetscReal)) < 0;
  st |= fprintf(fp, "      <Attribute Name=\"normal\" AttributeType=\"Vector\" Center=\"Cell\">\n") < 0;
  st |= fprintf(fp, "        <DataItem Dimensions=\"%" PetscInt_FMT " 2\" NumberType=\"Float\" Precision=\"%d\" Format=\"HDF\">walls.h5:/walls/normal</DataItem>\n      </Attribute>\n", nseg, (int)sizeof(PetscReal)) < 0;
  st |= fprintf(fp, "      <Attribute Name=\"length\" AttributeType=\"Scalar\" Center=\"Cell\">\n") < 0;
  st |= fprintf(fp, "        <DataItem Dimensions=\"%" PetscInt_FMT "\" NumberType=\"Float\" Precision=\"%d\" Format=\"HDF\">walls.h5:/walls/length</DataItem>\n      </Attribute>\n", nseg, (int)sizeof(PetscReal)) < 0;
  st |= fprintf(fp, "    </Grid>\n  </Domain>\n</Xdmf>\n") < 0;
  if (st) err = errno ? errno : EIO;
  if (fclose(fp) != 0 && !err) err = errno ? errno : EIO;
  return err;
}

/* walls.h5 (collective: rank 0 holds every segment) and walls.xdmf (rank 0), each tmp + rename */
static PetscErrorCode FSGeometryWriteWalls(FSSolver s, const FSWalls *w, const char dir[])
{
  MPI_Comm      comm = PetscObjectComm((PetscObject)s);
  PetscMPIInt   rank;
  PetscInt      n, nw = w->nwalls, nseg = w->nseg;
  PetscReal    *pts, *wall, *nrm, *len;
  PetscInt     *conn;
  FSOutputField fields[4];
  IS            is;
  PetscViewer   viewer;
  char          path[PETSC_MAX_PATH_LEN], tmp[PETSC_MAX_PATH_LEN], *names;
  size_t        namelen = 1;
  int           err = 0;

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
    nrm[2 * k]      = sg[6];
    nrm[2 * k + 1]  = sg[7];
    len[k]          = sg[8];
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
  PetscFunctionReturn(0);
}

/*
   FSSolverGeometryView - writes the set-up as files to look at before running: a picture of the walls
   and the particles, <dir>/geometry.png, and the wall segments, <dir>/walls.h5 + walls.xdmf, for
   ParaView next to the particle snapshots (particles.xdmf); then prints where they are.

   Collective

   Input Parameters:
+  s   - the solver, after FSSolverSetUp()
-  dir - the directory (created if needed)

   Options Database Key:
.  -fs_geometry_view - FSSolverSetUp() calls this on the output directory, also writes the particles
                       at step 0 (snapshot_000000.h5 in particles.xdmf) and FSSolverSolve() then
                       stops without time stepping

   Notes:
   The picture is FS_GEOMETRY_SIZE (1600) pixels on its longer side with a 20-pixel white margin and
   the aspect ratio of the walls' bounding box (of the domain's x-y box without walls; a 3-D run shows
   the particles projected on x-y). Each named wall has its own dark colour (the first wall dark grey,
   then red, green, purple, orange, teal); short ticks along the normals, every 24 pixels of wall,
   stand on the side of the wall away from the liquid; particles are blue dots. Rank 0 draws, after
   gathering every rank's particle positions, so the picture does not depend on the number of ranks.
*/
PetscErrorCode FSSolverGeometryView(FSSolver s, const char dir[])
{
  MPI_Comm     comm = PetscObjectComm((PetscObject)s);
  PetscMPIInt  rank, size, nl2, *counts = NULL, *displs = NULL;
  PetscInt     n, ntot = 0;
  PetscReal   *x, *mine, *all = NULL, lo[2], hi[2];
  FSWalls     *w = s->wd && s->wd->walls.nseg ? &s->wd->walls : NULL;
  FSImage      img = {0, 0, NULL};
  char         path[PETSC_MAX_PATH_LEN];

  PetscFunctionBegin;
  PetscCheck(s->setupcalled, comm, PETSC_ERR_ARG_WRONGSTATE, "FSSolverGeometryView needs the solver set up (FSSolverSetUp)");
  PetscCall(FSMakeDirectory(comm, dir, "-fs_output_dir"));
  PetscCallMPI(MPI_Comm_rank(comm, &rank));
  PetscCallMPI(MPI_Comm_size(comm, &size));
  /* the particles' x, y, gathered on rank 0 in rank order */
  PetscCall(DMSwarmGetLocalSize(s->swarm, &n));
  PetscCall(PetscMalloc1(2 * n + 1, &mine));
  PetscCall(DMSwarmGetField(s->swarm, FS_FIELD_POSITION, NULL, NULL, (void **)&x));
  for (PetscInt k = 0; k < n; k++) {
    mine[2 * k]     = x[k * s->dim];
    mine[2 * k + 1] = x[k * s->dim + 1];
  }
  PetscCall(DMSwarmRestoreField(s->swarm, FS_FIELD_POSITION, NULL, NULL, (void **)&x));
  PetscCall(PetscMPIIntCast(2 * n, &nl2));
  if (rank == 0) PetscCall(PetscMalloc2(size, &counts, size + 1, &displs));
  PetscCallMPI(MPI_Gather(&nl2, 1, MPI_INT, counts, 1, MPI_INT, 0, comm));
  if (rank == 0) {
    displs[0] = 0;
    for (PetscMPIInt r = 0; r < size; r++) {
      PetscCheck((PetscInt64)displs[r] + counts[r] <= PETSC_MPI_INT_MAX, PETSC_COMM_SELF, PETSC_ERR_ARG_SIZ, "-fs_geometry_view: too many particles to gather on one rank");
      displs[r + 1] = displs[r] + counts[r];
    }
    ntot = displs[size] / 2;
    PetscCall(PetscMalloc1(2 * ntot + 1, &all));
  }
  PetscCallMPI(MPI_Gatherv(mine, nl2, MPIU_REAL, all, counts, displs, MPIU_REAL, 0, comm));
  PetscCall(PetscFree(mine));
  PetscCallMPI(MPI_Bcast(&ntot, 1, MPIU_INT, 0, comm));

  /* the picture */
  for (PetscInt d = 0; d < 2; d++) {
    lo[d] = w ? w->lo[d] : s->lo[d];
    hi[d] = w ? w->hi[d] : s->hi[d];
  }
  if (rank == 0) PetscCall(FSGeometryDraw(s, w, ntot, all, lo, hi, &img));
  PetscCall(PetscSNPrintf(path, sizeof(path), "%s/geometry.png", dir));
  PetscCall(FSImageWritePNG(comm, &img, path));
  PetscCallMPI(MPI_Bcast(&img.width, 1, MPIU_INT, 0, comm));
  PetscCallMPI(MPI_Bcast(&img.height, 1, MPIU_INT, 0, comm));
  PetscCall(PetscPrintf(comm, "Geometry view: %s (%" PetscInt_FMT " x %" PetscInt_FMT " pixels, %" PetscInt_FMT " particles in blue", path, img.width, img.height, ntot));
  if (w) PetscCall(PetscPrintf(comm, ", %" PetscInt_FMT " wall(s) with ticks on the side away from the liquid", w->nwalls));
  PetscCall(PetscPrintf(comm, ")\n"));
  if (rank == 0) PetscCall(FSImageDestroy(&img));
  PetscCall(PetscFree2(counts, displs));
  PetscCall(PetscFree(all));

  /* the walls for ParaView */
  if (w) {
    PetscCall(FSGeometryWriteWalls(s, w, dir));
    PetscCall(PetscPrintf(comm, "Geometry view: %s/walls.xdmf (+ walls.h5): %" PetscInt_FMT " segments of %" PetscInt_FMT " wall(s) (", dir, w->nseg, w->nwalls));
    for (PetscInt q = 0; q < w->nwalls; q++) PetscCall(PetscPrintf(comm, "%s%" PetscInt_FMT " %s", q ? ", " : "", q, w->name[q]));
    PetscCall(PetscPrintf(comm, "), to open in ParaView with the XDMF Reader next to particles.xdmf\n"));
  } else PetscCall(PetscPrintf(comm, "Geometry view: this case has no walls (no walls.xdmf)\n"));
  PetscFunctionReturn(0);
}
