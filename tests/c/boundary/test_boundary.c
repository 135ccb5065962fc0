/*
   Unit test of the FSBoundary object (src/boundary: the interface and the polygon method) on
   hand-placed particles, without the solver: the boundary is created, given a rectangular tank and
   set up as a case and FSSolverSetUp would; the candidate lists come from FSNeighbours as in
   src/solver/stepping.c; then FSBoundaryUpdate and FSBoundaryPrepare, and the checks:
   - gamma of a particle at distance d from a flat wall against the reference values of
     test_walls.c (0.507427 at 0.01h, 0.823497 at 0.5h, 0.971491 at h, 1 at 1.9h; 0.743619 in a corner),
     exactly 1 far from the walls;
   - the wall lists (FSBoundaryGetView): each element lies within the support 2h and faces the
     particle, every facing element nearer than 1.9h is listed, and for a flat wall the elements'
     int W dS (wW s) add up to the line integral of the kernel computed here;
   - a hydrostatic column (particles filling a small tank, p = rho0 g (H - y)): the wall pressure of
     the floor's elements, the floor's load against the liquid's weight rho0 g H L, the side walls'
     against rho0 g H^2/2 (FSBoundaryGetLoads), the lid's zero;
   - the leak report: a particle outside the tank is named by FSBoundaryLeak with the nearest wall;
   - the bounce: a particle just inside a wall moving towards it is put back at the bounce distance
     with its normal velocity reversed (scaled by the restitution), the energy callback measuring the
     change; particles moving away or far from the walls are left alone;
   - errors: FSBoundarySetType with an unknown name names it, FSBoundaryPolygonSetWalls on a boundary
     that is not a polygon one fails.
   On 2 ranks the particles are dealt out over the ranks: the wall pressure and the loads are sums
   over all of them (FSBoundaryPrepare and FSBoundaryGetLoads are collective) and must not change.
*/
#include <string.h>
#include "boundarytest.h"
#include "boundary/impls/polygon/walls.h"

#define TCHECK(cond, ...) PetscCheck(cond, PETSC_COMM_SELF, PETSC_ERR_PLIB, "test_boundary: " __VA_ARGS__)

#define S 6 /* record: x (2), u (2), rho, m */

static const PetscReal rho0 = 1000, grav = 9.81, c0 = 20;

/* A rectangular tank L x H whose floor, right and left sides are walls of their own ("floor",
   "right", "left"; the lid stays "tank"), as a polygon boundary set up for spacing dx and smoothing
   length h, with the candidate radius of the solver (support + half an h of skin). */
static PetscErrorCode TankBoundary(MPI_Comm comm, PetscReal L, PetscReal H, PetscReal dx, PetscReal h, FSBoundary *b)
{
  FSWalls w;

  PetscFunctionBegin;
  PetscCall(FSWallsCreate(&w));
  PetscCall(FSWallsRectangularTank(&w, comm, L, H));
  PetscCall(FSWallsSetEdgeWall(&w, comm, 0, 0, "floor"));
  PetscCall(FSWallsSetEdgeWall(&w, comm, 0, 1, "right"));
  PetscCall(FSWallsSetEdgeWall(&w, comm, 0, 3, "left"));
  PetscCall(FSWallsCheck(&w, comm));
  PetscCall(FSBoundaryCreate(comm, b));
  PetscCall(FSBoundarySetType(*b, FSBOUNDARYPOLYGON));
  PetscCall(FSBoundaryPolygonSetWalls(*b, &w));
  TCHECK(w.npoly == 0 && !w.vert, "FSBoundaryPolygonSetWalls must take the walls over and zero them");
  PetscCall(FSBoundarySetFromOptions(*b));
  PetscCall(FSBoundarySetUp(*b, 2, dx, h, 2.5 * h));
  PetscFunctionReturn(0);
}

/* a particle at rest at (x, y) with density rho and mass rho0 dx^2 */
static void Place(TestParticles *pa, PetscInt i, PetscReal x, PetscReal y, PetscReal rho, PetscReal dx)
{
  PetscReal *r = &pa->rec[i * S];
  r[0]         = x;
  r[1]         = y;
  r[2] = r[3] = 0;
  r[4]        = rho;
  r[5]        = rho0 * dx * dx;
  pa->vol[i]  = r[5] / rho;
  pa->p[i]    = c0 * c0 * (rho - rho0);
}

/* distance from x to the segment p0-p1 (computed here, not with the library's helper) */
static PetscReal SegmentDistance(const PetscReal p0[], const PetscReal p1[], const PetscReal x[])
{
  const PetscReal tx = p1[0] - p0[0], ty = p1[1] - p0[1];
  PetscReal       u = ((x[0] - p0[0]) * tx + (x[1] - p0[1]) * ty) / (tx * tx + ty * ty);
  u                 = u < 0 ? 0 : (u > 1 ? 1 : u);
  return PetscSqrtReal((p0[0] + u * tx - x[0]) * (p0[0] + u * tx - x[0]) +
                       (p0[1] + u * ty - x[1]) * (p0[1] + u * ty - x[1]));
}

/* int W(sqrt(t^2 + d^2)) dt over the line at distance d, Wendland C2 in 2-D written out, composite Simpson */
static PetscReal LineIntegral(PetscReal h, PetscReal d)
{
  const PetscInt  m = 4000;
  const PetscReal T = PetscSqrtReal(4 * h * h - d * d), dt = 2 * T / m;
  PetscReal       sum = 0;
  for (PetscInt k = 0; k <= m; k++) {
    const PetscReal t = -T + k * dt, q = PetscSqrtReal(t * t + d * d) / h, a = q < 2 ? 1 - 0.5 * q : 0;
    const PetscReal W = 7 / (4 * PETSC_PI * h * h) * a * a * a * a * (2 * q + 1);
    sum += (k == 0 || k == m ? 1 : (k % 2 ? 4 : 2)) * W;
  }
  return sum * dt / 3;
}

/*
   gamma and the wall lists in the 2 x 2 tank of test_walls.c (h = 0.1, dx = h/2): particles at
   d = 0.01h, 0.5h, h and 1.9h above the floor's middle, one in the corner, one in the middle of the
   tank; particle k lives on rank k % size.
*/
static PetscErrorCode TestGammaAndLists(MPI_Comm comm)
{
  const PetscReal h = 0.1, dx = 0.5 * h, dist[4] = {0.01, 0.5, 1.0, 1.9}, ref[4] = {0.507427, 0.823497, 0.971491, 1.0};
  const PetscReal all[6][2] = {{1 + 0.37 * dx, dist[0] * h}, {1 + 0.37 * dx, dist[1] * h}, {1 + 0.37 * dx, dist[2] * h},
                               {1 + 0.37 * dx, dist[3] * h}, {0.5 * h, 0.7 * h},           {1.0, 1.0}};
  const PetscReal allref[6] = {ref[0], ref[1], ref[2], ref[3], 0.743619, 1.0};
  PetscInt        mine[6], n = 0;
  PetscMPIInt     rank, size;
  FSBoundary      b;
  TestParticles   pa;
  FSBoundaryLeak  leak;
  const FSWallView *V;
  const PetscInt   *wstart, *wk;
  const PetscReal  *wW;
  PetscReal         maxg = 0, maxint = 0;

  PetscFunctionBegin;
  PetscCallMPI(MPI_Comm_rank(comm, &rank));
  PetscCallMPI(MPI_Comm_size(comm, &size));
  for (PetscInt k = 0; k < 6; k++)
    if (k % size == rank) mine[n++] = k;
  PetscCall(TankBoundary(comm, 2.0, 2.0, dx, h, &b));
  PetscCall(TestParticlesCreate(2, n, &pa));
  for (PetscInt i = 0; i < n; i++) Place(&pa, i, all[mine[i]][0], all[mine[i]][1], rho0, dx);
  PetscCall(TestUpdateAndPrepare(b, h, grav, &pa, &leak));
  TCHECK(leak.particle < 0, "a leak reported for particles inside the tank (particle %" PetscInt_FMT ")",
         leak.particle);
  PetscCall(FSBoundaryGetView(b, &V, &wstart, &wk, &wW));
  TCHECK(V->dim == 2 && V->nwalls == 4 && V->nelements > 0 && V->pressure,
         "the view: dim %" PetscInt_FMT ", %" PetscInt_FMT " walls, %" PetscInt_FMT " elements", V->dim, V->nwalls,
         V->nelements);
  for (PetscInt i = 0; i < n; i++) {
    const PetscInt   k    = mine[i];
    const PetscReal *x    = &pa.rec[i * S];
    PetscReal        sumW = 0;
    { /* gamma at the same point through FSBoundaryShepardAt (the static grid, as the wave gauges use it) */
      PetscReal g;
      PetscCall(FSBoundaryShepardAt(b, x, &g));
      TCHECK(PetscAbsReal(g - pa.gamma[i]) < 1e-14, "FSBoundaryShepardAt gives %.17g, the particle's gamma %.17g",
             (double)g, (double)pa.gamma[i]);
    }
    if (k == 5)
      TCHECK(pa.gamma[i] == 1.0, "far from the walls gamma must be exactly 1, got %.17g", (double)pa.gamma[i]);
    else {
      TCHECK(PetscAbsReal(pa.gamma[i] - allref[k]) < 2e-6,
             "gamma of particle %" PetscInt_FMT " at (%g, %g): %.7f, reference %.6f", k, (double)x[0], (double)x[1],
             (double)pa.gamma[i], (double)allref[k]);
      maxg = PetscMax(maxg, PetscAbsReal(pa.gamma[i] - allref[k]));
    }
    /* its list: within the support, facing it, a positive mean kernel value */
    for (PetscInt q = wstart[i]; q < wstart[i + 1]; q++) {
      const PetscReal *e = &V->element[wk[q] * V->stride], *c = e + V->centroid, *nn = e + V->normal, s = e[V->measure];
      const PetscReal  p1[2] = {2 * c[0] - e[0], 2 * c[1] - e[1]}, r = SegmentDistance(e, p1, x),
                      face = (e[0] - x[0]) * nn[0] + (e[1] - x[1]) * nn[1];
      TCHECK(r < 2 * h,
             "particle %" PetscInt_FMT ": element %" PetscInt_FMT " at distance %g is listed, outside the support %g",
             k, wk[q], (double)r, (double)(2 * h));
      TCHECK(face > 0,
             "particle %" PetscInt_FMT ": element %" PetscInt_FMT " is listed but does not face it ((p0 - x).n = %g)",
             k, wk[q], (double)face);
      TCHECK(wW[q] > 0, "particle %" PetscInt_FMT ": element %" PetscInt_FMT " listed with the mean kernel value %g", k,
             wk[q], (double)wW[q]);
      sumW += wW[q] * s;
    }
    /* and complete: every element nearer than 1.9h that faces it */
    for (PetscInt e = 0; e < V->nelements; e++) {
      const PetscReal *el = &V->element[e * V->stride], *c = el + V->centroid, *nn = el + V->normal;
      const PetscReal  p1[2]  = {2 * c[0] - el[0], 2 * c[1] - el[1]};
      PetscBool        listed = PETSC_FALSE;
      if (SegmentDistance(el, p1, x) >= 1.9 * h || (el[0] - x[0]) * nn[0] + (el[1] - x[1]) * nn[1] <= 0) continue;
      for (PetscInt q = wstart[i]; q < wstart[i + 1]; q++) listed = (PetscBool)(listed || wk[q] == e);
      TCHECK(listed,
             "particle %" PetscInt_FMT ": element %" PetscInt_FMT " at distance %g faces it but is not in its list", k,
             e, (double)SegmentDistance(el, p1, x));
    }
    if (k < 4) { /* a flat wall: the list's int W dS add up to the kernel's integral along the wall's line (the
                    boundary's 8-point Gauss rule per piece: 7e-9 at 0.01h, where W varies on the scale d) */
      const PetscReal exact = LineIntegral(h, x[1]), err = PetscAbsReal(sumW - exact) / exact;
      TCHECK(err < 1e-8,
             "particle %" PetscInt_FMT
             " at %gh from the floor: sum of int W dS %.15g, line integral %.15g (relative error %.3g)",
             k, (double)dist[k], (double)sumW, (double)exact, (double)err);
      maxint = PetscMax(maxint, err);
    }
    if (k == 5)
      TCHECK(wstart[i + 1] == wstart[i], "the particle in the middle of the tank has %" PetscInt_FMT " wall elements",
             wstart[i + 1] - wstart[i]);
  }
  PetscCallMPI(MPI_Allreduce(MPI_IN_PLACE, &maxg, 1, MPIU_REAL, MPI_MAX, comm));
  PetscCallMPI(MPI_Allreduce(MPI_IN_PLACE, &maxint, 1, MPIU_REAL, MPI_MAX, comm));
  PetscCall(PetscPrintf(comm,
                        "  gamma: largest difference from the reference values %.3g (tolerance 2e-6); int W dS against "
                        "the line integral: %.3g (tolerance 1e-8)\n",
                        (double)maxg, (double)maxint));
  PetscCall(TestParticlesDestroy(&pa));
  PetscCall(FSBoundaryDestroy(&b));
  PetscFunctionReturn(0);
}

/*
   A hydrostatic column: a tank 0.4 m long and 0.3 m high filled to H = 0.1 m with particles on a
   lattice of spacing dx = 1 cm (h = 2 dx), at rest with p = rho0 g (H - y) and rho = rho0 + p/c0^2;
   particle k lives on rank k % size. The wall pressure of the floor is rho0 g H, its load the
   liquid's weight rho0 g H L (pointing down), the side walls' rho0 g H^2/2 (outwards), the lid's 0.
*/
static PetscErrorCode TestHydrostatic(MPI_Comm comm)
{
  const PetscReal L = 0.4, Ht = 0.3, H = 0.1, dx = 0.01, h = 2 * dx;
  const PetscInt  nx = 40, ny = 10;
  /* measured (1 and 2 ranks): floor pressure 1.9e-4 and floor load 1.89e-4, from the hydrostatic
     correction's rho_j g.(x_k - x_j), which takes the compressed density (rho_j - rho0 = p_j/c0^2, up
     to g H/c0^2 = 2.5e-3 rho0 here); side loads 1.24e-3, almost all from the elements just above the
     free surface, whose extrapolated tension (-5 Pa, -1 Pa, ...) counts with the square of their wetted share */
  const PetscReal    tolp = 2.5e-4, tolfloor = 2.5e-4, tolside = 1.5e-3;
  PetscMPIInt        rank, size;
  PetscInt           n = 0, floorw, rightw, leftw, lidw, nwalls;
  FSBoundary         b;
  TestParticles      pa;
  FSBoundaryLeak     leak;
  const FSWallView  *V;
  const PetscInt    *wstart, *wk;
  const PetscReal   *wW, *loads;
  const char *const *names;
  PetscReal          maxp = 0, weight = rho0 * grav * H * L, side = 0.5 * rho0 * grav * H * H, ef, er, el;

  PetscFunctionBegin;
  PetscCallMPI(MPI_Comm_rank(comm, &rank));
  PetscCallMPI(MPI_Comm_size(comm, &size));
  PetscCall(TankBoundary(comm, L, Ht, dx, h, &b));
  PetscCall(TestWallIndex(b, "floor", &floorw));
  PetscCall(TestWallIndex(b, "right", &rightw));
  PetscCall(TestWallIndex(b, "left", &leftw));
  PetscCall(TestWallIndex(b, "tank", &lidw));
  for (PetscInt k = 0; k < nx * ny; k++) n += (k % size == rank);
  PetscCall(TestParticlesCreate(2, n, &pa));
  for (PetscInt k = 0, i = 0; k < nx * ny; k++) {
    const PetscReal x = (k % nx + 0.5) * dx, y = (k / nx + 0.5) * dx;
    if (k % size != rank) continue;
    Place(&pa, i++, x, y, rho0 + rho0 * grav * (H - y) / (c0 * c0), dx);
  }
  PetscCall(TestUpdateAndPrepare(b, h, grav, &pa, &leak));
  TCHECK(leak.particle < 0, "a leak reported in the hydrostatic column (particle %" PetscInt_FMT ")", leak.particle);
  PetscCall(FSBoundaryGetView(b, &V, &wstart, &wk, &wW));
  /* the wall pressure of the floor's elements (every rank knows every element's) */
  for (PetscInt e = 0; e < V->nelements; e++) {
    const PetscReal err = PetscAbsReal(V->pressure[e] - rho0 * grav * H) / (rho0 * grav * H);
    if (V->elementwall[e] != floorw) continue;
    TCHECK(err < tolp,
           "the wall pressure of floor element %" PetscInt_FMT
           " at x = %g: %g, expected rho0 g H = %g (relative error %.3g > %g)",
           e, (double)V->element[e * V->stride + V->centroid], (double)V->pressure[e], (double)(rho0 * grav * H),
           (double)err, (double)tolp);
    maxp = PetscMax(maxp, err);
  }
  PetscCall(FSBoundaryGetWallNames(b, &nwalls, &names));
  PetscCall(FSBoundaryGetLoads(b, &nwalls, &loads));
  TCHECK(nwalls == 4 && !strcmp(names[floorw], "floor"),
         "FSBoundaryGetLoads: %" PetscInt_FMT " walls, wall %" PetscInt_FMT " named \"%s\"", nwalls, floorw,
         names[floorw]);
  ef = PetscAbsReal(loads[6 * floorw + 1] + weight) / weight;
  er = PetscAbsReal(loads[6 * rightw + 0] - side) / side;
  el = PetscAbsReal(loads[6 * leftw + 0] + side) / side;
  TCHECK(ef < tolfloor,
         "the floor's load %g, expected minus the liquid's weight -rho0 g H L = %g (relative error %.3g > %g)",
         (double)loads[6 * floorw + 1], (double)-weight, (double)ef, (double)tolfloor);
  TCHECK(PetscAbsReal(loads[6 * floorw + 0]) < 1e-12 * weight, "the floor's horizontal load %g must be 0",
         (double)loads[6 * floorw + 0]);
  TCHECK(er < tolside, "the right wall's load %g, expected rho0 g H^2/2 = %g (relative error %.3g > %g)",
         (double)loads[6 * rightw + 0], (double)side, (double)er, (double)tolside);
  TCHECK(el < tolside, "the left wall's load %g, expected -rho0 g H^2/2 = %g (relative error %.3g > %g)",
         (double)loads[6 * leftw + 0], (double)-side, (double)el, (double)tolside);
  TCHECK(PetscAbsReal(loads[6 * rightw + 1]) < 1e-12 * side && PetscAbsReal(loads[6 * leftw + 1]) < 1e-12 * side,
         "the side walls' vertical loads %g, %g must be 0", (double)loads[6 * rightw + 1],
         (double)loads[6 * leftw + 1]);
  for (PetscInt c = 0; c < 6; c++)
    TCHECK(loads[6 * lidw + c] == 0, "the lid, above the liquid, carries the load %g (component %" PetscInt_FMT ")",
           (double)loads[6 * lidw + c], c);
  PetscCall(PetscPrintf(comm,
                        "  hydrostatic column: floor pressure error %.3g (tolerance %g), floor load %.3g (tolerance "
                        "%g), side loads %.3g and %.3g (tolerance %g)\n",
                        (double)maxp, (double)tolp, (double)ef, (double)tolfloor, (double)er, (double)el,
                        (double)tolside));
  PetscCall(TestParticlesDestroy(&pa));
  PetscCall(FSBoundaryDestroy(&b));
  PetscFunctionReturn(0);
}

/* The leak report: a particle outside the tank, first past the left wall, then under the floor. Not collective. */
static PetscErrorCode TestLeak(void)
{
  const PetscReal    h = 0.1, dx = 0.5 * h;
  const PetscReal    xy[2][3][2] = {{{1.0, 1.0}, {-0.3 * dx, 0.7}, {0.5, -0.2 * dx}},
                                    {{1.0, 1.0}, {0.9, 0.2 * dx}, {0.9, -0.2 * dx}}};
  const PetscInt     expect[2]   = {1, 2};
  const char        *wall[2]     = {"left", "floor"};
  FSBoundary         b;
  TestParticles      pa;
  FSBoundaryLeak     leak;
  FSNeighbours       nb;
  PetscInt           w;
  const char *const *names;
  PetscInt           nwalls;

  PetscFunctionBegin;
  PetscCall(TankBoundary(PETSC_COMM_SELF, 2.0, 2.0, dx, h, &b));
  PetscCall(FSBoundaryGetWallNames(b, &nwalls, &names));
  PetscCall(TestParticlesCreate(2, 3, &pa));
  for (PetscInt c = 0; c < 2; c++) {
    for (PetscInt i = 0; i < 3; i++) Place(&pa, i, xy[c][i][0], xy[c][i][1], rho0, dx);
    PetscCall(PetscMemzero(&nb, sizeof(nb)));
    PetscCall(FSNeighboursBuildCells(&nb, 2, pa.n, pa.rec, S, 2.5 * h));
    PetscCall(FSNeighboursBuildCandidates(&nb, pa.n, pa.rec, S, 2.5 * h));
    PetscCall(FSBoundaryUpdate(b, pa.n, pa.rec, S, &nb, &leak));
    PetscCall(FSNeighboursDestroy(&nb));
    PetscCall(TestWallIndex(b, wall[c], &w));
    TCHECK(leak.particle == expect[c],
           "leak: particle %" PetscInt_FMT " reported, expected %" PetscInt_FMT " (at (%g, %g))", leak.particle,
           expect[c], (double)xy[c][expect[c]][0], (double)xy[c][expect[c]][1]);
    TCHECK(leak.wall == w, "leak of particle %" PetscInt_FMT ": wall \"%s\" reported, expected the nearest, \"%s\"",
           leak.particle, leak.wall >= 0 && leak.wall < nwalls ? names[leak.wall] : "(none)", wall[c]);
  }
  PetscCall(TestParticlesDestroy(&pa));
  PetscCall(FSBoundaryDestroy(&b));
  PetscFunctionReturn(0);
}

/* the energy callback of the bounce test: kinetic + potential (tank frame), and the same + 1 (absolute); counts its
 * calls */
typedef struct {
  PetscInt calls;
} EnergyCtx;

static void Energy(void *ctx, const PetscReal x[], const PetscReal v[], PetscReal m, PetscReal e[2])
{
  ((EnergyCtx *)ctx)->calls++;
  e[0] = 0.5 * m * (v[0] * v[0] + v[1] * v[1]) + m * grav * x[1];
  e[1] = e[0] + 1;
}

/*
   The bounce, with the default restitution 1 and with -fs_walls_bounce_restitution 0.5: particle 0
   just above the floor moving down, 1 at the same height moving up, 2 just left of the right wall
   moving right, 3 in the middle of the tank. Not collective.
*/
static PetscErrorCode TestBounce(void)
{
  const PetscReal h = 0.1, dx = 0.5 * h, dmin = 0.1 * dx; /* the default bounce distance, 0.1 dx */
  const PetscReal x0[4][2] = {{1.0 + 0.37 * dx, 0.03 * dx}, {0.7, 0.03 * dx}, {2.0 - 0.05 * dx, 1.3}, {1.0, 1.0}};
  const PetscReal v0[4][2] = {{0.2, -0.5}, {0.2, 0.5}, {0.8, -0.1}, {-3.0, -4.0}};
  const PetscReal m[4]     = {2.5, 2.5, 2.5, 2.5};

  PetscFunctionBegin;
  for (PetscInt pass = 0; pass < 2; pass++) {
    const PetscReal e = pass ? 0.5 : 1.0;
    FSBoundary      b;
    PetscBool       on;
    PetscReal       x[8], v[8], de[2], ede;
    EnergyCtx       ctx = {0};

    if (pass) PetscCall(PetscOptionsSetValue(NULL, "-fs_walls_bounce_restitution", "0.5"));
    PetscCall(TankBoundary(PETSC_COMM_SELF, 2.0, 2.0, dx, h, &b));
    if (pass) PetscCall(PetscOptionsClearValue(NULL, "-fs_walls_bounce_restitution"));
    PetscCall(FSBoundaryGetBounce(b, &on));
    TCHECK(on, "bounces must be on by default");
    for (PetscInt i = 0; i < 4; i++)
      for (PetscInt d = 0; d < 2; d++) {
        x[2 * i + d] = x0[i][d];
        v[2 * i + d] = v0[i][d];
      }
    PetscCall(FSBoundaryBounce(b, 4, x, v, m, Energy, &ctx, de));
    /* particle 0 off the floor (normal (0, -1)): y = dmin, v_y = +e 0.5 */
    TCHECK(PetscAbsReal(x[1] - dmin) <= 1e-15 && x[0] == x0[0][0],
           "bounce off the floor: position (%.17g, %.17g), expected (%.17g, %.17g)", (double)x[0], (double)x[1],
           (double)x0[0][0], (double)dmin);
    TCHECK(v[0] == v0[0][0] && PetscAbsReal(v[1] - e * 0.5) <= 1e-15,
           "bounce off the floor: velocity (%.17g, %.17g), expected (%g, %g)", (double)v[0], (double)v[1],
           (double)v0[0][0], (double)(e * 0.5));
    /* particle 2 off the right wall (normal (1, 0)): x = 2 - dmin, v_x = -e 0.8 */
    TCHECK(PetscAbsReal(x[4] - (2.0 - dmin)) <= 1e-15 && x[5] == x0[2][1],
           "bounce off the right wall: position (%.17g, %.17g), expected (%.17g, %.17g)", (double)x[4], (double)x[5],
           (double)(2.0 - dmin), (double)x0[2][1]);
    TCHECK(PetscAbsReal(v[4] + e * 0.8) <= 1e-15 && v[5] == v0[2][1],
           "bounce off the right wall: velocity (%.17g, %.17g), expected (%g, %g)", (double)v[4], (double)v[5],
           (double)(-e * 0.8), (double)v0[2][1]);
    /* particles 1 (moving away) and 3 (far) untouched */
    for (PetscInt i = 1; i < 4; i += 2)
      for (PetscInt d = 0; d < 2; d++)
        TCHECK(x[2 * i + d] == x0[i][d] && v[2 * i + d] == v0[i][d],
               "particle %" PetscInt_FMT " bounced: it moves away from the wall or is far from it", i);
    /* the callback before and after each of the two bounces, and the energy change it measured */
    TCHECK(ctx.calls == 4, "the energy callback was called %" PetscInt_FMT " times for two bounces, expected 4",
           ctx.calls);
    ede = m[0] * grav * (dmin - x0[0][1]) + 0.5 * m[0] * (e * e - 1) * 0.5 * 0.5 + 0.5 * m[2] * (e * e - 1) * 0.8 * 0.8;
    TCHECK(
        PetscAbsReal(de[0] - ede) <= 1e-12 * PetscMax(1.0, PetscAbsReal(ede)) && PetscAbsReal(de[1] - de[0]) <= 1e-12,
        "bounce energy change %.17g (absolute frame %.17g), expected %.17g", (double)de[0], (double)de[1], (double)ede);
    PetscCall(FSBoundaryDestroy(&b));
  }
  PetscFunctionReturn(0);
}

/* errors: an unknown method names itself and the registered ones; the polygon's geometry on a boundary without that
 * method */
static PetscErrorCode TestErrors(MPI_Comm comm)
{
  FSBoundary     b;
  FSWalls        w;
  PetscErrorCode ierr, ierr2;
  const char    *text;
  char          *msg;

  PetscFunctionBegin;
  PetscCall(FSBoundaryCreate(comm, &b));
  PetscCall(PetscPushErrorHandler(PetscReturnErrorHandler, NULL));
  ierr = FSBoundarySetType(b, "trimesh_of_the_future");
  PetscCall(PetscPopErrorHandler());
  TCHECK(ierr == PETSC_ERR_ARG_UNKNOWN_TYPE,
         "FSBoundarySetType with an unknown name returned %d, expected PETSC_ERR_ARG_UNKNOWN_TYPE (%d)", (int)ierr,
         (int)PETSC_ERR_ARG_UNKNOWN_TYPE);
  PetscCall(PetscErrorMessage(ierr, &text, &msg));
  TCHECK(msg && strstr(msg, "\"trimesh_of_the_future\"") && strstr(msg, "polygon"),
         "the error must name the unknown method and the registered ones: \"%s\"", msg ? msg : "(none)");
  PetscCall(FSWallsCreate(&w));
  PetscCall(FSWallsRectangularTank(&w, comm, 1.0, 1.0));
  PetscCall(PetscPushErrorHandler(PetscReturnErrorHandler, NULL));
  ierr  = FSBoundaryPolygonSetWalls(b, &w);
  ierr2 = FSBoundarySetUp(b, 2, 0.1, 0.2, 0.5);
  PetscCall(PetscPopErrorHandler());
  TCHECK(ierr != 0 && w.npoly == 1,
         "FSBoundaryPolygonSetWalls on a boundary without a method must fail and leave the walls to the caller");
  TCHECK(ierr2 == PETSC_ERR_ARG_WRONGSTATE,
         "FSBoundarySetUp without a method returned %d, expected PETSC_ERR_ARG_WRONGSTATE (%d)", (int)ierr2,
         (int)PETSC_ERR_ARG_WRONGSTATE);
  PetscCall(FSWallsDestroy(&w));
  PetscCall(FSBoundaryDestroy(&b));
  PetscFunctionReturn(0);
}

int main(int argc, char **argv)
{
  PetscFunctionBeginUser;
  PetscCall(PetscInitialize(&argc, &argv, NULL, NULL));
  PetscCall(FSInitializePackage());
  PetscCall(TestGammaAndLists(PETSC_COMM_WORLD));
  PetscCall(TestHydrostatic(PETSC_COMM_WORLD));
  PetscCall(TestLeak());
  PetscCall(TestBounce());
  PetscCall(TestErrors(PETSC_COMM_WORLD));
  PetscCall(PetscPrintf(PETSC_COMM_WORLD, "test_boundary: OK\n"));
  PetscCall(PetscFinalize());
  return 0;
}
