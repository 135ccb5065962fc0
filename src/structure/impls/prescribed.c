/*
   Structure "prescribed": the tank moved as a forced-sloshing rig moves it, whatever the liquid does.
   No state (ndof 0): the motion is a function of time. Its components: the translation of the tank's
   reference point along x, y (and z in 3-D), the roll angle about z through that point
   (-fs_tank_reference, default the middle of the floor), and in 3-D the pitch about x, the yaw about y
   and a rotation about a given axis (-fs_motion_axis_direction) through it. Each component is the sum of
   what is given:

     -fs_motion_<c>_sines A1,T1,phi1,...  sum of A sin(2 pi t/T + phi), phi in degrees
     -fs_motion_<c>_poly  c0[,c1[,c2]]     c0 + c1 t + c2 t^2/2 (an offset, a rate, a uniform acceleration)
     -fs_motion_<c>_file  FILE            a time series (time, value), natural cubic spline (motionseries.c)

   with <c> one of x, y, z (metres) or roll, pitch, yaw, axis (degrees, right-handed about their axes), and
   in 3-D a 6-DOF file (-fs_motion_file: lines 't x y z rx ry rz', one spline a column) whose columns add to
   x, y, z, pitch, yaw and roll. The rotations compose as intrinsic turns, Q = R_y(yaw) R_x(pitch) R_z(roll)
   R_n(axis) (FSTankMotionRotate): yaw about the vertical first, then pitch about the tank's turned x, then
   roll about its z, then the turn about n, fixed in the tank. A 3-D run with a pitch, yaw, axis or 6-DOF
   file gives the coupling the whole rotation (Q, its angular velocity and acceleration); without them the
   roll alone as before. The smooth start is
   the ramp s(t/T_r), s(u) = 10u^3 - 15u^4 + 6u^5 (0 before t = 0, 1 after T_r = -fs_motion_ramp),
   whose first and second derivatives vanish at both ends: the sines and the file's values are
   multiplied by it (an envelope), and each polynomial term's highest derivative is (the offset c0 s,
   the velocity c1 s, the acceleration c2 s, integrated exactly), so that a uniform acceleration
   reaches c2 without overshoot. The rig starts from rest with no jump in velocity or acceleration. The liquid feels the
   motion through the coupling's inertial accelerations (src/coupling/coupling.c); the energy budget books the work the
   motion does on the liquid (work_motion, src/solver/energy.c).
*/
#include <math.h>
#include <flexslosh.h>
#include "io/fsoutput.h"
#include "motionseries.h"

#define MAX_SINES 16
enum { COMP_X, COMP_Y, COMP_Z, COMP_ROLL, COMP_PITCH, COMP_YAW, COMP_AXIS, NCOMP };

static const char *CompName[NCOMP] = {"x", "y", "z", "roll", "pitch", "yaw", "axis"};
/* the 6-DOF file's columns after the time: x, y, z, rx (pitch), ry (yaw), rz (roll) */
static const PetscInt SixComp[6] = {COMP_X, COMP_Y, COMP_Z, COMP_PITCH, COMP_YAW, COMP_ROLL};

#define IS_ANGLE(c) ((c) >= COMP_ROLL)

typedef struct {
  PetscInt       nsines;
  PetscReal      sine[3 * MAX_SINES]; /* A, T, phi (degrees) */
  PetscInt       npoly;
  PetscReal      poly[3];
  char           file[PETSC_MAX_PATH_LEN];
  FSMotionSeries series; /* loaded at set-up when file is set */
  PetscBool      loaded;
} Component;

typedef struct {
  Component      comp[NCOMP];
  PetscReal      ramp;
  PetscInt       dim;
  PetscReal      axis[3]; /* -fs_motion_axis_direction */
  PetscInt       naxis;
  char           file6[PETSC_MAX_PATH_LEN]; /* -fs_motion_file */
  FSMotionSeries six[6];
  PetscBool      loaded6;
  PetscBool      rotated; /* 3-D, a pitch, yaw, axis or 6-DOF file given: the whole rotation */
} Prescribed;

static PetscBool ComponentGiven(const Prescribed *p, PetscInt c)
{
  const Component *cp = &p->comp[c];
  if (cp->nsines || cp->npoly || cp->file[0]) return PETSC_TRUE;
  return (PetscBool)(p->file6[0] && c != COMP_AXIS);
}

static PetscErrorCode SetFromOptions(FSStructure st, PetscOptionItems *PetscOptionsObject)
{
  Prescribed *p = (Prescribed *)st->data;

  PetscFunctionBegin;
  PetscOptionsHeadBegin(PetscOptionsObject,
                        "Structure prescribed: the tank moved by a given motion (translation x, y[, z] and roll about "
                        "z through -fs_tank_reference; 3-D: pitch about x, yaw about y, a turn about an axis)");
  PetscCall(FSOptionsReal(PetscOptionsObject, "-fs_motion_ramp",
                          "Smooth start: the motion times s(t/T), s = 10u^3 - 15u^4 + 6u^5, over this time T (s; 0: "
                          "none)",
                          "", &p->ramp, NULL, 0, PETSC_INFINITY, FS_RANGE_CLOSED));
  for (PetscInt c = 0; c < NCOMP; c++) {
    Component  *cp   = &p->comp[c];
    const char *unit = IS_ANGLE(c) ? "degrees" : "m";
    char        opt[64], help[256];
    PetscBool   set;

    PetscCall(PetscSNPrintf(opt, sizeof(opt), "-fs_motion_%s_sines", CompName[c]));
    PetscCall(PetscSNPrintf(help, sizeof(help),
                            "%s: sum of A sin(2 pi t/T + phi), given as A,T,phi,... (A in %s, T in s, phi in degrees)",
                            CompName[c], unit));
    cp->nsines = 3 * MAX_SINES;
    PetscCall(FSOptionsRealArray(PetscOptionsObject, opt, help, "", cp->sine, &cp->nsines, &set, PETSC_NINFINITY,
                                 PETSC_INFINITY, FS_RANGE_OPEN));
    if (!set) cp->nsines = 0;
    else {
      PetscCheck(cp->nsines > 0 && cp->nsines % 3 == 0, st->comm, PETSC_ERR_ARG_SIZ,
                 "%s takes triples A,T,phi (at most %d); got %" PetscInt_FMT " values", opt, MAX_SINES, cp->nsines);
      for (PetscInt k = 0; k < cp->nsines; k += 3)
        PetscCheck(cp->sine[k + 1] > 0, st->comm, PETSC_ERR_ARG_OUTOFRANGE,
                   "%s: the period %g of sine %" PetscInt_FMT " is out of range: expected T > 0 (s)", opt,
                   (double)cp->sine[k + 1], k / 3 + 1);
      cp->nsines /= 3;
    }
    PetscCall(PetscSNPrintf(opt, sizeof(opt), "-fs_motion_%s_poly", CompName[c]));
    PetscCall(PetscSNPrintf(help, sizeof(help),
                            "%s: c0 + c1 t + c2 t^2/2, given as c0[,c1[,c2]] (an offset in %s, a rate, a uniform "
                            "acceleration)",
                            CompName[c], unit));
    cp->npoly = 3;
    PetscCall(FSOptionsRealArray(PetscOptionsObject, opt, help, "", cp->poly, &cp->npoly, &set, PETSC_NINFINITY,
                                 PETSC_INFINITY, FS_RANGE_OPEN));
    if (!set) cp->npoly = 0;
    PetscCall(PetscSNPrintf(opt, sizeof(opt), "-fs_motion_%s_file", CompName[c]));
    PetscCall(PetscSNPrintf(help, sizeof(help),
                            "%s: a time-series file of lines 'time value' (value in %s), natural cubic spline",
                            CompName[c], unit));
    PetscCall(PetscOptionsString(opt, help, "", cp->file, cp->file, sizeof(cp->file), NULL));
  }
  p->naxis = 3;
  PetscCall(FSOptionsRealArray(PetscOptionsObject, "-fs_motion_axis_direction",
                               "3-D: the direction nx,ny,nz (tank's axes) of the axis the axis component turns about, "
                               "through -fs_tank_reference",
                               "", p->axis, &p->naxis, NULL, PETSC_NINFINITY, PETSC_INFINITY, FS_RANGE_OPEN));
  PetscCall(PetscOptionsString("-fs_motion_file",
                               "3-D: a 6-DOF time-series file of lines 't x y z rx ry rz' (m; degrees about x, y, z: "
                               "pitch, yaw, roll), natural cubic spline a column",
                               "", p->file6, p->file6, sizeof(p->file6), NULL));
  PetscOptionsHeadEnd();
  PetscFunctionReturn(0);
}

static PetscErrorCode SetUp(FSStructure st)
{
  Prescribed *p = (Prescribed *)st->data;
  FSSolver    solver;

  PetscFunctionBegin;
  PetscCall(FSStructureGetSolver(st, &solver));
  PetscCall(FSSolverGetDimension(solver, &p->dim));
  {
    const Component *z = &p->comp[COMP_Z];
    PetscCheck(p->dim == 3 || (!z->nsines && !z->npoly && !z->file[0]), st->comm, PETSC_ERR_ARG_INCOMP,
               "-fs_motion_z_sines, -fs_motion_z_poly and -fs_motion_z_file move the tank across the plane: 3-D runs "
               "only (-fs_dim 3)");
    PetscCheck(p->dim == 3 || !p->file6[0], st->comm, PETSC_ERR_ARG_INCOMP,
               "-fs_motion_file %s: a 6-DOF motion is for 3-D runs only (-fs_dim 3); a 2-D tank takes "
               "-fs_motion_x_file, -fs_motion_y_file and -fs_motion_roll_file",
               p->file6);
    for (PetscInt c = COMP_PITCH; c <= COMP_AXIS; c++)
      PetscCheck(p->dim == 3 || !ComponentGiven(p, c), st->comm, PETSC_ERR_ARG_INCOMP,
                 "-fs_motion_%s_sines, -fs_motion_%s_poly and -fs_motion_%s_file turn the tank out of the plane: 3-D "
                 "runs only (-fs_dim 3; a 2-D tank rolls about z, -fs_motion_roll_*)",
                 CompName[c], CompName[c], CompName[c]);
    PetscCheck(p->naxis == 0 || p->naxis == 3, st->comm, PETSC_ERR_ARG_SIZ,
               "-fs_motion_axis_direction takes three values nx,ny,nz; got %" PetscInt_FMT, p->naxis);
    PetscCheck(p->naxis == 0 || p->axis[0] * p->axis[0] + p->axis[1] * p->axis[1] + p->axis[2] * p->axis[2] > 0,
               st->comm, PETSC_ERR_ARG_OUTOFRANGE,
               "-fs_motion_axis_direction %g,%g,%g has no direction: expected a nonzero vector", (double)p->axis[0],
               (double)p->axis[1], (double)p->axis[2]);
    PetscCheck(!ComponentGiven(p, COMP_AXIS) || p->naxis == 3, st->comm, PETSC_ERR_ARG_WRONGSTATE,
               "-fs_motion_axis_sines, -fs_motion_axis_poly and -fs_motion_axis_file turn the tank about an axis: give "
               "its direction, "
               "-fs_motion_axis_direction nx,ny,nz");
  }
  for (PetscInt c = 0; c < NCOMP; c++) {
    Component *cp = &p->comp[c];
    char       opt[64];
    if (!cp->file[0]) continue;
    PetscCall(PetscSNPrintf(opt, sizeof(opt), "-fs_motion_%s_file", CompName[c]));
    PetscCall(FSMotionSeriesLoad(st->comm, cp->file, opt, IS_ANGLE(c) ? PETSC_PI / 180 : 1, &cp->series));
    cp->loaded = PETSC_TRUE;
  }
  if (p->file6[0]) {
    const PetscReal deg = PETSC_PI / 180, scale[6] = {1, 1, 1, deg, deg, deg};
    PetscCall(FSMotionSeriesLoadColumns(st->comm, p->file6, "-fs_motion_file", 6, scale,
                                        "seven finite numbers: the time, x, y, z (m), rx, ry, rz (degrees)", p->six));
    p->loaded6 = PETSC_TRUE;
  }
  p->rotated     = (PetscBool)(p->dim == 3 && (ComponentGiven(p, COMP_PITCH) || ComponentGiven(p, COMP_YAW) ||
                                           ComponentGiven(p, COMP_AXIS) || p->file6[0]));
  st->ndof       = 0;
  st->min_period = 0;
  PetscCall(FSStructureAddColumn(st, "motion_disp_x"));
  PetscCall(FSStructureAddColumn(st, "motion_disp_y"));
  if (p->dim == 3) PetscCall(FSStructureAddColumn(st, "motion_disp_z"));
  PetscCall(FSStructureAddColumn(st, "motion_angle"));
  if (p->rotated) {
    PetscCall(FSStructureAddColumn(st, "motion_pitch"));
    PetscCall(FSStructureAddColumn(st, "motion_yaw"));
    if (ComponentGiven(p, COMP_AXIS)) PetscCall(FSStructureAddColumn(st, "motion_axis_angle"));
  }
  PetscFunctionReturn(0);
}

/* one component's value, velocity and acceleration v[0..2] before the ramp (angles in radians); six: the 6-DOF
   file's column for it, or NULL */
static void ComponentEval(const Component *cp, PetscBool roll, const FSMotionSeries *six, PetscReal t, PetscReal v[3])
{
  const PetscReal deg = PETSC_PI / 180, scale = roll ? deg : 1;

  v[0] = v[1] = v[2] = 0;
  for (PetscInt k = 0; k < cp->nsines; k++) {
    const PetscReal A = scale * cp->sine[3 * k], w = 2 * PETSC_PI / cp->sine[3 * k + 1];
    const PetscReal arg = w * t + deg * cp->sine[3 * k + 2], sn = PetscSinReal(arg), cs = PetscCosReal(arg);
    v[0] += A * sn;
    v[1] += A * w * cs;
    v[2] -= A * w * w * sn;
  }
  if (cp->loaded) {
    PetscReal s[3];
    FSMotionSeriesEval(&cp->series, t, s);
    for (PetscInt d = 0; d < 3; d++) v[d] += s[d];
  }
  if (six) {
    PetscReal s[3];
    FSMotionSeriesEval(six, t, s);
    for (PetscInt d = 0; d < 3; d++) v[d] += s[d];
  }
}

/* the ramp s(t/T), its first two time derivatives r[1], r[2], and its first two time integrals from 0, r[3], r[4] */
static void Ramp(PetscReal T, PetscReal t, PetscReal r[5])
{
  if (t <= 0) {
    r[0] = T > 0 ? 0 : 1;
    r[1] = r[2] = r[3] = r[4] = 0;
  } else if (t >= T) { /* with the integrals over the ramp, T/2 and T^2/7 */
    const PetscReal d = t - T;
    r[0]              = 1;
    r[1] = r[2] = 0;
    r[3]        = 0.5 * T + d;
    r[4]        = T * T / 7 + 0.5 * T * d + 0.5 * d * d;
  } else {
    const PetscReal u = t / T, u2 = u * u, u4 = u2 * u2;
    r[0] = u2 * u * (10 - 15 * u + 6 * u2);
    r[1] = 30 * u2 * (1 - u) * (1 - u) / T;
    r[2] = 60 * u * (1 - u) * (1 - 2 * u) / (T * T);
    r[3] = T * u4 * (2.5 - 3 * u + u2);
    r[4] = T * T * u4 * u * (0.5 - 0.5 * u + u2 / 7);
  }
}

/* the polynomial terms with the ramp on their highest derivative: the offset c0 r(t), the rate c1 r(t) as the
   velocity, the acceleration c2 r(t): value c0 r + c1 int r + c2 int int r, and its two derivatives, added to v */
static void PolyEval(const Component *cp, PetscReal scale, const PetscReal r[5], PetscReal v[3])
{
  const PetscReal c0 = scale * cp->poly[0], c1 = cp->npoly > 1 ? scale * cp->poly[1] : 0,
                  c2 = cp->npoly > 2 ? scale * cp->poly[2] : 0;

  v[0] += c0 * r[0] + c1 * r[3] + c2 * r[4];
  v[1] += c0 * r[1] + c1 * r[0] + c2 * r[3];
  v[2] += c0 * r[2] + c1 * r[1] + c2 * r[0];
}

static PetscErrorCode RHS(FSStructure st, PetscReal t, const PetscReal y[], const FSLoads *loads, PetscReal ydot[])
{
  PetscFunctionBegin; /* no state */
  PetscFunctionReturn(0);
}

/* every component's value, velocity and acceleration (angles in radians) at t, the ramp applied */
static void ComponentsAt(const Prescribed *p, PetscReal t, PetscReal f[NCOMP][3])
{
  PetscReal r[5];

  Ramp(p->ramp, t, r);
  for (PetscInt c = 0; c < NCOMP; c++) {
    const FSMotionSeries *six = NULL;
    PetscReal             g[3];
    for (PetscInt k = 0; p->loaded6 && k < 6; k++)
      if (SixComp[k] == c) six = &p->six[k];
    ComponentEval(&p->comp[c], (PetscBool)IS_ANGLE(c), six, t, g); /* sines and files, times the ramp */
    f[c][0] = r[0] * g[0];
    f[c][1] = r[1] * g[0] + r[0] * g[1];
    f[c][2] = r[2] * g[0] + 2 * r[1] * g[1] + r[0] * g[2];
    if (p->comp[c].npoly) PolyEval(&p->comp[c], IS_ANGLE(c) ? PETSC_PI / 180 : 1, r, f[c]);
  }
}

static PetscErrorCode Motion(FSStructure st, PetscReal t, const PetscReal y[], const PetscReal ydot[], FSTankMotion *m)
{
  Prescribed     *p = (Prescribed *)st->data;
  PetscReal       f[NCOMP][3];
  const PetscReal ex[3] = {1, 0, 0}, ey[3] = {0, 1, 0}, ez[3] = {0, 0, 1};

  PetscFunctionBegin;
  PetscCall(PetscMemzero(m, sizeof(*m)));
  ComponentsAt(p, t, f);
  for (PetscInt d = 0; d < 3; d++) {
    m->disp[d] = f[d][0];
    m->vel[d]  = f[d][1];
    m->acc[d]  = f[d][2];
  }
  m->angle  = f[COMP_ROLL][0];
  m->rate   = f[COMP_ROLL][1];
  m->angacc = f[COMP_ROLL][2];
  if (p->rotated) { /* Q = R_y(yaw) R_x(pitch) R_z(roll) R_n(axis) */
    PetscCall(FSTankMotionRotate(m, ey, f[COMP_YAW]));
    PetscCall(FSTankMotionRotate(m, ex, f[COMP_PITCH]));
    PetscCall(FSTankMotionRotate(m, ez, f[COMP_ROLL]));
    if (ComponentGiven(p, COMP_AXIS)) PetscCall(FSTankMotionRotate(m, p->axis, f[COMP_AXIS]));
  }
  PetscFunctionReturn(0);
}

/* time-series columns: the displacement of the reference point and the roll angle (rad); with the whole rotation
   the pitch, the yaw (and the angle about the axis) too */
static PetscErrorCode Columns(FSStructure st, PetscReal t, const PetscReal y[], const PetscReal ydot[],
                              PetscReal vals[])
{
  Prescribed *p = (Prescribed *)st->data;
  PetscReal   f[NCOMP][3];
  PetscInt    k = 0;

  PetscFunctionBegin;
  ComponentsAt(p, t, f);
  for (PetscInt d = 0; d < p->dim; d++) vals[k++] = f[d][0];
  vals[k++] = f[COMP_ROLL][0];
  if (p->rotated) {
    vals[k++] = f[COMP_PITCH][0];
    vals[k++] = f[COMP_YAW][0];
    if (ComponentGiven(p, COMP_AXIS)) vals[k++] = f[COMP_AXIS][0];
  }
  PetscFunctionReturn(0);
}

/* one line per component given: what it is made of */
static PetscErrorCode View(FSStructure st, PetscViewer viewer)
{
  Prescribed *p = (Prescribed *)st->data;

  PetscFunctionBegin;
  PetscCall(PetscViewerASCIIPrintf(viewer, "prescribed motion, ramp %g s\n", (double)p->ramp));
  for (PetscInt c = 0; c < NCOMP; c++) {
    const Component *cp = &p->comp[c];
    if (!cp->nsines && !cp->npoly && !cp->file[0]) continue;
    PetscCall(PetscViewerASCIIPrintf(viewer, "  %s: %" PetscInt_FMT " sines, %" PetscInt_FMT " polynomial terms%s%s\n",
                                     CompName[c], cp->nsines, cp->npoly, cp->file[0] ? ", file " : "", cp->file));
  }
  if (p->naxis == 3)
    PetscCall(PetscViewerASCIIPrintf(viewer, "  axis direction %g,%g,%g\n", (double)p->axis[0], (double)p->axis[1],
                                     (double)p->axis[2]));
  if (p->file6[0]) PetscCall(PetscViewerASCIIPrintf(viewer, "  6-DOF file %s (x y z rx ry rz)\n", p->file6));
  if (p->rotated)
    PetscCall(PetscViewerASCIIPrintf(viewer, "  rotation Q = R_y(yaw) R_x(pitch) R_z(roll) R_n(axis), intrinsic\n"));
  PetscFunctionReturn(0);
}

static PetscErrorCode Summary(FSStructure st, FSJSON js)
{
  Prescribed *p = (Prescribed *)st->data;

  PetscFunctionBegin;
  PetscCall(FSJSONWriteReal(js, "ramp", p->ramp));
  for (PetscInt c = 0; c < NCOMP; c++) {
    const Component *cp = &p->comp[c];
    char             key[64];
    PetscCall(PetscSNPrintf(key, sizeof(key), "%s_sines", CompName[c]));
    if (cp->nsines) PetscCall(FSJSONWriteRealArray(js, key, 3 * cp->nsines, cp->sine));
    PetscCall(PetscSNPrintf(key, sizeof(key), "%s_poly", CompName[c]));
    if (cp->npoly) PetscCall(FSJSONWriteRealArray(js, key, cp->npoly, cp->poly));
    PetscCall(PetscSNPrintf(key, sizeof(key), "%s_file", CompName[c]));
    if (cp->file[0]) PetscCall(FSJSONWriteString(js, key, cp->file));
  }
  if (p->naxis == 3) PetscCall(FSJSONWriteRealArray(js, "axis_direction", 3, p->axis));
  if (p->file6[0]) PetscCall(FSJSONWriteString(js, "file", p->file6));
  PetscFunctionReturn(0);
}

static PetscErrorCode Destroy(FSStructure st)
{
  Prescribed *p = (Prescribed *)st->data;

  PetscFunctionBegin;
  for (PetscInt c = 0; c < NCOMP; c++)
    if (p->comp[c].loaded) PetscCall(FSMotionSeriesDestroy(&p->comp[c].series));
  for (PetscInt k = 0; p->loaded6 && k < 6; k++) PetscCall(FSMotionSeriesDestroy(&p->six[k]));
  PetscCall(PetscFree(st->data));
  PetscFunctionReturn(0);
}

PETSC_EXTERN PetscErrorCode FSStructureCreate_Prescribed(FSStructure st)
{
  Prescribed *p;

  PetscFunctionBegin;
  PetscCall(PetscNew(&p));
  st->data               = p;
  st->prescribed         = PETSC_TRUE;
  st->ops.setfromoptions = SetFromOptions;
  st->ops.setup          = SetUp;
  st->ops.rhs            = RHS;
  st->ops.motion         = Motion;
  st->ops.columns        = Columns;
  st->ops.view           = View;
  st->ops.summary        = Summary;
  st->ops.destroy        = Destroy;
  PetscFunctionReturn(0);
}
