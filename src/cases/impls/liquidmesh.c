/* Set-up shared by the 3-D cases with walls: a body of liquid on a lattice in a triangle-mesh tank, hydrostatic,
 * at rest or with a given velocity field. */
#include <strings.h>
#include <flexslosh.h>
#include "boundary/fsboundary.h"
#include "liquid.h"
#include "packing.h"
#include "sys/fssys.h"

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
   ends half a spacing from the walls). Points closer to a wall than half a spacing are left out. The masses
   rho dx_x dx_y dx_z are scaled to the liquid's exact volume where the lattice does not fit it
   (FSCaseFitLiquidMass()).
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

/* the mesh into the solver's boundary (which takes it over) */
static PetscErrorCode MeshGive(FSSolver s, FSMesh *m)
{
  FSBoundary b;

  PetscFunctionBegin;
  PetscCall(FSSolverGetBoundary(s, &b));
  PetscCall(FSBoundarySetType(b, FSBOUNDARYTRIMESH));
  PetscCall(FSBoundaryTrimeshSetMesh(b, m));
  PetscFunctionReturn(0);
}

/* the particles of the liquid of m in lo..hi checked before anything is allocated (FSCheckParticleCount): their
   count from the liquid's exact volume vol over dx^3 (a tank much smaller than its bounding box is not refused for
   its box), with the advice on the unit of an STL file (-fs_tank_stl_scale) where the walls come from one */
static PetscErrorCode MeshSizeCheck(FSSolver s, const FSMesh *m, const PetscReal lo[3], const PetscReal hi[3],
                                    PetscReal vol, const char what[])
{
  const PetscReal len[3] = {hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2]};
  PetscReal       dx;
  char            region[256 + PETSC_MAX_PATH_LEN];
  const char     *src = m->nwalls ? m->source[0] : "none", *ext = strrchr(src, '.');
  const PetscBool stl = (PetscBool)(ext && !strcasecmp(ext, ".stl"));

  PetscFunctionBegin;
  PetscCall(FSSolverGetParameters(s, &dx, NULL, NULL, NULL, NULL));
  PetscCall(PetscSNPrintf(region, sizeof(region), "%s: the liquid region %g x %g x %g, %.4g m^3 of liquid (walls: %s)",
                          what, (double)len[0], (double)len[1], (double)len[2], (double)vol, src));
  PetscCall(FSCheckParticleCount(PetscObjectComm((PetscObject)s), 3, dx, (double)vol / ((double)dx * dx * dx), region,
                                 stl ? "check the STL file's unit: its coordinates are read in metres "
                                       "(-fs_tank_stl_scale mm for a file in millimetres)"
                                     : NULL));
  PetscFunctionReturn(0);
}

/* the exact volume of the liquid of m in the box lo..hi and the integral over it of the hydrostatic density
   rho0 (1 + |g| (hi[1] - y) / c0^2), the mass it should have (FSMeshLiquidBelow at hi[1] less that at lo[1]) */
static void MeshExactMass(const FSMesh *m, const PetscReal lo[3], const PetscReal hi[3], PetscReal rho0,
                          PetscReal g_c02, PetscReal *vol, PetscReal *mass)
{
  PetscReal v1, q1, v0, q0;

  FSMeshLiquidBelow(m, lo, hi, hi[1], &v1, &q1);
  FSMeshLiquidBelow(m, lo, hi, lo[1], &v0, &q0);
  *vol  = v1 - v0;
  *mass = rho0 * (*vol + g_c02 * (q1 - q0 - (hi[1] - lo[1]) * v0));
}

typedef struct {
  const FSMesh *m;
  PetscReal     lo[3], hi[3], rho0, g_c02;
} MeshLevel;

static void MeshLevelAt(const void *ctx, PetscReal t, PetscReal *vol, PetscReal *mass)
{
  const MeshLevel *p     = (const MeshLevel *)ctx;
  PetscReal        hi[3] = {p->hi[0], t, p->hi[2]};
  MeshExactMass(p->m, p->lo, hi, p->rho0, p->g_c02, vol, mass);
}

/*
   FSCaseFillLevelMesh - the level of the liquid of m in the box lo..hi (x and z extents; above lo[1], at most hi[1])
   that holds the volume target (m^3) or the hydrostatic mass target (kg).

   Collective

   Level: developer
*/
PetscErrorCode FSCaseFillLevelMesh(FSSolver s, const FSMesh *m, const PetscReal lo[3], const PetscReal hi[3],
                                   PetscBool bymass, PetscReal target, const char what[], PetscReal *level)
{
  MeshLevel p;
  PetscReal g[3], c0;

  PetscFunctionBegin;
  p.m = m;
  for (PetscInt d = 0; d < 3; d++) {
    p.lo[d] = lo[d];
    p.hi[d] = hi[d];
  }
  PetscCall(FSSolverGetGravity(s, g));
  PetscCall(FSSolverGetParameters(s, NULL, NULL, &p.rho0, &c0, NULL));
  p.g_c02 = FSCaseHeadGravity(g, 3) / (c0 * c0);
  PetscCall(FSCaseFillLevel(s, MeshLevelAt, &p, lo[1], hi[1], bymass, target, what, level));
  PetscFunctionReturn(0);
}

/* this rank's rows of the lattice in the liquid region of m inside lo..hi (hi[1] the surface), points closer to a
   wall than margin times the spacing left out: positions, hydrostatic densities and masses (allocated here) */
static PetscErrorCode MeshLatticePoints(FSSolver s, const FSMesh *m, const PetscReal lo[3], const PetscReal hi[3],
                                        PetscReal vol, const char what[], PetscReal margin, PetscInt *np,
                                        PetscReal **xp, PetscReal **rhop, PetscReal **mp)
{
  MPI_Comm    comm = PetscObjectComm((PetscObject)s);
  PetscReal  *x, *rho, *mass, g[3], gmag, dx, rho0, c0, hy, hz, *cross;
  PetscInt    ny, nz, n = 0, r0, r1, nxmax;
  PetscInt64  cap;
  PetscMPIInt rank, size;

  PetscFunctionBegin;
  PetscCall(FSSolverGetGravity(s, g));
  PetscCall(FSSolverGetParameters(s, &dx, NULL, &rho0, &c0, NULL));
  PetscCall(MeshSizeCheck(s, m, lo, hi, vol, what)); /* before the counts are converted to PetscInt */
  gmag  = FSCaseHeadGravity(g, 3);
  ny    = (PetscInt)((hi[1] - lo[1]) / dx + 0.5);
  nz    = (PetscInt)((hi[2] - lo[2]) / dx + 0.5);
  nxmax = (PetscInt)((hi[0] - lo[0]) / dx + 0.5) + 1;
  PetscCheck(nxmax >= 2 && ny >= 1 && nz >= 1, comm, PETSC_ERR_ARG_OUTOFRANGE,
             "%s: -fs_dx %g leaves no particle in the liquid region %g x %g x %g", what, (double)dx,
             (double)(hi[0] - lo[0]), (double)(hi[1] - lo[1]), (double)(hi[2] - lo[2]));
  hy = (hi[1] - lo[1]) / ny;
  hz = (hi[2] - lo[2]) / nz;
  PetscCallMPI(MPI_Comm_rank(comm, &rank));
  PetscCallMPI(MPI_Comm_size(comm, &size));
  r0 = (PetscInt)((PetscInt64)ny * nz * rank / size);
  r1 = (PetscInt)((PetscInt64)ny * nz * (rank + 1) / size);
  /* a row's intervals hold at most their length / dx + 1/2 points each, and there are fewer of them than ntri
     (the crossings) (and at most 2 nxmax: each is at least dx / 2 long) */
  cap = (PetscInt64)(r1 - r0) * (nxmax + PetscMin(m->ntri, nxmax)) + 1;
  PetscCheck(3 * cap < PETSC_MAX_INT, PETSC_COMM_SELF, PETSC_ERR_ARG_OUTOFRANGE,
             "%s: -fs_dx %g: this rank's %" PetscInt64_FMT
             " places for particles are more than an index can count: use "
             "more ranks or a coarser -fs_dx",
             what, (double)dx, cap);
  PetscCall(PetscMalloc3(3 * cap, &x, cap, &rho, cap, &mass));
  PetscCall(PetscMalloc1(m->ntri + 2, &cross));
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
        if (!FSMeshInLiquid(m, p, margin * PetscMin(hx, PetscMin(hy, hz)))) continue;
        for (PetscInt d = 0; d < 3; d++) x[3 * n + d] = p[d];
        rho[n]  = rho0 + rho0 * gmag * (hi[1] - p[1]) / (c0 * c0);
        mass[n] = rho[n] * hx * hy * hz;
        n++;
      }
    }
  }
  PetscCall(PetscFree(cross));
  *np   = n;
  *xp   = x;
  *rhop = rho;
  *mp   = mass;
  PetscFunctionReturn(0);
}

/* whether every input triangle of m faces along x, y or z (its normal's other components zero to round-off) */
static PetscBool FSMeshAlongAxes(const FSMesh *m)
{
  for (PetscInt t = 0; t < m->ntri; t++) {
    const PetscReal *a = &m->vert[3 * m->tri[3 * t]], *b = &m->vert[3 * m->tri[3 * t + 1]],
                    *c   = &m->vert[3 * m->tri[3 * t + 2]];
    const PetscReal u[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]}, v[3] = {c[0] - a[0], c[1] - a[1], c[2] - a[2]};
    const PetscReal n[3] = {PetscAbsReal(u[1] * v[2] - u[2] * v[1]), PetscAbsReal(u[2] * v[0] - u[0] * v[2]),
                            PetscAbsReal(u[0] * v[1] - u[1] * v[0])};
    const PetscReal big  = PetscMax(n[0], PetscMax(n[1], n[2]));
    if (n[0] + n[1] + n[2] - big > 1e-12 * big) return PETSC_FALSE;
  }
  return PETSC_TRUE;
}

/* this rank's particles of the liquid region of m inside lo..hi (hi[1] the surface), added to the solver: the
   lattice, or where -fs_fill_packing asks for it the lattice relaxed in the region (FSCasePackRelax); hydrostatic,
   their masses fitted to the exact volume. m's elements are refined for the relaxation (the boundary refines them
   again). */
static PetscErrorCode MeshLattice(FSSolver s, FSMesh *m, const PetscReal lo[3], const PetscReal hi[3],
                                  const char what[], FSCaseVelocityFn velocity, void *ctx)
{
  PetscReal    *x, *u, *rho, *mass, g[3], gmag, rho0, c0, vol, exact;
  PetscInt      n;
  FSFillPacking pk;
  PetscBool     relax;

  PetscFunctionBegin;
  PetscCall(FSSolverGetGravity(s, g));
  PetscCall(FSSolverGetParameters(s, NULL, NULL, &rho0, &c0, NULL));
  PetscCall(FSSolverGetFillPacking(s, &pk));
  gmag = FSCaseHeadGravity(g, 3);
  MeshExactMass(m, lo, hi, rho0, gmag / (c0 * c0), &vol, &exact);
  PetscCall(MeshLatticePoints(s, m, lo, hi, vol, what, 0.499, &n, &x, &rho, &mass));
  PetscCall(FSCaseLatticeFits(s, pk.type, FSMeshAlongAxes(m), exact, n, mass, &relax));
  if (relax) { /* from the lattice of every point inside, relaxed */
    FSPackRegion region;
    PetscReal    dx, h;
    PetscCall(PetscFree3(x, rho, mass));
    PetscCall(FSSolverGetParameters(s, &dx, &h, NULL, NULL, NULL));
    PetscCall(MeshLatticePoints(s, m, lo, hi, vol, what, 0, &n, &x, &rho, &mass));
    PetscCall(FSPackRegionFromMesh(&region, m, lo, hi, dx, h));
    PetscCall(FSCasePackRelax(s, &region, vol, &n, x, what));
    PetscCall(FSPackRegionDestroy(&region));
    PetscCall(FSCaseRelaxedDensities(s, 3, hi[1], vol, n, x, rho, mass));
  }
  PetscCall(PetscCalloc1(3 * n, &u));
  if (velocity)
    for (PetscInt i = 0; i < n; i++) PetscCall((*velocity)(&x[3 * i], &u[3 * i], ctx));
  PetscCall(FSCaseFitLiquidMass(s, vol, exact, n, mass));
  PetscCall(FSSolverAddParticles(s, n, x, u, rho, mass));
  PetscCall(PetscFree3(x, rho, mass));
  PetscCall(PetscFree(u));
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
  MPI_Comm comm = PetscObjectComm((PetscObject)s);

  PetscFunctionBegin;
  PetscCall(FSMeshCheck(m, comm));
  PetscCheck(lo[0] >= m->lo[0] && hi[0] <= m->hi[0] && lo[1] >= m->lo[1] && hi[1] <= m->hi[1] && lo[2] >= m->lo[2] &&
                 hi[2] <= m->hi[2],
             comm, PETSC_ERR_ARG_OUTOFRANGE,
             "%s: the liquid region [%g, %g] x [%g, %g] x [%g, %g] reaches outside the tank [%g, %g] x [%g, %g] x [%g, "
             "%g]",
             what, (double)lo[0], (double)hi[0], (double)lo[1], (double)hi[1], (double)lo[2], (double)hi[2],
             (double)m->lo[0], (double)m->hi[0], (double)m->lo[1], (double)m->hi[1], (double)m->lo[2],
             (double)m->hi[2]);
  PetscCall(FSCaseSetDomainAround(s, 3, m->lo, m->hi));
  PetscCall(MeshLattice(s, m, lo, hi, what, velocity, ctx));
  PetscCall(MeshGive(s, m));
  PetscFunctionReturn(0);
}

/*
   FSCaseFillLiquidMeshBoxes - the 3-D FSCaseFillLiquidBoxes: gives the solver the triangle-mesh walls m
   (checked with FSMeshCheck) and fills each of the nbox boxes (x0, x1, y0, y1, z0, z1 each,
   -fs_liquid_box) with liquid at rest, hydrostatic below its own top y1. A box must lie in the liquid
   region: inside the mesh's bounding box, not cut by a triangle (it may touch one), its middle in the
   liquid; and boxes must not overlap: each failure an error naming the option, the box (and the
   triangle).

   Collective

   Level: developer
*/
PetscErrorCode FSCaseFillLiquidMeshBoxes(FSSolver s, FSMesh *m, PetscInt nbox, const PetscReal box[], const char what[])
{
  MPI_Comm  comm = PetscObjectComm((PetscObject)s);
  PetscReal eps;

  PetscFunctionBegin;
  PetscCall(FSMeshCheck(m, comm));
  eps = 1e-9 * ((m->hi[0] - m->lo[0]) + (m->hi[1] - m->lo[1]) + (m->hi[2] - m->lo[2]));
  for (PetscInt k = 0; k < nbox; k++) {
    const PetscReal *b = &box[6 * k], lo[3] = {b[0], b[2], b[4]}, hi[3] = {b[1], b[3], b[5]};
    const PetscReal  mid[3] = {0.5 * (b[0] + b[1]), 0.5 * (b[2] + b[3]), 0.5 * (b[4] + b[5])};
    PetscCheck(b[1] > b[0] && b[3] > b[2] && b[5] > b[4], comm, PETSC_ERR_ARG_OUTOFRANGE,
               "%s: box %" PetscInt_FMT " (%g,%g,%g,%g,%g,%g) is empty: expected xmin < xmax, ymin < ymax, zmin < zmax",
               what, k, (double)b[0], (double)b[1], (double)b[2], (double)b[3], (double)b[4], (double)b[5]);
    for (PetscInt d = 0; d < 3; d++)
      PetscCheck(
          lo[d] >= m->lo[d] - eps && hi[d] <= m->hi[d] + eps, comm, PETSC_ERR_ARG_OUTOFRANGE,
          "%s: box %" PetscInt_FMT " (%g,%g,%g,%g,%g,%g) reaches outside the tank [%g, %g] x [%g, %g] x [%g, %g]", what,
          k, (double)b[0], (double)b[1], (double)b[2], (double)b[3], (double)b[4], (double)b[5], (double)m->lo[0],
          (double)m->hi[0], (double)m->lo[1], (double)m->hi[1], (double)m->lo[2], (double)m->hi[2]);
    PetscCheck(FSMeshInLiquid(m, mid, 0), comm, PETSC_ERR_ARG_OUTOFRANGE,
               "%s: box %" PetscInt_FMT " (%g,%g,%g,%g,%g,%g) is not in the liquid region of the tank (its middle is "
               "inside a wall)",
               what, k, (double)b[0], (double)b[1], (double)b[2], (double)b[3], (double)b[4], (double)b[5]);
    for (PetscInt t = 0; t < m->ntri; t++) {
      const PetscReal *v[3] = {&m->vert[3 * m->tri[3 * t]], &m->vert[3 * m->tri[3 * t + 1]],
                               &m->vert[3 * m->tri[3 * t + 2]]};
      PetscBool        cut  = PETSC_FALSE;
      /* a triangle enters the open box if one of its edges does, or if it cuts one of the box's edges */
      for (PetscInt e = 0; e < 3 && !cut; e++) cut = FSSegmentEntersBox(v[e], v[(e + 1) % 3], lo, hi, 3, eps);
      for (PetscInt e = 0; e < 12 && !cut; e++) {
        /* the box's 12 edges, shrunk by eps: along axis a = e / 4, at the corner given by the bits of e % 4 */
        const PetscInt a = e / 4, c1 = (a + 1) % 3, c2 = (a + 2) % 3;
        PetscReal      p[3], q[3];
        p[c1] = q[c1] = (e & 1) ? hi[c1] - eps : lo[c1] + eps;
        p[c2] = q[c2] = (e & 2) ? hi[c2] - eps : lo[c2] + eps;
        p[a]          = lo[a] + eps;
        q[a]          = hi[a] - eps;
        cut           = FSTriangleCrossesSegment(v[0], v[1], v[2], p, q);
      }
      PetscCheck(!cut, comm, PETSC_ERR_ARG_OUTOFRANGE,
                 "%s: box %" PetscInt_FMT " (%g,%g,%g,%g,%g,%g) overlaps wall \"%s\": its triangle %" PetscInt_FMT
                 " (of %s) cuts the box",
                 what, k, (double)b[0], (double)b[1], (double)b[2], (double)b[3], (double)b[4], (double)b[5],
                 m->name[m->triwall[t]], m->trisrc[t], m->source[m->triwall[t]]);
    }
    for (PetscInt j = 0; j < k; j++) {
      const PetscReal *c     = &box[6 * j];
      PetscBool        apart = PETSC_FALSE;
      for (PetscInt d = 0; d < 3; d++)
        apart = (PetscBool)(apart || b[2 * d + 1] <= c[2 * d] + eps || c[2 * d + 1] <= b[2 * d] + eps);
      PetscCheck(apart, comm, PETSC_ERR_ARG_OUTOFRANGE, "%s: boxes %" PetscInt_FMT " and %" PetscInt_FMT " overlap",
                 what, j, k);
    }
  }
  PetscCall(FSCaseSetDomainAround(s, 3, m->lo, m->hi));
  for (PetscInt k = 0; k < nbox; k++) {
    const PetscReal lo[3] = {box[6 * k], box[6 * k + 2], box[6 * k + 4]},
                    hi[3] = {box[6 * k + 1], box[6 * k + 3], box[6 * k + 5]};
    PetscCall(MeshLattice(s, m, lo, hi, what, NULL, NULL));
  }
  PetscCall(MeshGive(s, m));
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
