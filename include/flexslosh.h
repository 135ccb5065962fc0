/*
   flexslosh: liquid sloshing in tanks carried by flexible structures (delta-LES-SPH + PETSc TS).

   Public interface of libflexslosh. The objects follow PETSc's pattern
   (Create / SetFromOptions / SetUp / Solve / View / Destroy, options prefixes, registries):

     FSSolver  the whole run: particles, decomposition, physics terms, time stepping, output
     FSTerm    one physics term of the right-hand side (continuity, pressure, viscosity, ...)
     FSCase    the set-up of a run (domain, particles, initial fields, default parameters)
     FSStructure  the structure that carries the tank (mass-spring-damper, modal beam, ...)
     FSBoundary   the walls (boundary integrals on polygons, ...): the Shepard factor, the wall terms' view
     FSMonitor    what a run reports after its steps (time series, energy budget, probes, snapshots,
                  checkpoints, or a user's own), attached to the solver as TS monitors are

   Implementations of terms, cases and structures are registered in tables (FSTermRegister,
   FSCaseRegister, FSStructureRegister) and chosen by name at run time (-fs_terms, -fs_case,
   -fs_structure). Plug-ins loaded with -dll_append register
   their own from their entry point PetscDLLibraryRegister_<libname>().
*/
#pragma once
#include <petscts.h>
#include <petscdmswarm.h>
#include <petscsf.h>

#define FLEXSLOSH_VERSION "0.1.0"

typedef struct _p_FSSolver    *FSSolver;
typedef struct _p_FSTerm      *FSTerm;
typedef struct _p_FSStructure *FSStructure;
typedef struct _p_FSBoundary  *FSBoundary;
typedef struct _p_FSMonitor   *FSMonitor;

PETSC_EXTERN PetscClassId FSSOLVER_CLASSID;
PETSC_EXTERN PetscClassId FSMONITOR_CLASSID;

/* ---------- library ---------- */
PETSC_EXTERN PetscErrorCode FSInitializePackage(void);
PETSC_EXTERN PetscErrorCode FSFinalizePackage(void);
PETSC_EXTERN PetscErrorCode FSCheckPlugins(MPI_Comm);
PETSC_EXTERN PetscErrorCode FSLoadPlugins(MPI_Comm);
PETSC_EXTERN PetscErrorCode FSOptionsLeft(MPI_Comm, PetscInt, const char *const[]);
PETSC_EXTERN PetscErrorCode FSErrorHandler(MPI_Comm, int, const char *, const char *, PetscErrorCode, PetscErrorType,
                                           const char *, void *);
PETSC_EXTERN PetscErrorCode FSErrorTraceHandler(MPI_Comm, int, const char *, const char *, PetscErrorCode,
                                                PetscErrorType, const char *, void *);
PETSC_EXTERN PetscBool      FSErrorPrinted(void);

/* ---------- options, checked where they are read (src/sys/options.c) ---------- */
/* Which bounds of a real option's range are open; PETSC_NINFINITY and PETSC_INFINITY stand for no bound. */
typedef enum { FS_RANGE_CLOSED, FS_RANGE_OPEN_LOWER, FS_RANGE_OPEN_UPPER, FS_RANGE_OPEN } FSRange;
PETSC_EXTERN PetscErrorCode FSOptionsReal(PetscOptionItems *, const char[], const char[], const char[], PetscReal *,
                                          PetscBool *, PetscReal, PetscReal, FSRange);
PETSC_EXTERN PetscErrorCode FSOptionsInt(PetscOptionItems *, const char[], const char[], const char[], PetscInt *,
                                         PetscBool *, PetscInt, PetscInt);
PETSC_EXTERN PetscErrorCode FSOptionsRealArray(PetscOptionItems *, const char[], const char[], const char[],
                                               PetscReal[], PetscInt *, PetscBool *, PetscReal, PetscReal, FSRange);

/* ---------- text inputs (src/sys/text.c): the byte-order mark a text file starts with, in words that show its bytes
   ("the bytes EF BB BF, a UTF-8 byte-order mark"), or NULL; flexslosh's readers, options files included, refuse one */
PETSC_EXTERN const char *FSTextByteOrderMark(const char[], size_t);

/* ---------- solver ---------- */
PETSC_EXTERN PetscErrorCode FSSolverCreate(MPI_Comm, FSSolver *);
PETSC_EXTERN PetscErrorCode FSSolverSetFromOptions(FSSolver);
PETSC_EXTERN PetscErrorCode FSSolverSetUp(FSSolver);
PETSC_EXTERN PetscErrorCode FSSolverSetOptionsChecked(FSSolver, PetscInt, const char *const[]);
PETSC_EXTERN PetscErrorCode FSSolverStep(FSSolver);
PETSC_EXTERN PetscErrorCode FSSolverSolve(FSSolver);
PETSC_EXTERN PetscErrorCode FSSolverView(FSSolver, PetscViewer);
PETSC_EXTERN PetscErrorCode FSSolverGeometryView(FSSolver, const char[]);
PETSC_EXTERN PetscErrorCode FSSolverDestroy(FSSolver *);
PETSC_EXTERN PetscErrorCode FSSolverGetTS(FSSolver, TS *);
PETSC_EXTERN PetscErrorCode FSSolverGetSwarm(FSSolver, DM *);
/* the particles' fields in the swarm (FSSolverGetSwarm(); this rank's owned particles): position and
   velocity dim reals per particle, density and mass one real, id one PetscInt */
#define FS_FIELD_POSITION "position"
#define FS_FIELD_VELOCITY "velocity"
#define FS_FIELD_DENSITY  "density"
#define FS_FIELD_MASS     "mass"
#define FS_FIELD_ID       "id"
PETSC_EXTERN PetscErrorCode FSSolverGetTime(FSSolver, PetscReal *, PetscInt *);
PETSC_EXTERN PetscErrorCode FSSolverGetDimension(FSSolver, PetscInt *);
PETSC_EXTERN PetscErrorCode FSSolverGetLocalSize(FSSolver, PetscInt *);

/* ---------- the state, for drivers (the Python package) ---------- */
#define FS_ENERGY_MAX_COLUMNS 32
PETSC_EXTERN PetscErrorCode FSSolverGetField(FSSolver, const char[], PetscInt *, PetscInt *, const PetscReal *[]);
PETSC_EXTERN PetscErrorCode FSSolverRestoreField(FSSolver, const char[], PetscInt *, PetscInt *, const PetscReal *[]);
PETSC_EXTERN PetscErrorCode FSSolverGetWallLoads(FSSolver, PetscInt *, const char *[], const PetscReal *[]);
PETSC_EXTERN PetscErrorCode FSSolverGetEnergy(FSSolver, PetscInt *, const char *[], PetscReal[]);
PETSC_EXTERN PetscErrorCode FSSolverGetLiquidMass(FSSolver, PetscReal *);
#define FS_PROBE_MAX_VALUES 5 /* values of one probe (pressure, velocity, filtered pressure) or gauge (elevation) */
PETSC_EXTERN PetscErrorCode FSSolverGetProbes(FSSolver, PetscInt *, const char *[], PetscInt[], PetscReal[]);
PETSC_EXTERN PetscErrorCode FSSolverWriteCheckpoint(FSSolver);

/* ---------- monitors (src/monitor/): what a run reports, each an object attached to the solver ---------- */
/* the built-in monitors (FSMonitorSetType()) */
#define FSMONITORTIMESERIES  "timeseries"  /* timeseries.csv */
#define FSMONITORENERGY      "energy"      /* energy.csv, the energy budget */
#define FSMONITORPROBES      "probes"      /* probes.csv, -fs_probes */
#define FSMONITORSNAPSHOTS   "snapshots"   /* snapshot_*.h5 and particles.xdmf, -fs_output_interval */
#define FSMONITORCHECKPOINTS "checkpoints" /* checkpoint_*.h5, -fs_checkpoint_interval */
#define FSMONITORRESTCHECK   "restcheck"   /* the at-rest check's warnings, -fs_rest_check_* */
#define FSMONITORPROGRESS    "progress"    /* the progress line on the terminal, -fs_progress */
#define FSMONITORSUMMARY     "summary"     /* summary.json */
typedef PetscErrorCode (*FSMonitorCreateFn)(FSMonitor);
/* a plain monitor (FSSolverMonitorSet()): called after each step with the step number and the time, and once before
   the first step */
typedef PetscErrorCode (*FSSolverMonitorFn)(FSSolver, PetscInt, PetscReal, void *);
/* What a monitor type does, the ops its create routine (FSMonitorCreateFn) fills with FSMonitorSetOps() (any may be
   NULL; docs/architecture.md, "The monitor object"):
   begin     - at the start of the run's output: open its files (collective)
   rowsize   - a monitor with a row whose sums are reduced with the other monitors' in one reduction (FSMonitorRows()):
               whether a row is due at this step and how many sums and maxima it takes;
   rowlocal  - this rank's sums and maxima;  rowvalues - the row from them reduced over the ranks (a check here stops
               the run before any row of the step is written);  rowwrite - its write
   step      - after each step and once before the first (first true), at its own interval (collective)
   end       - at the end of the run (collective) */
typedef struct _FSMonitorOps {
  PetscErrorCode (*setfromoptions)(FSMonitor, PetscOptionItems *);
  PetscErrorCode (*setup)(FSMonitor, FSSolver);
  PetscErrorCode (*begin)(FSMonitor, FSSolver);
  PetscErrorCode (*rowsize)(FSMonitor, FSSolver, PetscBool *due, PetscInt *nsum, PetscInt *nmax);
  PetscErrorCode (*rowlocal)(FSMonitor, FSSolver, PetscReal sum[], PetscReal max[]);
  PetscErrorCode (*rowvalues)(FSMonitor, FSSolver, const PetscReal sum[], const PetscReal max[]);
  PetscErrorCode (*rowwrite)(FSMonitor, FSSolver);
  PetscErrorCode (*step)(FSMonitor, FSSolver, PetscInt step, PetscReal t, PetscBool first);
  PetscErrorCode (*end)(FSMonitor, FSSolver);
  PetscErrorCode (*view)(FSMonitor, PetscViewer);
  PetscErrorCode (*destroy)(FSMonitor);
} FSMonitorOps;
PETSC_EXTERN PetscErrorCode FSMonitorRegister(const char[], const char[], FSMonitorCreateFn);
PETSC_EXTERN PetscErrorCode FSMonitorSetOps(FSMonitor, const FSMonitorOps *);
PETSC_EXTERN PetscErrorCode FSMonitorSetContext(FSMonitor, void *);
PETSC_EXTERN PetscErrorCode FSMonitorGetContext(FSMonitor, void *);
PETSC_EXTERN PetscErrorCode FSMonitorRegisterAll(void);
PETSC_EXTERN PetscErrorCode FSMonitorListView(PetscViewer);
PETSC_EXTERN PetscErrorCode FSMonitorCreate(MPI_Comm, FSMonitor *);
PETSC_EXTERN PetscErrorCode FSMonitorSetType(FSMonitor, const char[]);
PETSC_EXTERN PetscErrorCode FSMonitorGetType(FSMonitor, const char *[]);
PETSC_EXTERN PetscErrorCode FSMonitorSetOptionsPrefix(FSMonitor, const char[]);
PETSC_EXTERN PetscErrorCode FSMonitorSetFromOptions(FSMonitor);
PETSC_EXTERN PetscErrorCode FSMonitorSetFromOptionItems(FSMonitor, PetscOptionItems *);
PETSC_EXTERN PetscErrorCode FSMonitorSetUp(FSMonitor, FSSolver);
PETSC_EXTERN PetscErrorCode FSMonitorBegin(FSMonitor, FSSolver);
PETSC_EXTERN PetscErrorCode FSMonitorRows(PetscInt, const FSMonitor[], FSSolver);
/* the rows due at a step between FSMonitorRowsBegin() and FSMonitorRowsEnd(): their sums and maxima, this rank's
   until the caller reduces them (sum[0..nsum) summed, max[0..nmax) the largest over the ranks). The batch keeps its
   arrays from step to step (nmon, nval: their room) until FSMonitorRowBatchDestroy() */
typedef struct {
  PetscInt   n, nsum, nmax;
  PetscReal *sum, *max;
  PetscInt  *off;
  PetscBool *due;
  PetscBool  active;
  PetscInt   nmon, nval;
} FSMonitorRowBatch;
PETSC_EXTERN PetscErrorCode FSMonitorRowsBegin(PetscInt, const FSMonitor[], FSSolver, FSMonitorRowBatch *);
PETSC_EXTERN PetscErrorCode FSMonitorRowsEnd(PetscInt, const FSMonitor[], FSSolver, FSMonitorRowBatch *);
PETSC_EXTERN PetscErrorCode FSMonitorRowBatchReset(FSMonitorRowBatch *);
PETSC_EXTERN PetscErrorCode FSMonitorRowBatchDestroy(FSMonitorRowBatch *);
PETSC_EXTERN PetscErrorCode FSMonitorStep(FSMonitor, FSSolver);
PETSC_EXTERN PetscErrorCode FSMonitorEnd(FSMonitor, FSSolver);
PETSC_EXTERN PetscErrorCode FSMonitorGetWriteStatus(FSMonitor, PetscInt *, PetscBool *);
PETSC_EXTERN PetscErrorCode FSMonitorRaiseWriteStatus(FSMonitor, PetscInt);
PETSC_EXTERN PetscErrorCode FSMonitorView(FSMonitor, PetscViewer);
PETSC_EXTERN PetscErrorCode FSMonitorDestroy(FSMonitor *);
/* the probes monitor's values (FSSolverGetProbes() for the solver's own), the checkpoints monitor's write (for
   FSSolverWriteCheckpoint()) and interval (whether the run attaches it) */
PETSC_EXTERN PetscErrorCode FSMonitorCheckpointsWrite(FSMonitor, FSSolver);
PETSC_EXTERN PetscErrorCode FSMonitorCheckpointsGetInterval(FSMonitor, PetscInt *);
PETSC_EXTERN PetscErrorCode FSMonitorProbesGetValues(FSMonitor, FSSolver, PetscInt *, const char *[], PetscInt[],
                                                     PetscReal[]);
PETSC_EXTERN PetscErrorCode FSSolverMonitorAdd(FSSolver, FSMonitor);
PETSC_EXTERN PetscErrorCode FSSolverMonitorSet(FSSolver, FSSolverMonitorFn, void *, PetscErrorCode (*)(void **));
PETSC_EXTERN PetscErrorCode FSSolverMonitorCancel(FSSolver);
PETSC_EXTERN PetscErrorCode FSSolverGetMonitors(FSSolver, PetscInt *, const FSMonitor *[]);

/* ---------- terms ---------- */
/* What a term needs the core to compute in the first pass over neighbour pairs. */
typedef enum {
  FS_NEED_NONE             = 0,
  FS_NEED_DENSITY_GRADIENT = 1, /* renormalized density gradient <grad rho>^L_i, also on ghosts */
  FS_NEED_STRAIN_RATE      = 2  /* ||D||_i = sqrt(2 D:D) with the corrected velocity gradient, also on ghosts */
} FSNeed;

/* Read-only view of the particles a term works on: owned particles 0..nowned-1, then ghost
   copies nowned..nowned+nghost-1 (neighbours on other ranks or periodic images).
   Per-particle record: rec[k*stride + ...] with position at 0, velocity at dim, density at
   2*dim, mass at 2*dim+1. aux[k*(dim+1)] holds the density gradient (dim) and ||D|| when requested. */
typedef struct {
  PetscInt         dim, nowned, nghost, stride;
  const PetscReal *rec;
  const PetscReal *aux;
  const PetscReal *vol;      /* V_k = m_k / rho_k, owned and ghosts */
  const PetscReal *pressure; /* p_k = c0^2 (rho_k - rho0) + background pressure, owned and ghosts */
  /* physical constants */
  PetscReal rho0, c0, h, dx, nu, gravity[3], background_pressure;
  PetscReal umax; /* largest particle speed at the start of the step */
  /* the Shepard factor of the walls (boundary integrals): NULL without walls, where gamma = 1 */
  const PetscReal *gamma;    /* gamma of the owned and ghost particles */
  const PetscReal *invgamma; /* 1/gamma, the same particles */
  /* 1/gamma of the laminar viscous terms: the share behind no-slip walls counts as liquid, since the
     no-slip wall term fills it (wall.c); the same array as invgamma without no-slip walls */
  const PetscReal *invgammav;
} FSParticles;

/* The neighbourhood of one owned particle i: n neighbours j[k] with x_j - x_i in dx[k*dim], the
   squared distance r2[k] and its inverse rinv2[k], the kernel gradient grad_i W(x_i - x_j) in
   gradW[k*dim], u_j - u_i in du[k*dim] and the neighbours' volumes V_j in Vj[k] (FSParticles' vol[j]),
   computed once per pair by the core and shared by all terms, in arrays a term's loop reads in order. */
typedef struct {
  PetscInt         i, n;
  const PetscInt  *j;
  const PetscReal *dx, *r2, *rinv2, *gradW;
  const PetscReal *du, *Vj;
} FSNeighbourhood;

/* The Wendland C2 kernel W(r) of the core (support 2h), for terms that need kernel values and not only the
   gradients of FSNeighbourhood. */
static inline PetscReal FSWendland(PetscInt dim, PetscReal h, PetscReal r)
{
  const PetscReal q = r / h, a = 1.0 - 0.5 * q,
                  norm = dim == 2 ? 7.0 / (4.0 * PETSC_PI * h * h) : 21.0 / (16.0 * PETSC_PI * h * h * h);
  return q >= 2 ? 0 : norm * a * a * a * a * (2 * q + 1);
}

/* ---------- walls, as the wall terms see them ---------- */
/*
   The boundary's wall elements (segments in 2-D, triangles in 3-D), each a row of `stride` reals in
   element[]: its dim vertices at `vertex` (dim reals each, one after the other: a segment's two ends,
   a triangle's three corners), its centroid at `centroid` (dim), its unit normal
   pointing out of the liquid at `normal` (dim) and its length or area at `measure`. The boundary
   (FSBoundary) hands this view to the wall terms with each particle's wall neighbourhood.
*/
typedef struct {
  PetscInt         dim, nwalls, nelements;
  PetscInt         stride, vertex, centroid, normal, measure; /* the element rows' layout */
  const PetscReal *element;
  const PetscInt  *elementwall; /* the wall each element belongs to */
  const PetscReal *pressure;    /* per element: the wall pressure interpolated from the liquid */
  const PetscBool *noslip;      /* per wall: no-slip (else free-slip) */
  PetscReal *load; /* per wall: force (3) and moment about loadpoint (3) of the liquid on the wall, this rank's share,
                      accumulated by the wall terms */
  PetscReal loadpoint[3];
} FSWallView;

/* The liquid's load on each wall (FSWallView.load, FSSolverGetWallLoads): a row of FS_WALL_LOAD_STRIDE
   reals per wall, the force (3) at FS_WALL_LOAD_FORCE and its moment about the load point (3) at
   FS_WALL_LOAD_MOMENT; in 2-D the moment about z is the row's last entry. */
#define FS_WALL_LOAD_STRIDE 6
#define FS_WALL_LOAD_FORCE  0
#define FS_WALL_LOAD_MOMENT 3

/* The wall elements k[q] (q < n) of particle i within its kernel support, with the mean kernel value
   W[q] over each (W[q] measure_k = int_k W(x - x_i) dS), as the boundary's lists give them. */
typedef struct {
  PetscInt         i, n;
  const PetscInt  *k;
  const PetscReal *W;
} FSWallNeighbourhood;

/* Rate of change of particle i accumulated by the terms: drho/dt, du/dt (dim), and a correction
   of the particle's transport velocity dx/dt = u + dx (particle shifting; zero for most terms). */
typedef struct {
  PetscReal drho, du[3], dx[3];
} FSRate;

/* For the terms' hot loops: a body written once for a compile-time dimension (called with the literal 2
   or 3) is inlined into each branch, so that its loops over d < dim unroll and the accumulators stay in
   registers instead of going through memory as they do with the run-time dimension. */
#if PetscHasAttribute(always_inline)
#  define FS_ALWAYS_INLINE static inline __attribute__((always_inline))
#else
#  define FS_ALWAYS_INLINE static inline
#endif

typedef struct {
  /* per owned particle, with its neighbours (hot: keep it free of PETSc calls) */
  void (*interact)(FSTerm, const FSParticles *, const FSNeighbourhood *, FSRate *);
  /* per owned particle, no neighbours (body forces) */
  void (*source)(FSTerm, const FSParticles *, PetscInt i, FSRate *);
  /* per owned particle near the walls, with its wall elements (a wall term: evaluated in the wall pass) */
  void (*wall)(FSTerm, const FSParticles *, const FSWallView *, const FSWallNeighbourhood *, FSRate *);
  /* once per right-hand side, after the first pass and its ghost refresh, before the pair pass */
  PetscErrorCode (*prepare)(FSTerm, const FSParticles *);
  /* a per-particle output field the term can provide for the owned particles (e.g. "turbulent_viscosity") */
  PetscErrorCode (*field)(FSTerm, const char[], const FSParticles *, PetscReal *, PetscBool *);
  PetscErrorCode (*setfromoptions)(FSTerm, PetscOptionItems *);
  /* once, before the first prepare of the run's first right-hand side, with the owned particles */
  PetscErrorCode (*setup)(FSTerm, const FSParticles *);
  PetscErrorCode (*view)(FSTerm, PetscViewer);
  PetscErrorCode (*destroy)(FSTerm);
} FSTermOps;

struct _p_FSTerm {
  char      name[64];
  char      description[256];
  FSSolver  solver;
  FSTermOps ops;
  PetscInt  needs;          /* FSNeed flags */
  PetscBool renormalized;   /* the core divides the term's rates by the Shepard factor gamma_i (boundary integrals) */
  PetscBool has_power;      /* the term dissipates: it accumulates power */
  PetscReal power;          /* dissipation power of the last right-hand side, this rank's share (seed Eq. 38) */
  PetscReal max_viscosity;  /* largest kinematic viscosity the term applies (time-step limit), set in prepare */
  PetscReal dt_coefficient; /* the term's own limit dt <= c h^2/max_viscosity (0: -fs_cfl_viscous's) */
  PetscReal dt_coefficient_rk4; /* dt_coefficient's default with RK4 (set up by FSSolverSetFromOptions; 0: none) */
  PetscBool split; /* advanced after each step by super-time-stepping (src/solver/split.c), not in the integrator's
                      stages: for a term whose only rate is drho, a diffusion in rho (term delta's -fs_delta_split) */
  void     *data;  /* implementation data */
  PetscBool setupcalled; /* ops.setup has run (src/solver/rhs.c) */
};

typedef PetscErrorCode (*FSTermCreateFn)(FSTerm);

PETSC_EXTERN PetscErrorCode FSTermRegister(const char[], const char[], FSTermCreateFn);
PETSC_EXTERN PetscErrorCode FSTermRegisterAll(void);
PETSC_EXTERN PetscErrorCode FSTermListView(PetscViewer);
PETSC_EXTERN PetscErrorCode FSTermGetSolver(FSTerm, FSSolver *);

/* ---------- cases ---------- */
#define FS_CASE_MAX_COLUMNS 4 /* a case's own columns in the time series */
/* A case sets up the run: called from FSSolverSetUp after options are read. It sets the domain
   box and periodicity (FSSolverSetDomain) and creates the particles (FSSolverAddParticles). */
typedef struct {
  PetscErrorCode (*setfromoptions)(FSSolver, PetscOptionItems *);
  PetscErrorCode (*setup)(FSSolver);
  /* optional columns of the case in the time series (a reference solution, a measured quantity):
     columns() fills values[0..ncolumns-1] (the same on every rank), named column_names[] */
  PetscErrorCode (*columns)(FSSolver, PetscReal t, PetscReal values[]);
  PetscInt    ncolumns;
  const char *column_names[FS_CASE_MAX_COLUMNS];
} FSCaseOps;

typedef PetscErrorCode (*FSCaseCreateFn)(FSSolver, FSCaseOps *);

PETSC_EXTERN PetscErrorCode FSCaseRegister(const char[], const char[], FSCaseCreateFn);
PETSC_EXTERN PetscErrorCode FSCaseRegisterAll(void);
PETSC_EXTERN PetscErrorCode FSCaseListView(PetscViewer);

PETSC_EXTERN PetscErrorCode FSSolverGetBoundary(FSSolver, FSBoundary *);
PETSC_EXTERN PetscErrorCode FSSolverSetDomain(FSSolver, const PetscReal lo[], const PetscReal hi[],
                                              const PetscBool periodic[]);
PETSC_EXTERN PetscErrorCode FSSolverAddParticles(FSSolver, PetscInt n, const PetscReal x[], const PetscReal u[],
                                                 const PetscReal rho[], const PetscReal m[]);
PETSC_EXTERN PetscErrorCode FSSolverAddLiquidVolume(FSSolver, PetscReal volume, PetscReal mass, PetscReal lattice_mass);
/* the case's liquid starts at rest, so deep: the at-rest check watches it (src/solver/restcheck.c) */
PETSC_EXTERN PetscErrorCode FSSolverSetLiquidAtRest(FSSolver, PetscBool, PetscReal depth);
PETSC_EXTERN PetscErrorCode FSSolverGetLiquidVolume(FSSolver, PetscReal *volume, PetscReal *mass,
                                                    PetscReal *lattice_mass);
/* How the cases place a body of liquid's particles (-fs_fill_packing, docs/walls.md): on a lattice cut by the walls, or
   relaxed against the walls and the fill level from that lattice; auto relaxes where the lattice does not fit the
   walls (its masses would need fitting to the exact volume) and keeps it where it does. */
typedef enum { FS_FILL_PACKING_AUTO, FS_FILL_PACKING_LATTICE, FS_FILL_PACKING_RELAXED } FSFillPackingType;
typedef struct {
  FSFillPackingType type;
  PetscInt          iterations; /* -fs_fill_packing_iterations */
  PetscReal         step;       /* -fs_fill_packing_step: each move, -step h^2 e_i */
  PetscReal         thin;       /* -fs_fill_packing_thin: the fullness above which the lattice is thinned (0: never) */
  char              cache[PETSC_MAX_PATH_LEN];     /* -fs_fill_packing_cache: a folder of packings, "" none */
  PetscReal         repulsion, repulsion_distance; /* the wall_pressure term's push near contact (-fs_walls_repulsion;
                                                      its distance in dx), which the relaxation balances */
  PetscBool visall; /* -fs_walls_visibility all: every wall element within the support counts, those that
                       face away included (the run's wall terms count them), else the facing ones */
} FSFillPacking;
PETSC_EXTERN PetscErrorCode FSSolverGetFillPacking(FSSolver, FSFillPacking *);
PETSC_EXTERN PetscErrorCode FSSolverGetParameters(FSSolver, PetscReal *dx, PetscReal *h, PetscReal *rho0, PetscReal *c0,
                                                  PetscReal *nu);
PETSC_EXTERN PetscErrorCode FSSolverSetDefaultPhysics(FSSolver, PetscReal rho0, PetscReal c0, PetscReal nu,
                                                      const PetscReal g[]);
PETSC_EXTERN PetscErrorCode FSSolverSetDefaultSpacing(FSSolver, PetscReal dx);
PETSC_EXTERN PetscErrorCode FSSolverSetDefaultFinalTime(FSSolver, PetscReal t);
PETSC_EXTERN PetscErrorCode FSSolverSetDefaultCFL(FSSolver, PetscReal cfl);
PETSC_EXTERN PetscErrorCode FSSolverSetDefaultTerms(FSSolver, const char terms[]);
PETSC_EXTERN PetscErrorCode FSSolverSetCaseData(FSSolver, void *data);
PETSC_EXTERN PetscErrorCode FSSolverGetCaseData(FSSolver, void *dataptr);
PETSC_EXTERN PetscErrorCode FSSolverGetGravity(FSSolver, PetscReal g[3]);

/* ---------- structures ---------- */
/*
   The structure that carries the tank. Its DOFs y (ndof values) are part of the TS state, owned by
   rank 0 and advanced by the same integrator as the particles: dy/dt = rhs(t, y, loads).
   Geometry: the beam lies along x from its clamp at x = 0; it deflects along y (vertical) and the
   tank turns about z. The tank reference point sits on the beam at x = a (-fs_beam_tank_position).
   Deflections are measured from the static equilibrium under gravity (the structure's weight is
   not a load).
*/

/* Loads on the tank reference point from the liquid (filled by the coupling; zero without it):
   force[3] in the global axes, moment[3] about the reference point. */
typedef struct {
  PetscReal force[3], moment[3];
} FSLoads;

/* The body acceleration a particle at x feels in the tank's frame without the Coriolis part:
   a(x) = b + alpha (r_y, -r_x) + omega^2 (r_x, r_y), r = x - ref, b = R(-theta) (g - A) (the coupling's
   tank frame; b = g without a coupling). The frame turns about z: in 3-D a_z = b_z (FSFrameFieldEval3).
   A 3-D frame turning about any axis (rotated, a prescribed pitch, yaw or rotation about an axis) has
   a(x) = b - dw x r - w x (w x r), r = x - (ref, ref_z), b = Q^T (g - A), w and dw the angular velocity and
   acceleration in the tank's axes (omega and alpha unused). */
typedef struct {
  PetscReal b[3], omega, alpha, ref[2];
  PetscReal ref_z;       /* the reference point's z (rotated frames) */
  PetscBool rotated;     /* the frame turns about any axis: w, dw below */
  PetscReal w[3], dw[3]; /* its angular velocity and acceleration, tank axes */
} FSFrameField;

static inline void FSFrameFieldEval(const FSFrameField *ff, const PetscReal x[], PetscReal a[])
{
  const PetscReal rx = x[0] - ff->ref[0], ry = x[1] - ff->ref[1], w2 = ff->omega * ff->omega;
  a[0] = ff->b[0] + ff->alpha * ry + w2 * rx;
  a[1] = ff->b[1] - ff->alpha * rx + w2 * ry;
}

static inline void FSFrameFieldEval3(const FSFrameField *ff, const PetscReal x[], PetscReal a[])
{
  if (ff->rotated) { /* b - dw x r - w x (w x r) */
    const PetscReal *w = ff->w, *dw = ff->dw;
    const PetscReal  r[3] = {x[0] - ff->ref[0], x[1] - ff->ref[1], x[2] - ff->ref_z};
    const PetscReal  c[3] = {w[1] * r[2] - w[2] * r[1], w[2] * r[0] - w[0] * r[2], w[0] * r[1] - w[1] * r[0]};
    a[0]                  = ff->b[0] - (dw[1] * r[2] - dw[2] * r[1]) - (w[1] * c[2] - w[2] * c[1]);
    a[1]                  = ff->b[1] - (dw[2] * r[0] - dw[0] * r[2]) - (w[2] * c[0] - w[0] * c[2]);
    a[2]                  = ff->b[2] - (dw[0] * r[1] - dw[1] * r[0]) - (w[0] * c[1] - w[1] * c[0]);
    return;
  }
  FSFrameFieldEval(ff, x, a);
  a[2] = ff->b[2];
}

/* Rigid motion of the tank reference point: displacement, velocity and acceleration, and the
   rotation (about z) angle, rate and angular acceleration. A 3-D motion that turns the tank about any
   axis (a prescribed pitch, yaw or rotation about an axis; FSTankMotionRotate) sets rotated to 1 and
   gives the rotation by Q, w and dw; angle, rate and angacc then hold the roll's share for the output
   only. All members are reals (the motion is broadcast as an array of them). */
typedef struct {
  PetscReal disp[3], vel[3], acc[3];
  PetscReal angle, rate, angacc;
  PetscReal rotated; /* 1: Q, w, dw give the rotation; 0: the angle about z alone */
  PetscReal Q[9];    /* the tank's axes in the global ones, row by row: X - X_ref = Q (x - x_ref) */
  PetscReal w[3];    /* the angular velocity, in the tank's axes */
  PetscReal dw[3];   /* the angular acceleration (the rate of w), in the tank's axes */
} FSTankMotion;

PETSC_EXTERN PetscErrorCode FSTankMotionRotate(FSTankMotion *, const PetscReal axis[3], const PetscReal angle[3]);

struct _n_FSJSON; /* the JSON summary writer of src/output (fsoutput.h) */

typedef struct {
  PetscErrorCode (*setfromoptions)(FSStructure, PetscOptionItems *);
  /* builds the model; sets ndof, min_period, the extra time-series columns (FSStructureAddColumn) */
  PetscErrorCode (*setup)(FSStructure);
  /* the initial state y0 (ndof values) */
  PetscErrorCode (*initial)(FSStructure, PetscReal y[]);
  /* dy/dt at time t for state y under the liquid loads (required) */
  PetscErrorCode (*rhs)(FSStructure, PetscReal t, const PetscReal y[], const FSLoads *, PetscReal ydot[]);
  /* the tank's motion at time t from the state and its rate (required; t for prescribed motions) */
  PetscErrorCode (*motion)(FSStructure, PetscReal t, const PetscReal y[], const PetscReal ydot[], FSTankMotion *);
  /* values of the model's own time-series columns (ncolumns of them) */
  PetscErrorCode (*columns)(FSStructure, PetscReal t, const PetscReal y[], const PetscReal ydot[], PetscReal vals[]);
  /* output at a snapshot time (rank 0; e.g. the deflected shape), into the directory given */
  PetscErrorCode (*snapshot)(FSStructure, const char dir[], PetscReal t, PetscInt step, const PetscReal y[]);
  /* optional: the energies at state y (rank 0): E[0] kinetic, E[1] potential (elastic, with the potential
     of constant applied forces such as -fs_beam_force), E[2] the damping power (dissipated, >= 0) */
  PetscErrorCode (*energy)(FSStructure, const PetscReal y[], PetscReal E[3]);
  /* the model's members of summary.json (rank 0 writes; called on every rank) */
  PetscErrorCode (*summary)(FSStructure, struct _n_FSJSON *);
  PetscErrorCode (*view)(FSStructure, PetscViewer);
  PetscErrorCode (*destroy)(FSStructure);
} FSStructureOps;

#define FS_STRUCTURE_MAX_COLUMNS 64
#define FS_STRUCTURE_MAX_MODES   32

struct _p_FSStructure {
  char           name[64];
  FSSolver       solver;
  MPI_Comm       comm;
  FSStructureOps ops;
  PetscInt       ndof;       /* state size, set by setup */
  PetscReal      min_period; /* shortest period the model resolves (time step without particles), set by setup */
  PetscInt       nmodes;     /* optional, set by setup: the model's modes, their periods longest first (the last is */
  PetscReal      period[FS_STRUCTURE_MAX_MODES]; /* min_period), for the time-step advice at set-up */
  PetscInt       ncolumns;                       /* the model's own time-series columns */
  PetscBool      prescribed; /* the motion is given, the loads do not move it: the energy budget books the work it
                                does on the liquid (work_motion) instead of the structure's energies */
  PetscBool rank0; /* its routines run on rank 0 alone, which broadcasts their results (the callbacks' models: a
                      Python structure); else (the default) every rank runs them on the same values, from the loads
                      reduced over the ranks, and holds the same state (docs/structures.md, "What runs where") */
  char  column[FS_STRUCTURE_MAX_COLUMNS][32];
  void *data; /* implementation data */
};

typedef PetscErrorCode (*FSStructureCreateFn)(FSStructure);

PETSC_EXTERN PetscErrorCode FSStructureRegister(const char[], const char[], FSStructureCreateFn);
PETSC_EXTERN PetscErrorCode FSStructureRegisterAll(void);
PETSC_EXTERN PetscErrorCode FSStructureListView(PetscViewer);
PETSC_EXTERN PetscErrorCode FSStructureAddColumn(FSStructure, const char[]);
PETSC_EXTERN PetscErrorCode FSStructureGetSolver(FSStructure, FSSolver *);
PETSC_EXTERN PetscErrorCode FSSolverGetStructure(FSSolver, FSStructure *);
PETSC_EXTERN PetscErrorCode FSSolverSetLoads(FSSolver, const FSLoads *);
PETSC_EXTERN PetscErrorCode FSSolverGetTankMotion(FSSolver, FSTankMotion *);
PETSC_EXTERN PetscErrorCode FSSolverGetStructureState(FSSolver, PetscInt *, PetscReal[]);
PETSC_EXTERN PetscErrorCode FSSolverSetDefaultStructure(FSSolver, const char[]);

/*
   A structure model whose operations are function pointers given at registration, for models written
   outside C (the Python package registers its classes so) or built at run time. impl is the model
   instance create returns for each FSStructure (ctx itself without create). A callback returns 0, or
   non-zero after FSStructureCallbacksSetError() with its message (or after a PETSc error of its own).
   ndof and min_period (the shortest period the model resolves, 0 if none) come from setup, which may
   also add time-series columns with FSStructureAddColumn(). Which rank calls which: create, setup,
   initial and destroy on every rank; rhs, motion, columns and energy on rank 0 only.
*/
typedef struct {
  PetscErrorCode (*create)(void *ctx, FSStructure, void **impl);                           /* optional */
  PetscErrorCode (*setup)(void *impl, FSStructure, PetscInt *ndof, PetscReal *min_period); /* required */
  PetscErrorCode (*initial)(void *impl, PetscInt ndof, PetscReal y[]);                     /* optional (else y = 0) */
  PetscErrorCode (*rhs)(void *impl, PetscReal t, PetscInt ndof, const PetscReal y[], const FSLoads *,
                        PetscReal ydot[]); /* required */
  PetscErrorCode (*motion)(void *impl, PetscInt ndof, const PetscReal y[], const PetscReal ydot[],
                           FSTankMotion *); /* required */
  PetscErrorCode (*columns)(void *impl, PetscReal t, PetscInt ndof, const PetscReal y[], const PetscReal ydot[],
                            PetscInt ncolumns, PetscReal vals[]); /* with columns */
  PetscErrorCode (*energy)(void *impl, PetscInt ndof, const PetscReal y[],
                           PetscReal E[3]); /* optional, as FSStructureOps.energy */
  PetscErrorCode (*destroy)(void *impl);    /* optional */
} FSStructureCallbacks;

PETSC_EXTERN PetscErrorCode FSStructureRegisterCallbacks(const char[], const char[], const FSStructureCallbacks *,
                                                         void *);
PETSC_EXTERN PetscErrorCode FSStructureCallbacksSetError(const char[]);
