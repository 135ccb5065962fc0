/*
   When the particles' lists are rebuilt (-fs_neighbour_rebuild): the migration, the ordering by cell,
   the halo, the cell list, the candidate lists and the walls' candidate elements are built with a
   skin of -fs_halo_skin h beyond the kernel support, and stay valid while no particle has moved more
   than half the skin since (two particles then come closer by less than the skin, so every pair within
   the support is still a candidate and every ghost it needs is still in the halo). With auto they are
   rebuilt only when the next step could break this; with always after every step.
*/
#include "solver/solverimpl.h"

/* the next step's largest displacement is taken as at most this times dt |u|max: the stages of an
   explicit integrator move a particle by dt times a speed that the step's accelerations change little
   (the skin's time-step limit, 0.4 skin h/|u|max against the check's skin/2, leaves 1.25) */
#define FS_REBUILD_SAFETY 1.5

/*
   FSSolverMarkBuild - records the owned particles' positions of the lists just built (from the work
   records) in the swarm's build field, from which the displacements are measured until the next build
   and which the checkpoints keep (a restart rebuilds the same lists from them).

   Not collective
*/
PetscErrorCode FSSolverMarkBuild(FSSolver s)
{
  const PetscInt dim = s->opt.dim, S = s->pw.stride, n = s->pw.nowned;
  PetscReal     *xb;

  PetscFunctionBegin;
  PetscCall(DMSwarmGetField(s->swarm, FS_FIELD_BUILD, NULL, NULL, (void **)&xb));
  for (PetscInt p = 0; p < n; p++)
    for (PetscInt d = 0; d < dim; d++) xb[p * dim + d] = s->pw.rec[p * S + d];
  PetscCall(DMSwarmRestoreField(s->swarm, FS_FIELD_BUILD, NULL, NULL, (void **)&xb));
  s->pw.moved = 0;
  PetscFunctionReturn(0);
}

/*
   FSSolverSwapBuildPositions - swaps the swarm's positions and build positions: a restart migrates and
   orders the particles by their positions at the checkpoint's last build, as that build did.

   Not collective
*/
PetscErrorCode FSSolverSwapBuildPositions(FSSolver s)
{
  PetscInt   n;
  PetscReal *x, *xb;

  PetscFunctionBegin;
  PetscCall(DMSwarmGetLocalSize(s->swarm, &n));
  PetscCall(DMSwarmGetField(s->swarm, FS_FIELD_POSITION, NULL, NULL, (void **)&x));
  PetscCall(DMSwarmGetField(s->swarm, FS_FIELD_BUILD, NULL, NULL, (void **)&xb));
  for (PetscInt k = 0; k < n * s->opt.dim; k++) {
    const PetscReal a = x[k];
    x[k]              = xb[k];
    xb[k]             = a;
  }
  PetscCall(DMSwarmRestoreField(s->swarm, FS_FIELD_BUILD, NULL, NULL, (void **)&xb));
  PetscCall(DMSwarmRestoreField(s->swarm, FS_FIELD_POSITION, NULL, NULL, (void **)&x));
  PetscFunctionReturn(0);
}

/*
   FSSolverRecordsAtBuild - puts the owned particles' build positions (the swarm's build field) into
   the work records, for a restart's build of the halo and the lists; the next pack puts the state's
   positions back.

   Not collective
*/
PetscErrorCode FSSolverRecordsAtBuild(FSSolver s)
{
  const PetscInt dim = s->opt.dim, S = s->pw.stride, n = s->pw.nowned;
  PetscReal     *xb;

  PetscFunctionBegin;
  PetscCall(DMSwarmGetField(s->swarm, FS_FIELD_BUILD, NULL, NULL, (void **)&xb));
  for (PetscInt p = 0; p < n; p++)
    for (PetscInt d = 0; d < dim; d++) s->pw.rec[p * S + d] = xb[p * dim + d];
  PetscCall(DMSwarmRestoreField(s->swarm, FS_FIELD_BUILD, NULL, NULL, (void **)&xb));
  PetscFunctionReturn(0);
}

/*
   FSSolverRebuildNeeded - after a step (and its bounces, the swarm holding the state), whether the
   lists must be rebuilt before the next one, and whether the particles are then ordered by cell.

   With auto: the largest displacement D since the build and the largest speed u are reduced over the
   ranks (every rank takes the same decision); the next step's dt is at most dt_max, the stable step of
   this speed and of the viscosities of the integrator's last right-hand side (FSSolverStableDtOf: what
   the next step takes unless the final time or an adaptive integrator shortens it), so it moves a
   particle by about d = max(dt_max u, the last step's largest move scaled by dt_max/dt); the lists are
   rebuilt when 2 (D + 1.5 d) would
   exceed the skin. The ordering follows -fs_sort_interval, counted from the last ordering. With always:
   every step, ordered at the steps that are multiples of -fs_sort_interval (as before the lazy rebuild).

   Collective
*/
PetscErrorCode FSSolverRebuildNeeded(FSSolver s, PetscBool *rebuild, PetscBool *sort)
{
  PetscReal loc[FS_REBUILD_N], nu;
  PetscInt  source;

  PetscFunctionBegin;
  if (s->opt.rebuild == FS_REBUILD_ALWAYS) {
    PetscCall(FSSolverRebuildDecide(s, NULL, 0, 0, rebuild, sort));
    PetscFunctionReturn(0);
  }
  PetscCall(FSSolverRebuildNeededLocal(s, loc));
  PetscCall(FSSolverReduceWithViscosity(s, FS_REBUILD_N, loc, &nu, &source)); /* one reduction */
  PetscCall(FSSolverRebuildDecide(s, loc, nu, source, rebuild, sort));
  PetscFunctionReturn(0);
}

/*
   FSSolverRebuildNeededLocal - FSSolverRebuildNeeded()'s pass over this rank's particles: the squares of the largest
   move since the build, speed and move over the step, loc[FS_REBUILD_N], to be reduced (MPI_MAX).

   Not collective
*/
PetscErrorCode FSSolverRebuildNeededLocal(FSSolver s, PetscReal loc[])
{
  const PetscInt     dim = s->opt.dim;
  const PetscInt     US  = s->state.ustride;
  PetscReal         *x, *v, *xb;
  const PetscScalar *u0;
  Vec                U0;
  PetscInt           n;

  PetscFunctionBegin;
  loc[0] = loc[1] = loc[2] = 0;
  PetscCall(DMSwarmGetLocalSize(s->swarm, &n));
  PetscCheck(n == s->pw.nowned, PETSC_COMM_SELF, PETSC_ERR_PLIB, "The swarm changed size since the lists were built");
  PetscCall(DMSwarmGetField(s->swarm, FS_FIELD_POSITION, NULL, NULL, (void **)&x));
  PetscCall(DMSwarmGetField(s->swarm, FS_FIELD_VELOCITY, NULL, NULL, (void **)&v));
  PetscCall(DMSwarmGetField(s->swarm, FS_FIELD_BUILD, NULL, NULL, (void **)&xb));
  PetscCall(FSSolverGetStepStart(s, &U0));
  PetscCall(VecGetArrayRead(U0, &u0));
  for (PetscInt p = 0; p < n; p++) {
    PetscReal d2 = 0, w2 = 0, s2 = 0;
    for (PetscInt d = 0; d < dim; d++) {
      d2 += PetscSqr(x[p * dim + d] - xb[p * dim + d]);
      w2 += PetscSqr(v[p * dim + d]);
      s2 += PetscSqr(x[p * dim + d] - u0[p * US + d]);
    }
    loc[0] = PetscMax(loc[0], d2);
    loc[1] = PetscMax(loc[1], w2);
    loc[2] = PetscMax(loc[2], s2);
  }
  PetscCall(VecRestoreArrayRead(U0, &u0));
  PetscCall(DMSwarmRestoreField(s->swarm, FS_FIELD_BUILD, NULL, NULL, (void **)&xb));
  PetscCall(DMSwarmRestoreField(s->swarm, FS_FIELD_VELOCITY, NULL, NULL, (void **)&v));
  PetscCall(DMSwarmRestoreField(s->swarm, FS_FIELD_POSITION, NULL, NULL, (void **)&x));
  PetscFunctionReturn(0);
}

/*
   FSSolverRebuildDecide - FSSolverRebuildNeeded()'s decision from the reduced values of FSSolverRebuildNeededLocal()
   and the viscosity bound (nu, source: FSSolverReduceWithViscosity()); loc is not read with -fs_rebuild always.

   Not collective (the same decision on every rank)
*/
PetscErrorCode FSSolverRebuildDecide(FSSolver s, const PetscReal loc[], PetscReal nu, PetscInt source,
                                     PetscBool *rebuild, PetscBool *sort)
{
  PetscReal u, dtmax, next, t, tprev, skin = s->opt.halo_skin * s->opt.h;
  PetscInt  step, limit;

  PetscFunctionBegin;
  PetscCall(TSGetStepNumber(s->ts, &step));
  if (s->opt.rebuild == FS_REBUILD_ALWAYS) {
    *rebuild = PETSC_TRUE;
    *sort    = (PetscBool)(step % s->opt.sort_interval == 0);
    PetscFunctionReturn(0);
  }
  s->pw.moved = PetscSqrtReal(loc[0]);
  u           = PetscSqrtReal(loc[1]);
  FSSolverStableDtOf(s, u, nu, source, &dtmax, &limit);
  /* the next step's move: dt_max u, or the last step's move scaled to dt_max (it holds the rates that
     move particles besides u, e.g. shifting, and the bounces) */
  next = dtmax * u;
  PetscCall(TSGetTime(s->ts, &t));
  PetscCall(TSGetPrevTime(s->ts, &tprev));
  if (t > tprev) next = PetscMax(next, PetscSqrtReal(loc[2]) * dtmax / (t - tprev));
  *rebuild = (PetscBool)(2 * (s->pw.moved + FS_REBUILD_SAFETY * next) > skin);
  *sort    = (PetscBool)(*rebuild && step - s->pw.sort_step >= s->opt.sort_interval);
  PetscCall(PetscInfo(s, "step %" PetscInt_FMT ": moved %g, next %g, skin %g: %s\n", step, (double)s->pw.moved,
                      (double)next, (double)skin, *rebuild ? "rebuild" : "keep"));
  PetscFunctionReturn(0);
}

/*
   FSSolverKeepLists - after a step that keeps the lists: the state vector takes the swarm's fields
   (the bounces changed some) in the same layout, unless packed says it took them already, and TS is told that
   the state changed outside of it. The ghosts are refreshed by every right-hand side.

   Collective
*/
PetscErrorCode FSSolverKeepLists(FSSolver s, PetscBool packed)
{
  PetscFunctionBegin;
  if (!packed) PetscCall(FSSolverPackState(s));
  PetscCall(TSRestartStep(s->ts));
  PetscFunctionReturn(0);
}

/*
   FSSolverGetWork - each owned particle's work in a right-hand side, counted in fluid candidate pairs (the unit of
   the passes over the pairs): 1 plus its candidates plus its walls' work (FSBoundaryAddWork), from the lists of the
   last build, which must be this swarm's particles in this order. Free with PetscFree(). Also the sum over this
   rank's particles.

   Not collective
*/
static PetscErrorCode FSSolverGetWork(FSSolver s, PetscInt64 **work, PetscInt64 *sum)
{
  const PetscInt n = s->pw.nowned;

  PetscFunctionBegin;
  PetscCall(PetscMalloc1(n, work));
  for (PetscInt i = 0; i < n; i++) (*work)[i] = 1 + FSNeighboursCandidateCount(&s->pw.nbrs, i);
  if (s->boundary) PetscCall(FSBoundaryAddWork(s->boundary, n, *work));
  *sum = 0;
  for (PetscInt i = 0; i < n; i++) *sum += (*work)[i];
  PetscFunctionReturn(0);
}

/*
   FSSolverGetWorkSum - this rank's work in a right-hand side, in fluid candidate pairs (FSSolverGetWork), whatever
   -fs_balance says: the parallel statistics' "work", the rebalancing's trigger. From the lists of the last build,
   counted once a build (FSSolverResize forgets it).

   Not collective
*/
PetscErrorCode FSSolverGetWorkSum(FSSolver s, PetscInt64 *sum)
{
  PetscFunctionBegin;
  if (s->pw.worksum < 0) {
    PetscInt64 *work;
    PetscCall(FSSolverGetWork(s, &work, &s->pw.worksum));
    PetscCall(PetscFree(work));
  }
  *sum = s->pw.worksum;
  PetscFunctionReturn(0);
}

/* balances the cuts on the swarm's particles weighted by work (NULL: 1 each) and tells the walls */
static PetscErrorCode FSSolverBalanceCuts(FSSolver s, const PetscInt64 work[])
{
  PetscReal *x;
  PetscInt   n;

  PetscFunctionBegin;
  PetscCall(DMSwarmGetLocalSize(s->swarm, &n));
  PetscCall(DMSwarmGetField(s->swarm, FS_FIELD_POSITION, NULL, NULL, (void **)&x));
  PetscCall(FSDecompBalance(&s->pw.decomp, PetscObjectComm((PetscObject)s), n, x, work,
                            s->pw.kernel.support + s->opt.halo_skin * s->opt.h));
  PetscCall(DMSwarmRestoreField(s->swarm, FS_FIELD_POSITION, NULL, NULL, (void **)&x));
  PetscCall(FSSolverPartitionWalls(s));
  PetscFunctionReturn(0);
}

/*
   FSSolverBalanceWork - at the set-up, with -fs_balance work on more than one rank, once the lists are built on the
   cuts balanced on the particles: balances the cuts on the particles' work (FSSolverGetWork), moves the particles
   to their new owners and builds the lists again. Not at a restart, which keeps the checkpoint's cuts.

   Collective
*/
PetscErrorCode FSSolverBalanceWork(FSSolver s)
{
  PetscInt64 *work, sum;
  PetscBool   changed;

  PetscFunctionBegin;
  if (s->pw.decomp.size == 1 || s->opt.balance != FS_BALANCE_WORK || s->opt.restart[0]) PetscFunctionReturn(0);
  PetscCall(FSSolverGetWork(s, &work, &sum));
  PetscCall(FSSolverBalanceCuts(s, work));
  PetscCall(PetscFree(work));
  PetscCall(FSSolverMigrate(s, &changed));
  PetscCall(FSSolverSortByCell(s));
  PetscCall(FSSolverResize(s, changed));
  PetscFunctionReturn(0);
}

/* whether a rebuild at this step may move the cuts (FSSolverRebalance) */
static PetscBool FSSolverRebalanceDue(FSSolver s, PetscInt step)
{
  return (PetscBool)(s->pw.decomp.size > 1 && s->opt.rebalance_threshold > 0 && s->pw.nglobal_particles > 0 &&
                     step - s->pw.balance_step >= s->opt.rebalance_interval);
}

/*
   FSSolverRebalanceWork - with -fs_balance work, when a rebuild at this step may move the cuts: this rank's work
   (FSSolverGetWorkSum), which the step's reduction sums and maximizes over the ranks (FSSolverStepReduce) for
   FSSolverRebalance, so that its imbalance takes no collective of its own. *wanted: whether it is needed.

   Not collective
*/
PetscErrorCode FSSolverRebalanceWork(FSSolver s, PetscInt step, PetscBool *wanted, PetscReal *work)
{
  PetscInt64 sum = 0;

  PetscFunctionBegin;
  *work   = 0;
  *wanted = (PetscBool)(s->opt.balance == FS_BALANCE_WORK && FSSolverRebalanceDue(s, step));
  if (!*wanted) PetscFunctionReturn(0);
  PetscCall(FSSolverGetWorkSum(s, &sum));
  *work = (PetscReal)sum; /* exact: below 2^53 */
  PetscFunctionReturn(0);
}

/*
   FSSolverRebalance - at a rebuild of the lists, before the migration: when the rank with the most work holds more
   than -fs_rebalance_threshold times the mean and -fs_rebalance_interval steps have passed since the cuts last moved,
   balances the cuts again on the particles' present positions (FSDecompBalance); the migration that follows sends
   each particle to its new owner. The work is a rank's particles (-fs_balance particles) or their work in a
   right-hand side (-fs_balance work, FSSolverGetWork: candidate pairs and wall elements). The cuts set at the start
   are balanced on the liquid as it was then; a sloshing or collapsing liquid leaves them behind (the largest rank's
   share drifts, measured in docs/performance.md). The imbalance comes from the step's reduction: the largest owned
   count, or with work the ranks' largest work and their sum (work[0], work[1], FSSolverRebalanceWork), so no
   collective is taken unless the cuts move. *moved says whether they did (on every rank).

   Collective
*/
PetscErrorCode FSSolverRebalance(FSSolver s, PetscInt step, const PetscReal work[2], PetscBool *moved)
{
  PetscReal   imbalance;
  PetscInt64 *pwork = NULL, sum;

  PetscFunctionBegin;
  *moved = PETSC_FALSE;
  if (!FSSolverRebalanceDue(s, step)) PetscFunctionReturn(0);
  if (s->opt.balance == FS_BALANCE_WORK) {
    PetscCheck(work[1] >= 0, PETSC_COMM_SELF, PETSC_ERR_PLIB, "The step's reduction did not sum the work");
    imbalance = work[1] > 0 ? work[0] / (work[1] / s->pw.decomp.size) : 1;
  } else imbalance = s->mon.par.step_max[0] / ((PetscReal)s->pw.nglobal_particles / s->pw.decomp.size);
  if (imbalance > s->opt.rebalance_threshold) {
    if (s->opt.balance == FS_BALANCE_WORK) PetscCall(FSSolverGetWork(s, &pwork, &sum));
    PetscCall(FSSolverBalanceCuts(s, pwork));
    PetscCall(PetscInfo(s, "step %" PetscInt_FMT ": imbalance %g above %g, cuts balanced again\n", step,
                        (double)imbalance, (double)s->opt.rebalance_threshold));
    s->pw.balance_step = step;
    s->mon.nrebalances++;
    *moved = PETSC_TRUE;
  }
  PetscCall(PetscFree(pwork));
  PetscFunctionReturn(0);
}

static PetscMPIInt FSSolverRankOf(void *ctx, const PetscReal x[]) { return FSDecompRankOf((const FSDecomp *)ctx, x); }

/*
   FSSolverPartitionWalls - tells the walls this rank's part of the domain and who owns which point
   (FSBoundarySetPartition), so that the wall pressure's sums go between neighbouring ranks only. At the set-up
   and whenever the cuts move.

   Collective
*/
PetscErrorCode FSSolverPartitionWalls(FSSolver s)
{
  const FSDecomp *dd = &s->pw.decomp;
  PetscReal       lo[3], hi[3];

  PetscFunctionBegin;
  if (!s->boundary) PetscFunctionReturn(0);
  for (PetscInt d = 0; d < 3; d++) {
    lo[d] = dd->cut[d][dd->coord[d]];
    hi[d] = dd->cut[d][dd->coord[d] + 1];
  }
  PetscCall(FSBoundarySetPartition(s->boundary, FSSolverRankOf, (void *)dd, lo, hi, s->pw.periodic));
  PetscFunctionReturn(0);
}
