/*
   Output writers of flexslosh: particle snapshots (HDF5 + XDMF index), checkpoints (HDF5),
   the time-series CSV and the JSON summary.

   These writers know nothing about the solver: they take plain arrays, so the solver, the
   tests and future front ends use them alike. Every file is written to "<name>.tmp" and
   renamed into place when complete, so a crash never corrupts a file already written.
*/
#pragma once
#include <petscsys.h>

/* A field's values written on demand: the nlocal*bs values of field f of the list into values */
typedef PetscErrorCode (*FSOutputFill)(void *ctx, PetscInt f, PetscReal values[]);

/* One per-particle real field: data holds nlocal*bs values (particle-major, bs per particle), or data is NULL
   and fill writes them when the field is written, into a buffer that the fields written so share (so that a
   writer holds one field's values at a time, not all of them). */
typedef struct {
  const char      *name; /* dataset name, e.g. "velocity" */
  PetscInt         bs;   /* components per particle: 1 (scalar) or dim (vector) */
  const PetscReal *data; /* local values, nlocal*bs; or NULL and fill */
  FSOutputFill     fill;
  void            *ctx;
} FSOutputField;

/* ---------------- particle snapshots ---------------- */
typedef struct _n_FSSnapshotWriter *FSSnapshotWriter;

PETSC_EXTERN PetscErrorCode FSSnapshotWriterCreate(MPI_Comm, const char dir[], PetscReal restart_time,
                                                   FSSnapshotWriter *);
PETSC_EXTERN PetscErrorCode FSSnapshotWriterWrite(FSSnapshotWriter, PetscReal time, PetscInt step, PetscInt dim,
                                                  PetscInt nlocal, PetscInt nfields, const FSOutputField fields[]);
PETSC_EXTERN PetscErrorCode FSSnapshotWriterGetCount(FSSnapshotWriter, PetscInt *);
PETSC_EXTERN PetscErrorCode FSSnapshotWriterDestroy(FSSnapshotWriter *);

/* ---------------- checkpoints ---------------- */
/* Global (replicated) data of a checkpoint: time, step, dt, and nglobal extra doubles
   (the state's global DOFs, e.g. structure DOFs and energy integrals), and the text that records the
   run's set-up (written when not NULL; read back with FSCheckpointReadSetUp()), and nlayout values that
   describe how the writing ranks split the domain (written when nlayout > 0; read back with
   FSCheckpointReadLayout()). All of it the same on every rank but global, which is rank 0's. version is the
   format version of a checkpoint read (FSCheckpointReadHeader(); a writer writes the current one). */
typedef struct {
  PetscReal        time, dt;
  PetscInt         step;
  PetscInt         version;
  PetscInt         nglobal;
  PetscReal        global[64];
  const char      *setup;
  PetscInt         nlayout;
  const PetscReal *layout;
} FSCheckpointHeader;

/* What the values of a checkpoint's field may be (FSCheckpointReadField()), besides finite: within lo and hi (bs
   bounds each, NULL: none; the bounds themselves excluded when open), integers when integer; expect says it in words
   for the error message, e.g. "a positive number". */
typedef struct {
  const PetscReal *lo, *hi;
  PetscBool        open, integer;
  const char      *expect;
} FSCheckpointRange;

PETSC_EXTERN PetscErrorCode FSCheckpointWrite(MPI_Comm, const char path[], const FSCheckpointHeader *, PetscInt nlocal,
                                              PetscInt nfields, const FSOutputField fields[]);
PETSC_EXTERN PetscErrorCode FSCheckpointReadHeader(MPI_Comm, const char path[], FSCheckpointHeader *,
                                                   PetscInt *nglobal_particles, PetscMPIInt *nranks_written);
PETSC_EXTERN PetscErrorCode FSCheckpointReadField(MPI_Comm, const char path[], const char name[], PetscInt bs,
                                                  PetscInt nlocal, const FSCheckpointRange *, PetscReal data[]);
PETSC_EXTERN PetscErrorCode FSCheckpointGetLocalSize(MPI_Comm, const char path[], PetscInt *nlocal);
PETSC_EXTERN PetscErrorCode FSCheckpointHasField(MPI_Comm, const char path[], const char name[], PetscBool *has);
PETSC_EXTERN PetscErrorCode FSCheckpointReadSetUp(MPI_Comm, const char path[], char **setup);
PETSC_EXTERN PetscErrorCode FSCheckpointReadLayout(MPI_Comm, const char path[], PetscInt cap, PetscReal layout[],
                                                   PetscInt *n);

/* ---------------- time series (CSV) ---------------- */
typedef struct _n_FSTimeSeries *FSTimeSeries;

PETSC_EXTERN PetscErrorCode FSTimeSeriesCreate(MPI_Comm, const char path[], PetscInt ncols, const char *const names[],
                                               PetscInt restart_step, FSTimeSeries *);
PETSC_EXTERN PetscErrorCode FSTimeSeriesAppend(FSTimeSeries, PetscInt step, const PetscReal values[]);
PETSC_EXTERN PetscErrorCode FSTimeSeriesSetDeferred(FSTimeSeries, PetscBool);
PETSC_EXTERN PetscErrorCode FSTimeSeriesGetFailure(FSTimeSeries, int *err, PetscBool *torn);
PETSC_EXTERN PetscErrorCode FSTimeSeriesRaiseFailure(FSTimeSeries, int err, PetscBool torn);
PETSC_EXTERN PetscErrorCode FSTimeSeriesDestroy(FSTimeSeries *);

/* ---------------- JSON ---------------- */
typedef struct _n_FSJSON *FSJSON;

PETSC_EXTERN PetscErrorCode FSJSONCreate(MPI_Comm, const char path[], FSJSON *);
PETSC_EXTERN PetscErrorCode FSJSONBeginObject(FSJSON, const char key[]);
PETSC_EXTERN PetscErrorCode FSJSONEndObject(FSJSON);
PETSC_EXTERN PetscErrorCode FSJSONWriteString(FSJSON, const char key[], const char value[]);
PETSC_EXTERN PetscErrorCode FSJSONWriteInt(FSJSON, const char key[], PetscInt64 value);
PETSC_EXTERN PetscErrorCode FSJSONWriteReal(FSJSON, const char key[], PetscReal value);
PETSC_EXTERN PetscErrorCode FSJSONWriteRealArray(FSJSON, const char key[], PetscInt n, const PetscReal values[]);
PETSC_EXTERN PetscErrorCode FSJSONWriteBool(FSJSON, const char key[], PetscBool value);
PETSC_EXTERN PetscErrorCode FSJSONDestroy(FSJSON *);

/* ---------------- helpers ---------------- */
PETSC_EXTERN PetscErrorCode FSMakeDirectory(MPI_Comm, const char path[], const char option[]);

/* one run per output directory (src/io/fsutil.c): a lock, and a new run's removal of an earlier run's results */
typedef struct _n_FSOutputLock *FSOutputLock;
PETSC_EXTERN PetscErrorCode     FSOutputDirLock(MPI_Comm, const char dir[], const char option[], FSOutputLock *);
PETSC_EXTERN PetscErrorCode     FSOutputDirUnlock(FSOutputLock *);
PETSC_EXTERN PetscErrorCode     FSOutputDirClear(MPI_Comm, const char dir[]);

/* Creating output files (src/io/fsutil.c): never through a link, never into a file already there; each returns 0 or
   an errno value and acts on the calling rank only. */
typedef struct {
  unsigned long long dev, ino;
} FSFileId; /* the file a writer created, checked before it is renamed into place */
PETSC_INTERN int FSFileCreate_Private(const char path[], FILE **fp, FSFileId *id);
PETSC_INTERN int FSFileReplace_Private(const char from[], const char to[], const FSFileId *id);
PETSC_INTERN int FSFileOpenAppend_Private(const char path[], FILE **fp);

/* Internal to the output writers (rank 0 acts, the outcome is broadcast over the communicator). */
PETSC_INTERN PetscErrorCode FSFileCreateShared_Private(MPI_Comm, const char path[], FSFileId *id);
PETSC_INTERN PetscErrorCode FSRenameFile_Private(MPI_Comm, const char from[], const char to[], const FSFileId *id);
PETSC_INTERN PetscErrorCode FSTestFile_Private(MPI_Comm, const char path[], PetscBool *exists);
PETSC_INTERN PetscErrorCode FSWriteCheck_Private(PetscErrorCode, int syserr, const char file[]);
PETSC_INTERN PetscErrorCode FSCheckFields_Private(MPI_Comm, const char file[], PetscInt dim, PetscInt nlocal,
                                                  PetscInt nfields, const FSOutputField fields[]);
PETSC_INTERN PetscErrorCode FSViewFields_Private(PetscViewer, MPI_Comm, PetscInt nlocal, PetscInt nfields,
                                                 const FSOutputField fields[]);
