/*
   Case "channel": plane channel flow between two walls y = 0 ("floor") and y = H ("lid"), periodic along
   x (length L) and, in 3-D, along z (width Lz), driven by a body force g along x (-fs_gravity g,0).
   Make the walls no-slip with -fs_walls_noslip floor,lid: from rest the flow is the start-up of plane
   Poiseuille flow, u(y, t) = g/(2 nu) y (H - y) - sum over odd n of 4 g H^2/(nu pi^3 n^3) sin(n pi y/H)
   exp(-n^2 pi^2 nu t/H^2), steady after a few H^2/(pi^2 nu) (tests/python/test_channel.py). With
   -fs_channel_shear S the liquid starts with the linear shear u = S y, whose viscous force vanishes away
   from the lid (the no-slip wall term's check). The walls are a closed outline reaching 4h beyond the
   periodic box, so that no particle sees its ends; the liquid fills the box on the lattice (i + 1/2) dx.
   The energy budget's potential energy of the body force jumps by m g L when a particle wraps around.
   Options: -fs_channel_length (1), -fs_channel_height (1), -fs_channel_width (3-D, 0.25),
   -fs_channel_shear (0). Defaults: dx = H/20, rho0 = 1, g = 1 along x, nu = 0.1, c0 = 10 (10 times the
   steady centre-line speed g H^2/(8 nu) and S H), final time 5 H^2/(pi^2 nu).
*/
#include <flexslosh.h>
#include "boundary/fsboundary.h"
#include "lattice.h"
#include "liquid.h"

typedef struct {
  PetscReal L, H, Lz, S;
} Channel;

static PetscErrorCode SetFromOptions(FSSolver s, PetscOptionItems *PetscOptionsObject)
{
  Channel  *ch;
  PetscReal g[3] = {1, 0, 0}, nu = 0.1;

  PetscFunctionBegin;
  PetscCall(FSSolverGetCaseData(s, &ch));
  PetscOptionsHeadBegin(PetscOptionsObject, "Case channel");
  PetscCall(FSOptionsReal(PetscOptionsObject, "-fs_channel_length", "Length L of the periodic box along x", "", &ch->L,
                          NULL, 0, PETSC_INFINITY, FS_RANGE_OPEN_LOWER));
  PetscCall(FSOptionsReal(PetscOptionsObject, "-fs_channel_height", "Height H between the walls", "", &ch->H, NULL, 0,
                          PETSC_INFINITY, FS_RANGE_OPEN_LOWER));
  PetscCall(FSOptionsReal(PetscOptionsObject, "-fs_channel_width", "Width Lz of the periodic box along z (3-D)", "",
                          &ch->Lz, NULL, 0, PETSC_INFINITY, FS_RANGE_OPEN_LOWER));
  PetscCall(FSOptionsReal(PetscOptionsObject, "-fs_channel_shear", "Initial linear shear S: u = S y along x", "",
                          &ch->S, NULL, -PETSC_INFINITY, PETSC_INFINITY, FS_RANGE_CLOSED));
  PetscOptionsHeadEnd();
  PetscCall(FSSolverSetDefaultPhysics(
      s, 1.0, 10 * PetscMax(g[0] * ch->H * ch->H / (8 * nu), PetscAbsReal(ch->S) * ch->H), nu, g));
  PetscCall(FSSolverSetDefaultTerms(s, "continuity,delta,pressure,viscosity,gravity,wall_continuity,wall_pressure,"
                                       "wall_viscosity"));
  PetscCall(FSSolverSetDefaultSpacing(s, ch->H / 20));
  PetscCall(FSSolverSetDefaultFinalTime(s, 5 * ch->H * ch->H / (PETSC_PI * PETSC_PI * nu)));
  PetscFunctionReturn(0);
}

static PetscErrorCode SetUp(FSSolver s)
{
  Channel   *ch;
  MPI_Comm   comm = PetscObjectComm((PetscObject)s);
  FSWalls    w;
  FSBoundary b;
  PetscReal  dx, h, rho0, M, lo[3] = {0, 0, 0}, hi[3] = {0, 0, 0}, *x, *u, *rho, *m, vol = 1;
  PetscBool  per[3] = {PETSC_TRUE, PETSC_FALSE, PETSC_TRUE};
  PetscInt   dim, n;

  PetscFunctionBegin;
  PetscCall(FSSolverGetCaseData(s, &ch));
  PetscCall(FSSolverGetDimension(s, &dim));
  PetscCall(FSSolverGetParameters(s, &dx, &h, &rho0, NULL, NULL));
  M = 4 * h;
  {
    const PetscReal xy[8] = {0, 0, ch->L + 2 * M, 0, ch->L + 2 * M, ch->H, 0, ch->H};
    PetscCall(FSWallsCreate(&w));
    PetscCall(FSWallsAddPolygon(&w, comm, "ends", 4, xy, "case channel"));
    PetscCall(FSWallsSetEdgeWall(&w, comm, 0, 0, "floor"));
    PetscCall(FSWallsSetEdgeWall(&w, comm, 0, 2, "lid"));
    PetscCall(FSWallsCheck(&w, comm));
  }
  PetscCall(FSSolverGetBoundary(s, &b));
  if (dim == 2) {
    PetscCall(FSWallsDiscretize(&w, dx));
    PetscCall(FSBoundarySetType(b, FSBOUNDARYPOLYGON));
    PetscCall(FSBoundaryPolygonSetWalls(b, &w));
  } else {
    FSMesh mesh;
    PetscCall(FSMeshCreate(&mesh));
    PetscCall(FSMeshExtrude(&mesh, comm, &w, ch->Lz + 2 * M));
    PetscCall(FSMeshCheck(&mesh, comm));
    PetscCall(FSBoundarySetType(b, FSBOUNDARYTRIMESH));
    PetscCall(FSBoundaryTrimeshSetMesh(b, &mesh));
    PetscCall(FSWallsDestroy(&w));
  }
  /* the periodic box: [M, M + L] along x, the walls' height, [M, M + Lz] along z */
  lo[0] = M;
  hi[0] = M + ch->L;
  hi[1] = ch->H;
  lo[2] = M;
  hi[2] = M + ch->Lz;
  {
    const PetscReal dlo[3] = {lo[0], -M, lo[2]}, dhi[3] = {hi[0], ch->H + M, hi[2]};
    PetscCall(FSSolverSetDomain(s, dlo, dhi, per));
  }
  PetscCall(FSLatticeCreate(s, lo, hi, &n, &x));
  PetscCall(PetscCalloc3(n * dim + 1, &u, n + 1, &rho, n + 1, &m));
  for (PetscInt d = 0; d < dim; d++) vol *= dx;
  for (PetscInt p = 0; p < n; p++) {
    u[p * dim] = ch->S * x[p * dim + 1];
    rho[p]     = rho0;
    m[p]       = rho0 * vol;
  }
  PetscCall(FSSolverAddParticles(s, n, x, u, rho, m));
  PetscCall(PetscFree(x));
  PetscCall(PetscFree3(u, rho, m));
  PetscFunctionReturn(0);
}

PETSC_EXTERN PetscErrorCode FSCaseCreate_Channel(FSSolver s, FSCaseOps *ops)
{
  Channel *ch;

  PetscFunctionBegin;
  PetscCall(PetscNew(&ch));
  ch->L  = 1;
  ch->H  = 1;
  ch->Lz = 0.25;
  PetscCall(FSSolverSetCaseData(s, ch));
  ops->setfromoptions = SetFromOptions;
  ops->setup          = SetUp;
  PetscFunctionReturn(0);
}
