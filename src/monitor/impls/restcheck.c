/*
   The at-rest check monitor (-fs_rest_check_*): over the first -fs_rest_check_time seconds of a run, warns once,
   with the numbers and what to try, when a liquid that the case started at rest (FSSolverSetLiquidAtRest(): a tank
   filled to a level) and that nothing forces (no structure) moves faster than -fs_rest_check_speed sqrt(g H), H the
   liquid's depth; and, in every run, when the time step's limit collapses below -fs_rest_check_dt of the start's. At
   its beginning it warns when a 3-D liquid at rest is less than FS_REST_MIN_DEPTH particles deep. The thresholds and
   the minimum depth are measured in docs/own-tank.md. Its options are read in the solver's options block; the run
   attaches it with or without -fs_output; what it watches comes from the solver (FSSolverGetRestView()).
*/
#include "monitor/monitorimpl.h"
#include "sys/fssys.h"

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

typedef struct {
  PetscReal time;                  /* -fs_rest_check_time: the simulated time watched from the start (0: none) */
  PetscReal speed;                 /* -fs_rest_check_speed: the largest speed of a liquid at rest, over sqrt(g H) */
  PetscReal dt_ratio;              /* -fs_rest_check_dt: the step's limit allowed down to this of the start's */
  PetscBool watch_speed, watch_dt; /* what this run's check watches (its beginning) */
  PetscBool warned_speed, warned_dt;
  PetscReal depth, g; /* the liquid's depth in a run the check watches (else 0), |g| */
  PetscReal dt0;      /* the step's limit at the start */
} FSMonitor_RestCheck;

static PetscErrorCode FSMonitorSetFromOptions_RestCheck(FSMonitor m, PetscOptionItems *PetscOptionsObject)
{
  FSMonitor_RestCheck *r = (FSMonitor_RestCheck *)m->data;

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
static PetscErrorCode FSRestMissingSettings(FSMonitor m, char text[], size_t len)
{
  size_t n = 0;

  PetscFunctionBegin;
  text[0] = 0;
  for (size_t k = 0; k < sizeof(FSRestSettings) / sizeof(FSRestSettings[0]); k++) {
    PetscBool given;
    PetscCall(PetscOptionsHasName(((PetscObject)m)->options, NULL, FSRestSettings[k][0], &given));
    if (given) continue;
    (void)snprintf(text + n, len - n, "%s%s%s%s", n ? " " : "", FSRestSettings[k][0],
                   FSRestSettings[k][1][0] ? " " : "", FSRestSettings[k][1]);
    PetscCall(PetscStrlen(text, &n));
  }
  PetscFunctionReturn(0);
}

/* what to try, for the warnings: the missing settings, a finer spacing when the liquid is shallow in particles */
static PetscErrorCode FSRestAdvice(FSMonitor m, PetscReal dx, char text[], size_t len)
{
  FSMonitor_RestCheck *r = (FSMonitor_RestCheck *)m->data;
  char                 missing[512], finer[256] = "";

  PetscFunctionBegin;
  PetscCall(FSRestMissingSettings(m, missing, sizeof(missing)));
  if (r->depth > 0 && r->depth / dx < FS_REST_MIN_DEPTH)
    (void)snprintf(finer, sizeof(finer), "a finer -fs_dx (at most %.3g for %d particles deep), ",
                   (double)(r->depth / FS_REST_MIN_DEPTH), FS_REST_MIN_DEPTH);
  (void)snprintf(text, len, "%s%s%s%s; docs/own-tank.md", finer, missing[0] ? "cases/own_tank.opts's settings (" : "",
                 missing, missing[0] ? ")" : "");
  PetscFunctionReturn(0);
}

/* the run's start: what the check watches, the liquid's depth along gravity, the step's limit at the start; the
   warning of a 3-D liquid at rest that is too shallow in particles. Nothing on a restart (its start is not the
   liquid's). */
static PetscErrorCode FSMonitorBegin_RestCheck(FSMonitor m, FSSolver s)
{
  FSMonitor_RestCheck   *r    = (FSMonitor_RestCheck *)m->data;
  MPI_Comm               comm = PetscObjectComm((PetscObject)m);
  FSSolverOutputSettings o;
  FSSolverRestView       v;
  PetscReal              v2 = 0;

  PetscFunctionBegin;
  PetscCall(FSSolverGetOutputSettings(s, &o));
  PetscCall(FSSolverGetRestView(s, &v));
  r->watch_speed = r->watch_dt = r->warned_speed = r->warned_dt = PETSC_FALSE;
  r->depth                                                      = 0;
  if (!(r->time > 0) || o.restart || v.nglobal == 0) PetscFunctionReturn(0);
  r->dt0      = v.dt_stable;
  r->watch_dt = (PetscBool)(r->dt0 > 0);
  r->g        = v.g;
  if (!v.at_rest || v.structure || !(r->g > 0)) PetscFunctionReturn(0);
  PetscCall(FSSolverMaxSpeed2(s, &v2)); /* a case may start it moving */
  if (v2 > 0) PetscFunctionReturn(0);
  r->depth       = v.depth;
  r->watch_speed = (PetscBool)(r->depth > 0);
  if (v.dim == 3 && r->watch_speed && r->depth / v.dx < FS_REST_MIN_DEPTH * (1 - 1e-9)) {
    char advice[1024], text[1536];
    PetscCall(FSRestAdvice(m, v.dx, advice, sizeof(advice)));
    (void)snprintf(text, sizeof(text),
                   "Warning: the liquid at rest is %.3g particles deep (its depth %.4g m over -fs_dx %g): a 3-D "
                   "liquid at rest needs at least %d, else the rows at the floor and at the surface stir it "
                   "(docs/own-tank.md: measured). Try %s",
                   (double)(r->depth / v.dx), (double)r->depth, (double)v.dx, FS_REST_MIN_DEPTH, advice);
    PetscCall(PetscPrintf(comm, "%s\n", text));
  }
  PetscFunctionReturn(0);
}

/* after each step of the first -fs_rest_check_time seconds: the liquid at rest's largest speed against
   -fs_rest_check_speed sqrt(g H), and the limit of the step just taken (from the state at its start) against
   -fs_rest_check_dt of the start's; each warned of once, with the step, the time, the numbers and what to try */
static PetscErrorCode FSMonitorStep_RestCheck(FSMonitor m, FSSolver s, PetscInt step, PetscReal t, PetscBool first)
{
  FSMonitor_RestCheck   *r    = (FSMonitor_RestCheck *)m->data;
  MPI_Comm               comm = PetscObjectComm((PetscObject)m);
  FSSolverOutputSettings o;
  FSSolverRestView       v;
  PetscReal              umax = 0;
  char                   advice[1024], text[2048];

  PetscFunctionBegin;
  if (first) PetscFunctionReturn(0); /* the state the run starts from: its beginning looked at it */
  if (!(r->watch_speed && !r->warned_speed) && !(r->watch_dt && !r->warned_dt)) PetscFunctionReturn(0);
  PetscCall(FSSolverGetOutputSettings(s, &o));
  if (t - o.t0 > r->time) { /* past the window: nothing more to watch */
    r->watch_speed = r->watch_dt = PETSC_FALSE;
    PetscFunctionReturn(0);
  }
  PetscCall(FSSolverGetRestView(s, &v));
  /* the largest speed now: one reduction a step while the speed is watched (a liquid at rest, within the window), and
     once when the step collapses (dt_stable is the same on every rank); a moving run's steps take no extra collective
   */
  if ((r->watch_speed && !r->warned_speed) || (r->watch_dt && !r->warned_dt && v.dt_stable < r->dt_ratio * r->dt0)) {
    PetscReal v2;
    PetscCall(FSSolverMaxSpeed2(s, &v2));
    umax = PetscSqrtReal(v2);
  }
  if (r->watch_speed && !r->warned_speed) {
    const PetscReal c = PetscSqrtReal(r->g * r->depth);
    if (umax > r->speed * c) {
      r->warned_speed = PETSC_TRUE;
      PetscCall(FSRestAdvice(m, v.dx, advice, sizeof(advice)));
      (void)snprintf(text, sizeof(text),
                     "Warning: the liquid at rest is moving: at step %" PetscInt_FMT
                     " (t = %.4g s) its largest speed is %.3g m/s, %.3g sqrt(g H) (H = %.4g m, the liquid's depth, "
                     "%.3g particles of -fs_dx %g), above -fs_rest_check_speed %g; a set-up that holds its liquid at "
                     "rest stays under 0.15 (measured with cases/own_tank.opts). Try %s",
                     step, (double)t, (double)umax, (double)(umax / c), (double)r->depth, (double)(r->depth / v.dx),
                     (double)v.dx, (double)r->speed, advice);
      PetscCall(PetscPrintf(comm, "%s\n", text));
    }
  }
  if (r->watch_dt && !r->warned_dt && v.dt_stable < r->dt_ratio * r->dt0) {
    r->warned_dt = PETSC_TRUE;
    (void)snprintf(text, sizeof(text),
                   "Warning: the time step collapsed: at step %" PetscInt_FMT
                   " (t = %.4g s) its limit (%s) is %.3g s, %.3g of the start's %.3g s (below -fs_rest_check_dt %g); "
                   "the largest speed is %.3g m/s, %.3g of -fs_c0 %g.",
                   step, (double)t, v.dt_limit, (double)v.dt_stable, (double)(v.dt_stable / r->dt0), (double)r->dt0,
                   (double)r->dt_ratio, (double)umax, (double)(umax / v.c0), (double)v.c0);
    if (r->depth > 0) { /* a liquid the case started at rest: something is wrong with the set-up */
      PetscCall(FSRestAdvice(m, v.dx, advice, sizeof(advice)));
      PetscCall(PetscStrlcat(text,
                             " The liquid moves far faster than the set-up allows: check the walls (a leak, "
                             "-fs_geometry_view) and the motion, or try ",
                             sizeof(text)));
      PetscCall(PetscStrlcat(text, advice, sizeof(text)));
    } else { /* a flow started in motion (a dam break, a release): impacts shorten the step; what to do about it */
      if (umax > 0.1 * v.c0)
        PetscCall(PetscStrlcat(text, " The liquid moves faster than c0/10: raise -fs_c0 for this flow.", sizeof(text)));
      if (v.dt_limit_term)
        PetscCall(PetscStrlcat(text,
                               " A term's diffusivity sets the step (it grows with the strain rate): -fs_delta_split "
                               "takes the density diffusion out of the step (docs/performance.md).",
                               sizeof(text)));
    }
    PetscCall(PetscPrintf(comm, "%s\n", text));
  }
  PetscFunctionReturn(0);
}

static PetscErrorCode FSMonitorView_RestCheck(FSMonitor m, PetscViewer viewer)
{
  FSMonitor_RestCheck *r = (FSMonitor_RestCheck *)m->data;

  PetscFunctionBegin;
  if (r->time > 0)
    PetscCall(PetscViewerASCIIPrintf(viewer, "the at-rest check over the first %g s\n", (double)r->time));
  else PetscCall(PetscViewerASCIIPrintf(viewer, "no at-rest check (-fs_rest_check_time 0)\n"));
  PetscFunctionReturn(0);
}

static PetscErrorCode FSMonitorDestroy_RestCheck(FSMonitor m)
{
  PetscFunctionBegin;
  PetscCall(PetscFree(m->data));
  PetscFunctionReturn(0);
}

/* FSMonitorCreate_RestCheck - the at-rest check (FSMONITORRESTCHECK): warnings on the terminal. */
PetscErrorCode FSMonitorCreate_RestCheck(FSMonitor m)
{
  FSMonitor_RestCheck *r;

  PetscFunctionBegin;
  PetscCall(PetscNew(&r));
  r->time                = 0.5; /* docs/own-tank.md: the thresholds measured */
  r->speed               = 0.25;
  r->dt_ratio            = 0.25;
  m->data                = r;
  m->ops->setfromoptions = FSMonitorSetFromOptions_RestCheck;
  m->ops->begin          = FSMonitorBegin_RestCheck;
  m->ops->step           = FSMonitorStep_RestCheck;
  m->ops->view           = FSMonitorView_RestCheck;
  m->ops->destroy        = FSMonitorDestroy_RestCheck;
  PetscFunctionReturn(0);
}
