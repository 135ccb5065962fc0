/*
   Case "dam_break": the 2-D dam break of Martin & Moyce (1952): a water column -fs_dam_width a wide
   and -fs_dam_height (2a) high at the left end of a tank -fs_dam_tank_length (4a) long and
   -fs_dam_tank_height (2.5a... default 2a + a) high collapses under gravity. In 3-D (-fs_dim 3) the tank
   and the column are -fs_dam_tank_width wide along z (default: as wide as the column is high).
   Reference (docs/validation.md): the surge front Z = x_front/a against T = t sqrt(2 g / a).
   The time series has the front position, the largest x of the particles on the floor (y < a/4),
   as column front_position, and the height of the liquid at the back wall (the top particle within dx
   of it, plus dx/2) as column_height, to compare with Martin & Moyce's residual column height
   H/(2a) against tau = t sqrt(g / a). Defaults: a = 1 m, dx = a/40, c0 = 10 sqrt(2 g 2a), rho0 = 1000,
   nu = 1e-6, g = 9.81 down, final time T = 3.
*/
#include <flexslosh.h>
#include "liquid.h"

typedef struct {
  PetscReal a, height, L, H, W;
  PetscInt  dim;
} DamBreak;

static PetscErrorCode SetFromOptions(FSSolver s, PetscOptionItems *PetscOptionsObject)
{
  DamBreak *db;
  PetscReal g[3] = {0, -9.81, 0};

  PetscFunctionBegin;
  PetscCall(FSSolverGetCaseData(s, &db));
  PetscOptionsHeadBegin(PetscOptionsObject, "Case dam_break");
  PetscCall(FSOptionsReal(PetscOptionsObject, "-fs_dam_width", "Width a of the water column", "", &db->a, NULL, 0,
                          PETSC_INFINITY, FS_RANGE_OPEN_LOWER));
  db->height = 2 * db->a;
  db->L      = 4 * db->a;
  PetscCall(FSOptionsReal(PetscOptionsObject, "-fs_dam_height", "Height of the water column (2a)", "", &db->height,
                          NULL, 0, PETSC_INFINITY, FS_RANGE_OPEN_LOWER));
  PetscCall(FSOptionsReal(PetscOptionsObject, "-fs_dam_tank_length", "Length of the tank (4a)", "", &db->L, NULL, 0,
                          PETSC_INFINITY, FS_RANGE_OPEN_LOWER));
  db->H = db->height + db->a;
  PetscCall(FSOptionsReal(PetscOptionsObject, "-fs_dam_tank_height", "Height of the tank (column height + a)", "",
                          &db->H, NULL, 0, PETSC_INFINITY, FS_RANGE_OPEN_LOWER));
  PetscCall(FSSolverGetDimension(s, &db->dim));
  db->W = db->height;
  PetscCall(FSOptionsReal(PetscOptionsObject, "-fs_dam_tank_width",
                          "Width of the tank and the column along z, 3-D (column height)", "", &db->W, NULL, 0,
                          PETSC_INFINITY, FS_RANGE_OPEN_LOWER));
  PetscOptionsHeadEnd();
  PetscCheck(db->W > 0, PETSC_COMM_WORLD, PETSC_ERR_ARG_OUTOFRANGE, "-fs_dam_tank_width %g must be positive",
             (double)db->W);
  PetscCheck(db->a > 0 && db->height > 0, PETSC_COMM_WORLD, PETSC_ERR_ARG_OUTOFRANGE,
             "-fs_dam_width %g and -fs_dam_height %g must be positive", (double)db->a, (double)db->height);
  PetscCheck(db->L > db->a, PETSC_COMM_WORLD, PETSC_ERR_ARG_OUTOFRANGE,
             "-fs_dam_tank_length %g must exceed the column width %g", (double)db->L, (double)db->a);
  PetscCheck(db->H >= db->height, PETSC_COMM_WORLD, PETSC_ERR_ARG_OUTOFRANGE,
             "-fs_dam_tank_height %g must be at least the column height %g", (double)db->H, (double)db->height);
  PetscCall(FSSolverSetDefaultPhysics(s, 1000.0, 10 * PetscSqrtReal(2 * 9.81 * db->height), 1e-6, g));
  PetscCall(FSSolverSetDefaultTerms(s, FS_WALL_CASE_TERMS));
  PetscCall(FSSolverSetDefaultSpacing(s, db->a / 40));
  PetscCall(FSSolverSetDefaultCFL(s, 2.0)); /* RK4 only; chosen by measurement (docs/decisions.md) */
  PetscCall(FSSolverSetDefaultFinalTime(s, 3.0 / PetscSqrtReal(2 * 9.81 / db->a)));
  PetscFunctionReturn(0);
}

static PetscErrorCode SetUp(FSSolver s)
{
  DamBreak *db;
  MPI_Comm  comm = PetscObjectComm((PetscObject)s);
  FSWalls   w;

  PetscFunctionBegin;
  PetscCall(FSSolverGetCaseData(s, &db));
  PetscCall(FSWallsCreate(&w));
  PetscCall(FSWallsRectangularTank(&w, comm, db->L, db->H));
  PetscCall(FSWallsCheck(&w, comm));
  if (db->dim == 3)
    PetscCall(FSCaseFillLiquidExtruded(s, &w, db->W, 0, db->a, 0, db->height, "the water column", NULL, NULL));
  else PetscCall(FSCaseFillLiquid(s, &w, 0, db->a, 0, db->height, "the water column"));
  PetscFunctionReturn(0);
}

/* the surge front, the largest x of the particles near the floor (y < a/4), and the height of the
   column at the back wall, the largest y of the particles within dx of it plus dx/2 (the surface lies
   half a spacing above the top particle: 2a at the start). The positions are the swarm's: at the
   monitors they are the state's, packed into it after the step's migration and reordering. */
static PetscErrorCode Columns(FSSolver s, PetscReal t, PetscReal values[])
{
  DamBreak  *db;
  DM         sw;
  PetscReal *pos, dx, top[2] = {0, 0};
  PetscInt   dim, n;

  PetscFunctionBegin;
  (void)t;
  PetscCall(FSSolverGetCaseData(s, &db));
  PetscCall(FSSolverGetParameters(s, &dx, NULL, NULL, NULL, NULL));
  PetscCall(FSSolverGetDimension(s, &dim));
  PetscCall(FSSolverGetSwarm(s, &sw));
  PetscCall(DMSwarmGetLocalSize(sw, &n));
  PetscCall(DMSwarmGetField(sw, FS_FIELD_POSITION, NULL, NULL, (void **)&pos));
  for (PetscInt p = 0; p < n; p++) {
    const PetscReal x = pos[p * dim], y = pos[p * dim + 1];
    if (y < 0.25 * db->a) top[0] = PetscMax(top[0], x);
    if (x < dx) top[1] = PetscMax(top[1], y + 0.5 * dx);
  }
  PetscCall(DMSwarmRestoreField(sw, FS_FIELD_POSITION, NULL, NULL, (void **)&pos));
  PetscCallMPI(MPI_Allreduce(top, values, 2, MPIU_REAL, MPI_MAX, PetscObjectComm((PetscObject)s)));
  PetscFunctionReturn(0);
}

PETSC_EXTERN PetscErrorCode FSCaseCreate_DamBreak(FSSolver s, FSCaseOps *ops)
{
  DamBreak *db;

  PetscFunctionBegin;
  PetscCall(PetscNew(&db));
  db->a = 1.0;
  PetscCall(FSSolverSetCaseData(s, db));
  ops->setfromoptions  = SetFromOptions;
  ops->setup           = SetUp;
  ops->columns         = Columns;
  ops->ncolumns        = 2;
  ops->column_names[0] = "front_position";
  ops->column_names[1] = "column_height";
  PetscFunctionReturn(0);
}
