/*
   The TS type "rk4lean": the classical fourth-order Runge-Kutta method kept in three or four vectors
   of the state's size where TSRK keeps nine (the state, four stages and four rates). A step of h
   from (t, U), with the state U, one stage Y, one rate k and the running sum S of the update:
     k1 = F(t, U),             S = U + h/6 k1,  Y = U + h/2 k1
     k2 = F(t + h/2, Y),       S += h/3 k2,     Y = U + h/2 k2
     k3 = F(t + h/2, Y),       S += h/3 k3,     Y = U + h k3
     k4 = F(t + h, Y),         S += h/6 k4,     Y = U,  U = S
   The same method as -ts_type rk -ts_rk_type 4, summed in another order (the results agree to
   round-off). When the right-hand side function may write its rate over its state (it reads all of
   the state before it writes: FSTSRK4LeanSetInPlace) each rate k_i goes over the stage Y it is
   evaluated at and three vectors do (U, Y, S); else k has a vector of its own. After a step, Y holds
   the state at its start (the solver's checks read it) and S (or k) is free until the next step (the
   solver's output evaluations write into it). No error estimate: the step is the one set with
   TSSetTimeStep(), as the solver's stable step is.
*/
#include "solver/solverimpl.h"
#include <petsc/private/tsimpl.h>

typedef struct {
  Vec       Y;       /* the stage's state (in place: then its rate); after a step, the state at its start */
  Vec       K;       /* the rate at the stage; not allocated in place (then the rate goes over Y) */
  Vec       S;       /* U + h sum_j b_j k_j, summed so far */
  PetscBool allowed; /* the right-hand side may write its rate over its state (FSTSRK4LeanSetInPlace) */
  PetscBool use;     /* -ts_rk4lean_in_place: then do so (both: three vectors, from the set-up) */
  PetscBool started; /* Y holds the state at the start of the last step */
} TS_RK4Lean;

/* F(t, X) into R, as TSComputeRHSFunction() does it, but allowing R == X (which it refuses: it locks X) */
static PetscErrorCode TSRK4LeanRHS(TS ts, PetscReal t, Vec X, Vec R)
{
  TSRHSFunction rhs;
  void         *ctx;

  PetscFunctionBegin;
  if (X != R) {
    PetscCall(TSComputeRHSFunction(ts, t, X, R));
    PetscFunctionReturn(0);
  }
  PetscCall(TSGetRHSFunction(ts, NULL, &rhs, &ctx));
  PetscCheck(rhs, PetscObjectComm((PetscObject)ts), PETSC_ERR_USER, "rk4lean needs a right-hand side function");
  PetscCall(PetscLogEventBegin(TS_FunctionEval, X, R, 0, 0));
  PetscCallBack("TS callback right-hand-side", (*rhs)(ts, t, X, R, ctx));
  ts->rhsfuncs++;
  PetscCall(PetscLogEventEnd(TS_FunctionEval, X, R, 0, 0));
  PetscFunctionReturn(0);
}

static PetscErrorCode TSStep_RK4Lean(TS ts)
{
  TS_RK4Lean     *rk = (TS_RK4Lean *)ts->data;
  const PetscReal t = ts->ptime, h = ts->time_step;
  const PetscReal c[4] = {0, 0.5, 0.5, 1};                     /* the stages' times, in h */
  const PetscReal a[3] = {0.5 * h, 0.5 * h, h};                /* the next stage: Y = U + a_i k_i */
  const PetscReal b[4] = {h / 6.0, h / 3.0, h / 3.0, h / 6.0}; /* the update: U + sum_i b_i k_i */
  Vec             U    = ts->vec_sol;

  PetscFunctionBegin;
  rk->started = PETSC_FALSE;
  for (PetscInt i = 0; i < 4; i++) {
    Vec X = i ? rk->Y : U;
    Vec R = rk->K ? rk->K : rk->Y; /* the rate: in place over the stage's state (from U into Y first) */
    PetscCall(TSPreStage(ts, t + c[i] * h));
    PetscCall(TSPostStage(ts, t + c[i] * h, i, &X)); /* the stage's state is final: before it is evaluated, as TSRK */
    PetscCall(TSRK4LeanRHS(ts, t + c[i] * h, X, R));
    if (i == 0) PetscCall(VecWAXPY(rk->S, b[0], R, U));
    else PetscCall(VecAXPY(rk->S, b[i], R));
    if (i < 3 && R == rk->Y) PetscCall(VecAYPX(rk->Y, a[i], U)); /* Y = U + a_i k_i, k_i in Y */
    else if (i < 3) PetscCall(VecWAXPY(rk->Y, a[i], R, U));
  }
  PetscCall(VecCopy(U, rk->Y)); /* S = U + sum b_i k_i is the new state; Y keeps the old, S (or K) is free */
  PetscCall(VecCopy(rk->S, U));
  rk->started = PETSC_TRUE;
  ts->ptime += h;
  PetscFunctionReturn(0);
}

static PetscErrorCode TSSetUp_RK4Lean(TS ts)
{
  TS_RK4Lean *rk = (TS_RK4Lean *)ts->data;

  PetscFunctionBegin;
  PetscCall(VecDuplicate(ts->vec_sol, &rk->Y));
  if (!(rk->allowed && rk->use)) PetscCall(VecDuplicate(ts->vec_sol, &rk->K));
  PetscCall(VecDuplicate(ts->vec_sol, &rk->S));
  rk->started = PETSC_FALSE;
  PetscFunctionReturn(0);
}

static PetscErrorCode TSReset_RK4Lean(TS ts)
{
  TS_RK4Lean *rk = (TS_RK4Lean *)ts->data;

  PetscFunctionBegin;
  PetscCall(VecDestroy(&rk->Y));
  PetscCall(VecDestroy(&rk->K));
  PetscCall(VecDestroy(&rk->S));
  rk->started = PETSC_FALSE;
  PetscFunctionReturn(0);
}

static PetscErrorCode TSDestroy_RK4Lean(TS ts)
{
  PetscFunctionBegin;
  PetscCall(TSReset_RK4Lean(ts));
  PetscCall(PetscFree(ts->data));
  PetscFunctionReturn(0);
}

static PetscErrorCode TSSetFromOptions_RK4Lean(TS ts, PetscOptionItems *PetscOptionsObject)
{
  TS_RK4Lean *rk = (TS_RK4Lean *)ts->data;

  PetscFunctionBegin;
  PetscOptionsHeadBegin(PetscOptionsObject, "RK4Lean options");
  PetscCall(
      PetscOptionsBool("-ts_rk4lean_in_place",
                       "Write each stage's rate over the stage where the right-hand side allows it (3 vectors, not 4)",
                       "FSTSRK4LeanSetInPlace", rk->use, &rk->use, NULL));
  PetscOptionsHeadEnd();
  PetscFunctionReturn(0);
}

static PetscErrorCode TSView_RK4Lean(TS ts, PetscViewer viewer)
{
  TS_RK4Lean *rk = (TS_RK4Lean *)ts->data;
  PetscBool   ascii;

  PetscFunctionBegin;
  PetscCall(PetscObjectTypeCompare((PetscObject)viewer, PETSCVIEWERASCII, &ascii));
  if (ascii && rk->allowed && rk->use) /* what the set-up does (did) */
    PetscCall(PetscViewerASCIIPrintf(
        viewer, "  classical RK4 (4 stages, order 4) in 3 vectors: state, stage (its rate over it), sum\n"));
  else if (ascii)
    PetscCall(
        PetscViewerASCIIPrintf(viewer, "  classical RK4 (4 stages, order 4) in 4 vectors: state, stage, rate, sum\n"));
  PetscFunctionReturn(0);
}

/* the stage vector (the only one a step keeps between its stages) */
static PetscErrorCode TSGetStages_RK4Lean(TS ts, PetscInt *ns, Vec **Y)
{
  TS_RK4Lean *rk = (TS_RK4Lean *)ts->data;

  PetscFunctionBegin;
  if (ns) *ns = rk->Y ? 1 : 0;
  if (Y) *Y = rk->Y ? &rk->Y : NULL;
  PetscFunctionReturn(0);
}

static PetscErrorCode TSCreate_RK4Lean(TS ts)
{
  TS_RK4Lean *rk;

  PetscFunctionBegin;
  PetscCall(PetscNew(&rk));
  rk->use                 = PETSC_TRUE;
  ts->data                = (void *)rk;
  ts->ops->setup          = TSSetUp_RK4Lean;
  ts->ops->step           = TSStep_RK4Lean;
  ts->ops->reset          = TSReset_RK4Lean;
  ts->ops->destroy        = TSDestroy_RK4Lean;
  ts->ops->view           = TSView_RK4Lean;
  ts->ops->setfromoptions = TSSetFromOptions_RK4Lean;
  ts->ops->getstages      = TSGetStages_RK4Lean;
  ts->default_adapt_type  = TSADAPTNONE;
  ts->usessnes            = PETSC_FALSE;
  PetscFunctionReturn(0);
}

/*
   FSTSRegisterRK4Lean - adds the TS type FSTSRK4LEAN ("rk4lean") to PETSc's table of TS types (-ts_type
   rk4lean). Registering again replaces the entry with itself, so every TS set-up may call it (and the type
   is there again after a PetscFinalize() and a new PetscInitialize(), which empty the table).

   Not collective
*/
PetscErrorCode FSTSRegisterRK4Lean(void)
{
  PetscFunctionBegin;
  PetscCall(TSRegister(FSTSRK4LEAN, TSCreate_RK4Lean));
  PetscFunctionReturn(0);
}

/*
   FSTSRK4LeanGetWork - for a TS of type rk4lean: the state at the start of its last step (NULL before a
   step, or after a reset) and a vector of the state's layout that is free until the next step (NULL
   before the set-up); both NULL for another type.

   Not collective
*/
PetscErrorCode FSTSRK4LeanGetWork(TS ts, Vec *start, Vec *free)
{
  PetscBool is;

  PetscFunctionBegin;
  if (start) *start = NULL;
  if (free) *free = NULL;
  PetscCall(PetscObjectTypeCompare((PetscObject)ts, FSTSRK4LEAN, &is));
  if (is && ts->setupcalled) {
    TS_RK4Lean *rk = (TS_RK4Lean *)ts->data;
    if (start && rk->started) *start = rk->Y;
    if (free) *free = rk->K ? rk->K : rk->S;
  }
  PetscFunctionReturn(0);
}

/*
   FSTSRK4LeanGetNumVectors - for a TS of type rk4lean that is set up: the number of state-sized vectors
   it allocated (3, or 2 in place); 0 otherwise.

   Not collective
*/
PetscErrorCode FSTSRK4LeanGetNumVectors(TS ts, PetscInt *n)
{
  PetscBool is;

  PetscFunctionBegin;
  *n = 0;
  PetscCall(PetscObjectTypeCompare((PetscObject)ts, FSTSRK4LEAN, &is));
  if (is && ts->setupcalled) {
    TS_RK4Lean *rk = (TS_RK4Lean *)ts->data;
    *n             = (rk->Y ? 1 : 0) + (rk->K ? 1 : 0) + (rk->S ? 1 : 0);
  }
  PetscFunctionReturn(0);
}

/*
   FSTSRK4LeanSetInPlace - says that the TS's right-hand side function reads all of its state before it
   writes any of its rate, so that a TS of type rk4lean may evaluate it with the rate's vector the state's
   own and keep three state-sized vectors instead of four (unless -ts_rk4lean_in_place false). Without
   effect for another type. Call it before TSSetUp().

   Logically collective
*/
PetscErrorCode FSTSRK4LeanSetInPlace(TS ts, PetscBool inplace)
{
  PetscBool is;

  PetscFunctionBegin;
  PetscCall(PetscObjectTypeCompare((PetscObject)ts, FSTSRK4LEAN, &is));
  if (!is) PetscFunctionReturn(0);
  PetscCheck(!ts->setupcalled, PetscObjectComm((PetscObject)ts), PETSC_ERR_ARG_WRONGSTATE,
             "FSTSRK4LeanSetInPlace() after TSSetUp()");
  ((TS_RK4Lean *)ts->data)->allowed = inplace;
  PetscFunctionReturn(0);
}
