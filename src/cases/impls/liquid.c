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

/* the crossings of the line {y = yr, z = zr} with the mesh's triangles, sorted along x. The line is moved
   by a tiny irrational offset first so that it never passes exactly through an edge or a vertex (the
   lattice's rows would, through the diagonals of a box's faces). */
static PetscErrorCode RowCrossings(const FSMesh *m, PetscReal yr, PetscReal zr, PetscReal *cross, PetscInt *nc)
{
  const PetscReal size = (m->hi[0] - m->lo[0]) + (m->hi[1] - m->lo[1]) + (m->hi[2] - m->lo[2]);
  const PetscReal y = yr + 3.1830988618e-10 * size, z = zr + 2.7182818284e-10 * size;

  PetscFunctionBegin;
  *nc = 0;
  for (PetscInt t = 0; t < m->ntri; t++) {
    const PetscReal *a = &m->vert[3 * m->tri[3 * t]], *b = &m->vert[3 * m->tri[3 * t + 1]],
                    *c = &m->vert[3 * m->tri[3 * t + 2]];
    /* the barycentric coordinates of (y, z) in the triangle's projection on the y-z plane */
    const PetscReal det = (b[1] - a[1]) * (c[2] - a[2]) - (c[1] - a[1]) * (b[2] - a[2]);
    PetscReal       u, v;
    if (det == 0) continue; /* parallel to the line */
    u = ((y - a[1]) * (c[2] - a[2]) - (c[1] - a[1]) * (z - a[2])) / det;
    v = ((b[1] - a[1]) * (z - a[2]) - (y - a[1]) * (b[2] - a[2])) / det;
    if (u < 0 || v < 0 || u + v > 1) continue;
    cross[(*nc)++] = a[0] + u * (b[0] - a[0]) + v * (c[0] - a[0]);
  }
  PetscCall(PetscSortReal(*nc, cross));
  PetscFunctionReturn(0);
}

/*
   FSCaseFillLiquidMesh - the 3-D FSCaseFillLiquid: gives the solver the triangle-mesh walls m (checked
   with FSMeshCheck) and a domain box around them (4h margin), and fills the liquid region of the mesh
   inside the box lo..hi (x, y, z; hi[1] the free surface) with particles at rest, hydrostatic, on a
   lattice that fits the region: rows along x at heights lo[1] + (j + 1/2) dx_y and depths
   lo[2] + (k + 1/2) dx_z, dx_y and dx_z the spacings closest to dx that divide the box, and along
   each row, each interval of liquid between walls with its own spacing dx_x closest to dx (the liquid
   ends half a spacing from the walls). Points closer to a wall than half a spacing are left out.
   The rows are split over the ranks, so ids do not depend on the number of ranks. The mesh is moved
   into the solver; what names the liquid region in the error messages.

   Collective

   Level: developer

.seealso: FSCaseFillLiquidMeshWithVelocity(), FSCaseFillLiquid()
*/
PetscErrorCode FSCaseFillLiquidMesh(FSSolver s, FSMesh *m, const PetscReal lo[3], const PetscReal hi[3],
                                    const char what[])
{
  PetscFunctionBegin;
  PetscCall(FSCaseFillLiquidMeshWithVelocity(s, m, lo, hi, what, NULL, NULL));
  PetscFunctionReturn(0);
}

/*
   FSCaseFillLiquidMeshWithVelocity - FSCaseFillLiquidMesh, with the particles' initial velocity given
   by velocity(x, u, ctx) at each particle's position x (3 components; NULL: at rest). The density stays
   hydrostatic.

   Collective

   Level: developer
*/
PetscErrorCode FSCaseFillLiquidMeshWithVelocity(FSSolver s, FSMesh *m, const PetscReal lo[3], const PetscReal hi[3],
                                                const char what[], FSCaseVelocityFn velocity, void *ctx)
{
  MPI_Comm    comm = PetscObjectComm((PetscObject)s);
  PetscReal   dlo[3], dhi[3], *x, *u, *rho, *mass, g[3], gmag, dx, h, rho0, c0, hy, hz, *cross;
  PetscBool   per[3] = {PETSC_FALSE, PETSC_FALSE, PETSC_FALSE};
  PetscInt    ny, nz, n = 0, r0, r1, cap, nxmax;
  PetscMPIInt rank, size;

  PetscFunctionBegin;
  PetscCall(FSMeshCheck(m, comm));
  PetscCall(FSSolverGetGravity(s, g));
  PetscCall(FSSolverGetParameters(s, &dx, &h, &rho0, &c0, NULL));
  gmag  = PetscSqrtReal(g[0] * g[0] + g[1] * g[1] + g[2] * g[2]);
  ny    = (PetscInt)((hi[1] - lo[1]) / dx + 0.5);
  nz    = (PetscInt)((hi[2] - lo[2]) / dx + 0.5);
  nxmax = (PetscInt)((hi[0] - lo[0]) / dx + 0.5) + 1;
  PetscCheck(nxmax >= 2 && ny >= 1 && nz >= 1, comm, PETSC_ERR_ARG_OUTOFRANGE,
             "%s: -fs_dx %g leaves no particle in the liquid region %g x %g x %g", what, (double)dx,
             (double)(hi[0] - lo[0]), (double)(hi[1] - lo[1]), (double)(hi[2] - lo[2]));
  PetscCheck(lo[0] >= m->lo[0] && hi[0] <= m->hi[0] && lo[1] >= m->lo[1] && hi[1] <= m->hi[1] && lo[2] >= m->lo[2] &&
                 hi[2] <= m->hi[2],
             comm, PETSC_ERR_ARG_OUTOFRANGE,
             "%s: the liquid region [%g, %g] x [%g, %g] x [%g, %g] reaches outside the tank [%g, %g] x [%g, %g] x [%g, "
             "%g]",
             what, (double)lo[0], (double)hi[0], (double)lo[1], (double)hi[1], (double)lo[2], (double)hi[2],
             (double)m->lo[0], (double)m->hi[0], (double)m->lo[1], (double)m->hi[1], (double)m->lo[2],
             (double)m->hi[2]);
  hy = (hi[1] - lo[1]) / ny;
  hz = (hi[2] - lo[2]) / nz;
  for (PetscInt d = 0; d < 3; d++) {
    dlo[d] = m->lo[d] - 4 * h;
    dhi[d] = m->hi[d] + 4 * h;
  }
  PetscCall(FSSolverSetDomain(s, dlo, dhi, per));
  PetscCallMPI(MPI_Comm_rank(comm, &rank));
  PetscCallMPI(MPI_Comm_size(comm, &size));
  r0  = (PetscInt)((PetscInt64)ny * nz * rank / size);
  r1  = (PetscInt)((PetscInt64)ny * nz * (rank + 1) / size);
  cap = (r1 - r0) * (nxmax + m->ntri) + 1;
  PetscCall(PetscMalloc5(3 * cap, &x, 3 * cap, &u, cap, &rho, cap, &mass, m->ntri + 2, &cross));
  for (PetscInt row = r0; row < r1; row++) {
    const PetscReal yr = lo[1] + (row % ny + 0.5) * hy, zr = lo[2] + (row / ny + 0.5) * hz;
    PetscInt        nc;
    PetscCall(RowCrossings(m, yr, zr, cross, &nc));
    for (PetscInt c = 0; c + 1 < nc; c++) {
      const PetscReal a = PetscMax(cross[c], lo[0]), e = PetscMin(cross[c + 1], hi[0]),
                      mid[3] = {0.5 * (cross[c] + cross[c + 1]), yr, zr};
      PetscInt  na;
      PetscReal hx;
      if (e <= a || !FSMeshInLiquid(m, mid, 0)) continue; /* outside the box, or inside a wall */
      na = (PetscInt)((e - a) / dx + 0.5);
      if (na < 1) continue;
      hx = (e - a) / na;
      for (PetscInt i = 0; i < na; i++) {
        const PetscReal p[3] = {a + (i + 0.5) * hx, yr, zr};
        if (!FSMeshInLiquid(m, p, 0.499 * PetscMin(hx, PetscMin(hy, hz)))) continue;
        for (PetscInt d = 0; d < 3; d++) {
          x[3 * n + d] = p[d];
          u[3 * n + d] = 0;
        }
        if (velocity) PetscCall((*velocity)(p, &u[3 * n], ctx));
        rho[n]  = rho0 + rho0 * gmag * (hi[1] - p[1]) / (c0 * c0);
        mass[n] = rho[n] * hx * hy * hz;
        n++;
      }
    }
  }
  {
    FSBoundary b;
    PetscCall(FSSolverGetBoundary(s, &b));
    PetscCall(FSBoundarySetType(b, FSBOUNDARYTRIMESH));
    PetscCall(FSBoundaryTrimeshSetMesh(b, m));
  }
  PetscCall(FSSolverAddParticles(s, n, x, u, rho, mass));
  PetscCall(PetscFree5(x, u, rho, mass, cross));
  PetscFunctionReturn(0);
}

/*
   FSCaseFillLiquidExtruded - the built-in 3-D tanks: the 2-D outline w (checked, made of horizontal and
   vertical edges) extruded across width along z (FSMeshExtrude), filled with liquid over the whole width
   in the box x0..x1, y0..ysurf (FSCaseFillLiquidMeshWithVelocity). w is destroyed.

   Collective

   Level: developer
*/
PetscErrorCode FSCaseFillLiquidExtruded(FSSolver s, FSWalls *w, PetscReal width, PetscReal x0, PetscReal x1,
                                        PetscReal y0, PetscReal ysurf, const char what[], FSCaseVelocityFn velocity,
                                        void *ctx)
{
  MPI_Comm  comm = PetscObjectComm((PetscObject)s);
  FSMesh    m;
  PetscReal lo[3] = {x0, y0, 0}, hi[3] = {x1, ysurf, width};

  PetscFunctionBegin;
  PetscCall(FSMeshCreate(&m));
  PetscCall(FSMeshExtrude(&m, comm, w, width));
  PetscCall(FSWallsDestroy(w));
  PetscCall(FSCaseFillLiquidMeshWithVelocity(s, &m, lo, hi, what, velocity, ctx));
  PetscCall(FSMeshDestroy(&m));
  PetscFunctionReturn(0);
}
