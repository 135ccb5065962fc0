/*
   The geometry view (-fs_geometry_view): the set-up as files a user can look at before running:
     <dir>/geometry.png         the particles, and the walls the boundary draws (rank 0 draws, after
                                gathering the particle positions of every rank)
     <dir>/walls.h5, walls.xdmf the walls, for ParaView next to particles.xdmf (FSBoundaryWriteGeometry)
*/
#include "solver/solverimpl.h"
#include "io/fsimage.h"

#define FS_GEOMETRY_SIZE   1600 /* pixels on the longer side */
#define FS_GEOMETRY_MARGIN 20   /* white pixels around the drawing */

/* the picture's colours (tests/python/test_geometry_view.py checks them) */
static const unsigned char FSGeometryWhite[3]    = {255, 255, 255};
static const unsigned char FSGeometryParticle[3] = {30, 90, 220};

/* Rank 0: the picture of the box lo-hi, the particles (x, y pairs), then the walls */
static PetscErrorCode FSGeometryDraw(FSSolver s, PetscInt np, const PetscReal xy[], const PetscReal lo[],
                                     const PetscReal hi[], FSImage *img)
{
  const PetscReal span = PetscMax(hi[0] - lo[0], hi[1] - lo[1]);
  FSImageMap      m;
  PetscInt        width, height;
  PetscReal       r;

  PetscFunctionBegin;
  m.x0     = lo[0];
  m.y0     = lo[1];
  m.margin = FS_GEOMETRY_MARGIN;
  m.scale  = (FS_GEOMETRY_SIZE - 1 - 2 * FS_GEOMETRY_MARGIN) / span;
  width    = FSImageRound((hi[0] - lo[0]) * m.scale) + 2 * FS_GEOMETRY_MARGIN + 1;
  height   = FSImageRound((hi[1] - lo[1]) * m.scale) + 2 * FS_GEOMETRY_MARGIN + 1;
  m.height = height;
  PetscCall(FSImageCreate(width, height, img));
  FSImageFill(img, FSGeometryWhite);
  /* particles: discs of a quarter of the spacing, at least one pixel, at most 4 pixels in radius */
  r = PetscMin(4.0, PetscMax(0.5, 0.25 * s->opt.dx * m.scale));
  for (PetscInt k = 0; k < np; k++)
    FSImageDrawDisc(img, FSImageMapX(&m, xy[2 * k]), FSImageMapY(&m, xy[2 * k + 1]), r, FSGeometryParticle);
  if (s->boundary) PetscCall(FSBoundaryDraw(s->boundary, img, &m));
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
  MPI_Comm           comm = PetscObjectComm((PetscObject)s);
  PetscMPIInt        rank, size, nl2, *counts = NULL, *displs = NULL;
  PetscInt           n, ntot = 0;
  PetscReal         *x, *mine, *all = NULL, lo[2], hi[2];
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
  /* the particles' x, y, gathered on rank 0 in rank order */
  PetscCall(DMSwarmGetLocalSize(s->swarm, &n));
  PetscCall(PetscMalloc1(2 * n + 1, &mine));
  PetscCall(DMSwarmGetField(s->swarm, FS_FIELD_POSITION, NULL, NULL, (void **)&x));
  for (PetscInt k = 0; k < n; k++) {
    mine[2 * k]     = x[k * s->opt.dim];
    mine[2 * k + 1] = x[k * s->opt.dim + 1];
  }
  PetscCall(DMSwarmRestoreField(s->swarm, FS_FIELD_POSITION, NULL, NULL, (void **)&x));
  PetscCall(PetscMPIIntCast(2 * n, &nl2));
  if (rank == 0) PetscCall(PetscMalloc2(size, &counts, size + 1, &displs));
  PetscCallMPI(MPI_Gather(&nl2, 1, MPI_INT, counts, 1, MPI_INT, 0, comm));
  if (rank == 0) {
    displs[0] = 0;
    for (PetscMPIInt r = 0; r < size; r++) {
      PetscCheck((PetscInt64)displs[r] + counts[r] <= PETSC_MPI_INT_MAX, PETSC_COMM_SELF, PETSC_ERR_ARG_SIZ,
                 "-fs_geometry_view: too many particles to gather on one rank");
      displs[r + 1] = displs[r] + counts[r];
    }
    ntot = displs[size] / 2;
    PetscCall(PetscMalloc1(2 * ntot + 1, &all));
  }
  PetscCallMPI(MPI_Gatherv(mine, nl2, MPIU_REAL, all, counts, displs, MPIU_REAL, 0, comm));
  PetscCall(PetscFree(mine));
  PetscCallMPI(MPI_Bcast(&ntot, 1, MPIU_INT, 0, comm));

  /* the picture: the walls' bounding box, or the domain's */
  for (PetscInt d = 0; d < 2; d++) {
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
  PetscCall(PetscPrintf(comm, ")\n"));
  if (rank == 0) PetscCall(FSImageDestroy(&img));
  PetscCall(PetscFree2(counts, displs));
  PetscCall(PetscFree(all));

  /* the walls for ParaView */
  if (s->boundary) PetscCall(FSBoundaryWriteGeometry(s->boundary, dir));
  else PetscCall(PetscPrintf(comm, "Geometry view: this case has no walls (no walls.xdmf)\n"));
  PetscFunctionReturn(0);
}
