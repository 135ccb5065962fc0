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
     file:        -fs_tank_file <path> in the polyline format of docs/walls.md (2-D).
     stl:         -fs_tank_stl <path>[,<path>...]: closed triangle meshes (3-D), every solid of a file a
                  named wall part (docs/walls.md). Their vertices are moved once, as read, to
                  R (scale x) + shift: -fs_tank_stl_scale (the metres a unit of the files: a number, or m,
                  cm, mm, in), -fs_tank_stl_rotate ax,ay,az (degrees about x, then y, then z, fixed axes)
                  and -fs_tank_stl_translate x,y,z (metres); everything downstream (walls, fill, probes)
                  sees the moved mesh. A tank over 50 m across, or over 20 m at more than 1000
                  spacings, is warned about as a file in millimetres read as metres.
   In 3-D (-fs_dim 3) the rectangular and baffled tanks are their 2-D outlines extruded across
   -fs_tank_width (0.1 m) along z: the 2-D cases are their cross-sections.
   The liquid fills the tank up to -fs_fill (fraction of the tank height, 0.5), or the boxes given by
   -fs_liquid_box xmin,xmax,ymin,ymax[,zmin,zmax][,...] (each box hydrostatic below its own top; a box
   outside the tank, crossed by a wall or overlapping another is an error), on a lattice of spacing
   dx, with the hydrostatic density rho = rho0 + rho0 |g| (y_fill - y) / c0^2 and masses that sum to its
   integral over the liquid's exact volume (docs/walls.md). -fs_fill 0 is an empty
   tank: no particles and no walls, the structure alone (with -fs_beam_payload_mass all ballast), the
   0 % point of a fill sweep. Instead of -fs_fill, -fs_fill_volume V or -fs_fill_mass M fill the tank
   to the level below which it holds the volume V (m^3; 2-D: the area, m^2 per metre of width) or the
   hydrostatic mass M (kg; 2-D: per metre of width), found by bisection on the exact volume and mass
   below a level (FSCaseFillLevel).
   Defaults: rho0 = 1000, c0 = 20 m/s and h/dx = 2 (seed), nu = 1e-6, g = 9.81 down, dx = H/30.
*/
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <flexslosh.h>
#include "liquid.h"

#define FS_TANK_MAX_BOXES 16

typedef struct {
  char      shape[32], file[PETSC_MAX_PATH_LEN];
  char      stl[8][PETSC_MAX_PATH_LEN]; /* -fs_tank_stl */
  PetscInt  nstl;
  PetscReal L, H, Lc, t, gap, hb, fill, width;
  PetscReal fillvol, fillmass; /* -fs_fill_volume, -fs_fill_mass (0: not given) */
  PetscInt  ncomp, dim;
  PetscReal box[6 * FS_TANK_MAX_BOXES]; /* -fs_liquid_box: 2 dim reals per box */
  PetscInt  nbox;
  char      stlunit[64];                      /* -fs_tank_stl_scale as given */
  PetscReal stlscale, stlrot[3], stlshift[3]; /* -fs_tank_stl_scale (in metres a unit), _rotate, _translate */
} Tank;

/* -fs_tank_stl_scale: a unit's name or a positive number of metres a unit of the files, or 0 if it is neither */
static PetscReal STLScale(const char unit[])
{
  static const struct {
    const char *name;
    PetscReal   metres;
  } units[] = {{"m", 1}, {"cm", 0.01}, {"mm", 0.001}, {"in", 0.0254}};
  char  *end;
  double v;

  for (size_t k = 0; k < sizeof(units) / sizeof(units[0]); k++)
    if (!strcmp(unit, units[k].name)) return units[k].metres;
  v = strtod(unit, &end);
  return end != unit && !*end && isfinite(v) && v > 0 ? (PetscReal)v : 0;
}

static PetscErrorCode SetFromOptions(FSSolver s, PetscOptionItems *PetscOptionsObject)
{
  Tank     *tk;
  PetscReal g[3] = {0, -9.81, 0};
  PetscBool rect, baff, file, stl, stlset, fillset, boxset, volset, massset;
  PetscInt  nboxv;
  char     *stlfiles[9];
  PetscInt  nstl = 9, nrot, nshift;
  PetscBool rotset, shiftset;

  PetscFunctionBegin;
  PetscCall(FSSolverGetCaseData(s, &tk));
  PetscCall(FSSolverGetDimension(s, &tk->dim));
  PetscOptionsHeadBegin(PetscOptionsObject, "Case tank");
  PetscCall(PetscOptionsString("-fs_tank_shape", "Tank shape: rectangular, baffled, file (2-D) or stl (3-D)", "",
                               tk->shape, tk->shape, sizeof(tk->shape), NULL));
  PetscCall(FSOptionsReal(PetscOptionsObject, "-fs_tank_length", "Length of the rectangular tank", "", &tk->L, NULL, 0,
                          PETSC_INFINITY, FS_RANGE_OPEN_LOWER));
  PetscCall(FSOptionsReal(PetscOptionsObject, "-fs_tank_height", "Height of the tank", "", &tk->H, NULL, 0,
                          PETSC_INFINITY, FS_RANGE_OPEN_LOWER));
  PetscCall(FSOptionsInt(PetscOptionsObject, "-fs_tank_compartments", "Compartments of the baffled tank", "",
                         &tk->ncomp, NULL, 1, PETSC_MAX_INT));
  PetscCall(FSOptionsReal(PetscOptionsObject, "-fs_tank_compartment_length",
                          "Length of a compartment of the baffled tank", "", &tk->Lc, NULL, 0, PETSC_INFINITY,
                          FS_RANGE_OPEN_LOWER));
  PetscCall(FSOptionsReal(PetscOptionsObject, "-fs_tank_baffle_thickness", "Thickness of the baffles", "", &tk->t, NULL,
                          0, PETSC_INFINITY, FS_RANGE_OPEN_LOWER));
  PetscCall(FSOptionsReal(PetscOptionsObject, "-fs_tank_baffle_gap",
                          "Opening between the floor and the baffles (0: baffles stand on the floor)", "", &tk->gap,
                          NULL, 0, PETSC_INFINITY, FS_RANGE_CLOSED));
  PetscCall(FSOptionsReal(PetscOptionsObject, "-fs_tank_baffle_height", "Height of the baffles", "", &tk->hb, NULL, 0,
                          PETSC_INFINITY, FS_RANGE_OPEN_LOWER));
  PetscCall(PetscOptionsString("-fs_tank_file", "Wall polygons of a tank of any shape (docs/walls.md: file format)", "",
                               tk->file, tk->file, sizeof(tk->file), NULL));
  PetscCall(PetscOptionsStringArray("-fs_tank_stl",
                                    "STL files of a 3-D tank (closed meshes; each solid a named wall part)", "",
                                    stlfiles, &nstl, &stlset));
  PetscCall(PetscOptionsString(
      "-fs_tank_stl_scale", "The metres a unit of the STL files: m, cm, mm, in, or a positive number (applied first)",
      "", tk->stlunit, tk->stlunit, sizeof(tk->stlunit), NULL));
  nrot = 3;
  PetscCall(FSOptionsRealArray(PetscOptionsObject, "-fs_tank_stl_rotate",
                               "Rotation of the STL tank in degrees about x, then y, then z (fixed axes; after the "
                               "scale)",
                               "", tk->stlrot, &nrot, &rotset, PETSC_NINFINITY, PETSC_INFINITY, FS_RANGE_CLOSED));
  nshift = 3;
  PetscCall(FSOptionsRealArray(PetscOptionsObject, "-fs_tank_stl_translate",
                               "Translation of the STL tank in metres x,y,z (after the scale and the rotation)", "",
                               tk->stlshift, &nshift, &shiftset, PETSC_NINFINITY, PETSC_INFINITY, FS_RANGE_CLOSED));
  PetscCall(FSOptionsReal(PetscOptionsObject, "-fs_tank_width",
                          "Width of the 3-D rectangular and baffled tanks (along z)", "", &tk->width, NULL, 0,
                          PETSC_INFINITY, FS_RANGE_OPEN_LOWER));
  PetscCall(FSOptionsReal(PetscOptionsObject, "-fs_fill", "Filling level, as a fraction of the tank height", "",
                          &tk->fill, &fillset, PETSC_NINFINITY, PETSC_INFINITY, FS_RANGE_CLOSED));
  PetscCall(
      FSOptionsReal(PetscOptionsObject, "-fs_fill_volume",
                    "The liquid's volume instead of -fs_fill: the level found below which the tank holds it (m^3; "
                    "2-D: m^2, the area in the plane)",
                    "", &tk->fillvol, &volset, 0, PETSC_INFINITY, FS_RANGE_OPEN_LOWER));
  PetscCall(FSOptionsReal(PetscOptionsObject, "-fs_fill_mass",
                          "The liquid's mass instead of -fs_fill: the level found below which the tank holds it at "
                          "rest, hydrostatic (kg; 2-D: kg per metre of width)",
                          "", &tk->fillmass, &massset, 0, PETSC_INFINITY, FS_RANGE_OPEN_LOWER));
  nboxv = 6 * FS_TANK_MAX_BOXES;
  PetscCall(FSOptionsRealArray(PetscOptionsObject, "-fs_liquid_box",
                               "Boxes of liquid instead of a filling level: xmin,xmax,ymin,ymax[,zmin,zmax] for each "
                               "box, one after the other (2 dim numbers per box)",
                               "", tk->box, &nboxv, &boxset, PETSC_NINFINITY, PETSC_INFINITY, FS_RANGE_CLOSED));
  PetscOptionsHeadEnd();
  if (stlset) {
    PetscCheck(nstl <= 8, PETSC_COMM_WORLD, PETSC_ERR_ARG_OUTOFRANGE,
               "-fs_tank_stl gives more than 8 files: join solids into fewer files (one file may hold many solids)");
    tk->nstl = nstl;
    for (PetscInt f = 0; f < nstl; f++) {
      PetscCall(PetscStrncpy(tk->stl[f], stlfiles[f], sizeof(tk->stl[f])));
      PetscCall(PetscFree(stlfiles[f]));
    }
  }
  tk->stlscale = STLScale(tk->stlunit);
  PetscCheck(tk->stlscale > 0, PETSC_COMM_WORLD, PETSC_ERR_ARG_OUTOFRANGE,
             "-fs_tank_stl_scale %s is not a scale: expected the unit of the STL files' coordinates, m, cm, mm or in, "
             "or the metres a unit as a positive number (0.001 for millimetres)",
             tk->stlunit);
  PetscCheck(!rotset || nrot == 3, PETSC_COMM_WORLD, PETSC_ERR_ARG_SIZ,
             "-fs_tank_stl_rotate gives %" PetscInt_FMT " numbers: expected 3, the degrees about x, y and z", nrot);
  PetscCheck(!shiftset || nshift == 3, PETSC_COMM_WORLD, PETSC_ERR_ARG_SIZ,
             "-fs_tank_stl_translate gives %" PetscInt_FMT " numbers: expected 3, the metres along x, y and z", nshift);
  PetscCall(PetscStrcmp(tk->shape, "rectangular", &rect));
  PetscCall(PetscStrcmp(tk->shape, "baffled", &baff));
  PetscCall(PetscStrcmp(tk->shape, "file", &file));
  PetscCall(PetscStrcmp(tk->shape, "stl", &stl));
  PetscCheck(rect || baff || file || stl, PETSC_COMM_WORLD, PETSC_ERR_ARG_UNKNOWN_TYPE,
             "-fs_tank_shape %s is not known: expected rectangular, baffled, file or stl", tk->shape);
  PetscCheck(!file || tk->file[0], PETSC_COMM_WORLD, PETSC_ERR_ARG_WRONG,
             "-fs_tank_shape file needs -fs_tank_file <path>");
  PetscCheck(!stl || tk->nstl > 0, PETSC_COMM_WORLD, PETSC_ERR_ARG_WRONG,
             "-fs_tank_shape stl needs -fs_tank_stl <path>[,<path>...]");
  PetscCheck(!(file && tk->dim == 3), PETSC_COMM_WORLD, PETSC_ERR_ARG_INCOMP,
             "-fs_tank_file %s gives 2-D walls (polygons) but the run is 3-D (-fs_dim 3): give the tank as an STL "
             "mesh with -fs_tank_shape stl -fs_tank_stl <path>",
             tk->file);
  PetscCheck(!(stl && tk->dim == 2), PETSC_COMM_WORLD, PETSC_ERR_ARG_INCOMP,
             "-fs_tank_stl %s gives 3-D walls (triangle meshes) but the run is 2-D: use -fs_dim 3",
             tk->nstl ? tk->stl[0] : "");
  PetscCheck(tk->dim == 2 || tk->width > 0, PETSC_COMM_WORLD, PETSC_ERR_ARG_OUTOFRANGE,
             "-fs_tank_width %g must be positive", (double)tk->width);
  if (boxset) {
    PetscCheck(nboxv > 0 && nboxv % (2 * tk->dim) == 0, PETSC_COMM_WORLD, PETSC_ERR_ARG_SIZ,
               "-fs_liquid_box gives %" PetscInt_FMT " numbers: expected %s for each box (at most %d boxes)", nboxv,
               tk->dim == 3 ? "6 (xmin,xmax,ymin,ymax,zmin,zmax)" : "4 (xmin,xmax,ymin,ymax)", FS_TANK_MAX_BOXES);
    PetscCheck(!fillset, PETSC_COMM_WORLD, PETSC_ERR_ARG_INCOMP,
               "-fs_fill and -fs_liquid_box both give the liquid: use one of them");
    tk->nbox = nboxv / (2 * tk->dim);
  }
  PetscCheck((fillset || boxset ? 1 : 0) + (volset ? 1 : 0) + (massset ? 1 : 0) <= 1, PETSC_COMM_WORLD,
             PETSC_ERR_ARG_INCOMP, "%s%s%s give the liquid more than once: use one of them",
             fillset ? "-fs_fill, " : (boxset ? "-fs_liquid_box, " : ""), volset ? "-fs_fill_volume" : "",
             massset ? (volset ? " and -fs_fill_mass" : "-fs_fill_mass") : "");
  PetscCheck(tk->fill >= 0 && tk->fill <= 1, PETSC_COMM_WORLD, PETSC_ERR_ARG_OUTOFRANGE,
             "-fs_fill %g is outside the tank: expected a fraction in [0, 1] of the tank height", (double)tk->fill);
  PetscCall(FSSolverSetDefaultPhysics(s, 1000.0, 20.0, 1e-6, g));
  PetscCall(FSSolverSetDefaultTerms(s, FS_WALL_CASE_TERMS));
  PetscCall(FSSolverSetDefaultSpacing(s, tk->H / 30));
  PetscCall(FSSolverSetDefaultCFL(s, 1.0)); /* RK4 only; chosen by measurement (docs/decisions.md) */
  PetscCall(FSSolverSetDefaultFinalTime(s, 1.0));
  PetscFunctionReturn(0);
}

/* the STL files' vertices moved by -fs_tank_stl_scale, _rotate, _translate (when given), the bounding box before and
   after printed; a tank that looks like millimetres read as metres warned about */
static PetscErrorCode TankMeshTransform(FSSolver s, Tank *tk, FSMesh *m)
{
  MPI_Comm        comm  = PetscObjectComm((PetscObject)s);
  const PetscBool moved = (PetscBool)(tk->stlscale != 1 || tk->stlrot[0] != 0 || tk->stlrot[1] != 0 ||
                                      tk->stlrot[2] != 0 || tk->stlshift[0] != 0 || tk->stlshift[1] != 0 ||
                                      tk->stlshift[2] != 0);
  PetscReal       lo[3], hi[3], size = 0, dx;

  PetscFunctionBegin;
  FSMeshVertexBox(m, lo, hi);
  if (moved) {
    PetscCall(PetscPrintf(comm, "STL tank %s%s: bounding box [%g, %g] x [%g, %g] x [%g, %g] as read; ", tk->stl[0],
                          tk->nstl > 1 ? ",..." : "", (double)lo[0], (double)hi[0], (double)lo[1], (double)hi[1],
                          (double)lo[2], (double)hi[2]));
    FSMeshTransform(m, tk->stlscale, tk->stlrot, tk->stlshift);
    FSMeshVertexBox(m, lo, hi);
    PetscCall(PetscPrintf(comm,
                          "[%g, %g] x [%g, %g] x [%g, %g] m after -fs_tank_stl_scale %s (x %g), -fs_tank_stl_rotate "
                          "%g,%g,%g, -fs_tank_stl_translate %g,%g,%g\n",
                          (double)lo[0], (double)hi[0], (double)lo[1], (double)hi[1], (double)lo[2], (double)hi[2],
                          tk->stlunit, (double)tk->stlscale, (double)tk->stlrot[0], (double)tk->stlrot[1],
                          (double)tk->stlrot[2], (double)tk->stlshift[0], (double)tk->stlshift[1],
                          (double)tk->stlshift[2]));
  }
  PetscCall(FSSolverGetParameters(s, &dx, NULL, NULL, NULL, NULL));
  for (PetscInt d = 0; d < 3; d++) size = PetscMax(size, hi[d] - lo[d]);
  if (size > 50 || (size > 20 && size > 1000 * dx))
    PetscCall(PetscPrintf(comm,
                          "Warning: the STL tank %s is %g m across (%g spacings of -fs_dx %g): a file in millimetres "
                          "read as metres? Its coordinates are taken in metres: -fs_tank_stl_scale mm (or cm, in, a "
                          "factor) converts them\n",
                          tk->stl[0], (double)size, (double)(size / dx), (double)dx));
  PetscFunctionReturn(0);
}

/* the 3-D tank's mesh: its 2-D outline w extruded across the width, or the STL files (moved as the options say) */
static PetscErrorCode TankMesh(FSSolver s, Tank *tk, PetscBool stl, FSWalls *w, FSMesh *m)
{
  MPI_Comm comm = PetscObjectComm((PetscObject)s);

  PetscFunctionBegin;
  PetscCall(FSMeshCreate(m));
  if (stl) {
    for (PetscInt f = 0; f < tk->nstl; f++) {
      char        name[64];
      const char *base = strrchr(tk->stl[f], '/') ? strrchr(tk->stl[f], '/') + 1 : tk->stl[f];
      char       *dot;
      PetscCall(PetscStrncpy(name, base, sizeof(name)));
      if ((dot = strrchr(name, '.'))) *dot = 0; /* the file's name without its extension names unnamed solids */
      PetscCall(FSMeshLoadSTL(m, comm, tk->stl[f], name));
    }
    PetscCall(TankMeshTransform(s, tk, m));
  } else {
    PetscCall(FSWallsCheck(w, comm));
    PetscCall(FSMeshExtrude(m, comm, w, tk->width));
  }
  PetscCall(FSMeshCheck(m, comm)); /* sets the bounding box */
  PetscFunctionReturn(0);
}

/* filled to a level under gravity along -y, the liquid starts at rest: the at-rest check watches it */
static PetscErrorCode TankAtRest(FSSolver s, PetscReal depth)
{
  PetscReal g[3];

  PetscFunctionBegin;
  PetscCall(FSSolverGetGravity(s, g));
  PetscCall(FSSolverSetLiquidAtRest(s, (PetscBool)(g[0] == 0 && g[2] == 0 && g[1] < 0), depth));
  PetscFunctionReturn(0);
}

/* the 3-D tank: the mesh, filled to the level or in the liquid boxes */
static PetscErrorCode SetUp3(FSSolver s, Tank *tk, PetscBool stl, FSWalls *w)
{
  MPI_Comm  comm = PetscObjectComm((PetscObject)s);
  FSMesh    m;
  PetscReal lo[3], hi[3];

  PetscFunctionBegin;
  PetscCheck(tk->nbox || tk->fill > 0 || tk->fillvol > 0 || tk->fillmass > 0, comm, PETSC_ERR_ARG_OUTOFRANGE,
             "-fs_fill 0 (an empty tank) is two-dimensional only: give a positive fill in 3-D");
  PetscCall(TankMesh(s, tk, stl, w, &m));
  if (tk->nbox) PetscCall(FSCaseFillLiquidMeshBoxes(s, &m, tk->nbox, tk->box, "-fs_liquid_box"));
  else {
    const char *what = tk->fillvol > 0 ? "-fs_fill_volume" : (tk->fillmass > 0 ? "-fs_fill_mass" : "-fs_fill");
    for (PetscInt d = 0; d < 3; d++) {
      lo[d] = m.lo[d];
      hi[d] = m.hi[d];
    }
    if (tk->fillvol > 0 || tk->fillmass > 0)
      PetscCall(FSCaseFillLevelMesh(s, &m, lo, hi, (PetscBool)(tk->fillmass > 0),
                                    tk->fillmass > 0 ? tk->fillmass : tk->fillvol, what, &hi[1]));
    else hi[1] = lo[1] + tk->fill * (m.hi[1] - m.lo[1]);
    PetscCall(FSCaseFillLiquidMesh(s, &m, lo, hi, what));
    PetscCall(TankAtRest(s, hi[1] - lo[1]));
  }
  PetscCall(FSMeshDestroy(&m));
  PetscFunctionReturn(0);
}

static PetscErrorCode SetUp(FSSolver s)
{
  Tank     *tk;
  MPI_Comm  comm = PetscObjectComm((PetscObject)s);
  FSWalls   w;
  PetscBool rect, baff, stl;

  PetscFunctionBegin;
  PetscCall(FSSolverGetCaseData(s, &tk));
  PetscCall(FSWallsCreate(&w));
  PetscCall(PetscStrcmp(tk->shape, "rectangular", &rect));
  PetscCall(PetscStrcmp(tk->shape, "baffled", &baff));
  PetscCall(PetscStrcmp(tk->shape, "stl", &stl));
  if (rect) PetscCall(FSWallsRectangularTank(&w, comm, tk->L, tk->H));
  else if (baff) PetscCall(FSWallsBaffledTank(&w, comm, tk->ncomp, tk->Lc, tk->t, tk->H, tk->gap, tk->hb));
  else if (!stl) PetscCall(FSWallsLoad(&w, comm, tk->file));
  if (tk->dim == 3) {
    PetscCall(SetUp3(s, tk, stl, &w));
    PetscCall(FSWallsDestroy(&w));
    PetscFunctionReturn(0);
  }
  PetscCall(FSWallsCheck(&w, comm)); /* sets the bounding box used below */
  if (tk->nbox) PetscCall(FSCaseFillLiquidBoxes(s, &w, tk->nbox, tk->box, "-fs_liquid_box"));
  else if (tk->fillvol > 0 || tk->fillmass > 0) {
    const char *what = tk->fillvol > 0 ? "-fs_fill_volume" : "-fs_fill_mass";
    PetscReal   level;
    PetscCall(FSCaseFillLevelPolygon(s, &w, w.lo[0], w.hi[0], w.lo[1], w.hi[1], (PetscBool)(tk->fillmass > 0),
                                     tk->fillmass > 0 ? tk->fillmass : tk->fillvol, what, &level));
    PetscCall(FSCaseFillLiquid(s, &w, w.lo[0], w.hi[0], w.lo[1], level, what));
    PetscCall(TankAtRest(s, level - w.lo[1]));
  } else if (tk->fill > 0) {
    PetscCall(FSCaseFillLiquid(s, &w, w.lo[0], w.hi[0], w.lo[1], w.lo[1] + tk->fill * (w.hi[1] - w.lo[1]), "-fs_fill"));
    PetscCall(TankAtRest(s, tk->fill * (w.hi[1] - w.lo[1])));
  } else { /* an empty tank (the 0 % point of a fill sweep): the structure alone, its payload all ballast */
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
  tk->width = 0.1;
  PetscCall(PetscStrncpy(tk->stlunit, "m", sizeof(tk->stlunit)));
  tk->stlscale = 1;
  PetscCall(FSSolverSetCaseData(s, tk));
  ops->setfromoptions = SetFromOptions;
  ops->setup          = SetUp;
  PetscFunctionReturn(0);
}
