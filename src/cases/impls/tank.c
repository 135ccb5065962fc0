/*
   Case "tank": liquid at rest in a fixed tank (the seed's tanks, Fig. 4), starting hydrostatic.
     -fs_tank_shape rectangular|baffled|file
     rectangular: -fs_tank_length (0.7 m) x -fs_tank_height (0.06 m), the seed's rectangular tank
     baffled:     -fs_tank_compartments (7) of -fs_tank_compartment_length (0.1 m) separated by baffles
                  of -fs_tank_baffle_thickness (0.005 m): 0.73 m overall as in the seed; each baffle spans
                  -fs_tank_baffle_gap (0: on the floor) to -fs_tank_baffle_gap + -fs_tank_baffle_height
                  (0.045 m) above the floor. The seed does not give the baffles' height or openings:
                  by default they stand on the floor and leave 15 mm below the lid, so up to 75 % fill
                  each compartment holds its own liquid unless it sloshes over (the seed: the baffles
                  "do not allow the wave to propagate"). With an opening under the baffles, keep the
                  liquid at rest quiet with -fs_walls_visibility all (measured: docs/walls.md).
     file:        -fs_tank_file <path> in the polyline format of docs/walls.md.
   The liquid fills the tank up to -fs_fill (fraction of the tank height, 0.5) on a lattice of spacing
   dx, with the hydrostatic density rho = rho0 + rho0 |g| (y_fill - y) / c0^2. -fs_fill 0 is an empty
   tank: no particles and no walls, the structure alone (with -fs_beam_payload_mass all ballast), the
   0 % point of a fill sweep.
   Defaults: rho0 = 1000, c0 = 20 m/s and h/dx = 2 (seed), nu = 1e-6, g = 9.81 down, dx = H/30.
*/
#include <flexslosh.h>
#include "liquid.h"

typedef struct {
  char      shape[32], file[PETSC_MAX_PATH_LEN];
  PetscReal L, H, Lc, t, gap, hb, fill;
  PetscInt  ncomp;
} Tank;

static PetscErrorCode SetFromOptions(FSSolver s, PetscOptionItems *PetscOptionsObject)
{
  Tank     *tk;
  PetscReal g[3] = {0, -9.81, 0};
  PetscBool rect, baff, file;

  PetscFunctionBegin;
  PetscCall(FSSolverGetCaseData(s, &tk));
  PetscOptionsHeadBegin(PetscOptionsObject, "Case tank");
  PetscCall(PetscOptionsString("-fs_tank_shape", "Tank shape: rectangular, baffled or file", "", tk->shape, tk->shape,
                               sizeof(tk->shape), NULL));
  PetscCall(PetscOptionsReal("-fs_tank_length", "Length of the rectangular tank", "", tk->L, &tk->L, NULL));
  PetscCall(PetscOptionsReal("-fs_tank_height", "Height of the tank", "", tk->H, &tk->H, NULL));
  PetscCall(
      PetscOptionsInt("-fs_tank_compartments", "Compartments of the baffled tank", "", tk->ncomp, &tk->ncomp, NULL));
  PetscCall(PetscOptionsReal("-fs_tank_compartment_length", "Length of a compartment of the baffled tank", "", tk->Lc,
                             &tk->Lc, NULL));
  PetscCall(PetscOptionsReal("-fs_tank_baffle_thickness", "Thickness of the baffles", "", tk->t, &tk->t, NULL));
  PetscCall(PetscOptionsReal("-fs_tank_baffle_gap",
                             "Opening between the floor and the baffles (0: baffles stand on the floor)", "", tk->gap,
                             &tk->gap, NULL));
  PetscCall(PetscOptionsReal("-fs_tank_baffle_height", "Height of the baffles", "", tk->hb, &tk->hb, NULL));
  PetscCall(PetscOptionsString("-fs_tank_file", "Wall polygons of a tank of any shape (docs/walls.md: file format)", "",
                               tk->file, tk->file, sizeof(tk->file), NULL));
  PetscCall(
      PetscOptionsReal("-fs_fill", "Filling level, as a fraction of the tank height", "", tk->fill, &tk->fill, NULL));
  PetscOptionsHeadEnd();
  PetscCall(PetscStrcmp(tk->shape, "rectangular", &rect));
  PetscCall(PetscStrcmp(tk->shape, "baffled", &baff));
  PetscCall(PetscStrcmp(tk->shape, "file", &file));
  PetscCheck(rect || baff || file, PETSC_COMM_WORLD, PETSC_ERR_ARG_UNKNOWN_TYPE,
             "-fs_tank_shape %s is not known: expected rectangular, baffled or file", tk->shape);
  PetscCheck(!file || tk->file[0], PETSC_COMM_WORLD, PETSC_ERR_ARG_WRONG,
             "-fs_tank_shape file needs -fs_tank_file <path>");
  PetscCheck(tk->H > 0, PETSC_COMM_WORLD, PETSC_ERR_ARG_OUTOFRANGE, "-fs_tank_height %g must be positive",
             (double)tk->H);
  PetscCheck(tk->fill >= 0 && tk->fill <= 1, PETSC_COMM_WORLD, PETSC_ERR_ARG_OUTOFRANGE,
             "-fs_fill %g is outside the tank: expected a fraction in [0, 1] of the tank height", (double)tk->fill);
  PetscCall(FSSolverSetDefaultPhysics(s, 1000.0, 20.0, 1e-6, g));
  PetscCall(FSSolverSetDefaultTerms(s, FS_WALL_CASE_TERMS));
  PetscCall(FSSolverSetDefaultSpacing(s, tk->H / 30));
  PetscCall(FSSolverSetDefaultCFL(s, 1.0)); /* RK4 only; chosen by measurement (docs/decisions.md) */
  PetscCall(FSSolverSetDefaultFinalTime(s, 1.0));
  PetscFunctionReturn(0);
}

static PetscErrorCode SetUp(FSSolver s)
{
  Tank     *tk;
  MPI_Comm  comm = PetscObjectComm((PetscObject)s);
  FSWalls   w;
  PetscBool rect, baff;

  PetscFunctionBegin;
  PetscCall(FSSolverGetCaseData(s, &tk));
  PetscCall(FSWallsCreate(&w));
  PetscCall(PetscStrcmp(tk->shape, "rectangular", &rect));
  PetscCall(PetscStrcmp(tk->shape, "baffled", &baff));
  if (rect) PetscCall(FSWallsRectangularTank(&w, comm, tk->L, tk->H));
  else if (baff) PetscCall(FSWallsBaffledTank(&w, comm, tk->ncomp, tk->Lc, tk->t, tk->H, tk->gap, tk->hb));
  else PetscCall(FSWallsLoad(&w, comm, tk->file));
  PetscCall(FSWallsCheck(&w, comm)); /* sets the bounding box used below */
  if (tk->fill > 0)
    PetscCall(FSCaseFillLiquid(s, &w, w.lo[0], w.hi[0], w.lo[1], w.lo[1] + tk->fill * (w.hi[1] - w.lo[1]), "-fs_fill"));
  else { /* an empty tank (the 0 % point of a fill sweep): the structure alone, its payload all ballast */
    FSStructure st;
    PetscCall(FSSolverGetStructure(s, &st));
    PetscCheck(st, comm, PETSC_ERR_ARG_WRONG,
               "-fs_fill 0 leaves the tank empty: there is nothing to compute without a structure (-fs_structure msd "
               "or modal)");
    const PetscReal lo[3] = {w.lo[0], w.lo[1], 0}, hi[3] = {w.hi[0], w.hi[1], 1};
    const PetscBool per[3] = {PETSC_FALSE, PETSC_FALSE, PETSC_FALSE};
    PetscCall(FSSolverSetDomain(s, lo, hi, per));
    PetscCall(FSWallsDestroy(&w));
  }
  PetscFunctionReturn(0);
}

PETSC_EXTERN PetscErrorCode FSCaseCreate_Tank(FSSolver s, FSCaseOps *ops)
{
  Tank *tk;

  PetscFunctionBegin;
  PetscCall(PetscNew(&tk));
  PetscCall(PetscStrncpy(tk->shape, "rectangular", sizeof(tk->shape)));
  tk->L     = 0.7;
  tk->H     = 0.06;
  tk->ncomp = 7;
  tk->Lc    = 0.1;
  tk->t     = 0.005;
  tk->gap   = 0.0;
  tk->hb    = 0.045;
  tk->fill  = 0.5;
  PetscCall(FSSolverSetCaseData(s, tk));
  ops->setfromoptions = SetFromOptions;
  ops->setup          = SetUp;
  PetscFunctionReturn(0);
}
