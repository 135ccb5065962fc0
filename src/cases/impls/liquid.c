/* Set-up shared by the cases with walls: a body of liquid on a lattice, hydrostatic, at rest or with a given velocity
 * field. */
#include <flexslosh.h>
#include "boundary/fsboundary.h"
#include "liquid.h"

/*
   FSCaseFillLiquid - gives the solver its walls (checked with FSWallsCheck) and a domain box around them (4h margin),
and fills the liquid region of the walls inside [x0, x1] x [y0, ysurf] with particles in rows y0 + (j + 1/2) dx_y, at
rest with the hydrostatic density rho = rho0 + rho0 |g| (ysurf - y) / c0^2 and mass rho dx_x dx_y. dx_y is the spacing
closest to dx that divides the depth, so the surface is at ysurf. Each row is cut by the walls into intervals of liquid
(between baffles, say), and each interval gets the spacing dx_x closest to dx that divides it: the liquid ends half a
spacing from the walls on both sides of every compartment (a lattice that left a gap at one wall would start the liquid
sloshing). Points closer to a wall than half a spacing (the underside of a baffle, other shapes) are left out. The rows
of the lattice are split over the ranks, so ids do not depend on the number of ranks. The walls are moved into the
solver. what names the liquid region in the error messages.

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
   FSCaseFillLiquidWithVelocity - FSCaseFillLiquid, with the particles' initial velocity given by
   velocity(x, u, ctx) at each particle's position x (NULL: at rest). The density stays hydrostatic.

   Collective

   Level: developer

.seealso: FSCaseFillLiquid()
*/
PetscErrorCode FSCaseFillLiquidWithVelocity(FSSolver s, FSWalls *w, PetscReal x0, PetscReal x1, PetscReal y0,
                                            PetscReal ysurf, const char what[], FSCaseVelocityFn velocity, void *ctx)
{
  MPI_Comm    comm = PetscObjectComm((PetscObject)s);
  PetscReal   lo[3], hi[3], *x, *u, *rho, *m, g[3], gmag, dx, h, rho0, c0;
  PetscBool   per[3] = {PETSC_FALSE, PETSC_FALSE, PETSC_FALSE};
  PetscInt    nx, ny, n = 0, r0, r1, cap;
  PetscReal   hy, *cross;
  PetscMPIInt rank, size;

  PetscFunctionBegin;
  PetscCall(FSSolverGetGravity(s, g));
  PetscCall(FSSolverGetParameters(s, &dx, &h, &rho0, &c0, NULL));
  gmag = PetscSqrtReal(g[0] * g[0] + g[1] * g[1]);
  nx   = (PetscInt)((x1 - x0) / dx + 0.5);
  ny   = (PetscInt)((ysurf - y0) / dx + 0.5);
  PetscCallMPI(MPI_Comm_rank(comm, &rank));
  PetscCallMPI(MPI_Comm_size(comm, &size));
  PetscCheck(nx >= 1 && ny >= 1, comm, PETSC_ERR_ARG_OUTOFRANGE,
             "%s: -fs_dx %g leaves no particle in the liquid region %g x %g", what, (double)dx, (double)(x1 - x0),
             (double)(ysurf - y0));
  hy = (ysurf - y0) / ny;
  PetscCall(FSWallsDiscretize(w, dx)); /* for the distance of the particles to the walls */
  for (PetscInt d = 0; d < 2; d++) {
    lo[d] = w->lo[d] - 4 * h;
    hi[d] = w->hi[d] + 4 * h;
  }
  PetscCall(FSSolverSetDomain(s, lo, hi, per));
  r0  = ny * rank / size;
  r1  = ny * (rank + 1) / size;
  cap = (r1 - r0) * (nx + w->nvert + 1) + 1; /* each interval holds at most its length / dx + 1/2 points */
  PetscCall(PetscMalloc5(2 * cap, &x, 2 * cap, &u, cap, &rho, cap, &m, w->nvert + 2, &cross));
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
        if (!FSWallsInLiquid(w, p, 0.499 * PetscMin(hx, hy))) continue;
        x[2 * n]     = p[0];
        x[2 * n + 1] = p[1];
        u[2 * n]     = 0;
        u[2 * n + 1] = 0;
        if (velocity) PetscCall((*velocity)(p, &u[2 * n], ctx));
        rho[n] = rho0 + rho0 * gmag * (ysurf - p[1]) / (c0 * c0);
        m[n]   = rho[n] * hx * hy;
        n++;
      }
    }
  }
  {
    FSBoundary b;
    PetscCall(FSSolverGetBoundary(s, &b));
    PetscCall(FSBoundarySetType(b, FSBOUNDARYPOLYGON));
    PetscCall(FSBoundaryPolygonSetWalls(b, w));
  }
  PetscCall(FSSolverAddParticles(s, n, x, u, rho, m));
  PetscCall(PetscFree5(x, u, rho, m, cross));
  PetscFunctionReturn(0);
}
