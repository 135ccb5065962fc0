/* Set-up shared by the cases with walls: a body of liquid on a lattice, hydrostatic, at rest or with a given velocity
 * field. */
#include <flexslosh.h>
#include "boundary/fsboundary.h"
#include "liquid.h"
#include "packing.h"
#include "sys/fssys.h"

/*
   FSCaseFillLiquid - gives the solver its walls (checked with FSWallsCheck) and a domain box around them (4h margin),
and fills the liquid region of the walls inside [x0, x1] x [y0, ysurf] with particles in rows y0 + (j + 1/2) dx_y, at
rest with the hydrostatic density rho = rho0 + rho0 |g| (ysurf - y) / c0^2 and mass rho dx_x dx_y. dx_y is the spacing
closest to dx that divides the depth, so the surface is at ysurf. Each row is cut by the walls into intervals of liquid
(between baffles, say), and each interval gets the spacing dx_x closest to dx that divides it: the liquid ends half a
spacing from the walls on both sides of every compartment (a lattice that left a gap at one wall would start the liquid
sloshing). Points closer to a wall than half a spacing (the underside of a baffle, other shapes) are left out. The rows
of the lattice are split over the ranks, so ids do not depend on the number of ranks. The walls are moved into the
solver. what names the liquid region in the error messages. Where the lattice does not fit the region, the masses are
scaled so that the liquid weighs the integral of rho over its exact area (FSCaseFitLiquidMass()).

   Collective

   Level: developer

.seealso: FSCaseFillLiquidWithVelocity()
*/
PetscErrorCode FSCaseFillLiquid(FSSolver s, FSWalls *w, PetscReal x0, PetscReal x1, PetscReal y0, PetscReal ysurf,
                                const char what[])
{
  PetscFunctionBegin;
  PetscCall(FSCaseFillLiquidWithVelocity(s, w, x0, x1, y0, ysurf, what, NULL, NULL));
  PetscFunctionReturn(0);
}

/*
   FSCaseSetDomainAround - the solver's domain: the walls' box lo..hi (dim values each) with a margin of 4h
   in every direction, not periodic.

   Collective

   Level: developer
*/
PetscErrorCode FSCaseSetDomainAround(FSSolver s, PetscInt dim, const PetscReal lo[], const PetscReal hi[])
{
  PetscReal dlo[3] = {0, 0, 0}, dhi[3] = {0, 0, 0}, h;
  PetscBool per[3] = {PETSC_FALSE, PETSC_FALSE, PETSC_FALSE};

  PetscFunctionBegin;
  PetscCall(FSSolverGetParameters(s, NULL, &h, NULL, NULL, NULL));
  for (PetscInt d = 0; d < dim; d++) {
    dlo[d] = lo[d] - 4 * h;
    dhi[d] = hi[d] + 4 * h;
  }
  PetscCall(FSSolverSetDomain(s, dlo, dhi, per));
  PetscFunctionReturn(0);
}

/* the lattice's points in [x0, x1] x [y0, ysurf] checked before anything is allocated (FSCheckParticleCount) */
static PetscErrorCode LatticeSizeCheck(FSSolver s, const FSWalls *w, PetscReal x0, PetscReal x1, PetscReal y0,
                                       PetscReal ysurf, const char what[])
{
  const PetscReal len[2] = {x1 - x0, ysurf - y0};
  PetscReal       dx;
  char            region[256 + FS_WALLS_WHERE_LEN];

  PetscFunctionBegin;
  PetscCall(FSSolverGetParameters(s, &dx, NULL, NULL, NULL, NULL));
  PetscCall(PetscSNPrintf(region, sizeof(region), "%s: the liquid region %g x %g (walls: %s)", what, (double)len[0],
                          (double)len[1], w->npoly ? w->where[0] : "none"));
  PetscCall(FSCheckParticleCount(PetscObjectComm((PetscObject)s), 2, dx, FSLatticeCount(2, len, dx), region, NULL));
  PetscFunctionReturn(0);
}

/* the domain around the walls; the segments, for the particles' distances to the walls */
static PetscErrorCode PolygonDomain(FSSolver s, FSWalls *w)
{
  PetscReal dx;

  PetscFunctionBegin;
  PetscCall(FSSolverGetParameters(s, &dx, NULL, NULL, NULL, NULL));
  PetscCall(FSWallsDiscretize(w, dx));
  PetscCall(FSCaseSetDomainAround(s, 2, w->lo, w->hi));
  PetscFunctionReturn(0);
}

/* the walls into the solver's boundary (which takes them over) */
static PetscErrorCode PolygonGive(FSSolver s, FSWalls *w)
{
  FSBoundary b;

  PetscFunctionBegin;
  PetscCall(FSSolverGetBoundary(s, &b));
  PetscCall(FSBoundarySetType(b, FSBOUNDARYPOLYGON));
  PetscCall(FSBoundaryPolygonSetWalls(b, w));
  PetscFunctionReturn(0);
}

/*
   FSCaseFitLiquidMass - sets the masses m[0..n-1] of this rank's particles of one body of liquid so that their sum
   over the ranks is mass, the integral of the initial density over the body's exact volume; records the body
   (FSSolverAddLiquidVolume). Where the lattice's mass already equals mass to round-off (1e-9 relative: a body on a
   lattice that fits it, a box along the axes), the lattice's masses are kept bit for bit; elsewhere (walls not along
   the axes, points left out near a wall) every mass is scaled by the same factor, the density kept hydrostatic.

   Collective

   Level: developer
*/
PetscErrorCode FSCaseFitLiquidMass(FSSolver s, PetscReal volume, PetscReal mass, PetscInt n, PetscReal m[])
{
  PetscReal sum = 0;

  PetscFunctionBegin;
  for (PetscInt i = 0; i < n; i++) sum += m[i];
  PetscCallMPI(MPI_Allreduce(MPI_IN_PLACE, &sum, 1, MPIU_REAL, MPIU_SUM, PetscObjectComm((PetscObject)s)));
  if (sum > 0 && PetscAbsReal(sum - mass) > 1e-9 * mass)
    for (PetscInt i = 0; i < n; i++) m[i] *= mass / sum;
  PetscCall(FSSolverAddLiquidVolume(s, volume, mass, sum));
  PetscFunctionReturn(0);
}

/*
   FSCaseLatticeFits - whether a body of liquid is relaxed (FSCasePackRelax) rather than left on its lattice: with
   -fs_fill_packing auto, where some wall is not along the axes (aligned false) and the lattice's masses m (n on this
   rank) do not sum over the ranks to the exact mass to round-off (1e-9, the rule of FSCaseFitLiquidMass()); with
   relaxed always, with lattice never. Walls along the axes keep the lattice even where it does not fit the fill
   (a lifted baffle between two rows): relaxed next to such walls the 3-D liquid at rest moved more (rms speed 1.7 times
   the lattice's in tests/python/test_walls_3d.py's lifted baffles).

   Collective

   Level: developer
*/
PetscErrorCode FSCaseLatticeFits(FSSolver s, FSFillPackingType type, PetscBool aligned, PetscReal mass, PetscInt n,
                                 const PetscReal m[], PetscBool *relax)
{
  PetscReal sum = 0;

  PetscFunctionBegin;
  *relax = (PetscBool)(type == FS_FILL_PACKING_RELAXED);
  if (type != FS_FILL_PACKING_AUTO || aligned) PetscFunctionReturn(0);
  for (PetscInt i = 0; i < n; i++) sum += m[i];
  PetscCallMPI(MPI_Allreduce(MPI_IN_PLACE, &sum, 1, MPIU_REAL, MPIU_SUM, PetscObjectComm((PetscObject)s)));
  *relax = (PetscBool)(PetscAbsReal(sum - mass) > 1e-9 * mass);
  PetscFunctionReturn(0);
}

/*
   FSCaseRelaxedDensities - the hydrostatic densities rho0 (1 + |g| (ysurf - y) / c0^2) of n relaxed particles x (dim
   reals each) and their masses rho V / N, the body's volume V shared evenly by its N particles (over the ranks).

   Collective

   Level: developer
*/
PetscErrorCode FSCaseRelaxedDensities(FSSolver s, PetscInt dim, PetscReal ysurf, PetscReal volume, PetscInt n,
                                      const PetscReal x[], PetscReal rho[], PetscReal m[])
{
  PetscReal g[3], gmag, rho0, c0;
  PetscInt  N = n;

  PetscFunctionBegin;
  PetscCall(FSSolverGetGravity(s, g));
  PetscCall(FSSolverGetParameters(s, NULL, NULL, &rho0, &c0, NULL));
  gmag = FSCaseHeadGravity(g, dim);
  PetscCallMPI(MPI_Allreduce(MPI_IN_PLACE, &N, 1, MPIU_INT, MPI_SUM, PetscObjectComm((PetscObject)s)));
  for (PetscInt i = 0; i < n; i++) {
    rho[i] = rho0 + rho0 * gmag * (ysurf - x[dim * i + 1]) / (c0 * c0);
    m[i]   = rho[i] * volume / N;
  }
  PetscFunctionReturn(0);
}

/* whether every edge of w's polygons runs along x or y (to round-off) */
static PetscBool FSWallsAlongAxes(const FSWalls *w)
{
  for (PetscInt p = 0; p < w->npoly; p++)
    for (PetscInt v = w->pstart[p]; v < w->pstart[p + 1]; v++) {
      const PetscInt   next = v + 1 < w->pstart[p + 1] ? v + 1 : w->pstart[p];
      const PetscReal *a = &w->vert[2 * v], *b = &w->vert[2 * next];
      const PetscReal  ex = PetscAbsReal(b[0] - a[0]), ey = PetscAbsReal(b[1] - a[1]);
      if (PetscMin(ex, ey) > 1e-12 * PetscMax(ex, ey)) return PETSC_FALSE;
    }
  return PETSC_TRUE;
}

/* the exact area of the liquid of w in [x0, x1] x [y0, ysurf] and the integral over it of the hydrostatic density
   rho0 (1 + |g| (ysurf - y) / c0^2), the mass it should have (FSWallsLiquidBelow at ysurf less that at y0) */
static void PolygonExactMass(const FSWalls *w, PetscReal x0, PetscReal x1, PetscReal y0, PetscReal ysurf,
                             PetscReal rho0, PetscReal g_c02, PetscReal *area, PetscReal *mass)
{
  PetscReal a1, q1, a0, q0;

  FSWallsLiquidBelow(w, x0, x1, ysurf, &a1, &q1);
  FSWallsLiquidBelow(w, x0, x1, y0, &a0, &q0);
  *area = a1 - a0;
  *mass = rho0 * (*area + g_c02 * (q1 - q0 - (ysurf - y0) * a0));
}

/*
   FSCaseFillLevel - the level in [y0, y1] below which the liquid has the volume target (bymass false) or the mass
   target (bymass true, hydrostatic below that level: the masses the particles get), f(t) giving both exactly for the
   level t (FSWallsLiquidBelow, FSMeshLiquidBelow). Both grow with the level, so bisection finds it, to round-off (a
   box's level is -fs_fill's to the last bits). what names the option in the errors: a target above the tank's
   capacity names both. Prints the level found.

   Collective (every rank computes the same level)

   Level: developer
*/
PetscErrorCode FSCaseFillLevel(FSSolver s, FSCaseLevelFn f, const void *ctx, PetscReal y0, PetscReal y1,
                               PetscBool bymass, PetscReal target, const char what[], PetscReal *level)
{
  MPI_Comm  comm = PetscObjectComm((PetscObject)s);
  PetscReal lo = y0, hi = y1, v, m, full;
  PetscInt  dim;

  PetscFunctionBegin;
  PetscCall(FSSolverGetDimension(s, &dim));
  f(ctx, y1, &v, &m);
  full = bymass ? m : v;
  PetscCheck(target > 0 && target <= full * (1 + 1e-12), comm, PETSC_ERR_ARG_OUTOFRANGE,
             "%s %g is more than the full tank holds: expected at most %g (%s)", what, (double)target, (double)full,
             bymass ? (dim == 2 ? "kg per metre of width, hydrostatic" : "kg, hydrostatic")
                    : (dim == 2 ? "m^2, the area in the plane: m^3 per metre of width" : "m^3"));
  for (PetscInt it = 0; it < 200 && hi - lo > 4 * PETSC_MACHINE_EPSILON * PetscMax(PetscAbsReal(lo), PetscAbsReal(hi));
       it++) {
    const PetscReal mid = 0.5 * (lo + hi);
    f(ctx, mid, &v, &m);
    if ((bymass ? m : v) < target) lo = mid;
    else hi = mid;
  }
  *level = 0.5 * (lo + hi);
  f(ctx, *level, &v, &m);
  PetscCall(PetscPrintf(comm,
                        "%s %g: the liquid's level is y = %.10g, %.6g of the tank's height (volume %g, mass %g%s)\n",
                        what, (double)target, (double)*level, (double)((*level - y0) / (y1 - y0)), (double)v, (double)m,
                        dim == 2 ? ", per metre of width" : ""));
  PetscFunctionReturn(0);
}

typedef struct {
  const FSWalls *w;
  PetscReal      x0, x1, y0, rho0, g_c02;
} PolygonLevel;

static void PolygonLevelAt(const void *ctx, PetscReal t, PetscReal *area, PetscReal *mass)
{
  const PolygonLevel *p = (const PolygonLevel *)ctx;
  PolygonExactMass(p->w, p->x0, p->x1, p->y0, t, p->rho0, p->g_c02, area, mass);
}

/*
   FSCaseFillLevelPolygon - the level of the liquid of w in the strip x0..x1 above y0 (at most y1) that holds the area
   target (m^2, per metre of width) or the hydrostatic mass target (kg per metre of width).

   Collective

   Level: developer
*/
PetscErrorCode FSCaseFillLevelPolygon(FSSolver s, const FSWalls *w, PetscReal x0, PetscReal x1, PetscReal y0,
                                      PetscReal y1, PetscBool bymass, PetscReal target, const char what[],
                                      PetscReal *level)
{
  PolygonLevel p = {w, x0, x1, y0, 0, 0};
  PetscReal    g[3], c0;

  PetscFunctionBegin;
  PetscCall(FSSolverGetGravity(s, g));
  PetscCall(FSSolverGetParameters(s, NULL, NULL, &p.rho0, &c0, NULL));
  p.g_c02 = FSCaseHeadGravity(g, 2) / (c0 * c0);
  PetscCall(FSCaseFillLevel(s, PolygonLevelAt, &p, y0, y1, bymass, target, what, level));
  PetscFunctionReturn(0);
}

/* this rank's rows of the lattice in the liquid region of w inside [x0, x1] x [y0, ysurf], points closer to a wall
   than margin times the spacing left out: positions, hydrostatic densities and masses rho hx hy (x, rho, m
   allocated here) */
static PetscErrorCode PolygonLatticePoints(FSSolver s, const FSWalls *w, PetscReal x0, PetscReal x1, PetscReal y0,
                                           PetscReal ysurf, const char what[], PetscReal margin, PetscInt *np,
                                           PetscReal **xp, PetscReal **rhop, PetscReal **mp)
{
  MPI_Comm    comm = PetscObjectComm((PetscObject)s);
  PetscReal  *x, *rho, *m, g[3], gmag, dx, rho0, c0;
  PetscInt    nx, ny, n = 0, r0, r1;
  PetscInt64  cap;
  PetscReal   hy, *cross;
  PetscMPIInt rank, size;

  PetscFunctionBegin;
  PetscCall(FSSolverGetGravity(s, g));
  PetscCall(FSSolverGetParameters(s, &dx, NULL, &rho0, &c0, NULL));
  gmag = FSCaseHeadGravity(g, 2);
  PetscCallMPI(MPI_Comm_rank(comm, &rank));
  PetscCallMPI(MPI_Comm_size(comm, &size));
  PetscCall(LatticeSizeCheck(s, w, x0, x1, y0, ysurf, what));
  nx = (PetscInt)((x1 - x0) / dx + 0.5);
  ny = (PetscInt)((ysurf - y0) / dx + 0.5);
  PetscCheck(nx >= 1 && ny >= 1, comm, PETSC_ERR_ARG_OUTOFRANGE,
             "%s: -fs_dx %g leaves no particle in the liquid region %g x %g", what, (double)dx, (double)(x1 - x0),
             (double)(ysurf - y0));
  hy = (ysurf - y0) / ny;
  r0 = ny * rank / size;
  r1 = ny * (rank + 1) / size;
  /* a row's intervals hold at most their length / dx + 1/2 points each, and there are fewer of them than nvert
     (the crossings) (and at most 2 nx + 1: each is at least dx / 2 long) */
  cap = (PetscInt64)(r1 - r0) * (nx + 1 + PetscMin(w->nvert, nx + 1)) + 1;
  PetscCheck(2 * cap < PETSC_MAX_INT, PETSC_COMM_SELF, PETSC_ERR_ARG_OUTOFRANGE,
             "%s: -fs_dx %g: this rank's %" PetscInt64_FMT
             " places for particles are more than an index can count: use "
             "more ranks or a coarser -fs_dx",
             what, (double)dx, cap);
  PetscCall(PetscMalloc3(2 * cap, &x, cap, &rho, cap, &m));
  PetscCall(PetscMalloc1(w->nvert + 2, &cross));
  for (PetscInt b = r0; b < r1; b++) {
    const PetscReal yr = y0 + (b + 0.5) * hy;
    PetscInt        nc = 0;
    /* the crossings of the row with the polygons' edges (half-open in y, so a vertex counts once) */
    for (PetscInt q = 0; q < w->npoly; q++)
      for (PetscInt e = w->pstart[q]; e < w->pstart[q + 1]; e++) {
        const PetscInt   f  = e + 1 < w->pstart[q + 1] ? e + 1 : w->pstart[q];
        const PetscReal *p0 = &w->vert[2 * e], *p1 = &w->vert[2 * f];
        if ((p0[1] <= yr && yr < p1[1]) || (p1[1] <= yr && yr < p0[1]))
          cross[nc++] = p0[0] + (yr - p0[1]) * (p1[0] - p0[0]) / (p1[1] - p0[1]);
      }
    PetscCall(PetscSortReal(nc, cross));
    for (PetscInt c = 0; c + 1 < nc; c++) {
      const PetscReal a = PetscMax(cross[c], x0), e = PetscMin(cross[c + 1], x1),
                      mid[2] = {0.5 * (cross[c] + cross[c + 1]), yr};
      PetscInt  na;
      PetscReal hx;
      if (e <= a || !FSWallsInLiquid(w, mid, 0)) continue; /* outside [x0, x1], or inside a wall */
      na = (PetscInt)((e - a) / dx + 0.5);
      if (na < 1) continue;
      hx = (e - a) / na;
      for (PetscInt i = 0; i < na; i++) {
        const PetscReal p[2] = {a + (i + 0.5) * hx, yr};
        if (!FSWallsInLiquid(w, p, margin * PetscMin(hx, hy))) continue;
        x[2 * n]     = p[0];
        x[2 * n + 1] = p[1];
        rho[n]       = rho0 + rho0 * gmag * (ysurf - p[1]) / (c0 * c0);
        m[n]         = rho[n] * hx * hy;
        n++;
      }
    }
  }
  PetscCall(PetscFree(cross));
  *np   = n;
  *xp   = x;
  *rhop = rho;
  *mp   = m;
  PetscFunctionReturn(0);
}

/* this rank's particles of the liquid region of w inside [x0, x1] x [y0, ysurf], added to the solver: the lattice,
   or where -fs_fill_packing asks for it the lattice relaxed in the region (FSCasePackRelax); hydrostatic, their
   masses fitted to the exact area */
static PetscErrorCode PolygonLattice(FSSolver s, const FSWalls *w, PetscReal x0, PetscReal x1, PetscReal y0,
                                     PetscReal ysurf, const char what[], FSCaseVelocityFn velocity, void *ctx)
{
  PetscReal    *x, *u, *rho, *m, g[3], gmag, rho0, c0, area, mass;
  PetscInt      n;
  FSFillPacking pk;
  PetscBool     relax;

  PetscFunctionBegin;
  PetscCall(FSSolverGetGravity(s, g));
  PetscCall(FSSolverGetParameters(s, NULL, NULL, &rho0, &c0, NULL));
  PetscCall(FSSolverGetFillPacking(s, &pk));
  gmag = FSCaseHeadGravity(g, 2);
  PolygonExactMass(w, x0, x1, y0, ysurf, rho0, gmag / (c0 * c0), &area, &mass);
  PetscCall(PolygonLatticePoints(s, w, x0, x1, y0, ysurf, what, 0.499, &n, &x, &rho, &m));
  PetscCall(FSCaseLatticeFits(s, pk.type, FSWallsAlongAxes(w), mass, n, m, &relax));
  if (relax) { /* from the lattice of every point inside, relaxed */
    FSPackRegion    region;
    PetscReal       dx;
    const PetscReal lo[2] = {x0, y0}, hi[2] = {x1, ysurf};
    PetscCall(PetscFree3(x, rho, m));
    PetscCall(FSSolverGetParameters(s, &dx, NULL, NULL, NULL, NULL));
    PetscCall(PolygonLatticePoints(s, w, x0, x1, y0, ysurf, what, 0, &n, &x, &rho, &m));
    PetscCall(FSPackRegionFromWalls(&region, w, lo, hi, dx));
    PetscCall(FSCasePackRelax(s, &region, area, &n, x, what));
    PetscCall(FSPackRegionDestroy(&region));
    PetscCall(FSCaseRelaxedDensities(s, 2, ysurf, area, n, x, rho, m));
  }
  PetscCall(PetscCalloc1(2 * n, &u));
  if (velocity)
    for (PetscInt i = 0; i < n; i++) PetscCall((*velocity)(&x[2 * i], &u[2 * i], ctx));
  PetscCall(FSCaseFitLiquidMass(s, area, mass, n, m));
  PetscCall(FSSolverAddParticles(s, n, x, u, rho, m));
  PetscCall(PetscFree3(x, rho, m));
  PetscCall(PetscFree(u));
  PetscFunctionReturn(0);
}

/*
   FSCaseFillLiquidWithVelocity - FSCaseFillLiquid, with the particles' initial velocity given by
   velocity(x, u, ctx) at each particle's position x (NULL: at rest). The density stays hydrostatic.

   Collective

   Level: developer

.seealso: FSCaseFillLiquid()
*/
PetscErrorCode FSCaseFillLiquidWithVelocity(FSSolver s, FSWalls *w, PetscReal x0, PetscReal x1, PetscReal y0,
                                            PetscReal ysurf, const char what[], FSCaseVelocityFn velocity, void *ctx)
{
  PetscFunctionBegin;
  PetscCall(LatticeSizeCheck(s, w, x0, x1, y0, ysurf, what));
  PetscCall(PolygonDomain(s, w));
  PetscCall(PolygonLattice(s, w, x0, x1, y0, ysurf, what, velocity, ctx));
  PetscCall(PolygonGive(s, w));
  PetscFunctionReturn(0);
}

/* FSSegmentClip - the part [t0, t1] of the segment p + t (q - p), 0 <= t <= 1, inside the box lo..hi (dim
   coordinates) grown by grow on every side (negative: shrunk); false where none is (Liang-Barsky clipping). A
   segment parallel to a face counts as inside when it lies strictly between the grown faces. */
PetscBool FSSegmentClip(const PetscReal p[], const PetscReal q[], const PetscReal lo[], const PetscReal hi[],
                        PetscInt dim, PetscReal grow, PetscReal *t0, PetscReal *t1)
{
  *t0 = 0;
  *t1 = 1;
  for (PetscInt d = 0; d < dim; d++) {
    const PetscReal dd = q[d] - p[d], a = lo[d] - grow, b = hi[d] + grow;
    if (dd == 0) {
      if (p[d] <= a || p[d] >= b) return PETSC_FALSE;
    } else {
      PetscReal ta = (a - p[d]) / dd, tb = (b - p[d]) / dd;
      if (ta > tb) {
        const PetscReal tt = ta;
        ta                 = tb;
        tb                 = tt;
      }
      *t0 = PetscMax(*t0, ta);
      *t1 = PetscMin(*t1, tb);
      if (*t0 >= *t1) return PETSC_FALSE;
    }
  }
  return PETSC_TRUE;
}

/* FSSegmentEntersBox - does the segment p-q enter the open box lo..hi (dim coordinates) shrunk by eps? */
PetscBool FSSegmentEntersBox(const PetscReal p[], const PetscReal q[], const PetscReal lo[], const PetscReal hi[],
                             PetscInt dim, PetscReal eps)
{
  PetscReal t0, t1;
  return FSSegmentClip(p, q, lo, hi, dim, -eps, &t0, &t1);
}

/*
   FSCaseFillLiquidBoxes - gives the solver its walls w (2-D, checked with FSWallsCheck) and fills each of
   the nbox boxes (x0, x1, y0, y1 each, -fs_liquid_box) with liquid at rest, hydrostatic below its own
   top y1, on its own lattice as FSCaseFillLiquid. A box must lie in the liquid region: not outside the
   walls' bounding box, not crossed by a wall (it may touch one), its middle inside the liquid; and boxes
   must not overlap. Each failure is an error naming the option and the box. The walls are moved into the
   solver.

   Collective

   Level: developer
*/
PetscErrorCode FSCaseFillLiquidBoxes(FSSolver s, FSWalls *w, PetscInt nbox, const PetscReal box[], const char what[])
{
  MPI_Comm  comm = PetscObjectComm((PetscObject)s);
  PetscReal size = (w->hi[0] - w->lo[0]) + (w->hi[1] - w->lo[1]), eps = 1e-9 * size;

  PetscFunctionBegin;
  for (PetscInt k = 0; k < nbox; k++) {
    const PetscReal *b = &box[4 * k], lo[2] = {b[0], b[2]}, hi[2] = {b[1], b[3]},
                    mid[2] = {0.5 * (b[0] + b[1]), 0.5 * (b[2] + b[3])};
    PetscCheck(b[1] > b[0] && b[3] > b[2], comm, PETSC_ERR_ARG_OUTOFRANGE,
               "%s: box %" PetscInt_FMT " (%g,%g,%g,%g) is empty: expected xmin < xmax and ymin < ymax", what, k,
               (double)b[0], (double)b[1], (double)b[2], (double)b[3]);
    PetscCheck(b[0] >= w->lo[0] - eps && b[1] <= w->hi[0] + eps && b[2] >= w->lo[1] - eps && b[3] <= w->hi[1] + eps,
               comm, PETSC_ERR_ARG_OUTOFRANGE,
               "%s: box %" PetscInt_FMT " (%g,%g,%g,%g) reaches outside the tank [%g, %g] x [%g, %g]", what, k,
               (double)b[0], (double)b[1], (double)b[2], (double)b[3], (double)w->lo[0], (double)w->hi[0],
               (double)w->lo[1], (double)w->hi[1]);
    PetscCheck(FSWallsInLiquid(w, mid, 0), comm, PETSC_ERR_ARG_OUTOFRANGE,
               "%s: box %" PetscInt_FMT
               " (%g,%g,%g,%g) is not in the liquid region of the tank (its middle is inside a "
               "wall or outside the container)",
               what, k, (double)b[0], (double)b[1], (double)b[2], (double)b[3]);
    for (PetscInt q = 0; q < w->npoly; q++)
      for (PetscInt e = w->pstart[q]; e < w->pstart[q + 1]; e++) {
        const PetscInt f = e + 1 < w->pstart[q + 1] ? e + 1 : w->pstart[q];
        PetscCheck(
            !FSSegmentEntersBox(&w->vert[2 * e], &w->vert[2 * f], lo, hi, 2, eps), comm, PETSC_ERR_ARG_OUTOFRANGE,
            "%s: box %" PetscInt_FMT " (%g,%g,%g,%g) overlaps wall \"%s\" (its edge (%g, %g)-(%g, %g) crosses the "
            "box)",
            what, k, (double)b[0], (double)b[1], (double)b[2], (double)b[3], w->name[w->vwall[e]],
            (double)w->vert[2 * e], (double)w->vert[2 * e + 1], (double)w->vert[2 * f], (double)w->vert[2 * f + 1]);
      }
    for (PetscInt j = 0; j < k; j++) {
      const PetscReal *c = &box[4 * j];
      PetscCheck(b[1] <= c[0] + eps || c[1] <= b[0] + eps || b[3] <= c[2] + eps || c[3] <= b[2] + eps, comm,
                 PETSC_ERR_ARG_OUTOFRANGE, "%s: boxes %" PetscInt_FMT " and %" PetscInt_FMT " overlap", what, j, k);
    }
  }
  for (PetscInt k = 0; k < nbox; k++)
    PetscCall(LatticeSizeCheck(s, w, box[4 * k], box[4 * k + 1], box[4 * k + 2], box[4 * k + 3], what));
  PetscCall(PolygonDomain(s, w));
  for (PetscInt k = 0; k < nbox; k++)
    PetscCall(PolygonLattice(s, w, box[4 * k], box[4 * k + 1], box[4 * k + 2], box[4 * k + 3], what, NULL, NULL));
  PetscCall(PolygonGive(s, w));
  PetscFunctionReturn(0);
}
