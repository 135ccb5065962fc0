/*
   Private data structures of libflexslosh. Not part of the public interface.

   Data flow of one run:  options -> case set-up (domain, particles) -> decomposition ->
   TS loop [ halo refresh -> cell list and neighbour lists -> first pass (correction matrix,
   density gradient, strain rate) -> ghost refresh of those -> pair pass of the terms ] ->
   monitors (src/monitor/: time series, snapshots, checkpoints, progress, summary; the blow-up checks).
*/
#pragma once
#include <flexslosh.h>
#include <petsc/private/petscimpl.h>
#include "sys/fssys.h"
#include "particles/fsparticles.h"
#include "terms/fsterms.h"
#include "structure/fsstructure.h"
#include "cases/fscases.h"
#include "coupling/fscoupling.h"
#include "io/fsoutput.h"
#include "boundary/fsboundary.h"
#include "solver/fssolver.h"

#define FS_MAX_GLOBAL 64

/* the swarm's field of the particles' positions at the last build of the lists (src/solver/rebuild.c) */
#define FS_FIELD_BUILD "build_position"

/* The global DOFs of the state (on rank 0, after the particles) are a short list of blocks:
   the structure's DOFs first, then one dissipated energy per term with a power, then the energy
   budget's own integrals and constants (FS_ENERGY_*, src/solver/energy.c). */
#define FS_MAX_GLOBAL_BLOCKS 4
typedef struct {
  char     name[32];
  PetscInt offset, n;
} FSGlobalBlock;

/* The run's options (-fs_*), read by FSSolverSetFromOptions() and the cases' defaults. */
typedef struct {
  char          casename[64];
  char          default_terms[1024]; /* the case's default for -fs_terms */
  char          outdir[PETSC_MAX_PATH_LEN];
  char          outname[64];  /* -fs_output_name: the default output directory's name, before its time stamp */
  PetscBool     outdir_auto;  /* no -fs_output_dir: outdir is output/<outname>-<time stamp>, made new by the run */
  PetscBool     outdir_taken; /* that directory made (FSSolverOutputDirChoose()) */
  char          restart[PETSC_MAX_PATH_LEN];
  char          allow_changes[1024]; /* -fs_restart_allow_changes: items of the set-up a restart may change */
  PetscInt      dim;
  PetscReal     dx, h_over_dx, h, rho0, c0, nu, gravity[3], background_pressure;
  PetscReal     cfl, cfl_visc, cfl_force, relax_time;
  PetscBool     cfl_set;   /* -fs_cfl given (else chosen by integrator) */
  PetscReal     halo_skin; /* extra halo width, in units of h */
  PetscReal     max_density_variation;
  PetscReal     final_time;
  PetscBool     write_output;
  PetscBool     terms_view;
  PetscBool     geometry_view; /* -fs_geometry_view: write the set-up's picture and walls, then stop */
  PetscInt      sort_interval;
  PetscReal     rebalance_threshold; /* -fs_rebalance_threshold: move the cuts when a rank owns this times the mean */
  PetscInt      rebalance_interval;  /* -fs_rebalance_interval: steps at least between two moves of the cuts */
  PetscInt      balance;             /* -fs_balance: what the cuts balance (FSBalance) */
  PetscInt      rebuild;             /* -fs_neighbour_rebuild: FS_REBUILD_AUTO or FS_REBUILD_ALWAYS */
  PetscInt      candidates;          /* -fs_neighbour_candidates: 0 auto, 1 indices, 2 bits (FSNeighboursForm) */
  PetscInt      paircache;           /* -fs_pair_cache: 0 auto (yes in 2-D, no in 3-D), 1 yes, 2 no */
  char          structname[64];
  PetscBool     structure_view;
  PetscReal     structure_cfl; /* dt = structure_cfl * shortest period, when there are no particles */
  PetscBool     options_check; /* -fs_options_check: refuse the -fs_ options nothing reads (FSSolverCheckOptions) */
  FSFillPacking packing;       /* -fs_fill_packing*: how the cases place the liquid's particles */
} FSSolverOptions;

/* When the particles' lists are rebuilt (-fs_neighbour_rebuild, src/solver/rebuild.c) */
typedef enum {
  FS_REBUILD_AUTO,  /* when a pair could come within the support without being a candidate */
  FS_REBUILD_ALWAYS /* after every step */
} FSRebuildType;

/* what the ranks' cuts balance (-fs_balance) */
typedef enum {
  FS_BALANCE_PARTICLES, /* the particles */
  FS_BALANCE_WORK       /* their work in a right-hand side: candidate pairs and wall elements (FSSolverRebalance) */
} FSBalance;

/* The particles' work: the domain and its decomposition, the records of the owned and ghost particles
   and the quantities derived from them at each right-hand side, the halo and the neighbour lists. */
typedef struct {
  PetscReal    lo[3], hi[3];
  PetscBool    periodic[3], domain_set;
  FSDecomp     decomp;
  FSKernel     kernel;
  PetscInt     nowned;
  PetscInt64   nglobal_particles;
  PetscInt     stride;    /* 2*dim+2 */
  PetscInt     auxstride; /* dim+1 */
  PetscReal   *rec, *aux, *vol, *pressure;
  PetscInt     reccap;
  FSHalo       halo;
  FSNeighbours nbrs;
  PetscReal   *scratch;  /* per-i neighbourhood scratch: dx, r2, gradW, 1/r2, u_j - u_i, V_j */
  PetscInt    *scratchj; /* per-i neighbourhood scratch: the neighbours' indices */
  PetscInt     scratchcap;
  /* the pair cache: the neighbours each owned particle's first pass picked and their kernel factors F(r), for the
     passes that follow at the same positions (FSSolverNeighbourhood); valid from the first pass to the next records */
  PetscInt  *pairstart; /* nowned+1: the first pair of each particle */
  PetscInt  *pairj;     /* the neighbours' indices */
  PetscReal *pairF;     /* F(r) of the pairs */
  PetscInt   pairstartcap;
  PetscInt64 paircap;
  PetscBool  pairsvalid;
  PetscInt  *passorder; /* the owned particles, those with no ghost among their candidates first (FSSolverResize) */
  PetscInt   ninterior, passcap;
  PetscReal *gamma,
      *invgamma; /* the walls' Shepard factor gamma of the owned and ghost particles and 1/gamma (with walls) */
  PetscReal *gammav, *invgammav; /* with no-slip walls: gamma plus the share behind them, and its inverse */
  PetscInt   gammacap;
  PetscReal *split;        /* the split step's work (FSSolverSplitStep): 6 arrays of splitcap */
  PetscInt   splitcap;     /* the particles (owned and ghosts) it has room for */
  PetscReal  moved;        /* the largest displacement of a particle since the last build of the lists (all ranks) */
  PetscInt   sort_step;    /* the step of the last ordering by cell */
  PetscInt   balance_step; /* the step at which the cuts were last balanced on the particles */
  PetscInt64 worksum;      /* this rank's work from the lists of the last build (FSSolverGetWorkSum; -1: not yet) */
  PetscBool  resume;       /* the next build takes the positions of the swarm's build field (a restart) */
} FSParticleWork;

/* What limits a time step (the time series' dt_limit column; FSSolverDtLimitName) */
typedef enum {
  FS_DT_ACOUSTIC,   /* CFL h/(c0 + |u|max) */
  FS_DT_VISCOUS,    /* CFL_v h^2/nu, the laminar viscosity -fs_nu */
  FS_DT_SKIN,       /* 0.4 skin h/|u|max: no particle outruns its candidate lists */
  FS_DT_BODY_FORCE, /* CFL_f sqrt(h/|g|) */
  FS_DT_STRUCTURE,  /* -fs_structure_cfl T_min */
  FS_DT_FINAL_TIME, /* the step shortened to land on the final time */
  FS_DT_INTEGRATOR, /* the integrator's own step control (adaptive TS) */
  FS_DT_TERM        /* FS_DT_TERM + t: the diffusivity of term t (e.g. delta, les_viscosity) */
} FSDtLimit;

/* The TS state: U packs (x, u, rho) per owned particle, then the global DOFs on rank 0 (blocks: the
   structure's DOFs, the dissipated energies, the energy budget's), and what the stepping keeps. A structure that
   runs on every rank (not rank0) has its DOFs after the particles on every rank too (nrepl of them), integrated
   there from the same rates: the same values everywhere, so that no rank waits for rank 0's. */
typedef struct {
  Vec U;
  Vec Uprev;             /* state at the start of the step (for the displacement check), only with an integrator that
                            keeps no copy of it (rk4lean and TSRK do: FSSolverGetStepStart) */
  Vec Fout;              /* the outputs' rates at the state (FSSolverEvaluateAtState) when the integrator has no
                            vector free for them (FSSolverGetFreeStage): made there and kept only by an
                            integrator that never has one, destroyed with U */
  PetscBool     rkstart; /* the integrator's own vector holds the state at the start of the last step */
  FSGlobalBlock gblock[FS_MAX_GLOBAL_BLOCKS];
  PetscInt      ngblocks;
  PetscInt gstruct, gdiss, genergy; /* offsets of the structure's DOFs, the dissipated energies, the energy block */
  PetscInt ndiss;                   /* dissipated energies: one per term with a power */
  PetscInt nglobaldofs;
  PetscInt nrepl;    /* the global DOFs every rank holds: the structure's when it runs on every rank, else 0 */
  struct {           /* the next step's time-step reduction, done with the step's own (FSSolverStep) */
    PetscBool ready; /* valid for the TS's step and time below, until the lists are rebuilt */
    PetscInt  step, source;
    PetscReal time, v2, nu, owned, pairs;
  } dtnext;
  PetscReal global0[FS_MAX_GLOBAL];
  PetscInt  ustride; /* 2*dim+1 */
  PetscReal dt_stable, umax;
  PetscReal nu_src[FS_MAX_TERMS + 1]; /* the viscosity bound of the next step per source, this rank's: -fs_nu, then
                                         each term's (scaled to -fs_cfl_viscous when the term has its own
                                         coefficient), from the integrator's last right-hand side */
  PetscInt           dt_limit;        /* what set the last step (FSDtLimit; FS_DT_TERM + t: term t's diffusivity) */
  PetscInt           dt_limit_steps[FS_DT_TERM + FS_MAX_TERMS]; /* steps each limit set since the run (re)started */
  FSCheckpointHeader restart_hdr;
  PetscReal          max_variation; /* max |rho/rho0 - 1| at the last check */
  PetscReal          rhs_time;      /* time of the right-hand side being evaluated */
  PetscBool evaluated;   /* the work arrays hold FSSolverEvaluateAtState's evaluation at U and rhs_time (until a step
                            or the integrator's next evaluation) */
  PetscReal ext_power;   /* P_ext of the last right-hand side, this rank's share */
  PetscReal relax_power; /* power of the start-up relaxation of the last right-hand side, this rank's share */
  PetscReal structure_energy[3]; /* coupled: the structure's energies at the stage's state (FSSolverCouplingRates; rank
                                    0 with a rank0 structure, else every rank) */
  PetscInt64 split_stages;       /* the split terms' RKL2 stages since the run (re)started (FSSolverSplitStep) */
  PetscInt   split_max_stages;   /* the most stages of one step */
} FSSolverState;

/* The run's parallel statistics (src/solver/parallelstats.c, summary.json's "parallel"): what this rank owned,
   its ghosts, and what it sent and how many collectives it took part in over the steps since the monitors began.
   The messages, bytes and collectives are PETSc's counters (every MPI call that petsclog.h counts, in flexslosh
   and in PETSc) read before and after each step, with what they miss added by hand (MPI_Reduce, the halo's
   handshake); the halo and the migration also count their own messages where they post them. */
typedef struct {
  PetscLogDouble msgs, bytes, colls;  /* sent messages, their bytes, collectives: over the steps */
  PetscLogDouble mark[3];             /* the counters at the start of the step in progress */
  PetscLogDouble uncounted;           /* collectives PETSc's counters miss (MPI_Reduce, MPI_Ibarrier) */
  PetscLogDouble mig_msgs, mig_bytes; /* the migrations' particles sent: messages (one per destination) and bytes */
  PetscLogDouble halo_msgs0, halo_bytes0, build_msgs0, build_bytes0; /* the halo's counts when the monitors began */
  PetscInt64     owned_sum, ghost_sum;     /* sums over the steps of this rank's owned particles and ghosts */
  PetscReal  max_owned_sum, max_pairs_sum; /* sums over the steps of the largest owned count and pair list of a rank */
  PetscInt64 pairs_sum;                    /* sum over the steps of this rank's pair list (one right-hand side's) */
  PetscReal  step_max[2];                  /* this step's largest owned count and pair list over the ranks */
  PetscInt   ghosts_first, owned_first, nbuilds0;
} FSParallelStats;

#define FS_MAX_MONITORS 16 /* monitors of each form a solver holds (FSSolverMonitorAdd(), FSSolverMonitorSet()) */

/* The monitors (src/monitor/, FSSolverMonitorAdd(); the built-in ones first) and the plain callbacks
   (FSSolverMonitorSet()), the output directory, and the run's statistics. */
typedef struct {
  FSMonitor         list[FS_MAX_MONITORS];
  PetscInt          nlist;
  PetscInt          nbuiltin; /* the built-in monitors the solver attached (FSSolverMonitorBegin()) */
  FSSolverMonitorFn fn[FS_MAX_MONITORS];
  void             *fnctx[FS_MAX_MONITORS];
  PetscErrorCode (*fndestroy[FS_MAX_MONITORS])(void **);
  PetscInt          nfn;
  PetscLogDouble    wall_start;
  PetscInt          step0;
  PetscInt64        pair_visits, particle_steps;
  PetscInt          nmigrations, nrhs;
  PetscInt          steps_taken; /* steps taken since set-up (this process) */
  PetscInt          nrebalances; /* moves of the cuts (FSSolverRebalance) since set-up */
  PetscInt          nrebuilds;   /* rebuilds of the lists after steps since set-up (this process) */
  FSMonitorRowBatch rows;        /* this step's rows, their sums reduced with the step's own (FSSolverStepReduce) */
  PetscReal        *reduce;      /* FSSolverStepReduce's room for its own values and the rows' (nreduce reals) */
  PetscInt          nreduce;
  PetscBool         monitoring;
  FSOutputLock      lock; /* the output directory, this run's (FSSolverOpenOutputDir()); NULL until it is open */
  PetscReal         t0;
  /* the built-in monitors, made with their options by FSSolverSetFromOptions() and set up by FSSolverSetUp(); the
     run's output attaches those it writes (FSSolverMonitorBegin()); FSSolverGetProbes() reads the probes */
  FSMonitor       series, energy, probes, snapshots, checkpoints, restcheck, progress, summary;
  PetscBool       at_rest;    /* the case starts its liquid at rest (FSSolverSetLiquidAtRest()), for the check */
  PetscReal       rest_depth; /* its depth */
  char           *setup;      /* the record of what defines the run, for the checkpoints (setuprecord.c) */
  FSParallelStats par;        /* summary.json's "parallel" */
} FSMonitorData;

typedef struct _FSSolverOps *FSSolverOps;
struct _FSSolverOps {
  PetscErrorCode (*dummy)(void);
};

/* The solver: its options, the swarm, the TS and its state, and its parts. */
struct _p_FSSolver {
  PETSCHEADER(struct _FSSolverOps);
  FSSolverOptions opt;
  PetscBool       setupcalled;
  FSCaseOps       caseops; /* the case */
  void           *casedata;
  DM              swarm; /* the particles: DMSwarm (BASIC) with fields position, velocity, density, mass, id */
  FSParticleWork  pw;
  FSTermSet       terms;
  FSStructure     structure;  /* NULL with -fs_structure none */
  FSLoads         loads;      /* liquid loads on the tank (the coupling fills them; zero until then) */
  PetscReal      *sy, *sydot; /* the structure's state and rate at the last right-hand side, every rank */
  FSCoupling      coupling;   /* the tank's frame and the loads (src/coupling) */
  PetscInt        nchecked;   /* FSSolverSetOptionsChecked(): the options FSSolverCheckOptions() looks at (0: all) */
  char          **checked;
  FSBoundary      boundary; /* the walls (boundary integrals), NULL without walls */
  TS              ts;
  FSSolverState   state;
  FSMonitorData   mon;
  PetscReal liquid[3]; /* the cases' liquid: its exact volume and mass, the lattice's mass (FSSolverAddLiquidVolume) */
};

/* solver pieces, one file each */
PETSC_INTERN PetscErrorCode FSSolverCreateSwarm(FSSolver);
PETSC_INTERN PetscErrorCode FSSolverOutputDirChoose(FSSolver);
PETSC_INTERN PetscErrorCode FSSolverCheckOptions(FSSolver, PetscBool);
PETSC_INTERN PetscErrorCode FSSolverStructureDtAdvice(FSSolver);
PETSC_INTERN void           FSSolverWrapPeriodic(FSSolver, PetscReal x[]);
PETSC_INTERN PetscErrorCode FSSolverMigrate(FSSolver, PetscBool *changed);
PETSC_INTERN PetscErrorCode FSSolverSortByCell(FSSolver);
PETSC_INTERN PetscErrorCode FSSolverPackState(FSSolver);
PETSC_INTERN PetscErrorCode FSSolverUnpackState(FSSolver);
PETSC_INTERN PetscErrorCode FSSolverEnsureWork(FSSolver, PetscInt n);
PETSC_INTERN PetscErrorCode FSSolverSetUpTS(FSSolver);
PETSC_INTERN PetscErrorCode FSSolverRHS(TS, PetscReal, Vec, Vec, void *);
PETSC_INTERN PetscErrorCode FSSolverComputeStableDt(FSSolver, PetscReal *);
PETSC_INTERN void           FSSolverStableDtOf(FSSolver, PetscReal umax, PetscReal nu, PetscInt source, PetscReal *dt,
                                               PetscInt *limit);
#define FS_REDUCE_MAX 4 /* values FSSolverReduceWithViscosity() reduces besides the viscosities */
PETSC_INTERN PetscErrorCode FSSolverReduceWithViscosity(FSSolver, PetscInt, PetscReal[], PetscReal *, PetscInt *);
PETSC_INTERN PetscErrorCode FSSolverViscosityBound(FSSolver, PetscReal *, PetscInt *);
PETSC_INTERN PetscErrorCode FSSolverDtLimitName(FSSolver, PetscInt, const char **);
PETSC_INTERN PetscErrorCode FSSolverMonitor(FSSolver);
PETSC_INTERN PetscErrorCode FSSolverMonitorBegin(FSSolver);
PETSC_INTERN PetscErrorCode FSSolverBuiltinMonitorsCreate(FSSolver);
PETSC_INTERN PetscErrorCode FSSolverBuiltinMonitorsSetUp(FSSolver);
PETSC_INTERN PetscErrorCode FSSolverBuiltinMonitorsDestroy(FSSolver);
PETSC_INTERN PetscErrorCode FSSolverOpenOutputDir(FSSolver);
PETSC_INTERN PetscErrorCode FSSolverMonitorEnd(FSSolver);
PETSC_INTERN PetscReal      FSSolverWriteStatus(FSSolver);
PETSC_INTERN PetscErrorCode FSSolverWriteStatusRaise(FSSolver, PetscReal);
PETSC_INTERN PetscErrorCode FSSolverResize(FSSolver, PetscBool);
PETSC_INTERN PetscErrorCode FSSolverCheckState(FSSolver);
#define FS_CHECK_N    5   /* the values FSSolverCheckStateLocal() gives to be reduced (MPI_MAX) */
#define FS_SUMMAX_MAX 256 /* the most values FSSolverReduceSumMax() reduces without allocating */
PETSC_INTERN PetscErrorCode FSSolverCheckStateLocal(FSSolver, PetscReal[]);
PETSC_INTERN PetscErrorCode FSSolverCheckStateEnd(FSSolver, const PetscReal[]);
PETSC_INTERN PetscErrorCode FSSolverCheckStart(FSSolver);
PETSC_INTERN PetscErrorCode FSSolverBlowUpCause(FSSolver, char[], size_t, PetscBool *);
PETSC_INTERN PetscErrorCode FSSolverGetStepStart(FSSolver, Vec *);
PETSC_INTERN PetscErrorCode FSSolverGetFreeStage(FSSolver, Vec *, PetscBool *later);
#define FSTSRK4LEAN "rk4lean" /* classical RK4 in three vectors (tsrk4lean.c): the default integrator */
PETSC_INTERN PetscErrorCode FSTSRegisterRK4Lean(void);
PETSC_INTERN PetscErrorCode FSTSRK4LeanGetWork(TS, Vec *, Vec *);
PETSC_INTERN PetscErrorCode FSTSRK4LeanGetNumVectors(TS, PetscInt *);
PETSC_INTERN PetscErrorCode FSTSRK4LeanSetInPlace(TS, PetscBool);
PETSC_INTERN PetscErrorCode FSSolverMarkBuild(FSSolver);
PETSC_INTERN PetscErrorCode FSSolverSwapBuildPositions(FSSolver);
PETSC_INTERN PetscErrorCode FSSolverRecordsAtBuild(FSSolver);
PETSC_INTERN PetscErrorCode FSSolverRebuildNeeded(FSSolver, PetscBool *rebuild, PetscBool *sort);
#define FS_REBUILD_N 3 /* the values FSSolverRebuildNeededLocal() gives to be reduced (MPI_MAX) */
PETSC_INTERN PetscErrorCode FSSolverRebuildNeededLocal(FSSolver, PetscReal[]);
PETSC_INTERN PetscErrorCode FSSolverRebuildDecide(FSSolver, const PetscReal[], PetscReal, PetscInt, PetscBool *,
                                                  PetscBool *);
PETSC_INTERN PetscErrorCode FSSolverKeepLists(FSSolver, PetscBool packed);
PETSC_INTERN PetscErrorCode FSSolverRebalance(FSSolver, PetscInt step, const PetscReal work[2], PetscBool *moved);
PETSC_INTERN PetscErrorCode FSSolverRebalanceWork(FSSolver, PetscInt step, PetscBool *wanted, PetscReal *work);
PETSC_INTERN PetscErrorCode FSSolverBalanceWork(FSSolver);
PETSC_INTERN PetscErrorCode FSSolverGetWorkSum(FSSolver, PetscInt64 *);
PETSC_INTERN PetscErrorCode FSSolverPartitionWalls(FSSolver);
PETSC_INTERN PetscErrorCode FSSolverLoadCheckpoint(FSSolver);
PETSC_INTERN PetscErrorCode FSParallelStatsBegin(FSSolver);
PETSC_INTERN void           FSParallelStatsStepBegin(FSSolver);
PETSC_INTERN void           FSParallelStatsStepEnd(FSSolver);
PETSC_INTERN PetscErrorCode FSParallelStatsSummary(FSSolver, FSJSON);
PETSC_INTERN PetscErrorCode FSSolverWriteMemory(FSSolver, FSJSON, PetscReal peak);
PETSC_INTERN PetscErrorCode FSSolverSetUpRecord(FSSolver);
PETSC_INTERN PetscErrorCode FSSolverCheckSetUp(FSSolver, const char[]);
PETSC_INTERN PetscErrorCode FSSolverCheckRanksAgree(FSSolver);
PETSC_INTERN PetscErrorCode FSSolverGetParticles(FSSolver, FSParticles *);
PETSC_INTERN PetscErrorCode FSSolverGatherRecordsBegin(FSSolver, const PetscReal *u);
PETSC_INTERN PetscErrorCode FSSolverGatherRecordsEnd(FSSolver);
PETSC_INTERN void           FSSolverVolumesAndPressures(FSSolver, PetscInt k0, PetscInt k1);
PETSC_INTERN PetscErrorCode FSSolverFirstPass(FSSolver);
PETSC_INTERN PetscErrorCode FSSolverSplitStep(FSSolver, PetscReal dt);
PETSC_INTERN void           FSRKL2Coefficients(PetscInt s, PetscInt j, PetscReal *mu, PetscReal *nu, PetscReal *mut,
                                               PetscReal *gt);
PETSC_INTERN PetscInt       FSRKL2Stages(PetscReal z);
PETSC_INTERN PetscErrorCode FSSolverEnergyAddTermWork(FSSolver, FSTerm, PetscReal);
PETSC_INTERN PetscReal      FSSolverCompressibilityEnergy(FSSolver, PetscReal rho);
PETSC_INTERN PetscErrorCode FSSolverEvaluateRates(FSSolver, const PetscReal *u, PetscReal *f, PetscBool count);

/* The energy block of the global DOFs: the time integrals of P_ext, of the start-up relaxation's
   power, of the structure's damping power (negative: energy lost) and of the coupling's power (the work
   of the difference between the loads the structure receives and the reaction of the walls' forces on
   the particles: energy the coupling creates), of the power a prescribed motion puts into the liquid
   (the walls' forces on the liquid times the walls' rigid velocity), the energy changes of the wall bounces (liquid,
   whole system; changed between steps, not by the integrator), and the liquid's and the whole system's energies at the
   start of the run (rate zero: kept through restarts by the checkpoints). */
enum {
  FS_ENERGY_WORK_EXT,
  FS_ENERGY_WORK_RELAX,
  FS_ENERGY_WORK_DAMPING,
  FS_ENERGY_WORK_COUPLING,
  FS_ENERGY_WORK_MOTION,
  FS_ENERGY_WORK_BOUNCE,
  FS_ENERGY_WORK_BOUNCE_TOTAL,
  FS_ENERGY_LIQUID0,
  FS_ENERGY_TOTAL0,
  FS_ENERGY_NDOF
};
PETSC_INTERN PetscErrorCode FSSolverEnergyInitial(FSSolver);
typedef struct {
  FSTankMotion mo;
  PetscReal    c, sn;
  PetscBool    coupled;
} FSEnergyFrame;
PETSC_INTERN PetscErrorCode FSSolverEnergyJumpFrame(FSSolver, FSEnergyFrame *);
PETSC_INTERN void           FSEnergyParticle(FSSolver, const FSEnergyFrame *, const PetscReal x[], const PetscReal v[],
                                             PetscReal m, PetscReal e[2]);
PETSC_INTERN PetscErrorCode FSSolverEnergyAddJump(FSSolver, const PetscReal[2], PetscBool);

/* the structure inside the solver (src/solver/structure.c), with the coupling's stages */
PETSC_INTERN PetscErrorCode FSSolverCouplingPredict(FSSolver, const PetscReal *u);
PETSC_INTERN PetscErrorCode FSSolverCouplingRates(FSSolver, PetscReal *f);
PETSC_INTERN PetscErrorCode FSSolverSetUpGlobalBlocks(FSSolver);
PETSC_INTERN PetscErrorCode FSSolverGlobalDofName(FSSolver, PetscInt, char[], size_t);
PETSC_INTERN PetscErrorCode FSSolverStructureRates(FSSolver, PetscBool broadcast, const PetscReal *u, PetscReal *f,
                                                   PetscErrorCode *rank0err);
PETSC_INTERN PetscErrorCode FSSolverStructureBroadcastState(FSSolver, const PetscReal *u);
/* the reals of an FSTankMotion, and the most a structure routine's result broadcast carries */
#define FS_MOTION_NREAL ((PetscInt)(sizeof(FSTankMotion) / sizeof(PetscReal)))
#define FS_RANK0_MAX    (32 + FS_MAX_GLOBAL) /* the tank's motion and the structure's state */
PETSC_INTERN PetscErrorCode FSSolverStructureResultRank0(FSSolver, PetscErrorCode, const char[], PetscInt, PetscReal[]);
/* whether the structure's routines run on this rank: on every rank, or on rank 0 alone for a rank0 structure */
static inline PetscBool FSSolverStructureHere(FSSolver s)
{
  return (PetscBool)(s->structure && (!s->structure->rank0 || s->pw.decomp.rank == 0));
}
/* the global DOFs this rank holds after its particles: all of them on rank 0, the structure's elsewhere when it
   runs on every rank */
static inline PetscInt FSSolverLocalGlobalDofs(FSSolver s, PetscMPIInt rank)
{
  return rank == 0 ? s->state.nglobaldofs : s->state.nrepl;
}
PETSC_INTERN PetscErrorCode FSSolverStructureDt(FSSolver, PetscReal *);
PETSC_INTERN PetscErrorCode FSSolverOwnedMaxSpeed2(FSSolver, PetscReal *);
PETSC_INTERN PetscErrorCode FSSolverStructureColumns(FSSolver, PetscInt *, const char *[]);
PETSC_INTERN PetscErrorCode FSSolverStructureValues(FSSolver, PetscReal vals[]);
PETSC_INTERN PetscErrorCode FSSolverStructureSummary(FSSolver, FSJSON);

/* u_j - u_i and V_j of the n neighbours j[] of particle i, for the terms (FSNeighbourhood) */
FS_ALWAYS_INLINE void FSFillNeighbourVelocitiesDim(const FSSolver s, const PetscInt dim, PetscInt i, PetscInt n,
                                                   const PetscInt *j, PetscReal *du, PetscReal *Vj)
{
  const PetscInt   S   = 2 * dim + 2; /* the records' stride (solver.c) */
  const PetscReal *rec = s->pw.rec, *ui = &rec[i * S + dim], *vol = s->pw.vol;

  for (PetscInt k = 0; k < n; k++) {
    const PetscReal *uj = &rec[j[k] * S + dim];
    for (PetscInt a = 0; a < dim; a++) du[k * dim + a] = uj[a] - ui[a];
    Vj[k] = vol[j[k]];
  }
}

/* Fills the neighbourhood scratch of particle i: its neighbours j (picked from the candidates), x_j - x_i,
   r^2, grad_i W, 1/r^2. Returns their number. */
FS_ALWAYS_INLINE PetscInt FSFillNeighbourhoodDim(const FSSolver s, const PetscInt dim, PetscInt i, PetscInt *j,
                                                 PetscReal *dx, PetscReal *r2, PetscReal *gw, PetscReal *ri2)
{
  const FSKernel *kern = &s->pw.kernel;
  const PetscInt  n    = FSNeighboursPick(&s->pw.nbrs, dim, i, s->pw.rec, 2 * dim + 2, kern->support2, j, dx, r2);

  /* F(r) in a loop of its own, which the compiler vectorizes (the same value as the first pass's) */
  for (PetscInt k = 0; k < n; k++) {
    const PetscReal F = FSKernelF(kern, PetscSqrtReal(r2[k]));
    for (PetscInt a = 0; a < dim; a++) gw[dim * k + a] = -F * dx[dim * k + a];
  }
  /* the inverses in a loop of their own, which the compiler vectorizes */
  for (PetscInt k = 0; k < n; k++) ri2[k] = 1.0 / r2[k];
  return n;
}

/* The same from the pair cache (FSSolverFirstPass), with u_j - u_i and V_j: the n neighbours j[] with their F(r)
   given, the same values as FSFillNeighbourhoodDim's and FSFillNeighbourVelocitiesDim's (the same operations on the
   same records) without the candidates' search and the square roots; positions and velocities two components at a
   time where the compiler has FSReal2 */
FS_ALWAYS_INLINE void FSFillCachedNeighbourhoodDim(const FSSolver s, const PetscInt dim, PetscInt i, PetscInt n,
                                                   const PetscInt *j, const PetscReal *F, PetscReal *dx, PetscReal *r2,
                                                   PetscReal *gw, PetscReal *ri2, PetscReal *du, PetscReal *Vj)
{
  const PetscInt   S   = 2 * dim + 2; /* the records' stride (FSSolverFirstPass checks it) */
  const PetscReal *rec = s->pw.rec, *xi = &rec[i * S], *vol = s->pw.vol;
#if defined(FS_HAVE_REAL2)
  const FSReal2 xi01 = FSLoad2(xi), ui01 = FSLoad2(xi + dim);
#endif

  for (PetscInt k = 0; k < n; k++) {
    const PetscReal *xj = &rec[j[k] * S];
    PetscReal        d2;
#if defined(FS_HAVE_REAL2)
    const FSReal2 d = FSLoad2(xj) - xi01, sq = d * d;
    FSStore2(&dx[k * dim], d);
    FSStore2(&du[k * dim], FSLoad2(xj + dim) - ui01);
    d2 = sq[0] + sq[1]; /* = 0 + d0^2 + d1^2 */
    if (dim == 3) {
      const PetscReal d3 = xj[2] - xi[2];
      dx[k * dim + 2]    = d3;
      d2 += d3 * d3;
      du[k * dim + 2] = xj[dim + 2] - xi[dim + 2];
    }
#else
    d2 = 0;
    for (PetscInt a = 0; a < dim; a++) {
      const PetscReal d = xj[a] - xi[a];
      dx[k * dim + a]   = d;
      d2 += d * d;
      du[k * dim + a] = xj[dim + a] - xi[dim + a];
    }
#endif
    r2[k] = d2;
    Vj[k] = vol[j[k]];
  }
  for (PetscInt k = 0; k < n; k++)
    for (PetscInt a = 0; a < dim; a++) gw[dim * k + a] = -F[k] * dx[dim * k + a];
  for (PetscInt k = 0; k < n; k++) ri2[k] = 1.0 / r2[k];
}

/* The neighbourhood of owned particle i in the solver's scratch (FSFillNeighbourhoodDim, or from the pair cache),
   for the terms' pair sums. The scratch: dx (dim a neighbour), r^2, grad W (dim), 1/r^2, u_j - u_i (dim), V_j. */
FS_ALWAYS_INLINE void FSSolverNeighbourhood(const FSSolver s, PetscInt i, FSNeighbourhood *nb)
{
  const PetscInt dim = s->opt.dim, cap = s->pw.scratchcap;
  PetscReal     *dx = s->pw.scratch, *r2 = dx + dim * cap, *gw = r2 + cap, *ri2 = gw + dim * cap, *du = ri2 + cap,
            *Vj = du + dim * cap;

  nb->i = i;
  nb->j = s->pw.scratchj;
  if (s->pw.pairsvalid) { /* the first pass's pairs at these positions */
    const PetscInt   p0 = s->pw.pairstart[i], *j = s->pw.pairj + p0;
    const PetscReal *F = s->pw.pairF + p0;
    nb->n              = s->pw.pairstart[i + 1] - p0;
    nb->j              = j;
    if (dim == 2) FSFillCachedNeighbourhoodDim(s, 2, i, nb->n, j, F, dx, r2, gw, ri2, du, Vj);
    else FSFillCachedNeighbourhoodDim(s, 3, i, nb->n, j, F, dx, r2, gw, ri2, du, Vj);
  } else if (dim == 2) {
    nb->n = FSFillNeighbourhoodDim(s, 2, i, s->pw.scratchj, dx, r2, gw, ri2);
    FSFillNeighbourVelocitiesDim(s, 2, i, nb->n, nb->j, du, Vj);
  } else {
    nb->n = FSFillNeighbourhoodDim(s, 3, i, s->pw.scratchj, dx, r2, gw, ri2);
    FSFillNeighbourVelocitiesDim(s, 3, i, nb->n, nb->j, du, Vj);
  }
  nb->dx    = dx;
  nb->r2    = r2;
  nb->rinv2 = ri2;
  nb->gradW = gw;
  nb->du    = du;
  nb->Vj    = Vj;
}
