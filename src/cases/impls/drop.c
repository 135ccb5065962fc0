/*
   Case "drop": a free body of liquid without walls or gravity, for the surface tension term (docs/surface-tension.md).
   The liquid starts at rest on a lattice of spacing dx, centred at the origin, as
     an ellipse (ellipsoid in 3-D) of semi-axes R a^(1/2) along x and R a^(-1/2) along y (and R along z in 3-D:
       the volume of the circle or sphere of radius R for any a = -fs_drop_aspect), or
     a square (cube) of the same area (volume) as the circle (sphere) of radius R, with -fs_drop_square.
   Surface tension relaxes the square towards a circle of radius R, with the Laplace pressure sigma/R (2-D) or
   2 sigma/R (3-D) inside; the ellipse oscillates in the mode n = 2 (Rayleigh; Lamb, Hydrodynamics, art. 275).
   Columns of the time series: drop_extent_x and drop_extent_y, the extent of the particles along x and y, and
   drop_pressure, the mean of c0^2 (rho - rho0) over the particles within R/2 of the liquid's centre of mass.
   With -fs_drop_slab the liquid is instead a flat layer 2R thick along y, periodic along x (and z): no curvature,
   so its drop_pressure is what the pressure inside reads without a Laplace jump (docs/surface-tension.md).
   Options: -fs_drop_radius (R = 1), -fs_drop_aspect (1), -fs_drop_square, -fs_drop_slab. Defaults: dx = R/20, rho0 = 1,
   c0 = 20, nu = 0.01, no gravity, final time 1, terms continuity,delta,pressure,viscosity,surface_tension with
   -fs_surface_tension_sigma to be given.
*/
#include <flexslosh.h>

typedef struct {
  PetscReal R, aspect;
  PetscBool square, slab;
} Drop;

static PetscErrorCode SetFromOptions(FSSolver s, PetscOptionItems *PetscOptionsObject)
{
  Drop     *dr;
  PetscReal g[3] = {0, 0, 0};

  PetscFunctionBegin;
  PetscCall(FSSolverGetCaseData(s, &dr));
  PetscOptionsHeadBegin(PetscOptionsObject, "Case drop");
  PetscCall(FSOptionsReal(PetscOptionsObject, "-fs_drop_radius", "radius R of the circle (sphere) of the same area", "",
                          &dr->R, NULL, 0, PETSC_INFINITY, FS_RANGE_OPEN_LOWER));
  PetscCall(FSOptionsReal(PetscOptionsObject, "-fs_drop_aspect",
                          "ratio a of the ellipse's semi-axes along x and y (1: a circle)", "", &dr->aspect, NULL, 0.1,
                          10, FS_RANGE_CLOSED));
  PetscCall(PetscOptionsBool("-fs_drop_square", "a square (cube) of the circle's (sphere's) area instead of an ellipse",
                             "", dr->square, &dr->square, NULL));
  PetscCall(PetscOptionsBool("-fs_drop_slab",
                             "a flat layer 2R thick along y instead, periodic along x (and z): the reference "
                             "without curvature",
                             "", dr->slab, &dr->slab, NULL));
  PetscOptionsHeadEnd();
  PetscCall(FSSolverSetDefaultPhysics(s, 1.0, 20.0, 0.01, g));
  PetscCall(FSSolverSetDefaultSpacing(s, dr->R / 20));
  PetscCall(FSSolverSetDefaultFinalTime(s, 1.0));
  PetscCall(FSSolverSetDefaultTerms(s, "continuity,delta,pressure,viscosity,surface_tension"));
  PetscFunctionReturn(0);
}

/* inside the drop's starting shape */
static PetscBool Inside(const Drop *dr, PetscInt dim, const PetscReal x[])
{
  if (dr->slab) return (PetscBool)(PetscAbsReal(x[1]) <= dr->R);
  if (dr->square) {
    const PetscReal half = 0.5 * dr->R * (dim == 2 ? PetscSqrtReal(PETSC_PI) : PetscCbrtReal(4 * PETSC_PI / 3));
    for (PetscInt d = 0; d < dim; d++)
      if (PetscAbsReal(x[d]) > half) return PETSC_FALSE;
    return PETSC_TRUE;
  } else {
    const PetscReal a = dr->R * PetscSqrtReal(dr->aspect), b = dr->R / PetscSqrtReal(dr->aspect);
    PetscReal       q = (x[0] / a) * (x[0] / a) + (x[1] / b) * (x[1] / b);
    if (dim == 3) q += (x[2] / dr->R) * (x[2] / dr->R);
    return (PetscBool)(q <= 1);
  }
}

static PetscErrorCode SetUp(FSSolver s)
{
  Drop       *dr;
  PetscReal   lo[3] = {0, 0, 0}, hi[3] = {0, 0, 0}, *x, *u, *rho, *m, vol = 1, dx, rho0, ext;
  PetscBool   per[3] = {PETSC_FALSE, PETSC_FALSE, PETSC_FALSE};
  PetscInt    dim, nside, n = 0, total = 1, kfirst, klast;
  PetscMPIInt rank, size;

  PetscFunctionBegin;
  PetscCall(FSSolverGetCaseData(s, &dr));
  PetscCall(FSSolverGetDimension(s, &dim));
  PetscCall(FSSolverGetParameters(s, &dx, NULL, &rho0, NULL, NULL));
  PetscCallMPI(MPI_Comm_rank(PetscObjectComm((PetscObject)s), &rank));
  PetscCallMPI(MPI_Comm_size(PetscObjectComm((PetscObject)s), &size));
  ext = dr->R * PetscMax(PetscSqrtReal(dr->aspect), 1 / PetscSqrtReal(dr->aspect)) * 1.2 + 2 * dx;
  PetscCheck(ext / dx < 2000, PetscObjectComm((PetscObject)s), PETSC_ERR_ARG_OUTOFRANGE,
             "-fs_drop_radius %g with -fs_dx %g puts %g particles across the drop: expected at most 2000",
             (double)dr->R, (double)dx, (double)(2 * ext / dx));
  nside = 2 * (PetscInt)PetscCeilReal(ext / dx);
  for (PetscInt d = 0; d < dim; d++) {
    const PetscBool periodic = (PetscBool)(dr->slab && d != 1);
    lo[d]                    = periodic ? -0.5 * nside * dx : -2.5 * ext; /* room for the oscillation */
    hi[d]                    = periodic ? 0.5 * nside * dx : 2.5 * ext;
    per[d]                   = periodic;
    vol *= dx;
  }
  PetscCall(FSSolverSetDomain(s, lo, hi, per));
  /* a lattice (k + 1/2) dx symmetric about the origin, cut by the shape */
  for (PetscInt d = 0; d < dim; d++) total *= nside;
  {
    const PetscInt first = (PetscInt)((PetscInt64)total * rank / size),
                   last  = (PetscInt)((PetscInt64)total * (rank + 1) / size);
    PetscCall(PetscMalloc4(dim * (last - first) + 1, &x, dim * (last - first) + 1, &u, last - first + 1, &rho,
                           last - first + 1, &m));
    kfirst = first;
    klast  = last;
  }
  /* this rank's contiguous share of the sites, so that the particles' ids follow the lattice on any number of ranks */
  for (PetscInt k = kfirst; k < klast; k++) {
    PetscReal p[3] = {0, 0, 0};
    PetscInt  r    = k;
    for (PetscInt d = 0; d < dim; d++) {
      p[d] = ((r % nside) - nside / 2 + 0.5) * dx;
      r /= nside;
    }
    if (!Inside(dr, dim, p)) continue;
    for (PetscInt d = 0; d < dim; d++) {
      x[n * dim + d] = p[d];
      u[n * dim + d] = 0;
    }
    rho[n] = rho0;
    m[n]   = rho0 * vol;
    n++;
  }
  PetscCall(FSSolverAddParticles(s, n, x, u, rho, m));
  PetscCall(PetscFree4(x, u, rho, m));
  PetscFunctionReturn(0);
}

/* the extents along x and y and the pressure near the centre of mass (the same on every rank) */
static PetscErrorCode Columns(FSSolver s, PetscReal t, PetscReal values[])
{
  Drop            *dr;
  const PetscReal *x, *rho, *m;
  PetscInt         n, dim;
  PetscReal        rho0, c0, box[4] = {PETSC_MAX_REAL, PETSC_MAX_REAL, PETSC_MAX_REAL, PETSC_MAX_REAL}, gbox[4];
  PetscReal        cm[4] = {0, 0, 0, 0}, gcm[4], pc[2] = {0, 0}, gpc[2];
  MPI_Comm         comm = PetscObjectComm((PetscObject)s);

  PetscFunctionBegin;
  (void)t;
  PetscCall(FSSolverGetCaseData(s, &dr));
  PetscCall(FSSolverGetDimension(s, &dim));
  PetscCall(FSSolverGetParameters(s, NULL, NULL, &rho0, &c0, NULL));
  PetscCall(FSSolverGetField(s, FS_FIELD_POSITION, &n, NULL, &x));
  PetscCall(FSSolverGetField(s, FS_FIELD_DENSITY, NULL, NULL, &rho));
  PetscCall(FSSolverGetField(s, FS_FIELD_MASS, NULL, NULL, &m));
  for (PetscInt p = 0; p < n; p++) {
    box[0] = PetscMin(box[0], x[p * dim]);
    box[1] = PetscMin(box[1], -x[p * dim]);
    box[2] = PetscMin(box[2], x[p * dim + 1]);
    box[3] = PetscMin(box[3], -x[p * dim + 1]);
    for (PetscInt d = 0; d < dim; d++) cm[d] += m[p] * x[p * dim + d];
    cm[3] += m[p];
  }
  PetscCallMPI(MPI_Allreduce(box, gbox, 4, MPIU_REAL, MPI_MIN, comm));
  PetscCallMPI(MPI_Allreduce(cm, gcm, 4, MPIU_REAL, MPIU_SUM, comm));
  for (PetscInt p = 0; p < n; p++) {
    PetscReal r2 = 0;
    for (PetscInt d = 0; d < dim; d++) {
      const PetscReal e = x[p * dim + d] - gcm[d] / gcm[3];
      r2 += e * e;
    }
    if (r2 > 0.25 * dr->R * dr->R) continue;
    pc[0] += c0 * c0 * (rho[p] - rho0);
    pc[1] += 1;
  }
  PetscCallMPI(MPI_Allreduce(pc, gpc, 2, MPIU_REAL, MPIU_SUM, comm));
  PetscCall(FSSolverRestoreField(s, FS_FIELD_POSITION, &n, NULL, &x));
  PetscCall(FSSolverRestoreField(s, FS_FIELD_DENSITY, NULL, NULL, &rho));
  PetscCall(FSSolverRestoreField(s, FS_FIELD_MASS, NULL, NULL, &m));
  values[0] = -gbox[1] - gbox[0];
  values[1] = -gbox[3] - gbox[2];
  values[2] = gpc[1] > 0 ? gpc[0] / gpc[1] : 0;
  PetscFunctionReturn(0);
}

PETSC_EXTERN PetscErrorCode FSCaseCreate_Drop(FSSolver s, FSCaseOps *ops)
{
  Drop *dr;

  PetscFunctionBegin;
  PetscCall(PetscNew(&dr));
  dr->R      = 1;
  dr->aspect = 1;
  PetscCall(FSSolverSetCaseData(s, dr));
  ops->setfromoptions  = SetFromOptions;
  ops->setup           = SetUp;
  ops->columns         = Columns;
  ops->ncolumns        = 3;
  ops->column_names[0] = "drop_extent_x";
  ops->column_names[1] = "drop_extent_y";
  ops->column_names[2] = "drop_pressure";
  PetscFunctionReturn(0);
}
