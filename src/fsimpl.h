/*
   Private data structures of libflexslosh. Not part of the public interface.

   Data flow of one run:  options -> case set-up (domain, particles) -> decomposition ->
   TS loop [ halo refresh -> cell list and neighbour lists -> first pass (correction matrix,
   density gradient, strain rate) -> ghost refresh of those -> pair pass of the terms ] ->
   monitors (time series, snapshots, checkpoints, progress, blow-up checks).
*/
#pragma once
#include <flexslosh.h>
#include <petsc/private/petscimpl.h>
#include "output/fsoutput.h"

#define FS_MAX_TERMS 32

/* A registration table (src/registry.c): creation routines by name, with descriptions. */
typedef struct _n_FSRegistryEntry {
  char                       name[64], description[256];
  struct _n_FSRegistryEntry *next;
} FSRegistryEntry;
typedef struct {
  PetscFunctionList list;
  FSRegistryEntry  *first; /* registration order */
} FSRegistry;

PETSC_INTERN PetscErrorCode FSRegistryAdd(FSRegistry *, const char[], const char[], void (*)(void));
PETSC_INTERN PetscErrorCode FSRegistryFind(FSRegistry *, const char[], void (**)(void));
PETSC_INTERN PetscErrorCode FSRegistryView(FSRegistry *, PetscViewer, const char[], const char[]);
PETSC_INTERN PetscErrorCode FSRegistryNames(FSRegistry *, char[], size_t);
#define FS_MAX_GLOBAL 64

/* Wendland C2 kernel with support 2h, dimension 2 or 3. */
typedef struct {
  PetscInt  dim;
  PetscReal h, support, support2;
  PetscReal wnorm; /* W(q) = wnorm (1 - q/2)^4 (2q + 1) */
  PetscReal fnorm; /* grad_i W = fnorm (1 - q/2)^3 (x_i - x_j), i.e. F(r) = W'(r)/r */
} FSKernel;

PETSC_INTERN PetscErrorCode FSKernelSetUp(FSKernel *, PetscInt dim, PetscReal h);
static inline PetscReal FSKernelW(const FSKernel *k, PetscReal r)
{
  const PetscReal q = r / k->h, a = 1.0 - 0.5 * q;
  return q >= 2.0 ? 0.0 : k->wnorm * a * a * a * a * (2.0 * q + 1.0);
}
/* F(r) such that grad_i W(x_i - x_j) = F(r) (x_i - x_j); valid for r < 2h. */
static inline PetscReal FSKernelF(const FSKernel *k, PetscReal r)
{
  const PetscReal a = 1.0 - 0.5 * r / k->h;
  return k->fnorm * a * a * a;
}

/* The body acceleration a particle at x feels in the tank's frame without the Coriolis part:
   a(x) = b + alpha (r_y, -r_x) + omega^2 (r_x, r_y), r = x - ref, b = R(-theta) (g - A) (coupling.c). */
typedef struct {
  PetscReal b[2], omega, alpha, ref[2];
} FSFrameField;

static inline void FSFrameFieldEval(const FSFrameField *ff, const PetscReal x[], PetscReal a[])
{
  const PetscReal rx = x[0] - ff->ref[0], ry = x[1] - ff->ref[1], w2 = ff->omega * ff->omega;
  a[0] = ff->b[0] + ff->alpha * ry + w2 * rx;
  a[1] = ff->b[1] - ff->alpha * rx + w2 * ry;
}

/* Orthogonal process grid over the domain box: rank (i,j,k) owns
   [cut[d][i_d], cut[d][i_d+1]) in every direction d. */
typedef struct {
  PetscInt    dim;
  PetscReal   lo[3], hi[3], len[3];
  PetscBool   periodic[3];
  PetscMPIInt size, rank;
  PetscMPIInt np[3];    /* ranks per direction */
  PetscMPIInt coord[3]; /* this rank's position in the grid */
  PetscReal  *cut[3];   /* np[d]+1 cut positions per direction */
} FSDecomp;

PETSC_INTERN PetscErrorCode FSDecompSetUp(FSDecomp *, MPI_Comm, PetscInt dim, const PetscReal lo[], const PetscReal hi[], const PetscBool periodic[], PetscReal minwidth);
PETSC_INTERN PetscErrorCode FSDecompBalance(FSDecomp *, MPI_Comm, PetscInt n, const PetscReal x[], PetscReal minwidth);
PETSC_INTERN PetscErrorCode FSDecompDestroy(FSDecomp *);
PETSC_INTERN PetscMPIInt    FSDecompRankOf(const FSDecomp *, const PetscReal x[]);
PETSC_INTERN PetscMPIInt    FSDecompRankAt(const FSDecomp *, const PetscMPIInt c[]);

/* Ghost particles: copies of owned particles of other ranks (or periodic images of this rank's)
   within the halo width of this rank's subdomain. Refreshed through a PetscSF each RHS. */
typedef struct {
  PetscInt   nghost, cap;
  PetscReal *shift; /* nghost*dim periodic shift added after each refresh */
  PetscSF    sf;    /* roots: owned records, leaves: ghost records */
  MPI_Datatype rectype, auxtype;
  PetscInt   recstride, auxstride;
  /* send-side work for building */
  PetscInt   nsend, sendcap;
  PetscInt  *send_index;
  PetscMPIInt *send_rank;
  PetscReal *send_shift;
} FSHalo;

PETSC_INTERN PetscErrorCode FSHaloBuild(FSHalo *, MPI_Comm, const FSDecomp *, PetscInt nowned, const PetscReal rec[], PetscInt stride, PetscReal width);
PETSC_INTERN PetscErrorCode FSHaloRefresh(FSHalo *, PetscInt dim, PetscInt nowned, PetscReal rec[]);
PETSC_INTERN PetscErrorCode FSHaloRefreshAux(FSHalo *, PetscReal aux[]);
PETSC_INTERN PetscErrorCode FSHaloRefreshScalar(FSHalo *, PetscReal a[]);
PETSC_INTERN PetscErrorCode FSHaloDestroy(FSHalo *);

/* Cell-linked list (counting sort) and the full neighbour list of owned particles (CSR). */
typedef struct {
  PetscInt   dim;
  PetscReal  lo[3], cellsize;
  PetscInt   nc[3], ncells;
  PetscInt  *cellstart; /* ncells+1 */
  PetscInt  *cellof;    /* cell of each particle */
  PetscInt  *order;     /* particles sorted by cell */
  PetscInt   ncap, ccap;
  /* candidate (Verlet) list, built once per step */
  PetscInt  *cstart;    /* nowned+1 */
  PetscInt  *cand;
  PetscInt   ccandcap, ncand;
  /* neighbour list, built at every right-hand side */
  PetscInt  *start;     /* nowned+1 */
  PetscInt  *nbr;       /* neighbour index per pair */
  PetscReal *F;         /* kernel gradient factor per pair */
  PetscInt   scap, pcap;
  PetscInt64 npairs;
} FSNeighbours;

PETSC_INTERN PetscErrorCode FSNeighboursBuildCells(FSNeighbours *, PetscInt dim, PetscInt n, const PetscReal rec[], PetscInt stride, PetscReal cellsize);
PETSC_INTERN PetscErrorCode FSNeighboursBuildCandidates(FSNeighbours *, PetscInt nowned, const PetscReal rec[], PetscInt stride, PetscReal radius);
PETSC_INTERN PetscErrorCode FSNeighboursReserveList(FSNeighbours *);
PETSC_INTERN PetscErrorCode FSNeighboursBuildList(FSNeighbours *, const FSKernel *, PetscInt nowned, const PetscReal rec[], PetscInt stride);
PETSC_INTERN PetscErrorCode FSNeighboursDestroy(FSNeighbours *);

/* Selected terms and the per-particle work of one right-hand side. */
typedef struct {
  PetscInt nterms;
  FSTerm   term[FS_MAX_TERMS];
  PetscInt needs;
} FSTermSet;

/* The global DOFs of the state (on rank 0, after the particles) are a short list of blocks:
   the structure's DOFs first, then one dissipated energy per term with a power, then the energy
   budget's own integrals and constants (FS_ENERGY_*, src/energy.c). */
#define FS_MAX_GLOBAL_BLOCKS 4
typedef struct {
  char     name[32];
  PetscInt offset, n;
} FSGlobalBlock;

/* The energy block of the global DOFs: the time integrals of P_ext, of the start-up relaxation's
   power, of the structure's damping power (negative: energy lost) and of the coupling's power (the work
   of the difference between the loads the structure receives and the reaction of the walls' forces on
   the particles: energy the coupling creates), the energy changes of the wall bounces (liquid, whole
   system; changed between steps, not by the integrator), and the liquid's and the whole
   system's energies at the start of the run (rate zero: kept through restarts by the checkpoints). */
enum { FS_ENERGY_WORK_EXT, FS_ENERGY_WORK_RELAX, FS_ENERGY_WORK_DAMPING, FS_ENERGY_WORK_COUPLING, FS_ENERGY_WORK_BOUNCE, FS_ENERGY_WORK_BOUNCE_TOTAL, FS_ENERGY_LIQUID0, FS_ENERGY_TOTAL0, FS_ENERGY_NDOF };
PETSC_INTERN PetscErrorCode FSSolverEnergyColumns(FSSolver, PetscInt *, const char *[]);
PETSC_INTERN PetscErrorCode FSSolverEnergyValues(FSSolver, PetscReal[]);
PETSC_INTERN PetscErrorCode FSSolverEnergyInitial(FSSolver);
typedef struct {
  FSTankMotion mo;
  PetscReal    c, sn;
} FSEnergyFrame;
PETSC_INTERN PetscErrorCode FSSolverEnergyJumpFrame(FSSolver, FSEnergyFrame *);
PETSC_INTERN void           FSEnergyParticle(FSSolver, const FSEnergyFrame *, const PetscReal x[], const PetscReal v[], PetscReal m, PetscReal e[2]);
PETSC_INTERN PetscErrorCode FSSolverEnergyAddJump(FSSolver, const PetscReal[2]);

PETSC_INTERN PetscErrorCode FSStructureCreate(FSSolver, const char name[], FSStructure *);
PETSC_INTERN PetscErrorCode FSStructureDestroy(FSStructure *);
PETSC_INTERN PetscErrorCode FSStructureHelpAll(FSSolver, PetscOptionItems *);
PETSC_INTERN PetscErrorCode FSStructureFind(const char name[], FSStructureCreateFn *);

typedef struct _FSSolverOps *FSSolverOps;
struct _FSSolverOps {
  PetscErrorCode (*dummy)(void);
};

struct _p_FSSolver {
  PETSCHEADER(struct _FSSolverOps);
  /* options */
  char      casename[64];
  char      default_terms[1024]; /* the case's default for -fs_terms */
  char      outdir[PETSC_MAX_PATH_LEN];
  char      restart[PETSC_MAX_PATH_LEN];
  PetscInt  dim;
  PetscReal dx, h_over_dx, h, rho0, c0, nu, gravity[3], background_pressure;
  PetscReal cfl, cfl_visc, cfl_force, relax_time;
  PetscBool cfl_set; /* -fs_cfl given (else chosen by integrator) */
  PetscReal halo_skin;        /* extra halo width, in units of h */
  PetscReal max_density_variation;
  PetscReal output_interval;
  PetscInt  checkpoint_interval;
  PetscBool progress, write_output;
  PetscReal progress_interval;
  PetscBool terms_view, setupcalled;
  PetscBool geometry_view;    /* -fs_geometry_view: write the set-up's picture and walls, then stop */
  PetscInt  sort_interval;

  /* case */
  FSCaseOps caseops;
  void     *casedata;

  /* geometry and decomposition */
  PetscReal lo[3], hi[3];
  PetscBool periodic[3], domain_set;
  FSDecomp  decomp;
  FSKernel  kernel;

  /* particles: DMSwarm (BASIC) with fields position, velocity, density, mass, id */
  DM       swarm;
  PetscInt nowned;
  PetscInt64 nglobal_particles;

  /* work arrays: particle records of owned + ghost particles, derived quantities */
  PetscInt   stride;    /* 2*dim+2 */
  PetscInt   auxstride; /* dim+1 */
  PetscReal *rec, *aux, *vol, *pressure;
  PetscInt   reccap;
  FSHalo       halo;
  FSNeighbours nbrs;
  PetscReal   *scratch;  /* per-i neighbourhood scratch: dx, r2, gradW */
  PetscInt     scratchcap;

  /* terms */
  FSTermSet terms;

  /* the structure (NULL with -fs_structure none) */
  char        structname[64];
  FSStructure structure;
  PetscBool   structure_view;
  PetscReal   structure_cfl;  /* dt = structure_cfl * shortest period, when there are no particles */
  FSLoads     loads;          /* liquid loads on the tank (the coupling fills them; zero until then) */
  PetscReal  *sy, *sydot;     /* the structure's state and rate at the last right-hand side, every rank */
  /* the coupling (src/coupling.c) */
  PetscBool    coupled;       /* liquid and structure coupled */
  PetscReal    tank_width;    /* across the 2-D plane: loads per unit width times this */
  PetscReal    tank_ref[2];   /* the tank's point on the beam, in the tank frame */
  PetscReal    liquid_mass;   /* of the whole tank (2-D mass times width) */
  FSLoads      static_loads;  /* of the liquid at rest in the undeflected tank, subtracted */
  FSTankMotion motion;        /* the tank's motion at the last right-hand side, every rank */
  PetscReal    angle;         /* the tank's angle at this stage (from the structure's state) */
  FSFrameField body;          /* the body acceleration field of the tank's frame predicted for this stage (FSSolverCouplingPredict; g without a coupling) */
  PetscReal    ext_power;     /* P_ext of the last right-hand side, this rank's share */
  PetscReal    reaction[3];   /* force (2) and moment of all terms but gravity on the liquid, tank frame, per unit width, all ranks */
  PetscBool    loads_from_walls; /* -fs_coupling_loads walls */
  PetscReal    tank_load[3];  /* the liquid's loads of the last right-hand side in the tank's frame, per unit width: force (2), moment about tank_ref */
  PetscReal    relax_power;   /* power of the start-up relaxation of the last right-hand side, this rank's share */
  PetscReal   rhs_time;       /* time of the right-hand side being evaluated */
  PetscInt    steps_taken;    /* steps taken since set-up (this process) */

  /* time stepping: U packs (x, u, rho) per owned particle, then the global DOFs on rank 0 */
  TS        ts;
  Vec       U;
  FSGlobalBlock gblock[FS_MAX_GLOBAL_BLOCKS];
  PetscInt  ngblocks;
  PetscInt  gstruct, gdiss, genergy; /* offsets of the structure's DOFs, the dissipated energies, the energy block */
  PetscInt  ndiss;          /* dissipated energies: one per term with a power */
  PetscInt  nglobaldofs;
  PetscReal global0[FS_MAX_GLOBAL];
  PetscInt  ustride; /* 2*dim+1 */
  PetscReal dt_stable, final_time, umax, nu_bound;
  PetscInt  nrhs;
  Vec       Uprev;               /* state at the start of the step (for the displacement check) */
  FSCheckpointHeader restart_hdr;
  PetscReal max_variation;       /* max |rho/rho0 - 1| at the last check */

  /* monitors and output */
  FSSnapshotWriter snapshots;
  FSTimeSeries     series;
  FSTimeSeries     energyseries;  /* energy.csv */
  PetscReal        next_output;
  PetscLogDouble   wall_start, wall_last_progress;
  PetscInt         step0;
  PetscInt64       pair_visits, particle_steps;
  PetscInt         nmigrations;
  PetscBool        monitoring;
  PetscReal        t0, last_snapshot_time;
  PetscReal       *field;        /* output staging */
  struct _n_FSWallData *wd;      /* walls (boundary integrals), NULL without walls: src/walls/walldata.h */
  PetscInt         fieldcap;
};

/* solver pieces, one file each */
PETSC_INTERN PetscErrorCode FSSolverCreateSwarm(FSSolver);
PETSC_INTERN PetscErrorCode FSSolverMigrate(FSSolver, PetscBool *changed);
PETSC_INTERN PetscErrorCode FSSolverSortByCell(FSSolver);
PETSC_INTERN PetscErrorCode FSSolverPackState(FSSolver);
PETSC_INTERN PetscErrorCode FSSolverUnpackState(FSSolver);
PETSC_INTERN PetscErrorCode FSSolverEnsureWork(FSSolver, PetscInt n);
PETSC_INTERN PetscErrorCode FSSolverSetUpTS(FSSolver);
PETSC_INTERN PetscErrorCode FSSolverRHS(TS, PetscReal, Vec, Vec, void *);
PETSC_INTERN PetscErrorCode FSSolverComputeStableDt(FSSolver, PetscReal *);
PETSC_INTERN PetscErrorCode FSSolverMonitor(FSSolver);
PETSC_INTERN PetscErrorCode FSSolverMonitorBegin(FSSolver);
PETSC_INTERN PetscErrorCode FSSolverMonitorEnd(FSSolver);
PETSC_INTERN PetscErrorCode FSSolverResize(FSSolver, PetscBool);
PETSC_INTERN PetscErrorCode FSSolverCheckState(FSSolver);
PETSC_INTERN PetscErrorCode FSSolverWriteSnapshot(FSSolver);
PETSC_INTERN PetscErrorCode FSSolverWriteCheckpoint(FSSolver);
PETSC_INTERN PetscErrorCode FSSolverLoadCheckpoint(FSSolver);
PETSC_INTERN PetscErrorCode FSSolverWriteSummary(FSSolver);
PETSC_INTERN PetscErrorCode FSSolverGetParticles(FSSolver, FSParticles *);
PETSC_INTERN PetscErrorCode FSSolverEvaluateRates(FSSolver, const PetscReal *u, PetscReal *f, PetscBool count);
PETSC_INTERN PetscErrorCode FSTermCreate(FSSolver, const char name[], FSTerm *);
PETSC_INTERN PetscErrorCode FSTermDestroy(FSTerm *);
PETSC_INTERN PetscErrorCode FSCaseFind(const char name[], FSCaseCreateFn *);
PETSC_INTERN PetscErrorCode FSTermHelpAll(FSSolver, PetscOptionItems *);
PETSC_INTERN PetscErrorCode FSCaseHelpAll(FSSolver, PetscOptionItems *);

/* the structure inside the solver (src/structure.c) */
PETSC_INTERN PetscErrorCode FSSolverSetUpGlobalBlocks(FSSolver);
PETSC_INTERN PetscErrorCode FSSolverStructureRates(FSSolver, PetscBool broadcast, const PetscReal *u, PetscReal *f, PetscErrorCode *rank0err);
PETSC_INTERN PetscErrorCode FSSolverStructureBroadcastState(FSSolver, const PetscReal *u);
/* the reals of an FSTankMotion, and the most a structure routine's result broadcast carries */
#define FS_MOTION_NREAL ((PetscInt)(sizeof(FSTankMotion) / sizeof(PetscReal)))
#define FS_RANK0_MAX    16
PETSC_INTERN PetscErrorCode FSSolverStructureResultRank0(FSSolver, PetscErrorCode, const char[], PetscInt, PetscReal[]);
PETSC_INTERN PetscErrorCode FSSolverCouplingSetUp(FSSolver);
PETSC_INTERN PetscErrorCode FSSolverCouplingPredict(FSSolver, const PetscReal *u);
PETSC_INTERN PetscErrorCode FSSolverCouplingRates(FSSolver, PetscReal *f);
PETSC_INTERN PetscErrorCode FSSolverCouplingInertia(FSSolver, PetscReal *f, PetscReal *power);
PETSC_INTERN PetscErrorCode FSSolverCouplingReaction(FSSolver, const PetscReal *f, PetscReal local[3]);
PETSC_INTERN PetscErrorCode FSSolverStructureDt(FSSolver, PetscReal *);
PETSC_INTERN PetscErrorCode FSSolverStructureColumns(FSSolver, PetscInt *, const char *[]);
PETSC_INTERN PetscErrorCode FSSolverStructureValues(FSSolver, PetscReal vals[]);
PETSC_INTERN PetscErrorCode FSSolverStructureSnapshot(FSSolver);
PETSC_INTERN PetscErrorCode FSSolverStructureSummary(FSSolver, FSJSON);

/* log events */
PETSC_EXTERN PetscLogEvent FS_Structure, FS_Coupling;
PETSC_EXTERN PetscLogEvent FS_Step, FS_Neighbours, FS_Halo, FS_FirstPass, FS_PairPass, FS_WallPass, FS_Walls, FS_Migrate, FS_Output, FS_RHS;

/* field names in the swarm */
#define FS_FIELD_POSITION "position"
#define FS_FIELD_VELOCITY "velocity"
#define FS_FIELD_DENSITY  "density"
#define FS_FIELD_MASS     "mass"
#define FS_FIELD_ID       "id"
