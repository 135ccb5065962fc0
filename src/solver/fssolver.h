/*
   The solver's interface to the monitors (src/monitor/): what a monitor reads of a run besides the public API. The
   quantities of an output row (the diagnostics, the walls' loads, the energy budget, the probes' samples, the
   snapshots' fields) are computed here, in the solver's folder; the monitors own the files, when they are written
   and the reductions that batch a row's sums (FSSolverReduceSumMax()).
*/
#pragma once
#include <flexslosh.h>
#include "particles/fsparticles.h"
#include "coupling/fscoupling.h"
#include "io/fsoutput.h"

/* the settings of the run's output that the built-in monitors follow (options of the solver: -fs_output_dir, ...;
   each monitor reads its own, -fs_output_interval, ...) */
typedef struct {
  const char    *outdir;     /* -fs_output_dir, or the run's own directory */
  PetscBool      restart;    /* the run continues from a checkpoint (-fs_restart): the files are cut, not new */
  PetscInt       step0;      /* the step the run's monitors began at */
  PetscReal      t0;         /* the time they began at */
  PetscLogDouble wall_start; /* the wall time they began at (PetscTime()) */
} FSSolverOutputSettings;
PETSC_INTERN PetscErrorCode FSSolverGetOutputSettings(FSSolver, FSSolverOutputSettings *);
PETSC_INTERN PetscErrorCode FSSolverAtEnd(FSSolver, PetscBool *);
PETSC_INTERN PetscErrorCode FSSolverReduceSumMax(FSSolver, PetscInt, PetscReal[], PetscInt, PetscReal[]);

/* timeseries.csv's row (src/solver/series.c) */
#define FS_SERIES_MAX_COLUMNS 256
#define FS_SERIES_NAME_LEN    80
PETSC_INTERN PetscErrorCode FSSolverSeriesColumns(FSSolver, PetscInt *, const char *[], char[][FS_SERIES_NAME_LEN]);
PETSC_INTERN PetscErrorCode FSSolverSeriesSize(FSSolver, PetscInt *nsum);
PETSC_INTERN PetscErrorCode FSSolverSeriesLocal(FSSolver, PetscReal sum[], PetscReal *v2max);
PETSC_INTERN PetscErrorCode FSSolverSeriesValues(FSSolver, const PetscReal sum[], PetscReal v2max, PetscReal vals[]);

/* energy.csv's row, the energy budget (src/solver/energy.c) */
#define FS_ENERGY_NSUMS 5 /* the liquid's energies a rank sums (FSSolverEnergyLocal()) */
PETSC_INTERN PetscErrorCode FSSolverEnergyColumns(FSSolver, PetscInt *, const char *[]);
PETSC_INTERN PetscErrorCode FSSolverEnergyLocal(FSSolver, PetscReal loc[], FSTankMotion *);
PETSC_INTERN PetscErrorCode FSSolverEnergySummed(FSSolver, const PetscReal liq[], const FSTankMotion *, PetscReal[]);

/* what the probes (src/monitor/impls/probes/) sample: this rank's owned particles' records, volumes and pressures as
   the last evaluation left them (FSSolverEvaluateAtState()), the kernel, the walls and the coupling's body field, the
   domain (src/solver/output.c) */
typedef struct {
  PetscInt         dim, stride, nowned;  /* a record is stride reals: position, velocity, density, ... */
  PetscInt64       nglobal;              /* the particles over the ranks */
  const PetscReal *rec, *vol, *pressure; /* nowned records, volumes, pressures */
  const FSKernel  *kernel;
  FSBoundary       boundary; /* NULL without walls */
  FSCoupling       coupling;
  PetscReal        lo[3], hi[3]; /* the domain */
  PetscReal        dx, background_pressure;
} FSSolverParticleView;
PETSC_INTERN PetscErrorCode FSSolverGetParticleView(FSSolver, FSSolverParticleView *);

/* a snapshot's fields (src/solver/output.c): a particle field into the writer's buffer (FSSolverGetField() without
   the copy), the evaluation at the state the derived fields come from (collective: made before the writer fills
   the fields rank by rank), the particles over the ranks, the structure's own output at a snapshot time */
PETSC_INTERN PetscErrorCode FSSolverFillField(FSSolver, const char[], PetscInt *bs, PetscReal values[]);
PETSC_INTERN PetscErrorCode FSSolverEvaluateAtState(FSSolver, PetscReal t);
PETSC_INTERN PetscErrorCode FSSolverGetGlobalSize(FSSolver, PetscInt64 *);
PETSC_INTERN PetscErrorCode FSSolverStructureSnapshot(FSSolver);

/* what the at-rest check (src/monitor/impls/restcheck.c) watches (src/solver/output.c): the liquid the case started
   at rest (FSSolverSetLiquidAtRest()), the particles' step limit and what set it, and the largest speed over the
   ranks (collective) */
typedef struct {
  PetscInt    dim;
  PetscReal   dx, c0, g;     /* spacing, speed of sound, |gravity| */
  PetscBool   at_rest;       /* the case starts its liquid at rest */
  PetscReal   depth;         /* its depth, as the case gave it */
  PetscBool   structure;     /* a structure carries the tank */
  PetscInt64  nglobal;       /* the particles over the ranks */
  PetscReal   dt_stable;     /* the particles' step limit from the state at the start of the last step */
  const char *dt_limit;      /* the limit that set it */
  PetscBool   dt_limit_term; /* a term's (its diffusivity) */
} FSSolverRestView;
PETSC_INTERN PetscErrorCode FSSolverGetRestView(FSSolver, FSSolverRestView *);
PETSC_INTERN PetscErrorCode FSSolverMaxSpeed2(FSSolver, PetscReal *);

/* summary.json's content (src/solver/output.c), which the summary monitor writes at the end of the run: what ran, how
   long, how fast, with which options (collective: the ranks' sums) */
PETSC_INTERN PetscErrorCode FSSolverSummaryWrite(FSSolver, FSJSON);

/* a checkpoint's content (src/solver/output.c), which the checkpoints monitor writes (FSMonitorCheckpointsWrite()):
   the header (time, step, dt, the global DOFs, the viscosity bound and the step's limit, the set-up record, the
   domain's split) and this rank's particle fields, the solver's arrays lent from FSSolverGetCheckpoint() to
   FSSolverRestoreCheckpoint() */
/* The most values a checkpoint's layout holds: the step of the last balance and the process grid's cuts
   (FSDecompLayoutSize: 6 + the ranks per direction, summed) */
#define FS_LAYOUT_MAX         4096
#define FS_CHECKPOINT_NFIELDS 6
typedef struct {
  const PetscInt *pid; /* the ids, written as reals (FSOutputField.fill) */
  PetscInt        n;
} FSSolverIds;
typedef struct {
  FSCheckpointHeader hdr;
  PetscInt           n; /* this rank's particles */
  FSOutputField      fields[FS_CHECKPOINT_NFIELDS];
  PetscReal          layout[FS_LAYOUT_MAX];
  FSSolverIds        ids;
} FSSolverCheckpoint;
PETSC_INTERN PetscErrorCode FSSolverGetCheckpoint(FSSolver, FSSolverCheckpoint *);
PETSC_INTERN PetscErrorCode FSSolverRestoreCheckpoint(FSSolver, FSSolverCheckpoint *);

/* the write status of the monitors' csv rows, carried to every rank and raised before another file is written
   (src/solver/monitor.c) */
PETSC_INTERN PetscErrorCode FSSolverWriteStatusCheck(FSSolver);
