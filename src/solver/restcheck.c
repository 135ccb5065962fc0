/*
   The at-rest check (-fs_rest_check_*): over the first -fs_rest_check_time seconds of a run, warns once, with the
   numbers and what to try, when a liquid that the case started at rest (FSSolverSetLiquidAtRest(): a tank filled to
   a level) and that nothing forces (no structure) moves faster than -fs_rest_check_speed sqrt(g H), H the liquid's
   depth; and, in every run, when the time step's limit collapses below -fs_rest_check_dt of the start's. At the
   start it warns when a 3-D liquid at rest is less than FS_REST_MIN_DEPTH particles deep. The thresholds and the
   minimum depth are measured in docs/own-tank.md.
*/
#include "solver/solverimpl.h"

/* the depth in particles below which a 3-D liquid at rest is warned of (docs/own-tank.md: measured) */
#define FS_REST_MIN_DEPTH 4

/* the settings of cases/own_tank.opts that hold a 3-D tank at rest, each with the value it sets */
static const char *const FSRestSettings[][2] = {
    {"-fs_c0", "8"},
    {"-fs_relax_time", "0.1"},
    {"-fs_delta_min", "0.1"},
    {"-fs_delta_hydrostatic", ""},
    {"-fs_walls_visibility", "all"},
    {"-fs_walls_repulsion", "0.5"},
};

/*
   FSSolverSetLiquidAtRest - says that the case starts its liquid at rest in equilibrium under gravity (a tank
   filled to a level), and how deep it is, so that the at-rest check watches it when nothing forces it.

   Logically collective

   Input Parameters:
+  s       - the solver, from the case's setup
.  at_rest - whether the liquid starts at rest
-  depth   - the liquid's depth, from the lowest point of the container to the free surface

   Options Database Keys:
+  -fs_rest_check_time T  - the simulated time watched from the start (0.5 s; 0: no check)
.  -fs_rest_check_speed F - warn when the largest speed exceeds F sqrt(g H), H the liquid's depth (0.25)
-  -fs_rest_check_dt F    - warn when the time step's limit falls below F of the start's (0.25)

.seealso: FSSolverSetUp()
*/
PetscErrorCode FSSolverSetLiquidAtRest(FSSolver s, PetscBool at_rest, PetscReal depth)
{
  PetscFunctionBegin;
  PetscValidHeaderSpecific(s, FSSOLVER_CLASSID, 1);
  s->mon.rest.at_rest = at_rest;
  s->mon.rest.depth0  = depth;
  PetscFunctionReturn(0);
}

/* FSSolverOptionsRestCheck - the at-rest check's options, in the solver's options block */
PetscErrorCode FSSolverOptionsRestCheck(FSSolver s, PetscOptionItems *PetscOptionsObject)
{
  FSRestCheck *r = &s->mon.rest;

  PetscFunctionBegin;
  PetscCall(FSOptionsReal(PetscOptionsObject, "-fs_rest_check_time",
                          "Simulated time from the start over which a liquid at rest is checked to stay at rest, and "
                          "every run's time step not to collapse (0: no check)",
                          "FSSolverSetLiquidAtRest", &r->time, NULL, 0, PETSC_INFINITY, FS_RANGE_CLOSED));
  PetscCall(FSOptionsReal(PetscOptionsObject, "-fs_rest_check_speed",
                          "Warn when a liquid at rest moves faster than this times sqrt(g H), H its depth",
                          "FSSolverSetLiquidAtRest", &r->speed, NULL, 0, PETSC_INFINITY, FS_RANGE_OPEN_LOWER));
  PetscCall(FSOptionsReal(PetscOptionsObject, "-fs_rest_check_dt",
                          "Warn when the time step's limit falls below this fraction of the start's",
                          "FSSolverSetLiquidAtRest", &r->dt_ratio, NULL, 0, 1, FS_RANGE_OPEN));
  PetscFunctionReturn(0);
}

/* the settings of cases/own_tank.opts that this run does not give, for the advice */
static PetscErrorCode FSRestMissingSettings(FSSolver s, char text[], size_t len)
{
  size_t n = 0;

  PetscFunctionBegin;
  text[0] = 0;
  for (size_t k = 0; k < sizeof(FSRestSettings) / sizeof(FSRestSettings[0]); k++) {
    PetscBool given;
    PetscCall(PetscOptionsHasName(((PetscObject)s)->options, NULL, FSRestSettings[k][0], &given));
    if (given) continue;
    (void)snprintf(text + n, len - n, "%s%s%s%s", n ? " " : "", FSRestSettings[k][0],
                   FSRestSettings[k][1][0] ? " " : "", FSRestSettings[k][1]);
    PetscCall(PetscStrlen(text, &n));
  }
  PetscFunctionReturn(0);
}

/* what to try, for the warnings: the missing settings, a finer spacing when the liquid is shallow in particles */
static PetscErrorCode FSRestAdvice(FSSolver s, char text[], size_t len)
{
  FSRestCheck *r = &s->mon.rest;
  char         missing[512], finer[256] = "";

  PetscFunctionBegin;
  PetscCall(FSRestMissingSettings(s, missing, sizeof(missing)));
  if (r->depth > 0 && r->depth / s->opt.dx < FS_REST_MIN_DEPTH)
    (void)snprintf(finer, sizeof(finer), "a finer -fs_dx (at most %.3g for %d particles deep), ",
                   (double)(r->depth / FS_REST_MIN_DEPTH), FS_REST_MIN_DEPTH);
  (void)snprintf(text, len, "%s%s%s%s; docs/own-tank.md", finer, missing[0] ? "cases/own_tank.opts's settings (" : "",
                 missing, missing[0] ? ")" : "");
  PetscFunctionReturn(0);
}

/*
   FSSolverRestCheckBegin - at the start of the run (FSSolverMonitorBegin()): what the check watches, the liquid's
   depth along gravity, the step's limit at the start; the warning of a 3-D liquid at rest that is too shallow in
   particles. Nothing on a restart (its start is not the liquid's).

   Collective
*/
PetscErrorCode FSSolverRestCheckBegin(FSSolver s)
{
  FSRestCheck   *r    = &s->mon.rest;
  MPI_Comm       comm = PetscObjectComm((PetscObject)s);
  const PetscInt dim  = s->opt.dim;
  PetscReal      g = 0, v2 = 0;

  PetscFunctionBegin;
  r->watch_speed = r->watch_dt = r->warned_speed = r->warned_dt = PETSC_FALSE;
  r->depth                                                      = 0;
  if (!(r->time > 0) || s->opt.restart[0] || s->pw.nglobal_particles == 0) PetscFunctionReturn(0);
  r->dt0      = s->state.dt_stable;
  r->watch_dt = (PetscBool)(r->dt0 > 0);
  for (PetscInt d = 0; d < dim; d++) g += s->opt.gravity[d] * s->opt.gravity[d];
  r->g = PetscSqrtReal(g);
  if (!r->at_rest || s->structure || !(r->g > 0)) PetscFunctionReturn(0);
  { /* a case may start it moving */
    PetscCall(FSSolverOwnedMaxSpeed2(s, &v2));
    PetscCallMPI(MPI_Allreduce(MPI_IN_PLACE, &v2, 1, MPIU_REAL, MPI_MAX, comm));
    if (v2 > 0) PetscFunctionReturn(0);
  }
  r->depth       = r->depth0;
  r->watch_speed = (PetscBool)(r->depth > 0);
  if (dim == 3 && r->watch_speed && r->depth / s->opt.dx < FS_REST_MIN_DEPTH * (1 - 1e-9)) {
    char advice[1024], text[1536];
    PetscCall(FSRestAdvice(s, advice, sizeof(advice)));
    (void)snprintf(text, sizeof(text),
                   "Warning: the liquid at rest is %.3g particles deep (its depth %.4g m over -fs_dx %g): a 3-D "
                   "liquid at rest needs at least %d, else the rows at the floor and at the surface stir it "
                   "(docs/own-tank.md: measured). Try %s",
                   (double)(r->depth / s->opt.dx), (double)r->depth, (double)s->opt.dx, FS_REST_MIN_DEPTH, advice);
    PetscCall(PetscPrintf(comm, "%s\n", text));
  }
  PetscFunctionReturn(0);
}

/*
   FSSolverRestCheck - after each step of the first -fs_rest_check_time seconds (FSSolverMonitor()): the liquid at
   rest's largest speed against -fs_rest_check_speed sqrt(g H), and the limit of the step just taken (from the state
   at its start) against -fs_rest_check_dt of the start's; each warned of once, with the step, the time, the numbers
   and what to try.

   Collective
*/
PetscErrorCode FSSolverRestCheck(FSSolver s)
{
  FSRestCheck *r    = &s->mon.rest;
  MPI_Comm     comm = PetscObjectComm((PetscObject)s);
  PetscReal    t, umax = 0;
  PetscInt     step;
  char         advice[1024], text[2048];

  PetscFunctionBegin;
  if (!(r->watch_speed && !r->warned_speed) && !(r->watch_dt && !r->warned_dt)) PetscFunctionReturn(0);
  PetscCall(TSGetTime(s->ts, &t));
  if (t - s->mon.t0 > r->time) { /* past the window: nothing more to watch */
    r->watch_speed = r->watch_dt = PETSC_FALSE;
    PetscFunctionReturn(0);
  }
  PetscCall(TSGetStepNumber(s->ts, &step));
  /* the largest speed now: one reduction a step while the speed is watched (a liquid at rest, within the window), and
     once when the step collapses (dt_stable is the same on every rank); a moving run's steps take no extra collective
   */
  if ((r->watch_speed && !r->warned_speed) ||
      (r->watch_dt && !r->warned_dt && s->state.dt_stable < r->dt_ratio * r->dt0)) {
    PetscReal v2;
    PetscCall(FSSolverOwnedMaxSpeed2(s, &v2));
    PetscCallMPI(MPI_Allreduce(MPI_IN_PLACE, &v2, 1, MPIU_REAL, MPI_MAX, comm));
    umax = PetscSqrtReal(v2);
  }
  if (r->watch_speed && !r->warned_speed) {
    const PetscReal c = PetscSqrtReal(r->g * r->depth);
    if (umax > r->speed * c) {
      r->warned_speed = PETSC_TRUE;
      PetscCall(FSRestAdvice(s, advice, sizeof(advice)));
      (void)snprintf(text, sizeof(text),
                     "Warning: the liquid at rest is moving: at step %" PetscInt_FMT
                     " (t = %.4g s) its largest speed is %.3g m/s, %.3g sqrt(g H) (H = %.4g m, the liquid's depth, "
                     "%.3g particles of -fs_dx %g), above -fs_rest_check_speed %g; a set-up that holds its liquid at "
                     "rest stays under 0.15 (measured with cases/own_tank.opts). Try %s",
                     step, (double)t, (double)umax, (double)(umax / c), (double)r->depth,
                     (double)(r->depth / s->opt.dx), (double)s->opt.dx, (double)r->speed, advice);
      PetscCall(PetscPrintf(comm, "%s\n", text));
    }
  }
  if (r->watch_dt && !r->warned_dt && s->state.dt_stable < r->dt_ratio * r->dt0) {
    const char *limit;
    r->warned_dt = PETSC_TRUE;
    PetscCall(FSSolverDtLimitName(s, s->state.dt_limit, &limit));
    (void)snprintf(text, sizeof(text),
                   "Warning: the time step collapsed: at step %" PetscInt_FMT
                   " (t = %.4g s) its limit (%s) is %.3g s, %.3g of the start's %.3g s (below -fs_rest_check_dt %g); "
                   "the largest speed is %.3g m/s, %.3g of -fs_c0 %g.",
                   step, (double)t, limit, (double)s->state.dt_stable, (double)(s->state.dt_stable / r->dt0),
                   (double)r->dt0, (double)r->dt_ratio, (double)umax, (double)(umax / s->opt.c0), (double)s->opt.c0);
    if (r->depth > 0) { /* a liquid the case started at rest: something is wrong with the set-up */
      PetscCall(FSRestAdvice(s, advice, sizeof(advice)));
      PetscCall(PetscStrlcat(text,
                             " The liquid moves far faster than the set-up allows: check the walls (a leak, "
                             "-fs_geometry_view) and the motion, or try ",
                             sizeof(text)));
      PetscCall(PetscStrlcat(text, advice, sizeof(text)));
    } else { /* a flow started in motion (a dam break, a release): impacts shorten the step; what to do about it */
      if (umax > 0.1 * s->opt.c0)
        PetscCall(PetscStrlcat(text, " The liquid moves faster than c0/10: raise -fs_c0 for this flow.", sizeof(text)));
      if (s->state.dt_limit >= FS_DT_TERM)
        PetscCall(PetscStrlcat(text,
                               " A term's diffusivity sets the step (it grows with the strain rate): -fs_delta_split "
                               "takes the density diffusion out of the step (docs/performance.md).",
                               sizeof(text)));
    }
    PetscCall(PetscPrintf(comm, "%s\n", text));
  }
  PetscFunctionReturn(0);
}
