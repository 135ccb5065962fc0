/*
   Unit tests of the wall geometry and of the geometric Shepard factor (docs/boundary-integrals.md):
   reference values of gamma near a flat wall and in a corner, independence of the discretization,
   thin baffles seen from either side, grad gamma against finite differences, the seed's baffled
   tank, and the errors on bad polygons and files.
*/
#include "boundary/impls/polygon/walls.h"

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

static PetscErrorCode ExpectError(PetscErrorCode ierr, const char what[])
{
  PetscFunctionBegin;
  CHECK(ierr != 0, "expected an error: %s", what);
  PetscFunctionReturn(0);
}

static PetscErrorCode TestErrors(const char dir[])
{
  FSWalls         w;
  const PetscReal bowtie[8] = {0, 0, 1, 1, 1, 0, 0, 1}, cw[8] = {0, 0, 0, 1, 1, 1, 1, 0}, line2[4] = {0, 0, 1, 0};
  char            path[PETSC_MAX_PATH_LEN];
  FILE           *fp;
  PetscErrorCode  ierr;

  PetscFunctionBegin;
  PetscCall(PetscPushErrorHandler(PetscReturnErrorHandler, NULL));
  PetscCall(FSWallsCreate(&w));
  ierr = FSWallsAddPolygon(&w, PETSC_COMM_SELF, "tank", 4, bowtie, "test");
  PetscCall(ExpectError(ierr, "self-intersecting polygon"));
  ierr = FSWallsAddPolygon(&w, PETSC_COMM_SELF, "tank", 2, line2, "test");
  PetscCall(ExpectError(ierr, "two vertices"));
  PetscCall(FSWallsDestroy(&w));
  PetscCall(FSWallsCreate(&w));
  PetscCall(FSWallsAddPolygon(&w, PETSC_COMM_SELF, "tank", 4, cw, "test"));
  ierr = FSWallsCheck(&w, PETSC_COMM_SELF);
  PetscCall(ExpectError(ierr, "clockwise container (inconsistent normals)"));
  PetscCall(FSWallsDestroy(&w));
  /* files: an open polygon, and a line that cannot be parsed */
  PetscCall(PetscSNPrintf(path, sizeof(path), "%s/open.walls", dir));
  fp = fopen(path, "w");
  fprintf(fp, "# open\nwall tank\n0 0\n1 0\n1 1\n");
  fclose(fp);
  PetscCall(FSWallsCreate(&w));
  ierr = FSWallsLoad(&w, PETSC_COMM_SELF, path);
  PetscCall(ExpectError(ierr, "open polygon in a file"));
  PetscCall(FSWallsDestroy(&w));
  PetscCall(PetscSNPrintf(path, sizeof(path), "%s/bad.walls", dir));
  fp = fopen(path, "w");
  fprintf(fp, "wall tank\n0 0\n1 zero\n1 1\nend\n");
  fclose(fp);
  PetscCall(FSWallsCreate(&w));
  ierr = FSWallsLoad(&w, PETSC_COMM_SELF, path);
  PetscCall(ExpectError(ierr, "unparsable line"));
  PetscCall(FSWallsDestroy(&w));
  PetscCall(PetscPopErrorHandler());
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
    PetscCall(TestErrors(dir));
    PetscCall(PetscPrintf(PETSC_COMM_SELF, "test_walls: OK\n"));
  }
  PetscCall(PetscFinalize());
  return 0;
}
