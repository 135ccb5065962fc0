/*
   Time stepping: the TS that advances the packed state, the stable time step, and the step loop
   (TS step -> checks -> [when needed: migration -> ordering by cell -> halo -> lists] -> repack -> monitors).
*/
#include "solver/solverimpl.h"
#include <petsc/private/tsimpl.h> /* whether the TS is set up (its stage vectors allocated) */

/* the stage vectors of a TSRK integrator that is set up (ns = 0 otherwise) */
static PetscErrorCode FSSolverRKStages(FSSolver s, PetscInt *ns, Vec **Y)
{
  PetscBool isrk = PETSC_FALSE;

  PetscFunctionBegin;
  *ns = 0;
  *Y  = NULL;
  if (s->ts) PetscCall(PetscObjectTypeCompare((PetscObject)s->ts, TSRK, &isrk));
  if (isrk && s->ts->setupcalled) PetscCall(TSGetStages(s->ts, ns, Y));
  if (!*Y) *ns = 0;
  PetscFunctionReturn(0);
}

/*
   FSSolverGetStepStart - the state at the start of the last step, for the checks after it: the
   integrator's own copy when it keeps one (rk4lean's stage vector, TSRK's first stage: so that the
   solver keeps no copy of its own), the solver's copy Uprev with another integrator, or U itself
   before a step (after the set-up or a rebuild of the state).
*/
PetscErrorCode FSSolverGetStepStart(FSSolver s, Vec *U0)
{
  PetscInt ns;
  Vec     *Y, lean;

  PetscFunctionBegin;
  *U0 = s->state.U;
  if (s->state.rkstart) {
    PetscCall(FSTSRK4LeanGetWork(s->ts, &lean, NULL));
    if (lean) *U0 = lean;
    else {
      PetscCall(FSSolverRKStages(s, &ns, &Y));
      PetscCheck(ns > 0, PETSC_COMM_SELF, PETSC_ERR_PLIB, "The RK integrator's stages are gone");
      *U0 = Y[0];
    }
  } else if (s->state.Uprev) *U0 = s->state.Uprev;
  PetscFunctionReturn(0);
}

/*
   FSSolverGetFreeStage - a vector of U's layout the outputs' evaluation may write its rates into (they
   are not kept): rk4lean's sum (or rate) vector, or TSRK's last stage when there is one besides the first
   (FSSolverGetStepStart's); the next step writes either before it reads it. Else NULL. *later (may be
   NULL) says whether the integrator has such a vector once it is set up (rk4lean and TSRK; a one-stage
   TSRK is counted in), so that a vector made for the outputs before the first step need not be kept.
*/
PetscErrorCode FSSolverGetFreeStage(FSSolver s, Vec *F, PetscBool *later)
{
  PetscInt ns;
  Vec     *Y;

  PetscFunctionBegin;
  *F = NULL;
  if (later) {
    *later = PETSC_FALSE;
    if (s->ts) PetscCall(PetscObjectTypeCompareAny((PetscObject)s->ts, later, FSTSRK4LEAN, TSRK, ""));
  }
  if (s->ts) PetscCall(FSTSRK4LeanGetWork(s->ts, NULL, F));
  if (*F) PetscFunctionReturn(0);
  PetscCall(FSSolverRKStages(s, &ns, &Y));
  *F = ns >= 2 ? Y[ns - 1] : NULL;
  PetscFunctionReturn(0);
}

/* FSSolverSetUpTS - creates the TS (classical RK4 in three vectors, FSTSRK4LEAN, by default; -ts_type and
   friends change it). Called from FSSolverSetFromOptions, so that -help shows the TS options with
   flexslosh's defaults. */
PetscErrorCode FSSolverSetUpTS(FSSolver s)
{
  MPI_Comm comm = PetscObjectComm((PetscObject)s);

  PetscFunctionBegin;
  PetscCall(FSTSRegisterRK4Lean());
  PetscCall(TSDestroy(&s->ts));
  PetscCall(TSCreate(comm, &s->ts));
  PetscCall(TSSetProblemType(s->ts, TS_NONLINEAR));
  PetscCall(TSSetType(s->ts, FSTSRK4LEAN));
  PetscCall(TSSetRHSFunction(s->ts, NULL, FSSolverRHS, s));
  PetscCall(TSSetMaxTime(s->ts, s->opt.final_time));
  PetscCall(TSSetExactFinalTime(s->ts, TS_EXACTFINALTIME_MATCHSTEP));
  /* the TS's integer options, checked as flexslosh's own are before PETSc reads them (its parser keeps a value's low
     32 bits): the number of steps, and the rejected steps and nonlinear solver failures allowed (-1: any) */
  PetscCall(FSOptionsCheckPetscInt(comm, "-ts_max_steps", 0, PETSC_MAX_INT));
  PetscCall(FSOptionsCheckPetscInt(comm, "-ts_max_reject", -1, PETSC_MAX_INT));
  PetscCall(FSOptionsCheckPetscInt(comm, "-ts_max_snes_failures", -1, PETSC_MAX_INT));
  PetscCall(TSSetFromOptions(s->ts));
  PetscCall(FSTSRK4LeanSetInPlace(s->ts, PETSC_TRUE)); /* FSSolverRHS reads all of its state first */
  PetscFunctionReturn(0);
}

/*
   FSSolverBoundaryUpdate - the boundary's work of a step (FSBoundaryUpdate): each particle's candidate
   wall elements, the fluid pairs cut by walls, and the leak check: a particle outside the liquid
   region stops the run, naming the step, time, particle and nearest wall.

   Collective
*/
static PetscErrorCode FSSolverBoundaryUpdate(FSSolver s)
{
  MPI_Comm       comm = PetscObjectComm((PetscObject)s);
  FSBoundaryLeak leak;
  PetscInt       nleak;

  PetscFunctionBegin;
  PetscCall(PetscLogEventBegin(FS_Walls, 0, 0, 0, 0));
  if (s->ts && s->pw.nowned > 0) { /* FLEXSLOSH_FAULT=leak:RANK:STEP (tests only): a particle out of the tank */
    PetscInt  step;
    PetscBool fire;
    PetscCall(TSGetStepNumber(s->ts, &step));
    PetscCall(FSDebugFault(comm, "leak", step, &fire));
    if (fire) { /* just under the walls' lowest point, within reach of the walls below it */
      PetscReal lo[3], hi[3];
      PetscCall(FSBoundaryGetBoundingBox(s->boundary, lo, hi));
      s->pw.rec[1] = lo[1] - 0.25 * s->opt.dx;
    }
  }
  PetscCall(FSBoundaryUpdate(s->boundary, s->pw.nowned, s->pw.rec, s->pw.stride, &s->pw.nbrs, &leak));
  nleak = leak.particle >= 0 ? 1 : 0;
  PetscCallMPI(MPI_Allreduce(MPI_IN_PLACE, &nleak, 1, MPIU_INT, MPI_SUM, comm));
  if (leak.particle >= 0) {
    const PetscInt     i = leak.particle, S = s->pw.stride;
    PetscInt           step = 0, *id, nwalls;
    PetscReal          t    = 0;
    const char *const *names;
    char               where[128];
    if (s->ts) {
      PetscCall(TSGetTime(s->ts, &t));
      PetscCall(TSGetStepNumber(s->ts, &step));
    }
    PetscCall(FSBoundaryGetWallNames(s->boundary, &nwalls, &names));
    PetscCall(DMSwarmGetField(s->swarm, FS_FIELD_ID, NULL, NULL, (void **)&id));
    PetscCall(PetscSNPrintf(where, sizeof(where), s->opt.dim == 3 ? "(%g, %g, %g)" : "(%g, %g)",
                            (double)s->pw.rec[i * S], (double)s->pw.rec[i * S + 1],
                            s->opt.dim == 3 ? (double)s->pw.rec[i * S + 2] : 0.0));
    PetscCall(PetscPrintf(PETSC_COMM_SELF,
                          "[flexslosh] leak: particle %" PetscInt_FMT " crossed wall \"%s\" (near its %s %" PetscInt_FMT
                          ") at step %" PetscInt_FMT ", time %g: it is at %s, outside the liquid region\n",
                          id[i], names[leak.wall], s->opt.dim == 3 ? "triangle" : "segment", leak.element, step,
                          (double)t, where));
    PetscCall(DMSwarmRestoreField(s->swarm, FS_FIELD_ID, NULL, NULL, (void **)&id));
  }
  PetscCheck(!nleak, comm, PETSC_ERR_CONV_FAILED,
             "Particles crossed a wall on %" PetscInt_FMT
             " rank(s) (the particle, wall, step and time are named above): reduce -fs_cfl or refine -fs_dx",
             nleak);
  PetscCall(PetscLogEventEnd(FS_Walls, 0, 0, 0, 0));
  PetscFunctionReturn(0);
}

/* the energy of one particle, before and after a wall bounce (FSBoundaryBounce), for the energy budget */
typedef struct {
  FSSolver      s;
  FSEnergyFrame fr;
} FSBounceEnergy;

static void FSBounceParticleEnergy(void *ctx, const PetscReal x[], const PetscReal v[], PetscReal m, PetscReal e[2])
{
  FSBounceEnergy *be = (FSBounceEnergy *)ctx;
  FSEnergyParticle(be->s, &be->fr, x, v, m, e);
}

/*
   FSSolverBoundaryBounce - after a step, the particles too close to a wall bounce back
   (FSBoundaryBounce); de returns this rank's change of the liquid's energy (tank frame, absolute
   frame), active whether bounces are on.

   Not collective
*/
static PetscErrorCode FSSolverBoundaryBounce(FSSolver s, PetscReal de[2], PetscBool *active)
{
  FSBounceEnergy be;
  PetscReal     *x, *v, *m;
  PetscInt       n;

  PetscFunctionBegin;
  de[0] = de[1] = 0;
  *active       = PETSC_FALSE;
  if (s->boundary) PetscCall(FSBoundaryGetBounce(s->boundary, active));
  if (!*active) PetscFunctionReturn(0);
  be.s = s;
  PetscCall(FSSolverEnergyJumpFrame(s, &be.fr));
  PetscCall(DMSwarmGetLocalSize(s->swarm, &n));
  PetscCall(DMSwarmGetField(s->swarm, FS_FIELD_POSITION, NULL, NULL, (void **)&x));
  PetscCall(DMSwarmGetField(s->swarm, FS_FIELD_VELOCITY, NULL, NULL, (void **)&v));
  PetscCall(DMSwarmGetField(s->swarm, FS_FIELD_MASS, NULL, NULL, (void **)&m));
  PetscCall(FSBoundaryBounce(s->boundary, n, x, v, m, FSBounceParticleEnergy, &be, de));
  PetscCall(DMSwarmRestoreField(s->swarm, FS_FIELD_MASS, NULL, NULL, (void **)&m));
  PetscCall(DMSwarmRestoreField(s->swarm, FS_FIELD_VELOCITY, NULL, NULL, (void **)&v));
  PetscCall(DMSwarmRestoreField(s->swarm, FS_FIELD_POSITION, NULL, NULL, (void **)&x));
  PetscFunctionReturn(0);
}

/*
   FSSolverResize - after a migration or reordering: (re)creates the state vector when the local
   sizes changed, packs the particles into it, rebuilds the halo, the cell and candidate lists and the
   walls' candidates, records the positions of this build (FSSolverMarkBuild), and tells TS that the
   state changed outside of it, keeping time, step number, dt and monitors.

   Collective
*/
PetscErrorCode FSSolverResize(FSSolver s, PetscBool resize)
{
  MPI_Comm    comm = PetscObjectComm((PetscObject)s);
  PetscMPIInt rank;
  PetscInt    nloc;

  PetscFunctionBegin;
  PetscCallMPI(MPI_Comm_rank(comm, &rank));
  s->state.dtnext.ready = PETSC_FALSE; /* the next time step is reduced anew */
  s->pw.worksum         = -1;          /* the work is counted again from the new lists (FSSolverGetWorkSum) */
  if (resize || !s->state.U) {
    Vec            U;
    const PetscInt ng = FSSolverLocalGlobalDofs(s, rank); /* after the particles */
    nloc              = s->pw.nowned * s->state.ustride + ng;
    if (s->state.U && ng) { /* keep the global DOFs */
      const PetscScalar *u;
      PetscInt           n;
      PetscCall(VecGetLocalSize(s->state.U, &n));
      PetscCall(VecGetArrayRead(s->state.U, &u));
      for (PetscInt k = 0; k < ng; k++) s->state.global0[k] = u[n - ng + k];
      PetscCall(VecRestoreArrayRead(s->state.U, &u));
    }
    PetscCall(VecCreateMPI(comm, nloc, PETSC_DETERMINE, &U));
    PetscCall(PetscObjectSetName((PetscObject)U, "state"));
    if (ng) {
      PetscScalar *u;
      PetscCall(VecGetArray(U, &u));
      for (PetscInt k = 0; k < ng; k++) u[nloc - ng + k] = s->state.global0[k];
      PetscCall(VecRestoreArray(U, &u));
    }
    PetscCall(VecDestroy(&s->state.U));
    PetscCall(VecDestroy(&s->state.Uprev));
    PetscCall(VecDestroy(&s->state.Fout)); /* the outputs' rates take the new layout */
    s->state.U       = U;
    s->state.rkstart = PETSC_FALSE; /* TSReset below: the stages go */
    if (s->ts) {
      DM tsdm;
      PetscCall(TSReset(s->ts));
      PetscCall(TSGetDM(s->ts, &tsdm));
      PetscCall(DMClearGlobalVectors(tsdm));
      PetscCall(DMClearLocalVectors(tsdm));
      PetscCall(TSSetSolution(s->ts, s->state.U));
    }
  }
  PetscCall(FSSolverPackState(s));
  if (s->pw.resume) PetscCall(FSSolverRecordsAtBuild(s)); /* a restart: the lists of the checkpoint's last build */
  PetscCall(PetscLogEventBegin(FS_Halo, 0, 0, 0, 0));
  PetscCall(FSHaloBuild(&s->pw.halo, comm, &s->pw.decomp, s->pw.nowned, s->pw.rec, s->pw.stride,
                        s->pw.kernel.support + s->opt.halo_skin * s->opt.h));
  PetscCall(PetscLogEventEnd(FS_Halo, 0, 0, 0, 0));
  PetscCall(FSSolverEnsureWork(s, s->pw.nowned + s->pw.halo.nghost));
  /* candidate neighbours for the whole step: kernel support plus the halo skin */
  PetscCall(FSHaloRefresh(&s->pw.halo, s->opt.dim, s->pw.nowned, s->pw.rec));
  PetscCall(PetscLogEventBegin(FS_Neighbours, 0, 0, 0, 0));
  s->pw.nbrs.form = s->opt.candidates == 2 || (s->opt.candidates == 0 && s->opt.dim == 3) ? FS_CANDIDATES_BITS
                                                                                          : FS_CANDIDATES_INDICES;
  PetscCall(FSNeighboursBuildCells(&s->pw.nbrs, s->opt.dim, s->pw.nowned + s->pw.halo.nghost, s->pw.rec, s->pw.stride,
                                   s->pw.kernel.support + s->opt.halo_skin * s->opt.h));
  PetscCall(FSNeighboursBuildCandidates(&s->pw.nbrs, s->pw.nowned, s->pw.rec, s->pw.stride,
                                        s->pw.kernel.support + s->opt.halo_skin * s->opt.h));
  if (s->boundary) PetscCall(FSSolverBoundaryUpdate(s));
  if (s->pw.nowned > s->pw.passcap) {
    PetscCall(PetscFree(s->pw.passorder));
    s->pw.passcap = PetscMax(s->pw.nowned, (PetscInt)(1.25 * s->pw.passcap));
    PetscCall(PetscMalloc1(s->pw.passcap, &s->pw.passorder));
  }
  PetscCall(FSNeighboursSplitByGhosts(&s->pw.nbrs, s->pw.nowned, s->pw.nowned + s->pw.halo.nghost, s->pw.passorder,
                                      &s->pw.ninterior));
  PetscCall(PetscLogEventEnd(FS_Neighbours, 0, 0, 0, 0));
  PetscCall(FSSolverMarkBuild(s));
  if (s->pw.resume) PetscCall(FSSolverPackState(s)); /* the records of the state again */
  s->pw.resume = PETSC_FALSE;
  if (s->ts) PetscCall(TSRestartStep(s->ts));
  PetscFunctionReturn(0);
}

/*
   FSSolverReduceWithViscosity - the largest of n values over the ranks (loc[0..n-1], replaced by the
   maxima) in the same reduction as the largest viscosity the next time step must resolve, over the ranks
   and the sources (-fs_nu, then each term's diffusivity), and the source that sets it (0: -fs_nu,
   1 + t: term t; the first one on a tie).

   Collective
*/
PetscErrorCode FSSolverReduceWithViscosity(FSSolver s, PetscInt n, PetscReal loc[], PetscReal *nu, PetscInt *source)
{
  const PetscInt nsrc = 1 + s->terms.nterms;
  PetscReal      v[FS_REDUCE_MAX + FS_MAX_TERMS + 1];

  PetscFunctionBegin;
  PetscCheck(n >= 0 && n <= FS_REDUCE_MAX, PETSC_COMM_SELF, PETSC_ERR_PLIB,
             "At most %d values reduced with the viscosity", FS_REDUCE_MAX);
  for (PetscInt k = 0; k < n; k++) v[k] = loc[k];
  for (PetscInt k = 0; k < nsrc; k++) v[n + k] = s->state.nu_src[k];
  v[n] = PetscMax(v[n], s->opt.nu);
  PetscCallMPI(
      MPI_Allreduce(MPI_IN_PLACE, v, (PetscMPIInt)(n + nsrc), MPIU_REAL, MPI_MAX, PetscObjectComm((PetscObject)s)));
  for (PetscInt k = 0; k < n; k++) loc[k] = v[k];
  *nu     = v[n];
  *source = 0;
  for (PetscInt k = 1; k < nsrc; k++)
    if (v[n + k] > *nu) {
      *nu     = v[n + k];
      *source = k;
    }
  PetscFunctionReturn(0);
}

/* the operation of FSSolverReduceSumMax on its packed buffer, one element of a contiguous type holding the whole
   buffer: v[0] the number of sums n (the same on every rank), v[1..n] summed, the rest the largest. Commutative: each
   pair is combined as MPI_SUM and MPI_MAX combine it. The buffer is one element so that no algorithm of MPI_Allreduce
   can cut it into pieces (a reduce-scatter or a ring hands the operation parts of a vector, where v[0] would not be
   the count: Open MPI's tuned allreduce does so from some rank counts on) */
static void MPIAPI FSSumMaxOp(void *in, void *inout, int *len, MPI_Datatype *type)
{
  int size;

  if (MPI_Type_size(*type, &size) != MPI_SUCCESS) return;
  const int m = size / (int)sizeof(PetscReal);
  for (int e = 0; e < *len; e++) {
    const PetscReal *a = (const PetscReal *)in + (size_t)e * m;
    PetscReal       *b = (PetscReal *)inout + (size_t)e * m;
    const int        n = (int)a[0];
    for (int k = 1; k <= n && k < m; k++) b[k] = a[k] + b[k];
    for (int k = n + 1; k < m; k++) b[k] = PetscMax(a[k], b[k]);
  }
}

static MPI_Op       FSSumMax     = MPI_OP_NULL;
static MPI_Datatype FSSumMaxType = MPI_DATATYPE_NULL; /* the buffer as one element, of FSSumMaxLen reals */
static PetscMPIInt  FSSumMaxLen  = 0;

static PetscErrorCode FSSumMaxFree(void)
{
  PetscFunctionBegin;
  if (FSSumMax != MPI_OP_NULL) PetscCallMPI(MPI_Op_free(&FSSumMax));
  if (FSSumMaxType != MPI_DATATYPE_NULL) PetscCallMPI(MPI_Type_free(&FSSumMaxType));
  FSSumMax     = MPI_OP_NULL;
  FSSumMaxType = MPI_DATATYPE_NULL;
  FSSumMaxLen  = 0;
  PetscFunctionReturn(0);
}

/*
   FSSolverReduceSumMax - one MPI_Allreduce for nsum sums (sum[], replaced by the sums over the ranks) and nmax
   maxima (max[], replaced by the largest over the ranks), where two reductions (MPI_SUM, MPI_MAX) would be needed.
   Any number of values (beyond FS_SUMMAX_MAX they are packed into memory allocated for the call).

   Collective
*/
PetscErrorCode FSSolverReduceSumMax(FSSolver s, PetscInt nsum, PetscReal sum[], PetscInt nmax, PetscReal max[])
{
  PetscReal buf[1 + FS_SUMMAX_MAX], *v = buf;

  PetscFunctionBegin;
  PetscCheck(nsum >= 0 && nmax >= 0, PETSC_COMM_SELF, PETSC_ERR_PLIB,
             "FSSolverReduceSumMax: %" PetscInt_FMT " sums and %" PetscInt_FMT " maxima", nsum, nmax);
  if (FSSumMax == MPI_OP_NULL) {
    PetscCallMPI(MPI_Op_create(FSSumMaxOp, 1, &FSSumMax));
    PetscCall(PetscRegisterFinalize(FSSumMaxFree));
  }
  if (nsum + nmax > FS_SUMMAX_MAX) PetscCall(PetscMalloc1(1 + nsum + nmax, &v)); /* many walls' loads */
  v[0] = (PetscReal)nsum;
  for (PetscInt k = 0; k < nsum; k++) v[1 + k] = sum[k];
  for (PetscInt k = 0; k < nmax; k++) v[1 + nsum + k] = max[k];
  if (FSSumMaxLen != (PetscMPIInt)(1 + nsum + nmax)) { /* the type of the last length is kept: it rarely changes */
    if (FSSumMaxType != MPI_DATATYPE_NULL) PetscCallMPI(MPI_Type_free(&FSSumMaxType));
    FSSumMaxLen = (PetscMPIInt)(1 + nsum + nmax);
    PetscCallMPI(MPI_Type_contiguous(FSSumMaxLen, MPIU_REAL, &FSSumMaxType));
    PetscCallMPI(MPI_Type_commit(&FSSumMaxType));
  }
  PetscCallMPI(MPI_Allreduce(MPI_IN_PLACE, v, 1, FSSumMaxType, FSSumMax, PetscObjectComm((PetscObject)s)));
  for (PetscInt k = 0; k < nsum; k++) sum[k] = v[1 + k];
  for (PetscInt k = 0; k < nmax; k++) max[k] = v[1 + nsum + k];
  if (v != buf) PetscCall(PetscFree(v));
  PetscFunctionReturn(0);
}

/* FSSolverViscosityBound - FSSolverReduceWithViscosity() without other values. Collective */
PetscErrorCode FSSolverViscosityBound(FSSolver s, PetscReal *nu, PetscInt *source)
{
  PetscFunctionBegin;
  PetscCall(FSSolverReduceWithViscosity(s, 0, NULL, nu, source));
  PetscFunctionReturn(0);
}

/* FSSolverDtLimitName - the name of a time-step limit (FSDtLimit, FS_DT_TERM + t: the term's name) */
PetscErrorCode FSSolverDtLimitName(FSSolver s, PetscInt limit, const char **name)
{
  static const char *names[] = {"acoustic", "viscous", "skin", "body_force", "structure", "final_time", "integrator"};

  PetscFunctionBegin;
  if (limit >= 0 && limit < FS_DT_TERM) *name = names[limit];
  else if (limit >= FS_DT_TERM && limit < FS_DT_TERM + s->terms.nterms) *name = s->terms.term[limit - FS_DT_TERM]->name;
  else *name = "unknown";
  PetscFunctionReturn(0);
}

/* dt = min(dt, cand), remembering which limit set it (the first one on a tie) */
static inline void FSDtTake(PetscReal *dt, PetscInt *limit, PetscReal cand, PetscInt which)
{
  if (cand < *dt) {
    *dt    = cand;
    *limit = which;
  }
}

/*
   FSSolverStableDtOf - the particles' time-step limits of FSSolverComputeStableDt for a largest speed
   umax and the largest viscosity nu from its source (FSSolverViscosityBound), and the limit that sets it.

   Not collective
*/
void FSSolverStableDtOf(FSSolver s, PetscReal umax, PetscReal nu, PetscInt source, PetscReal *dt, PetscInt *limit)
{
  PetscReal g2 = 0;

  *limit = FS_DT_ACOUSTIC;
  *dt    = s->opt.cfl * s->opt.h / (s->opt.c0 + umax);
  if (nu > 0)
    FSDtTake(dt, limit, s->opt.cfl_visc * s->opt.h * s->opt.h / nu, source ? FS_DT_TERM + source - 1 : FS_DT_VISCOUS);
  if (umax > 0) /* no particle outruns its candidate lists */
    FSDtTake(dt, limit, 0.4 * s->opt.halo_skin * s->opt.h / umax, FS_DT_SKIN);
  for (PetscInt d = 0; d < s->opt.dim; d++) g2 += s->opt.gravity[d] * s->opt.gravity[d];
  if (g2 > 0) FSDtTake(dt, limit, s->opt.cfl_force * PetscSqrtReal(s->opt.h / PetscSqrtReal(g2)), FS_DT_BODY_FORCE);
  if (s->structure && s->structure->min_period > 0)
    FSDtTake(dt, limit, s->opt.structure_cfl * s->structure->min_period, FS_DT_STRUCTURE);
}

/*
   FSSolverOwnedMaxSpeed2 - the largest squared speed of this rank's owned particles in the state U

   Not collective
*/
PetscErrorCode FSSolverOwnedMaxSpeed2(FSSolver s, PetscReal *v2)
{
  const PetscInt     dim = s->opt.dim, US = s->state.ustride;
  const PetscScalar *u;

  PetscFunctionBegin;
  *v2 = 0;
  PetscCall(VecGetArrayRead(s->state.U, &u));
  for (PetscInt p = 0; p < s->pw.nowned; p++) {
    PetscReal w2 = 0;
    for (PetscInt d = 0; d < dim; d++) w2 += u[p * US + dim + d] * u[p * US + dim + d];
    *v2 = PetscMax(*v2, w2);
  }
  PetscCall(VecRestoreArrayRead(s->state.U, &u));
  PetscFunctionReturn(0);
}

/*
   FSSolverComputeStableDt - the SPH time-step limit for the current state:
     dt = min(CFL h/(c0 + |u|max), CFL_v h^2/nu_max, 0.4 skin h/|u|max, CFL_f sqrt(h/|g|)),
   nu_max being the largest viscosity any term applied in the integrator's last right-hand side
   (kept in checkpoints, so that a restarted run takes the same steps); a term with its own
   coefficient (the delta term's -fs_delta_cfl, or its default with RK4) enters scaled to CFL_v. With a structure, dt
   also resolves its shortest period (dt <= -fs_structure_cfl T_min, explicit integrators being stable and accurate only
   for omega dt = O(1)). Without particles dt comes from the structure alone (FSSolverStructureDt: -ts_dt if given, else
   -fs_structure_cfl T_min). Which limit set dt goes to s->state.dt_limit (the time series' dt_limit column).

   Collective
*/
PetscErrorCode FSSolverComputeStableDt(FSSolver s, PetscReal *dt)
{
  PetscReal v2 = 0, nu, loc[3];
  PetscInt  source, limit;

  PetscFunctionBegin;
  if (s->pw.nglobal_particles == 0) {
    PetscCall(FSSolverStructureDt(s, dt));
    s->state.dt_limit = FS_DT_STRUCTURE;
    PetscFunctionReturn(0);
  }
  if (s->state.dtnext.ready) { /* reduced with the last step's own values (FSSolverStepReduce)? */
    PetscInt  step;
    PetscReal t;
    PetscCall(TSGetStepNumber(s->ts, &step));
    PetscCall(TSGetTime(s->ts, &t));
    s->state.dtnext.ready = (PetscBool)(step == s->state.dtnext.step && t == s->state.dtnext.time);
  }
  if (s->state.dtnext.ready) {
    loc[0]                = s->state.dtnext.v2;
    loc[1]                = s->state.dtnext.owned;
    loc[2]                = s->state.dtnext.pairs;
    nu                    = s->state.dtnext.nu;
    source                = s->state.dtnext.source;
    s->state.dtnext.ready = PETSC_FALSE;
  } else {
    PetscCall(FSSolverOwnedMaxSpeed2(s, &v2));
    /* one reduction for the speed, the viscosities and, for the parallel statistics, the largest owned count and
       pair list (the last right-hand side's) of a rank */
    loc[0] = v2;
    loc[1] = (PetscReal)s->pw.nowned;
    loc[2] = (PetscReal)s->pw.nbrs.npairs;
    PetscCall(FSSolverReduceWithViscosity(s, 3, loc, &nu, &source));
  }
  s->state.umax          = PetscSqrtReal(loc[0]);
  s->mon.par.step_max[0] = loc[1];
  s->mon.par.step_max[1] = loc[2];
  FSSolverStableDtOf(s, s->state.umax, nu, source, dt, &limit);
  s->state.dt_stable = *dt;
  s->state.dt_limit  = limit;
  PetscFunctionReturn(0);
}

/*
   FSSolverBlowUpCause - the likely cause of a value of the state or of the energies that is no longer
   finite, for the messages: a time step too long for the structure (more than -fs_structure_cfl times its
   shortest period: a -ts_dt given without particles, or an adaptive integrator's step), else the advice
   for the particles or the structure.

   Not collective

   Input Parameters:
+  s   - the solver, after a step (or at the start of the run)
-  len - the size of cause

   Output Parameters:
+  cause - the text, e.g. "the time step 0.5 (-ts_dt) is 3.02 times the structure's shortest period ..."
-  found - (may be NULL) whether the time step is the cause found (else cause is the general advice)

.seealso: FSSolverCheckState()
*/
PetscErrorCode FSSolverBlowUpCause(FSSolver s, char cause[], size_t len, PetscBool *found)
{
  PetscReal t, tprev, dt, T = s->structure ? s->structure->min_period : 0;
  PetscBool given;

  PetscFunctionBegin;
  PetscCall(TSGetTime(s->ts, &t));
  PetscCall(TSGetPrevTime(s->ts, &tprev));
  dt = t - tprev; /* the step just taken; before the first, the one proposed */
  if (!(dt > 0)) PetscCall(TSGetTimeStep(s->ts, &dt));
  PetscCall(PetscOptionsHasName(NULL, NULL, "-ts_dt", &given));
  if (found) *found = (PetscBool)(T > 0 && dt > s->opt.structure_cfl * T * (1 + 1e-9));
  if (T > 0 && dt > s->opt.structure_cfl * T * (1 + 1e-9))
    PetscCall(
        PetscSNPrintf(cause, len,
                      "the time step %g%s is %.3g times the structure's shortest period %g s, too long for it "
                      "(an explicit integrator resolves it with steps of a small fraction of it: "
                      "-fs_structure_cfl %g)%s",
                      (double)dt, given ? " (-ts_dt)" : "", (double)(dt / T), (double)T, (double)s->opt.structure_cfl,
                      given ? ": reduce -ts_dt, or leave it out to take -fs_structure_cfl times the period" : ""));
  else if (s->pw.nglobal_particles > 0)
    PetscCall(PetscSNPrintf(cause, len, "reduce -fs_cfl, or check the set-up (the structure's options, the loads)"));
  else PetscCall(PetscSNPrintf(cause, len, "check the structure's model and options, or reduce the time step"));
  PetscFunctionReturn(0);
}

/* FSSolverStartOrigin - where the state a run starts from comes from, for the messages */
static PetscErrorCode FSSolverStartOrigin(FSSolver s, char text[], size_t len)
{
  PetscFunctionBegin;
  if (s->opt.restart[0]) PetscCall(PetscSNPrintf(text, len, "checkpoint \"%s\" (-fs_restart)", s->opt.restart));
  else PetscCall(PetscSNPrintf(text, len, "the set-up of case %s", s->opt.casename));
  PetscFunctionReturn(0);
}

/* FSSolverStartAdvice - what to do about a state the run cannot start from, for the messages */
static PetscErrorCode FSSolverStartAdvice(FSSolver s, PetscBool ckpt, char text[], size_t len)
{
  PetscFunctionBegin;
  if (ckpt)
    PetscCall(PetscSNPrintf(text, len,
                            "the checkpoint holds a state this run cannot start from: restart from an "
                            "earlier one"));
  else if (s->structure)
    PetscCall(PetscSNPrintf(text, len,
                            "check the options of case %s and of structure %s (-fs_structure), and the files they name",
                            s->opt.casename, s->structure->name));
  else PetscCall(PetscSNPrintf(text, len, "check the options of case %s and the files they name", s->opt.casename));
  PetscFunctionReturn(0);
}

/*
   FSSolverCheckStart - the particles a run starts from, before anything else is done with them: after the case's
   set-up (the structure's, whose payload takes the liquid's mass, comes next) and after a checkpoint is loaded. Each
   position, velocity, density and mass must be finite, and |rho/rho0 - 1| at most -fs_max_density_variation (the
   check of every step, FSSolverCheckState()); a checkpoint's particles, besides, no further from the positions the
   lists were built at than half the halo skin. The error names where the state comes from (the case, or the
   checkpoint), the particle, and what to do: for a case whose initial density is too far from rho0, the -fs_c0 at
   which it would not be (the density of a state at rest, rho0 (1 + p/(rho0 c0^2)), moves from rho0 as 1/c0^2).

   Collective
*/
PetscErrorCode FSSolverCheckStart(FSSolver s)
{
  MPI_Comm        comm = PetscObjectComm((PetscObject)s);
  const PetscInt  dim  = s->opt.dim;
  const PetscBool ckpt = (PetscBool)(s->opt.restart[0] && s->state.restart_hdr.dt > 0);
  PetscInt        n, *id, kind = 0, worst_p = -1;
  PetscReal      *x, *u, *rho, *m, *xb = NULL, worst = 0, move = 0, glob[3], info[6] = {0, 0, 0, 0, 0, 0};
  PetscMPIInt     rank, owner, gowner;
  char            origin[PETSC_MAX_PATH_LEN + 64], advice[512];

  PetscFunctionBegin;
  PetscCallMPI(MPI_Comm_rank(comm, &rank));
  PetscCall(DMSwarmGetLocalSize(s->swarm, &n));
  PetscCall(DMSwarmGetField(s->swarm, FS_FIELD_POSITION, NULL, NULL, (void **)&x));
  PetscCall(DMSwarmGetField(s->swarm, FS_FIELD_VELOCITY, NULL, NULL, (void **)&u));
  PetscCall(DMSwarmGetField(s->swarm, FS_FIELD_DENSITY, NULL, NULL, (void **)&rho));
  PetscCall(DMSwarmGetField(s->swarm, FS_FIELD_MASS, NULL, NULL, (void **)&m));
  PetscCall(DMSwarmGetField(s->swarm, FS_FIELD_ID, NULL, NULL, (void **)&id));
  if (ckpt) PetscCall(DMSwarmGetField(s->swarm, FS_FIELD_BUILD, NULL, NULL, (void **)&xb));
  for (PetscInt p = 0; p < n && kind != 1; p++) {
    PetscBool finite = (PetscBool)(!PetscIsInfOrNanReal(rho[p]) && !PetscIsInfOrNanReal(m[p]));
    PetscReal var, d2 = 0;
    for (PetscInt d = 0; d < dim; d++)
      if (PetscIsInfOrNanReal(x[p * dim + d]) || PetscIsInfOrNanReal(u[p * dim + d])) finite = PETSC_FALSE;
    if (!finite) {
      kind    = 1;
      worst_p = p;
      break;
    }
    var = PetscAbsReal(rho[p] / s->opt.rho0 - 1.0);
    if (var > worst) {
      worst   = var;
      worst_p = p;
    }
    if (xb)
      for (PetscInt d = 0; d < dim; d++) d2 += PetscSqr(x[p * dim + d] - xb[p * dim + d]);
    move = PetscMax(move, d2);
  }
  glob[0] = kind ? PETSC_MAX_REAL : worst;
  glob[1] = PetscSqrtReal(move);
  glob[2] = kind;
  PetscCallMPI(MPI_Allreduce(MPI_IN_PLACE, glob, 3, MPIU_REAL, MPI_MAX, comm));
  /* the particle that sets the worst variation (the first rank that has it), for the message */
  owner = (worst_p >= 0 && (kind ? PETSC_MAX_REAL : worst) == glob[0]) ? rank : PETSC_MPI_INT_MAX;
  PetscCallMPI(MPI_Allreduce(&owner, &gowner, 1, MPI_INT, MPI_MIN, comm));
  if (rank == gowner) {
    info[0] = (PetscReal)id[worst_p];
    for (PetscInt d = 0; d < dim; d++) info[1 + d] = x[worst_p * dim + d];
    info[4] = rho[worst_p];
    info[5] = m[worst_p];
  }
  if (xb) PetscCall(DMSwarmRestoreField(s->swarm, FS_FIELD_BUILD, NULL, NULL, (void **)&xb));
  PetscCall(DMSwarmRestoreField(s->swarm, FS_FIELD_ID, NULL, NULL, (void **)&id));
  PetscCall(DMSwarmRestoreField(s->swarm, FS_FIELD_MASS, NULL, NULL, (void **)&m));
  PetscCall(DMSwarmRestoreField(s->swarm, FS_FIELD_DENSITY, NULL, NULL, (void **)&rho));
  PetscCall(DMSwarmRestoreField(s->swarm, FS_FIELD_VELOCITY, NULL, NULL, (void **)&u));
  PetscCall(DMSwarmRestoreField(s->swarm, FS_FIELD_POSITION, NULL, NULL, (void **)&x));
  if (gowner != PETSC_MPI_INT_MAX) PetscCallMPI(MPI_Bcast(info, 6, MPIU_REAL, gowner, comm));
  if (ckpt) PetscCall(FSSolverStartOrigin(s, origin, sizeof(origin)));
  else PetscCall(PetscSNPrintf(origin, sizeof(origin), "case %s (its initial state)", s->opt.casename));
  PetscCall(FSSolverStartAdvice(s, ckpt, advice, sizeof(advice)));
  PetscCheck(glob[2] == 0, comm, PETSC_ERR_FILE_UNEXPECTED,
             "The particles of %s are not finite: particle %" PetscInt_FMT
             " at (%g, %g, %g), density %g, mass %g (or its velocity): %s",
             origin, (PetscInt)info[0], (double)info[1], (double)info[2], (double)info[3], (double)info[4],
             (double)info[5], advice);
  if (glob[0] > s->opt.max_density_variation) {
    if (ckpt)
      SETERRQ(comm, PETSC_ERR_FILE_UNEXPECTED,
              "The particles of %s have a density variation |rho/rho0 - 1| of %g, above -fs_max_density_variation %g: "
              "particle %" PetscInt_FMT " at (%g, %g, %g), density %g (rho0 %g). The run would stop there at once: if "
              "the run that wrote it had a larger -fs_max_density_variation, give that; else %s",
              origin, (double)glob[0], (double)s->opt.max_density_variation, (PetscInt)info[0], (double)info[1],
              (double)info[2], (double)info[3], (double)info[4], (double)s->opt.rho0, advice);
    SETERRQ(comm, PETSC_ERR_ARG_OUTOFRANGE,
            "The particles of %s have a density variation |rho/rho0 - 1| of %g, above -fs_max_density_variation %g: "
            "particle %" PetscInt_FMT
            " at (%g, %g, %g), density %g (rho0 %g). -fs_c0 %g is too small for the liquid's initial "
            "pressure (its hydrostatic or flow pressure p gives rho = rho0 (1 + p/(rho0 c0^2))): raise -fs_c0 to at "
            "least %.3g, or -fs_max_density_variation",
            origin, (double)glob[0], (double)s->opt.max_density_variation, (PetscInt)info[0], (double)info[1],
            (double)info[2], (double)info[3], (double)info[4], (double)s->opt.rho0, (double)s->opt.c0,
            (double)(s->opt.c0 * PetscSqrtReal(glob[0] / s->opt.max_density_variation) * 1.001));
  }
  PetscCheck(2 * glob[1] <= s->opt.halo_skin * s->opt.h, comm, PETSC_ERR_FILE_UNEXPECTED,
             "The particles of %s are up to %g from the positions their neighbour lists were built at "
             "(/particles/build_position), more than half the halo skin %g: %s",
             origin, (double)glob[1], (double)(s->opt.halo_skin * s->opt.h), advice);
  PetscFunctionReturn(0);
}

/* what a value that is not finite is, for the messages */
static const char *FSNonFiniteName(PetscReal v) { return PetscIsNanReal(v) ? "NaN" : (v > 0 ? "+Inf" : "-Inf"); }

/*
   FSSolverCheckState - stops the run on NaN or Inf in the state: in a particle, in the global DOFs
   (the structure's DOFs, the dissipated energies, the energy block) or in the loads the structure
   receives; on a density blow-up (|rho/rho0 - 1| above -fs_max_density_variation) and on particles
   that moved further since the lists were built than the halo skin allows (half the skin). The
   message names the step, the time, the particle and place or the quantity, and the likely cause.
   Called after each step before its outputs (and at the start of the run), so that no row, snapshot
   or checkpoint of a state that is not finite is written.

   Collective
*/
PetscErrorCode FSSolverCheckState(FSSolver s)
{
  PetscReal glob[FS_CHECK_N];

  PetscFunctionBegin;
  PetscCall(FSSolverCheckStateLocal(s, glob));
  PetscCallMPI(MPI_Allreduce(MPI_IN_PLACE, glob, FS_CHECK_N, MPIU_REAL, MPI_MAX, PetscObjectComm((PetscObject)s)));
  PetscCall(FSSolverCheckStateEnd(s, glob));
  PetscFunctionReturn(0);
}

/*
   FSSolverCheckStateLocal - FSSolverCheckState()'s pass over this rank's particles: glob[FS_CHECK_N] to be reduced
   (MPI_MAX) for FSSolverCheckStateEnd(); a particle that is not finite or blew up is named here (this rank prints).

   Not collective
*/
PetscErrorCode FSSolverCheckStateLocal(FSSolver s, PetscReal glob[])
{
  const PetscInt     dim = s->opt.dim, US = s->state.ustride;
  const PetscScalar *u, *u0;
  Vec                U0;
  PetscInt          *id, bad = -1, kind = 0, step;
  PetscReal          worst = 0, move = 0, t, *xb;
  PetscMPIInt        rank;

  PetscFunctionBegin;
  PetscCallMPI(MPI_Comm_rank(PetscObjectComm((PetscObject)s), &rank));
  PetscCall(VecGetArrayRead(s->state.U, &u));
  PetscCall(FSSolverGetStepStart(s, &U0));
  PetscCall(VecGetArrayRead(U0, &u0));
  PetscCall(DMSwarmGetField(s->swarm, FS_FIELD_BUILD, NULL, NULL, (void **)&xb));
  for (PetscInt p = 0; p < s->pw.nowned; p++) {
    PetscReal d2 = 0, var;
    for (PetscInt a = 0; a < US; a++)
      if (PetscIsInfOrNanReal(u[p * US + a])) {
        bad  = p;
        kind = 1;
      }
    if (kind == 1) break;
    var = PetscAbsReal(u[p * US + 2 * dim] / s->opt.rho0 - 1.0);
    if (var > worst) {
      worst = var;
      if (var > s->opt.max_density_variation) {
        bad  = p;
        kind = 2;
      }
    }
    for (PetscInt d = 0; d < dim; d++) d2 += PetscSqr(u[p * US + d] - xb[p * dim + d]);
    move = PetscMax(move, d2);
  }
  PetscCall(DMSwarmRestoreField(s->swarm, FS_FIELD_BUILD, NULL, NULL, (void **)&xb));
  glob[0] = kind;
  glob[1] = worst;
  glob[2] = PetscSqrtReal(move);
  glob[3] = glob[4] = -1; /* rank 0: the first global DOF and the first load component that is not finite */
  if (!rank) {
    const PetscReal *L[2] = {s->loads.force, s->loads.moment};
    for (PetscInt g = 0; g < s->state.nglobaldofs && glob[3] < 0; g++)
      if (PetscIsInfOrNanReal(u[s->pw.nowned * US + g])) glob[3] = g;
    for (PetscInt c = 0; c < 6 && glob[4] < 0; c++)
      if (PetscIsInfOrNanReal(L[c / 3][c % 3])) glob[4] = c;
  }
  PetscCall(TSGetTime(s->ts, &t));
  PetscCall(TSGetStepNumber(s->ts, &step));
  if (bad >= 0) {
    PetscCall(DMSwarmGetField(s->swarm, FS_FIELD_ID, NULL, NULL, (void **)&id));
    PetscCall(PetscPrintf(PETSC_COMM_SELF,
                          "[%d] flexslosh: %s at step %" PetscInt_FMT ", time %g: particle %" PetscInt_FMT
                          " at (%g, %g, %g), density %g (rho0 %g)\n",
                          rank, kind == 1 ? "NaN or Inf in the state" : "density blow-up", step, (double)t, id[bad],
                          (double)u0[bad * US], (double)u0[bad * US + 1], dim == 3 ? (double)u0[bad * US + 2] : 0.0,
                          (double)u[bad * US + 2 * dim], (double)s->opt.rho0));
    PetscCall(DMSwarmRestoreField(s->swarm, FS_FIELD_ID, NULL, NULL, (void **)&id));
  }
  PetscCall(VecRestoreArrayRead(U0, &u0));
  PetscCall(VecRestoreArrayRead(s->state.U, &u));
  PetscFunctionReturn(0);
}

/*
   FSSolverCheckStateEnd - FSSolverCheckState()'s verdict from the reduced glob[FS_CHECK_N] of
   FSSolverCheckStateLocal(): the run stops with the messages described there, else the largest density variation
   is kept (s->state.max_variation). The state U and its start must be those the local pass read.

   Collective
*/
PetscErrorCode FSSolverCheckStateEnd(FSSolver s, const PetscReal glob[])
{
  MPI_Comm           comm = PetscObjectComm((PetscObject)s);
  const PetscInt     US   = s->state.ustride;
  const PetscScalar *u, *u0;
  Vec                U0;
  PetscInt           step;
  PetscReal          t;
  PetscMPIInt        rank;
  PetscBool          start; /* before the first step: the state comes from the case or a checkpoint */
  char               origin[PETSC_MAX_PATH_LEN + 64], advice[512];

  PetscFunctionBegin;
  PetscCallMPI(MPI_Comm_rank(comm, &rank));
  PetscCall(VecGetArrayRead(s->state.U, &u));
  PetscCall(FSSolverGetStepStart(s, &U0));
  PetscCall(VecGetArrayRead(U0, &u0));
  PetscCall(TSGetTime(s->ts, &t));
  PetscCall(TSGetStepNumber(s->ts, &step));
  start = (PetscBool)(step == s->mon.step0 && !s->mon.steps_taken);
  PetscCall(FSSolverStartOrigin(s, origin, sizeof(origin)));
  PetscCall(FSSolverStartAdvice(s, (PetscBool)(s->opt.restart[0] != 0), advice, sizeof(advice)));
  if (glob[0] != 1 && (glob[3] >= 0 || glob[4] >= 0)) { /* the quantity, its value and the likely cause */
    static const char *load[] = {"force_x", "force_y", "force_z", "moment_x", "moment_y", "moment_z"};
    const PetscInt     g      = (PetscInt)glob[3];
    char               what[128], value[96] = "", cause[512];
    PetscReal          v[2] = {0, 0};
    if (g >= 0) {
      PetscCall(FSSolverGlobalDofName(s, g, what, sizeof(what)));
      if (!rank) { /* its value, and the value it had at the start of the step */
        v[0] = u[s->pw.nowned * US + g];
        v[1] = u0[s->pw.nowned * US + g];
      }
    } else {
      PetscCall(PetscSNPrintf(what, sizeof(what), "the structure's load %s", load[(PetscInt)glob[4]]));
      if (!rank) v[0] = glob[4] < 3 ? s->loads.force[(PetscInt)glob[4]] : s->loads.moment[(PetscInt)glob[4] - 3];
    }
    PetscCallMPI(MPI_Bcast(v, 2, MPIU_REAL, 0, comm));
    if (g >= 0 && U0 != s->state.U)
      PetscCall(PetscSNPrintf(value, sizeof(value), " (it was %g at the start of the step)", (double)v[1]));
    PetscCall(FSSolverBlowUpCause(s, cause, sizeof(cause), NULL));
    PetscCall(VecRestoreArrayRead(U0, &u0));
    PetscCall(VecRestoreArrayRead(s->state.U, &u));
    PetscCheck(!start, comm, PETSC_ERR_FILE_UNEXPECTED,
               "The state the run starts from, %s, is not finite: %s is %s at step %" PetscInt_FMT ", time %g: %s",
               origin, what, FSNonFiniteName(v[0]), step, (double)t, advice);
    SETERRQ(comm, PETSC_ERR_FP, "The run blew up: %s is %s at step %" PetscInt_FMT ", time %g%s. Likely cause: %s",
            what, FSNonFiniteName(v[0]), step, (double)t, value, cause);
  }
  PetscCall(VecRestoreArrayRead(U0, &u0));
  PetscCall(VecRestoreArrayRead(s->state.U, &u));
  /* at the start (FSSolverCheckStart() has checked the particles, so only a state changed since gets here) the
     state is not a blow-up: it comes from the case or the checkpoint */
  PetscCheck(!start || (glob[0] == 0 && 2 * glob[2] <= s->opt.halo_skin * s->opt.h), comm, PETSC_ERR_FILE_UNEXPECTED,
             "The state the run starts from, %s, %s (the particle is named above): %s", origin,
             glob[0] == 1 ? "holds NaN or Inf"
                          : (glob[0] == 2 ? "has a density variation above -fs_max_density_variation"
                                          : "has particles further than half the halo skin from where their "
                                            "neighbour lists were built"),
             advice);
  PetscCheck(glob[0] != 1, comm, PETSC_ERR_FP,
             "The run blew up: NaN or Inf at step %" PetscInt_FMT
             ", time %g (the particle is named above); reduce -fs_cfl or check the set-up",
             step, (double)t);
  PetscCheck(glob[0] != 2, comm, PETSC_ERR_CONV_FAILED,
             "The run blew up: density variation %g above -fs_max_density_variation %g at step %" PetscInt_FMT
             ", time %g (the particle is named above); reduce -fs_cfl, raise -fs_c0, or check the set-up",
             (double)glob[1], (double)s->opt.max_density_variation, step, (double)t);
  PetscCheck(2 * glob[2] <= s->opt.halo_skin * s->opt.h, comm, PETSC_ERR_CONV_FAILED,
             "A particle moved %g since the neighbour lists were built (step %" PetscInt_FMT
             ", time %g), more than half the halo skin %g: reduce -fs_cfl or raise -fs_halo_skin",
             (double)glob[2], step, (double)t, (double)(s->opt.halo_skin * s->opt.h));
  s->state.max_variation = glob[1];
  PetscFunctionReturn(0);
}

/*
   FSSolverStepReduce - the step's own reductions in one (FSSolverReduceSumMax): the state check's maxima (check,
   FSSolverCheckStateLocal()), the bounces' energy changes (jump, summed in place), the rebuild decision's maxima
   and the viscosity bound (FSSolverRebuildNeeded()), and the next step's time-step reduction (the largest speed,
   which the rebuild decision's is once the particles stay where they are, the viscosity bound, the largest owned
   count and pair list), and the write status of the last csv rows (FSSolverWriteStatus()): kept in s->state.dtnext
   for FSSolverComputeStableDt() when the lists are kept, and when the cuts may move on the work, the ranks' largest
   work and its sum (work[0], work[1]; work[1] = -1 when not summed) for FSSolverRebalance(). Then a failed row's
   error, the check's verdict (FSSolverCheckStateEnd()) and the rebuild decision.

   Collective
*/
static PetscErrorCode FSSolverStepReduce(FSSolver s, PetscReal check[], PetscReal jump[2], PetscBool *rebuild,
                                         PetscBool *sort, PetscReal work[2])
{
  const PetscInt nsrc = 1 + s->terms.nterms;
  PetscReal      mx[FS_CHECK_N + FS_REBUILD_N + 2 + FS_MAX_TERMS + 3], *rb = mx + FS_CHECK_N, *cnt = rb + FS_REBUILD_N,
                                                                  *nus = cnt + 2, nu, sums[3];
  PetscInt           source                                            = 0, step;
  const PetscInt     nmx  = FS_CHECK_N + FS_REBUILD_N + 2 + nsrc + 2; /* the last: the work's largest */
  FSMonitorRowBatch *rows = &s->mon.rows;
  PetscBool          haswork;

  PetscFunctionBegin;
  PetscCall(TSGetStepNumber(s->ts, &step));
  for (PetscInt k = 0; k < FS_CHECK_N; k++) mx[k] = check[k];
  PetscCall(FSSolverRebuildNeededLocal(s, rb));
  cnt[0] = (PetscReal)s->pw.nowned;
  cnt[1] = (PetscReal)s->pw.nbrs.npairs;
  for (PetscInt k = 0; k < nsrc; k++) nus[k] = s->state.nu_src[k];
  nus[0]    = PetscMax(nus[0], s->opt.nu);
  nus[nsrc] = FSSolverWriteStatus(s); /* the last rows' write status (rank 0's) */
  /* a rebuild that may move the cuts on the work: the ranks' work, its sum and largest (FSSolverRebalance) */
  PetscCall(FSSolverRebalanceWork(s, step, &haswork, &sums[2]));
  nus[nsrc + 1] = sums[2];
  sums[0]       = jump[0];
  sums[1]       = jump[1];
  if (rows->nsum + rows->nmax == 0) PetscCall(FSSolverReduceSumMax(s, 3, sums, nmx, mx));
  else { /* this step's rows' sums and maxima too (FSMonitorRowsBegin()), in room kept from step to step */
    PetscReal *sum, *max;
    if (3 + rows->nsum + nmx + rows->nmax > s->mon.nreduce) {
      PetscCall(PetscFree(s->mon.reduce));
      s->mon.nreduce = 3 + rows->nsum + nmx + rows->nmax;
      PetscCall(PetscMalloc1(s->mon.nreduce, &s->mon.reduce));
    }
    sum = s->mon.reduce;
    max = sum + 3 + rows->nsum;
    PetscCall(PetscArraycpy(sum, sums, 3));
    PetscCall(PetscArraycpy(sum + 3, rows->sum, rows->nsum));
    PetscCall(PetscArraycpy(max, mx, nmx));
    PetscCall(PetscArraycpy(max + nmx, rows->max, rows->nmax));
    PetscCall(FSSolverReduceSumMax(s, 3 + rows->nsum, sum, nmx + rows->nmax, max));
    PetscCall(PetscArraycpy(sums, sum, 3));
    PetscCall(PetscArraycpy(rows->sum, sum + 3, rows->nsum));
    PetscCall(PetscArraycpy(mx, max, nmx));
    PetscCall(PetscArraycpy(rows->max, max + nmx, rows->nmax));
  }
  jump[0] = sums[0];
  jump[1] = sums[1];
  work[0] = nus[nsrc + 1];                           /* the largest rank's work */
  work[1] = haswork ? sums[2] : -1;                  /* the ranks' (-1: not summed) */
  PetscCall(FSSolverWriteStatusRaise(s, nus[nsrc])); /* a failed row: the run stops one step after it */
  PetscCall(FSSolverCheckStateEnd(s, mx));
  nu = nus[0]; /* as FSSolverReduceWithViscosity() */
  for (PetscInt k = 1; k < nsrc; k++)
    if (nus[k] > nu) {
      nu     = nus[k];
      source = k;
    }
  PetscCall(FSSolverRebuildDecide(s, rb, nu, source, rebuild, sort));
  s->state.dtnext.ready  = (PetscBool) !*rebuild;
  s->state.dtnext.step   = step;
  s->state.dtnext.v2     = rb[1];
  s->state.dtnext.owned  = cnt[0];
  s->state.dtnext.pairs  = cnt[1];
  s->state.dtnext.nu     = nu;
  s->state.dtnext.source = source;
  PetscCall(TSGetTime(s->ts, &s->state.dtnext.time));
  PetscFunctionReturn(0);
}

/*
   FSSolverStep - advances the run by one time step of the stable size (or less, to land on the
   final time), then, when the lists must be rebuilt (FSSolverRebuildNeeded), migrates, reorders and
   repacks the particles and rebuilds the lists; else repacks them in place. The first step of a run opens its
   output with the state before it (FSSolverMonitorBegin: step 0), as FSSolverSolve does.

   Collective
*/
PetscErrorCode FSSolverStep(FSSolver s)
{
  PetscReal         dt, t, tmax, dtts;
  PetscBool         changed, adaptive;
  TSAdapt           adapt;
  TSConvergedReason reason;
  PetscInt          step;
  PetscReal         ejump[2], check[FS_CHECK_N], work[2];
  PetscBool         bounced, rebuild, sort;

  PetscFunctionBegin;
  s->state.evaluated = PETSC_FALSE; /* the step changes the state */
  PetscCall(FSSolverSetUp(s));
  if (!s->mon.monitoring) PetscCall(FSSolverMonitorBegin(s)); /* the output's step 0 is the state before this step */
  FSParallelStatsStepBegin(s);
  PetscCall(PetscLogEventBegin(FS_Step, 0, 0, 0, 0));
  PetscCall(FSSolverComputeStableDt(s, &dt));
  PetscCall(TSGetTime(s->ts, &t));
  PetscCall(TSGetMaxTime(s->ts, &tmax));
  PetscCall(TSGetAdapt(s->ts, &adapt));
  PetscCall(PetscObjectTypeCompare((PetscObject)adapt, TSADAPTNONE, &adaptive));
  adaptive = (PetscBool)!adaptive;
  if (adaptive) {
    PetscCall(TSGetTimeStep(s->ts, &dtts));
    if (dtts > 0 && s->mon.steps_taken > 0 && dtts < dt) {
      dt                = dtts;
      s->state.dt_limit = FS_DT_INTEGRATOR;
    }
  }
  if (t + dt > tmax - 1e-12 * tmax) {
    dt                = tmax - t;
    s->state.dt_limit = FS_DT_FINAL_TIME;
  }
  s->state.dt_limit_steps[s->state.dt_limit]++;
  PetscCall(TSSetTimeStep(s->ts, dt));
  {
    PetscBool keeps; /* rk4lean and TSRK keep the state at the start of the step (FSSolverGetStepStart) */
    PetscCall(PetscObjectTypeCompareAny((PetscObject)s->ts, &keeps, FSTSRK4LEAN, TSRK, ""));
    if (!keeps) {
      if (!s->state.Uprev) PetscCall(VecDuplicate(s->state.U, &s->state.Uprev));
      PetscCall(VecCopy(s->state.U, s->state.Uprev));
    }
    s->state.rkstart = PETSC_FALSE;
    PetscCall(TSStep(s->ts));
    s->state.rkstart = keeps;
  }
  PetscCall(TSGetConvergedReason(s->ts, &reason));
  PetscCall(TSGetStepNumber(s->ts, &step));
  PetscCheck(reason >= 0, PetscObjectComm((PetscObject)s), PETSC_ERR_CONV_FAILED,
             "The time integrator failed at step %" PetscInt_FMT ": %s", step, TSConvergedReasons[reason]);
  s->mon.particle_steps += s->pw.nglobal_particles;
  s->mon.steps_taken++;
  PetscCall(FSSolverSplitStep(s, dt)); /* the split terms' diffusion over the step (-fs_delta_split), then the checks */
  PetscCall(FSSolverCheckStateLocal(s, check)); /* its verdict after the reduction below */
  PetscCall(FSSolverUnpackState(s));
  PetscCall(FSSolverBoundaryBounce(s, ejump, &bounced)); /* with the bounces' energy changes, for the energy budget */
  /* this step's rows (FSSolverMonitor), their sums taken now to ride on the step's reduction: the state, the loads
     and the masses are the step's end's, before the lists are rebuilt and the particles move between the ranks; the
     bounces moved the particles' fields, so the state takes them first (FSSolverKeepLists() need not again) */
  if (bounced) PetscCall(FSSolverPackState(s));
  PetscCall(FSMonitorRowsBegin(s->mon.nlist, s->mon.list, s, &s->mon.rows));
  PetscCall(FSSolverStepReduce(s, check, ejump, &rebuild, &sort, work)); /* the check, the rebuild, the next dt */
  if (rebuild) {
    PetscBool rebalanced;
    PetscCall(FSSolverRebalance(s, step, work, &rebalanced));
    PetscCall(FSSolverMigrate(s, &changed));
    if (sort || rebalanced) { /* the particles a rebalance brings are in no order */
      PetscCall(FSSolverSortByCell(s));
      s->pw.sort_step = step;
    }
    PetscCall(FSSolverResize(s, changed));
    /* the particles were reordered (on every rank alike): the rows' sums are taken again in the new order, with
       their own reduction (FSMonitorRows()), so that a run restarted from this step's checkpoint makes the same row */
    if (changed || sort || rebalanced) PetscCall(FSMonitorRowBatchReset(&s->mon.rows));
    s->mon.nrebuilds++;
  } else PetscCall(FSSolverKeepLists(s, bounced));
  if (bounced && s->pw.nglobal_particles > 0) PetscCall(FSSolverEnergyAddJump(s, ejump, PETSC_TRUE));
  PetscCall(PetscLogEventEnd(FS_Step, 0, 0, 0, 0));
  PetscCall(FSSolverMonitor(s));
  FSParallelStatsStepEnd(s);
  PetscFunctionReturn(0);
}

/* FSSolverAtEnd - whether the run has reached -ts_max_time (to round-off) or -ts_max_steps. Not collective */
PetscErrorCode FSSolverAtEnd(FSSolver s, PetscBool *end)
{
  PetscReal t, tmax;
  PetscInt  step, maxsteps;

  PetscFunctionBegin;
  PetscCall(TSGetTime(s->ts, &t));
  PetscCall(TSGetMaxTime(s->ts, &tmax));
  PetscCall(TSGetStepNumber(s->ts, &step));
  PetscCall(TSGetMaxSteps(s->ts, &maxsteps));
  *end = (PetscBool)(t >= tmax - 1e-12 * PetscMax(1.0, PetscAbsReal(tmax)) || step >= maxsteps);
  PetscFunctionReturn(0);
}

/*
   FSSolverSolve - runs to the final time (-ts_max_time) or step count (-ts_max_steps), writing the
   output the options ask for.

   Collective

   Options Database Key:
.  -fs_geometry_view - take no step: the set-up's files are written (FSSolverGeometryView()) and the
                       run stops, so the set-up can be checked before running
*/
PetscErrorCode FSSolverSolve(FSSolver s)
{
  PetscFunctionBegin;
  PetscCall(FSSolverSetUp(s));
  PetscCall(FSSolverMonitorBegin(s));
  if (s->opt.geometry_view)
    PetscCall(PetscPrintf(PetscObjectComm((PetscObject)s),
                          "-fs_geometry_view: stopping after set-up; run again without it to compute\n"));
  while (!s->opt.geometry_view) { /* -fs_geometry_view: no time stepping */
    PetscBool end = PETSC_FALSE;
    PetscCall(FSSolverAtEnd(s, &end));
    if (end) break;
    PetscCall(FSSolverStep(s));
  }
  PetscCall(FSSolverMonitorEnd(s));
  PetscFunctionReturn(0);
}
