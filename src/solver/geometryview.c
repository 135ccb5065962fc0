/*
   The geometry view (-fs_geometry_view): the set-up as files a user can look at before running:
     <dir>/geometry.png         the particles, and the walls the boundary draws (rank 0 draws, after
                                gathering the particle positions of every rank); in 3-D three views
     <dir>/walls.h5, walls.xdmf the walls, for ParaView next to particles.xdmf (FSBoundaryWriteGeometry)
*/
#include "solver/solverimpl.h"
#include "io/fsimage.h"

#define FS_GEOMETRY_SIZE   1600 /* pixels on the longer side */
#define FS_GEOMETRY_MARGIN 20   /* white pixels around the drawing */
#define FS_GEOMETRY_GAP    40   /* 3-D: white pixels between two views (a margin for each) */

/* the picture's colours (tests/python/test_geometry_view.py checks them) */
static const unsigned char FSGeometryWhite[3]    = {255, 255, 255};
static const unsigned char FSGeometryParticle[3] = {30, 90, 220};

/*
   The picture's layout for the box lo-hi: the maps of its views and its size. 2-D: one view, x to the
   right, y up. 3-D: three views at the same scale, in first-angle projection,
       front (x right, y up)                    side (z right, y up: seen from the x = lo end)
       top (x right, z down: seen from above)
   the top view below the front one with the back (z = lo) next to it, the side view right of the
   front one with the back next to it, FS_GEOMETRY_GAP white pixels between them. The longer side of
   the picture is FS_GEOMETRY_SIZE pixels.
*/
static void FSGeometryLayout(PetscInt dim, const PetscReal lo[], const PetscReal hi[], PetscInt *nviews,
                             FSImageMap view[3], PetscInt *width, PetscInt *height)
{
  const PetscInt M = FS_GEOMETRY_MARGIN, G = FS_GEOMETRY_GAP;

  if (dim == 2) {
    FSImageMap *m = &view[0];

    m->x0    = lo[0];
    m->y0    = lo[1];
    m->ax    = 0;
    m->ay    = 1;
    m->down  = PETSC_FALSE;
    m->scale = (FS_GEOMETRY_SIZE - 1 - 2 * M) / PetscMax(hi[0] - lo[0], hi[1] - lo[1]);
    *width   = FSImageRound((hi[0] - lo[0]) * m->scale) + 2 * M + 1;
    *height  = FSImageRound((hi[1] - lo[1]) * m->scale) + 2 * M + 1;
    m->i0    = M;
    m->j0    = *height - 1 - M;
    *nviews  = 1;
  } else {
    const PetscReal L = hi[0] - lo[0], H = hi[1] - lo[1], W = hi[2] - lo[2];
    const PetscReal scale = (FS_GEOMETRY_SIZE - 1 - 2 * M - G) / PetscMax(L + W, H + W);
    /* front, top, side: the world axes and the pixel of the corner lo */
    const PetscInt  ax[3] = {0, 0, 2}, ay[3] = {1, 2, 1};
    const PetscReal i0[3] = {M, M, M + L * scale + G}, j0[3] = {M + H * scale, M + H * scale + G, M + H * scale};

    for (PetscInt v = 0; v < 3; v++) {
      view[v].ax    = ax[v];
      view[v].ay    = ay[v];
      view[v].x0    = lo[ax[v]];
      view[v].y0    = lo[ay[v]];
      view[v].scale = scale;
      view[v].i0    = i0[v];
      view[v].j0    = j0[v];
      view[v].down  = v == 1 ? PETSC_TRUE : PETSC_FALSE;
    }
    *width  = FSImageRound((L + W) * scale) + 2 * M + G + 1;
    *height = FSImageRound((H + W) * scale) + 2 * M + G + 1;
    *nviews = 3;
  }
}

/* Rank 0: the picture of the box lo-hi, the particles (dim coordinates each), then the walls */
static PetscErrorCode FSGeometryDraw(FSSolver s, PetscInt np, const PetscReal x[], const PetscReal lo[],
                                     const PetscReal hi[], FSImage *img)
{
  const PetscInt dim = s->opt.dim;
  FSImageMap     view[3];
  PetscInt       nviews, width, height;
  PetscReal      r;

  PetscFunctionBegin;
  FSGeometryLayout(dim, lo, hi, &nviews, view, &width, &height);
  PetscCall(FSImageCreate(width, height, img));
  FSImageFill(img, FSGeometryWhite);
  /* particles: discs of a quarter of the spacing, at least one pixel, at most 4 pixels in radius */
  r = PetscMin(4.0, PetscMax(0.5, 0.25 * s->opt.dx * view[0].scale));
  for (PetscInt v = 0; v < nviews; v++)
    for (PetscInt k = 0; k < np; k++) {
      PetscReal px, py;

      FSImageMapPoint(&view[v], &x[dim * k], &px, &py);
      FSImageDrawDisc(img, px, py, r, FSGeometryParticle);
    }
  /* the walls over the particles, in every view */
  if (s->boundary)
    for (PetscInt v = 0; v < nviews; v++) PetscCall(FSBoundaryDraw(s->boundary, img, &view[v]));
  PetscFunctionReturn(0);
}

/*
   FSSolverGeometryView - writes the set-up as files to look at before running: a picture of the walls
   and the particles, <dir>/geometry.png, and the walls (segments in 2-D, triangles in 3-D),
   <dir>/walls.h5 + walls.xdmf, for ParaView next to the particle snapshots (particles.xdmf); then
   prints where they are.

   Collective

   Input Parameters:
+  s   - the solver, after FSSolverSetUp()
-  dir - the directory (created if needed)

   Options Database Key:
.  -fs_geometry_view - FSSolverSetUp() calls this on the output directory, also writes the particles
                       at step 0 (snapshot_000000.h5 in particles.xdmf) and FSSolverSolve() then
                       stops without time stepping

   Notes:
   The picture is FS_GEOMETRY_SIZE (1600) pixels on its longer side with a 20-pixel white margin. In 2-D
   it has the aspect ratio of the walls' bounding box (of the domain's box without walls). In 3-D it
   holds three views of that box at the same scale, 40 white pixels apart, in first-angle projection:
   the front view (x to the right, y up) at the top left; the top view (seen from above: x to the
   right, z growing downwards, the back z = lo next to the front view) below it; the side view (seen
   from the x = lo end: z to the right, y up) to the right of the front view; the bottom right corner
   stays white. Particles are blue dots; the boundary draws its walls in every view, each named wall
   in its own dark colour (FSImagePalette: the first wall dark grey, then red, green, purple, orange,
   teal), with short ticks along the normals on the side away from the liquid (in 2-D every 24 pixels
   of wall; in 3-D the edges of the walls' triangles as given, and a tick at the centre of each
   triangle seen edge-on). Rank 0 draws, after gathering every rank's particle positions, so the
   picture does not depend on the number of ranks.
*/
PetscErrorCode FSSolverGeometryView(FSSolver s, const char dir[])
{
  MPI_Comm           comm = PetscObjectComm((PetscObject)s);
  const PetscInt     dim  = s->opt.dim;
  PetscMPIInt        rank, size, nl, *counts = NULL, *displs = NULL;
  PetscInt           n, ntot = 0;
  PetscReal         *x, *mine, *all = NULL, lo[3], hi[3];
  FSImage            img    = {0, 0, NULL};
  PetscInt           nwalls = 0;
  const char *const *names;
  char               path[PETSC_MAX_PATH_LEN];

  PetscFunctionBegin;
  PetscCheck(s->setupcalled, comm, PETSC_ERR_ARG_WRONGSTATE,
             "FSSolverGeometryView needs the solver set up (FSSolverSetUp)");
  PetscCall(FSMakeDirectory(comm, dir, "-fs_output_dir"));
  PetscCallMPI(MPI_Comm_rank(comm, &rank));
  PetscCallMPI(MPI_Comm_size(comm, &size));
  /* the particles' positions (dim coordinates each), gathered on rank 0 in rank order */
  PetscCall(DMSwarmGetLocalSize(s->swarm, &n));
  PetscCall(PetscMalloc1(dim * n + 1, &mine));
  PetscCall(DMSwarmGetField(s->swarm, FS_FIELD_POSITION, NULL, NULL, (void **)&x));
  PetscCall(PetscArraycpy(mine, x, dim * n));
  PetscCall(DMSwarmRestoreField(s->swarm, FS_FIELD_POSITION, NULL, NULL, (void **)&x));
  PetscCall(PetscMPIIntCast(dim * n, &nl));
  if (rank == 0) PetscCall(PetscMalloc2(size, &counts, size + 1, &displs));
  PetscCallMPI(MPI_Gather(&nl, 1, MPI_INT, counts, 1, MPI_INT, 0, comm));
  if (rank == 0) {
    displs[0] = 0;
    for (PetscMPIInt r = 0; r < size; r++) {
      PetscCheck((PetscInt64)displs[r] + counts[r] <= PETSC_MPI_INT_MAX, PETSC_COMM_SELF, PETSC_ERR_ARG_SIZ,
                 "-fs_geometry_view: too many particles to gather on one rank");
      displs[r + 1] = displs[r] + counts[r];
    }
    ntot = displs[size] / dim;
    PetscCall(PetscMalloc1(dim * ntot + 1, &all));
  }
  PetscCallMPI(MPI_Gatherv(mine, nl, MPIU_REAL, all, counts, displs, MPIU_REAL, 0, comm));
  PetscCall(PetscFree(mine));
  PetscCallMPI(MPI_Bcast(&ntot, 1, MPIU_INT, 0, comm));

  /* the picture: the walls' bounding box, or the domain's */
  for (PetscInt d = 0; d < dim; d++) {
    lo[d] = s->pw.lo[d];
    hi[d] = s->pw.hi[d];
  }
  if (s->boundary) {
    PetscCall(FSBoundaryGetBoundingBox(s->boundary, lo, hi));
    PetscCall(FSBoundaryGetWallNames(s->boundary, &nwalls, &names));
  }
  if (rank == 0) PetscCall(FSGeometryDraw(s, ntot, all, lo, hi, &img));
  PetscCall(PetscSNPrintf(path, sizeof(path), "%s/geometry.png", dir));
  PetscCall(FSImageWritePNG(comm, &img, path));
  PetscCallMPI(MPI_Bcast(&img.width, 1, MPIU_INT, 0, comm));
  PetscCallMPI(MPI_Bcast(&img.height, 1, MPIU_INT, 0, comm));
  PetscCall(PetscPrintf(
      comm, "Geometry view: %s (%" PetscInt_FMT " x %" PetscInt_FMT " pixels, %" PetscInt_FMT " particles in blue",
      path, img.width, img.height, ntot));
  if (s->boundary)
    PetscCall(PetscPrintf(comm, ", %" PetscInt_FMT " wall(s) with ticks on the side away from the liquid", nwalls));
  if (dim == 3) PetscCall(PetscPrintf(comm, "; the front view, the top view below it, the side view to its right"));
  PetscCall(PetscPrintf(comm, ")\n"));
  if (rank == 0) PetscCall(FSImageDestroy(&img));
  PetscCall(PetscFree2(counts, displs));
  PetscCall(PetscFree(all));

  /* the walls for ParaView */
  if (s->boundary) PetscCall(FSBoundaryWriteGeometry(s->boundary, dir, PETSC_TRUE));
  else PetscCall(PetscPrintf(comm, "Geometry view: this case has no walls (no walls.xdmf)\n"));
  PetscFunctionReturn(0);
}
