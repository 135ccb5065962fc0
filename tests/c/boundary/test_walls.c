/*
   Unit tests of the wall geometry and of the geometric Shepard factor (docs/boundary-integrals.md):
   reference values of gamma near a flat wall and in a corner, independence of the discretization,
   thin baffles seen from either side, grad gamma against finite differences, the seed's baffled
   tank, and the errors on bad polygons and files (on rank 0); then, on every rank together, the
   boundary and the wall terms on particles dealt out over the ranks as a run does, against the serial
   evaluation of the same particles (TestParallel, below).
*/
#include <string.h>
#include "boundarytest.h"
#include "../errorcapture.h"
#include "../tempdir.h"
#include "boundary/impls/polygon/walls.h"
#include "terms/fsterms.h"

#define CHECK(c, ...) PetscCheck(c, PETSC_COMM_SELF, PETSC_ERR_PLIB, __VA_ARGS__)

/* gamma against the 6-digit reference values: measured 2.3e-7 at most (1.9e-7 in the corner, 8.4e-8 beside a
   baffle), the rounding of the references' last digit, for every discretization tried (dx = h/8, h/2, 5h) */
#define REFTOL 3e-7
/* h grad gamma against central differences (step 1e-5 h): measured 3.4e-9 at most */
#define GRADTOL 5e-9

static PetscErrorCode Gamma(FSWalls *w, PetscReal h, PetscReal x, PetscReal y, PetscReal *g, PetscReal grad[])
{
  PetscReal xy[2] = {x, y}, gr[2];
  PetscFunctionBegin;
  PetscCall(FSWallsShepard(w, h, xy, PETSC_FALSE, g, grad ? grad : gr));
  PetscFunctionReturn(0);
}

static PetscErrorCode TestReference(PetscReal dx)
{
  FSWalls         w;
  const PetscReal h = 0.1, ref[4] = {0.507427, 0.823497, 0.971491, 1.0}, dist[4] = {0.01, 0.5, 1.0, 1.9};
  PetscReal       g;

  PetscFunctionBegin;
  PetscCall(FSWallsCreate(&w));
  PetscCall(FSWallsRectangularTank(&w, PETSC_COMM_SELF, 2.0, 2.0));
  PetscCall(FSWallsCheck(&w, PETSC_COMM_SELF));
  PetscCall(FSWallsDiscretize(&w, dx));
  for (PetscInt k = 0; k < 4; k++) {
    PetscCall(Gamma(&w, h, 1.0 + 0.37 * dx, dist[k] * h, &g, NULL)); /* off the segment joints on purpose */
    CHECK(PetscAbsReal(g - ref[k]) < REFTOL, "flat wall at d = %gh: gamma %.7f, reference %.6f (dx %g)",
          (double)dist[k], (double)g, (double)ref[k], (double)dx);
  }
  PetscCall(Gamma(&w, h, 0.5 * h, 0.7 * h, &g, NULL));
  CHECK(PetscAbsReal(g - 0.743619) < REFTOL, "corner: gamma %.7f, reference 0.743619 (dx %g)", (double)g, (double)dx);
  PetscCall(Gamma(&w, h, 1.0, 1.0, &g, NULL));
  CHECK(g == 1.0, "far from the walls gamma must be exactly 1, got %.17g", (double)g);
  PetscCall(FSWallsDestroy(&w));
  PetscFunctionReturn(0);
}

static PetscErrorCode TestGradient(void)
{
  FSWalls         w;
  const PetscReal h = 0.1, e = 1e-5;
  PetscReal       g, gp, gm, grad[2];

  PetscFunctionBegin;
  PetscCall(FSWallsCreate(&w));
  PetscCall(FSWallsRectangularTank(&w, PETSC_COMM_SELF, 2.0, 2.0));
  PetscCall(FSWallsCheck(&w, PETSC_COMM_SELF));
  PetscCall(FSWallsDiscretize(&w, h / 2));          /* segments as long as the solver's (dx = h/2) */
  for (PetscReal xc = 0.7 * h; xc < 1.1; xc += 0.3) /* near the corner, then mid-wall */
    for (PetscReal d = 0.3; d < 1.8; d += 0.4) {
      PetscCall(Gamma(&w, h, xc, d * h, &g, grad));
      PetscCall(Gamma(&w, h, xc, d * h + e, &gp, NULL));
      PetscCall(Gamma(&w, h, xc, d * h - e, &gm, NULL));
      CHECK(PetscAbsReal(grad[1] - (gp - gm) / (2 * e)) < GRADTOL / h,
            "grad gamma at (%g, %gh): %g, finite difference %g", (double)xc, (double)d, (double)grad[1],
            (double)((gp - gm) / (2 * e)));
      PetscCall(Gamma(&w, h, xc + e, d * h, &gp, NULL));
      PetscCall(Gamma(&w, h, xc - e, d * h, &gm, NULL));
      CHECK(PetscAbsReal(grad[0] - (gp - gm) / (2 * e)) < GRADTOL / h,
            "grad gamma_x at (%g, %gh): %g, finite difference %g", (double)xc, (double)d, (double)grad[0],
            (double)((gp - gm) / (2 * e)));
    }
  PetscCall(FSWallsDestroy(&w));
  PetscFunctionReturn(0);
}

static PetscErrorCode TestBaffles(void)
{
  FSWalls         w;
  const PetscReal h = 0.005;
  PetscReal       g, x[2];

  PetscFunctionBegin;
  /* the seed's baffled tank: 7 x 0.1 m compartments, 5 mm baffles, free-standing (openings below and above) */
  PetscCall(FSWallsCreate(&w));
  PetscCall(FSWallsBaffledTank(&w, PETSC_COMM_SELF, 7, 0.1, 0.005, 0.06, 0.01, 0.04));
  PetscCall(FSWallsCheck(&w, PETSC_COMM_SELF));
  CHECK(w.npoly == 7 && w.nwalls == 2,
        "baffled tank: %" PetscInt_FMT " polygons and %" PetscInt_FMT " walls, expected 7 and 2", w.npoly, w.nwalls);
  CHECK(PetscAbsReal(w.hi[0] - 0.73) < 1e-14, "baffled tank length %g, expected 0.73", (double)w.hi[0]);
  PetscCall(FSWallsDiscretize(&w, h / 2));
  /* a particle 0.5h left of the first baffle, and one 0.5h right of it: both see a flat wall */
  x[0] = 0.1 - 0.5 * h;
  x[1] = 0.03;
  PetscCall(Gamma(&w, h, x[0], x[1], &g, NULL));
  CHECK(PetscAbsReal(g - 0.823497) < REFTOL, "left of a thin baffle: gamma %.7f, expected the flat-wall 0.823497",
        (double)g);
  PetscCall(Gamma(&w, h, 0.105 + 0.5 * h, 0.03, &g, NULL));
  CHECK(PetscAbsReal(g - 0.823497) < REFTOL, "right of a thin baffle: gamma %.7f, expected the flat-wall 0.823497",
        (double)g);
  CHECK(FSWallsInLiquid(&w, x, 0), "a point left of the baffle must be in the liquid");
  x[0] = 0.1025;
  CHECK(!FSWallsInLiquid(&w, x, 0), "a point inside a baffle must not be in the liquid");
  x[1] = 0.005;
  CHECK(FSWallsInLiquid(&w, x, 0), "a point in the opening under a baffle must be in the liquid");
  PetscCall(FSWallsDestroy(&w));
  /* baffles from the bottom are part of the outline */
  PetscCall(FSWallsCreate(&w));
  PetscCall(FSWallsBaffledTank(&w, PETSC_COMM_SELF, 7, 0.1, 0.005, 0.06, 0.0, 0.03));
  PetscCall(FSWallsCheck(&w, PETSC_COMM_SELF));
  CHECK(w.npoly == 1 && w.pstart[1] == 4 + 4 * 6,
        "bottom baffles: %" PetscInt_FMT " polygons, %" PetscInt_FMT " vertices", w.npoly, w.pstart[1]);
  PetscCall(FSWallsDestroy(&w));
  PetscFunctionReturn(0);
}

/* FSWallsLiquidBelow against the areas and moments by hand: the baffled tank with free-standing baffles (an
   obstacle polygon each), whole and in a strip, below and above the baffles' tops, and a trapezoid whose side walls
   lean outwards */
static PetscErrorCode TestLiquidBelow(void)
{
  FSWalls         w;
  const PetscReal trap[8] = {0, 0, 1, 0, 1.2, 1, -0.2, 1};
  PetscReal       a, q;

  PetscFunctionBegin;
  PetscCall(FSWallsCreate(&w));
  PetscCall(FSWallsBaffledTank(&w, PETSC_COMM_SELF, 7, 0.1, 0.005, 0.06, 0.01, 0.04));
  PetscCall(FSWallsCheck(&w, PETSC_COMM_SELF));
  FSWallsLiquidBelow(&w, 0, 0.73, 0.03, &a, &q);
  CHECK(PetscAbsReal(a - (0.73 * 0.03 - 6 * 0.005 * 0.02)) < 1e-15 &&
            PetscAbsReal(q - (0.73 * 0.03 * 0.015 - 6 * 0.005 * 0.02 * 0.01)) < 1e-15,
        "baffled tank below 0.03: area %g, moment %g", (double)a, (double)q);
  FSWallsLiquidBelow(&w, 0, 0.73, 0.055, &a, &q);
  CHECK(PetscAbsReal(a - (0.73 * 0.055 - 6 * 0.005 * 0.04)) < 1e-15 &&
            PetscAbsReal(q - (0.73 * 0.055 * 0.0275 - 6 * 0.005 * 0.04 * 0.025)) < 1e-15,
        "baffled tank below 0.055: area %g, moment %g", (double)a, (double)q);
  FSWallsLiquidBelow(&w, 0.05, 0.2, 0.03, &a, &q);
  CHECK(PetscAbsReal(a - (0.15 * 0.03 - 0.005 * 0.02)) < 1e-15, "baffled tank in a strip: area %g", (double)a);
  PetscCall(FSWallsDestroy(&w));
  PetscCall(FSWallsCreate(&w));
  PetscCall(FSWallsAddPolygon(&w, PETSC_COMM_SELF, "tank", 4, trap, "a trapezoid"));
  PetscCall(FSWallsCheck(&w, PETSC_COMM_SELF));
  FSWallsLiquidBelow(&w, -1, 2, 0.5, &a, &q); /* the width is 1 + 0.4 y */
  CHECK(PetscAbsReal(a - 0.55) < 1e-15 && PetscAbsReal(q - (0.125 + 0.4 * (0.0625 - 0.125 / 3))) < 1e-15,
        "trapezoid below 0.5: area %g, moment %g", (double)a, (double)q);
  FSWallsLiquidBelow(&w, 0.5, 2, 0.5, &a, &q); /* its right half: 0.5 + 0.2 y */
  CHECK(PetscAbsReal(a - 0.275) < 1e-15, "trapezoid's right half below 0.5: area %g", (double)a);
  PetscCall(FSWallsDestroy(&w));
  PetscFunctionReturn(0);
}

/*
   The parallel test: the 4-compartment baffled tank (free-standing baffles 5 mm thick, a 1 cm gap below
   them; walls "floor", "right", "left", "tank" (the lid) and "baffles", the floor and the baffles no-slip)
   filled to 4 cm with a lattice of particles (dx = 5 mm, h = 2 dx) moving in a smooth velocity field,
   with a hydrostatic density and a ripple. The particles are dealt out as a run does (FSDecomp balanced
   on them, each owned by the rank of its box, the halo built and refreshed), and the boundary's work of a
   step and of a right-hand side is done on them: the fluid candidates, FSBoundaryUpdate (the pairs seen
   through a baffle cut), FSBoundaryPrepare (gamma, the share behind no-slip walls, the wall lists, the wall
   pressure, the pressure loads), the wall terms (wall_continuity, wall_pressure, wall_viscosity, whose
   reaction adds to the loads) and the loads summed over the ranks (FSBoundaryGetLoads). The same is done on
   every rank on one rank's worth of work (PETSC_COMM_SELF, all particles): the serial evaluation. Each
   owned particle's values must be those its serial twin gets, gamma and grad gamma also those of
   FSWallsShepard at its position; the loads of every wall those of the serial run.
*/
#define PS 7 /* the parallel test's record: x (2), u (2), rho, m, then the particle's id */

static const PetscReal prho0 = 1000, pc0 = 20, pgrav = 9.81, pnu = 1e-3;

/* the baffled tank of the parallel test, its outline's edges named */
static PetscErrorCode BaffledWalls(MPI_Comm comm, FSWalls *w)
{
  PetscFunctionBegin;
  PetscCall(FSWallsCreate(w));
  PetscCall(FSWallsBaffledTank(w, comm, 4, 0.1, 0.005, 0.06, 0.01, 0.04));
  PetscCall(FSWallsSetEdgeWall(w, comm, 0, 0, "floor"));
  PetscCall(FSWallsSetEdgeWall(w, comm, 0, 1, "right"));
  PetscCall(FSWallsSetEdgeWall(w, comm, 0, 3, "left"));
  PetscCall(FSWallsCheck(w, comm));
  PetscFunctionReturn(0);
}

static PetscErrorCode BaffledBoundary(MPI_Comm comm, PetscReal dx, PetscReal h, PetscReal radius, FSBoundary *b)
{
  FSWalls w;

  PetscFunctionBegin;
  PetscCall(BaffledWalls(comm, &w));
  PetscCall(FSBoundaryCreate(comm, b));
  PetscCall(FSBoundarySetType(*b, FSBOUNDARYPOLYGON));
  PetscCall(FSBoundaryPolygonSetWalls(*b, &w));
  PetscCall(PetscOptionsSetValue(NULL, "-fs_walls_noslip", "floor,baffles"));
  PetscCall(FSBoundarySetFromOptions(*b));
  PetscCall(PetscOptionsClearValue(NULL, "-fs_walls_noslip"));
  PetscCall(FSBoundarySetUp(*b, 2, dx, h, radius));
  PetscFunctionReturn(0);
}

/* the distance from x to the nearest baffle of the tank: within 2h of one, the boundary's lists leave out the wall
   segments hidden behind it (those whose midpoint the particle sees through another segment), which
   FSWallsShepard counts if they face the particle */
static PetscReal BaffleDistance(const PetscReal x[])
{
  PetscReal best = PETSC_MAX_REAL;
  for (PetscInt k = 1; k < 4; k++) {
    const PetscReal x0 = k * 0.1 + (k - 1) * 0.005, x1 = x0 + 0.005, y0 = 0.01, y1 = 0.05;
    const PetscReal ex = x[0] < x0 ? x0 - x[0] : (x[0] > x1 ? x[0] - x1 : 0);
    const PetscReal ey = x[1] < y0 ? y0 - x[1] : (x[1] > y1 ? x[1] - y1 : 0);
    best               = PetscMin(best, PetscSqrtReal(ex * ex + ey * ey));
  }
  return best;
}

/* the record of lattice particle g at (x, y) */
static void LatticeRecord(PetscReal r[], PetscReal x, PetscReal y, PetscInt g, PetscReal dx, PetscReal H)
{
  r[0] = x;
  r[1] = y;
  r[2] = 0.3 * PetscSinReal(7.1 * x + 3.0 * y);
  r[3] = 0.2 * PetscCosReal(5.3 * x - 11.0 * y);
  r[4] = prho0 + prho0 * pgrav * (H - y) / (pc0 * pc0) + 0.5 * PetscSinReal(13.0 * x);
  r[5] = prho0 * dx * dx;
  r[6] = (PetscReal)g;
}

/* the particles a rank works on and what the boundary and the wall terms give them */
typedef struct {
  PetscInt     n, nghost; /* owned, ghosts */
  PetscReal   *rec;       /* (n + nghost) records */
  PetscReal   *vol, *p, *gamma, *gammav, *invgamma, *invgammav;
  FSRate      *rate; /* of the owned particles, from the wall terms */
  FSNeighbours nb;
  PetscInt64   cut; /* fluid candidate pairs removed by FSBoundaryUpdate */
} WallWork;

static PetscErrorCode WallWorkAllocate(WallWork *ww, PetscInt n, PetscInt nghost)
{
  const PetscInt m = n + nghost + 1;

  PetscFunctionBegin;
  ww->n      = n;
  ww->nghost = nghost;
  PetscCall(PetscCalloc1(m * PS, &ww->rec));
  PetscCall(PetscCalloc6(m, &ww->vol, m, &ww->p, m, &ww->gamma, m, &ww->gammav, m, &ww->invgamma, m, &ww->invgammav));
  PetscCall(PetscCalloc1(m, &ww->rate));
  PetscCall(PetscMemzero(&ww->nb, sizeof(ww->nb)));
  PetscFunctionReturn(0);
}

static PetscErrorCode WallWorkDestroy(WallWork *ww)
{
  PetscFunctionBegin;
  PetscCall(FSNeighboursDestroy(&ww->nb));
  PetscCall(PetscFree(ww->rec));
  PetscCall(PetscFree6(ww->vol, ww->p, ww->gamma, ww->gammav, ww->invgamma, ww->invgammav));
  PetscCall(PetscFree(ww->rate));
  PetscFunctionReturn(0);
}

/*
   WallEvaluate - the boundary's work of a step and a right-hand side on ww's particles (records in place,
   ghosts refreshed), as src/solver/stepping.c and rhs.c do it, then the wall terms of every owned particle
   (their reaction into the boundary's loads). Collective on b.
*/
static PetscErrorCode WallEvaluate(FSBoundary b, FSTerm term[3], WallWork *ww, PetscReal h, PetscReal dx,
                                   PetscReal radius)
{
  const PetscInt      n = ww->n, m = ww->n + ww->nghost;
  const FSFrameField  body = {{0, -pgrav, 0}, 0, 0, {0, 0}};
  FSBoundaryLeak      leak;
  FSBoundaryParticles bp;
  FSParticles         P;
  const FSWallView   *V;
  const PetscInt     *wstart, *wk;
  const PetscReal    *wW;
  PetscInt64          before;

  PetscFunctionBegin;
  PetscCall(FSNeighboursBuildCells(&ww->nb, 2, m, ww->rec, PS, radius));
  PetscCall(FSNeighboursBuildCandidates(&ww->nb, n, ww->rec, PS, radius));
  before = ww->nb.ncand;
  PetscCall(FSBoundaryUpdate(b, n, ww->rec, PS, &ww->nb, &leak));
  CHECK(leak.particle < 0, "a leak reported in the baffled tank (particle %" PetscInt_FMT ")", leak.particle);
  ww->cut = before - ww->nb.ncand;
  for (PetscInt k = 0; k < m; k++) {
    ww->vol[k] = ww->rec[k * PS + 5] / ww->rec[k * PS + 4];
    ww->p[k]   = pc0 * pc0 * (ww->rec[k * PS + 4] - prho0);
  }
  bp.dim                 = 2;
  bp.nowned              = n;
  bp.stride              = PS;
  bp.rec                 = ww->rec;
  bp.vol                 = ww->vol;
  bp.pressure            = ww->p;
  bp.body                = &body;
  bp.background_pressure = 0;
  PetscCall(FSBoundaryPrepare(b, &bp, ww->gamma, ww->gammav));
  for (PetscInt i = 0; i < n; i++) { /* as src/solver/rhs.c: gamma_v adds the share behind no-slip walls */
    ww->gammav[i] += ww->gamma[i];
    ww->invgamma[i]  = 1 / ww->gamma[i];
    ww->invgammav[i] = 1 / ww->gammav[i];
  }
  PetscCall(PetscMemzero(&P, sizeof(P)));
  P.dim        = 2;
  P.nowned     = n;
  P.nghost     = ww->nghost;
  P.stride     = PS;
  P.rec        = ww->rec;
  P.vol        = ww->vol;
  P.pressure   = ww->p;
  P.rho0       = prho0;
  P.c0         = pc0;
  P.h          = h;
  P.dx         = dx;
  P.nu         = pnu;
  P.gravity[1] = -pgrav;
  P.gamma      = ww->gamma;
  P.invgamma   = ww->invgamma;
  P.invgammav  = ww->invgammav;
  PetscCall(FSBoundaryGetView(b, &V, &wstart, &wk, &wW));
  for (PetscInt i = 0; i < n; i++) {
    const FSWallNeighbourhood wn = {i, wstart[i + 1] - wstart[i], wk + wstart[i], wW + wstart[i]};
    PetscCall(PetscMemzero(&ww->rate[i], sizeof(FSRate)));
    if (!wn.n) continue;
    for (PetscInt t = 0; t < 3; t++) term[t]->ops.wall(term[t], &P, V, &wn, &ww->rate[i]);
  }
  PetscFunctionReturn(0);
}

/* the ids of the fluid candidates of owned particle i, sorted */
static PetscErrorCode CandidateIds(const WallWork *ww, PetscInt i, PetscInt *nc, PetscInt ids[])
{
  FSCandidateIter it;
  PetscInt        j;

  PetscFunctionBegin;
  *nc = 0;
  FSNeighboursCandidateBegin(&ww->nb, i, &it);
  while (FSNeighboursCandidateNext(&ww->nb, &it, &j)) ids[(*nc)++] = (PetscInt)ww->rec[j * PS + 6];
  PetscCall(PetscSortInt(*nc, ids));
  PetscFunctionReturn(0);
}

static PetscMPIInt RankOf(void *ctx, const PetscReal x[]) { return FSDecompRankOf((const FSDecomp *)ctx, x); }

static PetscErrorCode TestParallel(MPI_Comm comm)
{
  const PetscReal  dx = 0.005, h = 2 * dx, radius = 2.5 * h, H = 0.04, lo[2] = {0, 0};
  const char      *wallname[5] = {"floor", "right", "left", "tank", "baffles"};
  PetscMPIInt      rank, size;
  FSWalls          ref; /* the same walls, for FSWallsShepard at the particles' positions */
  FSBoundary       b, bs;
  FSSolver         s;
  FSTerm           term[3];
  FSDecomp         dd;
  FSHalo           hl;
  WallWork         par, ser;
  PetscInt         N = 0, nx, ny, ncreate = 0, nown = 0, *owned, nwalls, nwallss, wix[5], *ida, *idb;
  PetscReal       *lattice, *xc, hi[2];
  const PetscReal *loads, *loadss;
  const PetscBool  periodic[2] = {PETSC_FALSE, PETSC_FALSE};
  /* what is measured: [0] gamma, [1] gamma_v, [2] the lists' mean kernel values (all three against the serial
     run), [3] gamma and [4] h grad gamma from the lists against FSWallsShepard, farther than 2h from the
     baffles, [5] the rates of the wall terms (relative to their size), [6] the wall pressure (relative to
     rho0 g H), [7] the loads (relative to the largest force on a wall), [8] gamma and [9] h grad gamma against
     FSWallsShepard within 2h of a baffle */
  PetscReal err[10] = {0, 0, 0, 0, 0, 0, 0, 0, 0, 0};
  /* the tolerances, measured on 1, 2, 3 and 4 ranks: [0-2] 0, every rank computes a particle's segments as the
     serial run does; [3] 1.1e-16 and [4] 1.4e-16, the same segments summed in another order; [5] 1.8e-16 on 2
     ranks (5.3e-16 on 3, 3.3e-16 on 4), [6] 2.9e-16 (5.8e-16 on 3 and 4) and [7] 8.5e-16 (1.9e-15 on 3, 1.5e-15
     on 4), the wall pressure's sums over the liquid added up rank by rank; [8] 8.4e-7 and [9] 3.0e-5 near the
     baffles, where FSWallsShepard counts hidden segments that face the particle */
  const PetscReal ptol[10]  = {0, 0, 0, 2.5e-16, 3e-16, 1e-15, 1e-15, 2.5e-15, 1e-6, 3.5e-5};
  const char     *pwhat[10] = {"gamma (against the serial run)",
                               "gamma_v (against the serial run)",
                               "mean kernel value of a wall element (against the serial run)",
                               "gamma (against FSWallsShepard, away from the baffles)",
                               "h grad gamma (from the lists, against FSWallsShepard, away from the baffles)",
                               "wall terms' rates (against the serial run)",
                               "wall pressure (against the serial run)",
                               "loads (against the serial run)",
                               "gamma (against FSWallsShepard, near a baffle)",
                               "h grad gamma (from the lists, against FSWallsShepard, near a baffle)"};
  PetscInt64      cnt[5] = {0, 0, 0, 0, 0}; /* owned particles with wall elements, candidate pairs with a ghost, with a
                                               ghost from another rank, pairs cut by the walls (parallel, serial) */
  PetscInt own[2];

  PetscFunctionBegin;
  PetscCallMPI(MPI_Comm_rank(comm, &rank));
  PetscCallMPI(MPI_Comm_size(comm, &size));
  PetscCall(BaffledWalls(PETSC_COMM_SELF, &ref));
  PetscCall(FSWallsDiscretize(&ref, dx));
  hi[0] = ref.hi[0];
  hi[1] = ref.hi[1];
  /* the lattice: every node in the liquid below H; particle g created on rank g % size */
  nx = (PetscInt)(hi[0] / dx);
  ny = (PetscInt)(H / dx + 0.5);
  PetscCall(PetscMalloc1(2 * nx * ny, &lattice));
  for (PetscInt j = 0; j < ny; j++)
    for (PetscInt i = 0; i < nx; i++) {
      const PetscReal x[2] = {(i + 0.5) * dx, (j + 0.5) * dx};
      if (!FSWallsInLiquid(&ref, x, 0)) continue;
      lattice[2 * N]     = x[0];
      lattice[2 * N + 1] = x[1];
      N++;
    }
  PetscCall(PetscMalloc1(2 * N, &xc));
  for (PetscInt g = rank; g < N; g += size, ncreate++) {
    xc[2 * ncreate]     = lattice[2 * g];
    xc[2 * ncreate + 1] = lattice[2 * g + 1];
  }
  PetscCall(FSDecompSetUp(&dd, comm, 2, lo, hi, periodic, radius));
  PetscCall(FSDecompBalance(&dd, comm, ncreate, xc, NULL, radius));
  PetscCall(PetscMalloc1(N, &owned));
  for (PetscInt g = 0; g < N; g++)
    if (FSDecompRankOf(&dd, &lattice[2 * g]) == rank) owned[nown++] = g;
  own[0] = -nown;
  own[1] = nown;
  PetscCallMPI(MPI_Allreduce(MPI_IN_PLACE, own, 2, MPIU_INT, MPI_MAX, comm));
  PetscCheck(own[0] < 0, comm, PETSC_ERR_PLIB, "a rank owns no particle: the parallel path is not tested");

  /* the parallel run: owned records, the halo */
  {
    PetscReal *rec;
    PetscCall(PetscMalloc1(nown * PS + 1, &rec));
    for (PetscInt i = 0; i < nown; i++)
      LatticeRecord(&rec[i * PS], lattice[2 * owned[i]], lattice[2 * owned[i] + 1], owned[i], dx, H);
    PetscCall(PetscMemzero(&hl, sizeof(hl)));
    hl.rectype = hl.auxtype = MPI_DATATYPE_NULL;
    PetscCall(FSHaloBuild(&hl, comm, &dd, nown, rec, PS, radius));
    PetscCall(WallWorkAllocate(&par, nown, hl.nghost));
    PetscCall(PetscArraycpy(par.rec, rec, nown * PS));
    PetscCall(PetscFree(rec));
    PetscCall(FSHaloRefresh(&hl, 2, nown, par.rec));
  }
  /* the serial run: every particle, on this rank alone */
  PetscCall(WallWorkAllocate(&ser, N, 0));
  for (PetscInt g = 0; g < N; g++) LatticeRecord(&ser.rec[g * PS], lattice[2 * g], lattice[2 * g + 1], g, dx, H);

  PetscCall(FSSolverCreate(PETSC_COMM_SELF, &s)); /* FSTermCreate only keeps it */
  PetscCall(FSTermRegisterAll());
  PetscCall(FSTermCreate(s, "wall_continuity", &term[0]));
  PetscCall(FSTermCreate(s, "wall_pressure", &term[1]));
  PetscCall(FSTermCreate(s, "wall_viscosity", &term[2]));
  PetscCall(BaffledBoundary(comm, dx, h, radius, &b));
  { /* the wall pressure's sums between the ranks that share an element, as a run does (FSSolverPartitionWalls) */
    PetscReal rlo[3], rhi[3];
    for (PetscInt d = 0; d < 3; d++) {
      rlo[d] = dd.cut[d][dd.coord[d]];
      rhi[d] = dd.cut[d][dd.coord[d] + 1];
    }
    PetscCall(FSBoundarySetPartition(b, RankOf, &dd, rlo, rhi, periodic));
  }
  PetscCall(BaffledBoundary(PETSC_COMM_SELF, dx, h, radius, &bs));
  PetscCall(WallEvaluate(b, term, &par, h, dx, radius));
  PetscCall(FSBoundaryGetLoads(b, &nwalls, &loads));
  PetscCall(WallEvaluate(bs, term, &ser, h, dx, radius));
  PetscCall(FSBoundaryGetLoads(bs, &nwallss, &loadss));

  /* particle by particle: the parallel values against the serial ones of the same particle */
  {
    const FSWallView *V, *Vs;
    const PetscInt   *wstart, *wk, *wstarts, *wks;
    const PetscReal  *wW, *wWs;
    PetscCall(FSBoundaryGetView(b, &V, &wstart, &wk, &wW));
    PetscCall(FSBoundaryGetView(bs, &Vs, &wstarts, &wks, &wWs));
    PetscCall(PetscMalloc2(par.nb.maxcand + 1, &ida, ser.nb.maxcand + par.nb.maxcand + 1, &idb));
    for (PetscInt i = 0; i < par.n; i++) {
      const PetscReal *r = &par.rec[i * PS];
      const PetscInt   g = (PetscInt)r[6], n = wstart[i + 1] - wstart[i];
      PetscInt         na, nb, near;
      PetscReal        gs, grad[2], lgrad[2] = {0, 0}, scale;
      CHECK(n == wstarts[g + 1] - wstarts[g],
            "particle %" PetscInt_FMT " at (%g, %g) has %" PetscInt_FMT " wall elements, %" PetscInt_FMT
            " in the serial run",
            g, (double)r[0], (double)r[1], n, wstarts[g + 1] - wstarts[g]);
      err[0] = PetscMax(err[0], PetscAbsReal(par.gamma[i] - ser.gamma[g]));
      err[1] = PetscMax(err[1], PetscAbsReal(par.gammav[i] - ser.gammav[g]));
      cnt[0] += n > 0;
      for (PetscInt q = 0; q < n; q++) {
        const PetscReal *e = &V->element[wk[wstart[i] + q] * V->stride];
        CHECK(wk[wstart[i] + q] == wks[wstarts[g] + q],
              "particle %" PetscInt_FMT ": wall element %" PetscInt_FMT " listed, %" PetscInt_FMT " in the serial run",
              g, wk[wstart[i] + q], wks[wstarts[g] + q]);
        err[2] = PetscMax(err[2], PetscAbsReal(wW[wstart[i] + q] - wWs[wstarts[g] + q]) / wWs[wstarts[g] + q]);
        for (PetscInt d = 0; d < 2; d++) lgrad[d] -= e[V->normal + d] * wW[wstart[i] + q] * e[V->measure];
      }
      PetscCall(FSWallsShepard(&ref, h, r, PETSC_FALSE, &gs, grad));
      near          = BaffleDistance(r) < 2 * h ? 5 : 0; /* within the support of a baffle: occlusion (see above) */
      err[3 + near] = PetscMax(err[3 + near], PetscAbsReal(par.gamma[i] - gs));
      err[4 + near] = PetscMax(err[4 + near],
                               h * PetscMax(PetscAbsReal(lgrad[0] - grad[0]), PetscAbsReal(lgrad[1] - grad[1])));
      /* the wall terms' rates: drho/dt and du/dt each relative to its own size */
      if (ser.rate[g].drho != 0)
        err[5] = PetscMax(err[5], PetscAbsReal(par.rate[i].drho - ser.rate[g].drho) / PetscAbsReal(ser.rate[g].drho));
      scale = PetscAbsReal(ser.rate[g].du[0]) + PetscAbsReal(ser.rate[g].du[1]);
      if (scale > 0)
        err[5] = PetscMax(err[5], (PetscAbsReal(par.rate[i].du[0] - ser.rate[g].du[0]) +
                                   PetscAbsReal(par.rate[i].du[1] - ser.rate[g].du[1])) /
                                      scale);
      /* the fluid candidates the walls left, by id: the same partners, ghosts or not */
      PetscCall(CandidateIds(&par, i, &na, ida));
      PetscCall(CandidateIds(&ser, g, &nb, idb));
      CHECK(na == nb,
            "particle %" PetscInt_FMT " at (%g, %g) keeps %" PetscInt_FMT " fluid candidates, %" PetscInt_FMT
            " in the serial run",
            g, (double)r[0], (double)r[1], na, nb);
      for (PetscInt q = 0; q < na; q++)
        CHECK(ida[q] == idb[q],
              "particle %" PetscInt_FMT ": fluid candidate %" PetscInt_FMT ", %" PetscInt_FMT " in the serial run", g,
              ida[q], idb[q]);
      FSCandidateIter it;
      PetscInt        j;
      FSNeighboursCandidateBegin(&par.nb, i, &it);
      while (FSNeighboursCandidateNext(&par.nb, &it, &j)) {
        if (j < par.n) continue;
        cnt[1]++;
        cnt[2] += FSDecompRankOf(&dd, &par.rec[j * PS]) != rank;
      }
    }
    PetscCall(PetscFree2(ida, idb));
    { /* the wall pressure where this rank uses it (its particles' wall lists) and where it owns the element (the
         loads); elsewhere only the ranks sharing the element know it (FSBoundarySetPartition) */
      PetscBool  *used;
      PetscInt    nowns = 0;
      PetscMPIInt size;
      PetscCall(PetscCalloc1(V->nelements, &used));
      for (PetscInt q = 0; q < wstart[par.n]; q++) used[wk[q]] = PETSC_TRUE;
      for (PetscInt k = 0; k < V->nelements; k++) {
        PetscBool owns;
        PetscCall(FSBoundaryOwnsElement(b, k, &owns));
        nowns += owns;
        if (owns || used[k])
          err[6] = PetscMax(err[6], PetscAbsReal(V->pressure[k] - Vs->pressure[k]) / (prho0 * pgrav * H));
      }
      PetscCall(PetscFree(used));
      PetscCallMPI(MPI_Comm_size(comm, &size));
      CHECK(nowns > 0 && (size == 1 || nowns < V->nelements),
            "this rank owns %" PetscInt_FMT " of %" PetscInt_FMT " elements", nowns, V->nelements);
    }
  }
  cnt[3] = par.cut;
  cnt[4] = ser.cut;
  CHECK(nwalls == 5 && nwallss == 5, "%" PetscInt_FMT " walls, expected 5", nwalls);
  {
    PetscReal fmax = 0;
    for (PetscInt w = 0; w < 5; w++) {
      PetscCall(TestWallIndex(b, wallname[w], &wix[w]));
      fmax = PetscMax(fmax, PetscAbsReal(loadss[6 * wix[w]]) + PetscAbsReal(loadss[6 * wix[w] + 1]));
    }
    for (PetscInt w = 0; w < 5; w++)
      for (PetscInt c = 0; c < 6; c++)
        err[7] = PetscMax(err[7], PetscAbsReal(loads[6 * wix[w] + c] - loadss[6 * wix[w] + c]) / fmax);
  }
  PetscCallMPI(MPI_Allreduce(MPI_IN_PLACE, err, 10, MPIU_REAL, MPI_MAX, comm));
  PetscCallMPI(MPI_Allreduce(MPI_IN_PLACE, cnt, 4, MPIU_INT64, MPI_SUM, comm));
  PetscCall(PetscPrintf(comm,
                        "  parallel baffled tank, %d rank(s): %" PetscInt_FMT " particles, %" PetscInt_FMT
                        " to %" PetscInt_FMT " owned, %" PetscInt64_FMT
                        " near the walls; candidate pairs with a ghost %" PetscInt64_FMT " (%" PetscInt64_FMT
                        " from another rank), cut by the walls %" PetscInt64_FMT " (serial %" PetscInt64_FMT ")\n",
                        (int)size, N, -own[0], own[1], cnt[0], cnt[1], cnt[2], cnt[3], cnt[4]));
  PetscCall(PetscPrintf(
      comm,
      "  against the serial run: gamma %.3g, gamma_v %.3g, int W dS %.3g, wall terms %.3g, wall "
      "pressure %.3g, loads %.3g; against FSWallsShepard: gamma %.3g, h grad gamma %.3g (near a baffle %.3g, %.3g)\n",
      (double)err[0], (double)err[1], (double)err[2], (double)err[5], (double)err[6], (double)err[7], (double)err[3],
      (double)err[4], (double)err[8], (double)err[9]));
  {
    PetscInt64 nearmin = 0;
    for (PetscInt i = 0; i < par.n; i++) {
      const FSWallView *V;
      const PetscInt   *wstart, *wk;
      const PetscReal  *wW;
      PetscCall(FSBoundaryGetView(b, &V, &wstart, &wk, &wW));
      nearmin += wstart[i + 1] > wstart[i];
    }
    nearmin = -nearmin;
    PetscCallMPI(MPI_Allreduce(MPI_IN_PLACE, &nearmin, 1, MPIU_INT64, MPI_MAX, comm));
    PetscCheck(nearmin < 0, comm, PETSC_ERR_PLIB,
               "a rank owns no particle near the walls: the parallel path is not tested");
  }
  PetscCheck(cnt[4] > 0 && cnt[3] == cnt[4], comm, PETSC_ERR_PLIB,
             "the walls cut %" PetscInt64_FMT " fluid candidate pairs on the ranks, %" PetscInt64_FMT
             " in the serial run (must be > 0)",
             cnt[3], cnt[4]);
  PetscCheck(size == 1 || cnt[2] > 0, comm, PETSC_ERR_PLIB,
             "no fluid candidate pair has its partner on another rank: the cut is not tested");
  for (PetscInt k = 0; k < 10; k++)
    PetscCheck(err[k] <= ptol[k], comm, PETSC_ERR_PLIB,
               "parallel baffled tank on %d rank(s): %s, difference %.3g > tolerance %.3g", (int)size, pwhat[k],
               (double)err[k], (double)ptol[k]);
  for (PetscInt t = 0; t < 3; t++) PetscCall(FSTermDestroy(&term[t]));
  PetscCall(FSSolverDestroy(&s));
  PetscCall(FSBoundaryDestroy(&b));
  PetscCall(FSBoundaryDestroy(&bs));
  PetscCall(WallWorkDestroy(&par));
  PetscCall(WallWorkDestroy(&ser));
  PetscCall(FSHaloDestroy(&hl));
  PetscCall(FSDecompDestroy(&dd));
  PetscCall(FSWallsDestroy(&ref));
  PetscCall(PetscFree(owned));
  PetscCall(PetscFree(xc));
  PetscCall(PetscFree(lattice));
  PetscFunctionReturn(0);
}

/* the error ierr of `what` must have happened, its message holding every string of must[] (NULL-terminated) */
static PetscErrorCode ExpectError(PetscErrorCode ierr, const ErrorText *e, const char what[], const char *must[])
{
  PetscFunctionBegin;
  CHECK(ierr != 0, "expected an error: %s", what);
  for (PetscInt k = 0; must[k]; k++)
    CHECK(strstr(e->text, must[k]), "the error of %s must say \"%s\": \"%s\"", what, must[k], e->text);
  PetscFunctionReturn(0);
}

/* calls `call`, which must fail with a message holding each of the strings that follow */
#define EXPECT_ERROR(call, ...)                       \
  do {                                                \
    const char    *must_[] = {__VA_ARGS__, NULL};     \
    ErrorText      e_      = {""};                    \
    PetscErrorCode ierr_;                             \
    FS_TEST_CAPTURE(call, e_, ierr_);                 \
    PetscCall(ExpectError(ierr_, &e_, #call, must_)); \
  } while (0)

static PetscErrorCode TestErrors(const char dir[])
{
  FSWalls         w;
  const PetscReal bowtie[8] = {0, 0, 1, 1, 1, 0, 0, 1}, cw[8] = {0, 0, 0, 1, 1, 1, 1, 0}, line2[4] = {0, 0, 1, 0};
  char            path[PETSC_MAX_PATH_LEN], where[PETSC_MAX_PATH_LEN + 64];
  FILE           *fp;

  PetscFunctionBegin;
  PetscCall(FSWallsCreate(&w));
  /* a self-intersecting polygon: the wall, where it comes from and the edges that cross */
  EXPECT_ERROR(FSWallsAddPolygon(&w, PETSC_COMM_SELF, "tank", 4, bowtie, "test"),
               "Wall \"tank\" (test) intersects itself", "edge 0 (0.,0.)-(1.,1.) meets edge 2 (1.,0.)-(0.,1.)");
  EXPECT_ERROR(FSWallsAddPolygon(&w, PETSC_COMM_SELF, "tank", 2, line2, "test"),
               "Wall \"tank\" (test) has 2 distinct vertices", "at least 3");
  PetscCall(FSWallsDestroy(&w));
  PetscCall(FSWallsCreate(&w));
  PetscCall(FSWallsAddPolygon(&w, PETSC_COMM_SELF, "tank", 4, cw, "test"));
  EXPECT_ERROR(FSWallsCheck(&w, PETSC_COMM_SELF), "Inconsistent normals",
               "the container wall \"tank\" (test, the first polygon) runs clockwise");
  PetscCall(FSWallsDestroy(&w));
  /* files: an open polygon, and a line that cannot be parsed; the messages name the file and the line */
  PetscCall(PetscSNPrintf(path, sizeof(path), "%s/open.walls", dir));
  fp = fopen(path, "w");
  fprintf(fp, "# open\nwall tank\n0 0\n1 0\n1 1\n");
  fclose(fp);
  PetscCall(PetscSNPrintf(where, sizeof(where), "%s: wall \"tank\" (line 2) has no \"end\"", path));
  PetscCall(FSWallsCreate(&w));
  EXPECT_ERROR(FSWallsLoad(&w, PETSC_COMM_SELF, path), where, "the polygon is open");
  PetscCall(FSWallsDestroy(&w));
  PetscCall(PetscSNPrintf(path, sizeof(path), "%s/bad.walls", dir));
  fp = fopen(path, "w");
  fprintf(fp, "wall tank\n0 0\n1 zero\n1 1\nend\n");
  fclose(fp);
  PetscCall(PetscSNPrintf(where, sizeof(where), "%s:3: cannot parse \"1 zero", path));
  PetscCall(FSWallsCreate(&w));
  EXPECT_ERROR(FSWallsLoad(&w, PETSC_COMM_SELF, path), where, "expected two numbers x y");
  PetscCall(FSWallsDestroy(&w));
  /* a good file: tank and a clockwise obstacle */
  PetscCall(PetscSNPrintf(path, sizeof(path), "%s/good.walls", dir));
  fp = fopen(path, "w");
  fprintf(fp, "wall tank   # container\n0 0\n2 0\n2 1\n0 1\nend\nwall post\n0.9 0.2\n0.9 0.4\n1.1 0.4\n1.1 0.2\nend\n");
  fclose(fp);
  PetscCall(FSWallsCreate(&w));
  PetscCall(FSWallsLoad(&w, PETSC_COMM_SELF, path));
  PetscCall(FSWallsCheck(&w, PETSC_COMM_SELF));
  CHECK(w.npoly == 2 && w.nwalls == 2, "good file: %" PetscInt_FMT " polygons", w.npoly);
  PetscCall(FSWallsDiscretize(&w, 0.1));
  CHECK(w.nseg == 60 + 8, "good file: %" PetscInt_FMT " segments, expected 68", w.nseg);
  PetscCall(FSWallsDestroy(&w));
  PetscFunctionReturn(0);
}

int main(int argc, char **argv)
{
  PetscMPIInt rank;
  char        dir[] = "/tmp/fswallsXXXXXX";

  PetscFunctionBeginUser;
  PetscCall(PetscInitialize(&argc, &argv, NULL, NULL));
  PetscCallMPI(MPI_Comm_rank(PETSC_COMM_WORLD, &rank));
  if (!rank) {
    PetscCheck(mkdtemp(dir), PETSC_COMM_SELF, PETSC_ERR_FILE_OPEN, "mkdtemp failed");
    PetscCall(TestReference(0.1 / 8));
    PetscCall(TestReference(0.1 / 2));
    PetscCall(TestReference(0.5));
    PetscCall(TestGradient());
    PetscCall(TestBaffles());
    PetscCall(TestLiquidBelow());
    PetscCall(TestErrors(dir));
    PetscCall(FSTestRemoveTree(dir));
  }
  PetscCall(FSInitializePackage());
  PetscCall(TestParallel(PETSC_COMM_WORLD));
  PetscCall(PetscPrintf(PETSC_COMM_WORLD, "test_walls: OK\n"));
  PetscCall(PetscFinalize());
  return 0;
}
