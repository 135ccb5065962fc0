/*
   Unit test of src/io: snapshots (2-D and 3-D) with their XDMF and CSV index, the snapshot
   index on restart, checkpoints (write, read back exactly, even split on another communicator
   size, error cases), the time-series CSV with restart, and the JSON writer. Every error case checks
   the code and, on every rank, the message (the file, field or option it must name).

   Usage: mpirun -n <1..3> test_output [output_dir]   (default: a fresh directory under /tmp)
   Prints "test_output: OK" and returns 0 on success.
*/
#define _POSIX_C_SOURCE 200809L
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <math.h>
#include <errno.h>
#include <signal.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <petscvec.h>
#include <petscviewerhdf5.h>
#include "io/fsoutput.h"
#include "../errorcapture.h"
#include "../tempdir.h"

/* Fails the test (on every rank of comm) when cond is false */
#define TCHECK(comm, cond, ...) PetscCheck(cond, comm, PETSC_ERR_PLIB, "test_output: " __VA_ARGS__)

typedef struct {
  MPI_Comm    comm;
  PetscMPIInt rank, size;
  char        dir[PETSC_MAX_PATH_LEN];
} TestCtx;

/* deterministic value of component c of field f for global particle g */
static PetscReal Value(PetscInt f, PetscInt g, PetscInt c)
{
  return (PetscReal)(1000 * f + g) + 0.125 * (PetscReal)c + 1.0 / 3.0;
}

static PetscErrorCode FillField(PetscInt f, PetscInt start, PetscInt nlocal, PetscInt bs, PetscReal *a)
{
  PetscFunctionBegin;
  for (PetscInt i = 0; i < nlocal; i++)
    for (PetscInt c = 0; c < bs; c++) a[i * bs + c] = Value(f, start + i, c);
  PetscFunctionReturn(0);
}

/* a field written on demand (FSOutputField.fill): the velocity of FillField, the particles start.. */
typedef struct {
  PetscInt start, nlocal, calls;
} VelocityFill;

static PetscErrorCode FillVelocity(void *ctx, PetscInt f, PetscReal values[])
{
  VelocityFill *c = (VelocityFill *)ctx;

  PetscFunctionBegin;
  (void)f;
  c->calls++;
  PetscCall(FillField(1, c->start, c->nlocal, 2, values));
  PetscFunctionReturn(0);
}

/* Reads a whole text file on rank 0 into a PetscMalloc'ed string */
static PetscErrorCode ReadText(const char path[], char **text)
{
  FILE *fp;
  long  n;

  PetscFunctionBegin;
  fp = fopen(path, "rb");
  PetscCheck(fp, PETSC_COMM_SELF, PETSC_ERR_FILE_OPEN, "test_output: cannot open %s", path);
  PetscCheck(fseek(fp, 0, SEEK_END) == 0, PETSC_COMM_SELF, PETSC_ERR_FILE_READ, "seek");
  n = ftell(fp);
  rewind(fp);
  PetscCall(PetscMalloc1(n + 1, text));
  PetscCheck(fread(*text, 1, (size_t)n, fp) == (size_t)n, PETSC_COMM_SELF, PETSC_ERR_FILE_READ,
             "test_output: short read of %s", path);
  (*text)[n] = '\0';
  fclose(fp);
  PetscFunctionReturn(0);
}

/* -verbose_errors prints the message of each expected error */
static PetscBool verbose_errors_ = PETSC_FALSE;

/* on every rank: the error of `what` has the code expected and its message holds every string of must[]
   (NULL-terminated); a rank that finds otherwise says why, and the test fails on every rank */
static PetscErrorCode CheckError(TestCtx *ctx, PetscErrorCode ierr, PetscErrorCode code, const ErrorText *e,
                                 const char what[], const char *must[])
{
  PetscInt    bad     = 0, gbad;
  const char *missing = NULL;

  PetscFunctionBegin;
  if (verbose_errors_ && ierr) PetscCall(PetscPrintf(ctx->comm, "expected error %d: %s\n", (int)ierr, e->text));
  for (PetscInt k = 0; must[k] && !missing; k++)
    if (!strstr(e->text, must[k])) missing = must[k];
  if (ierr != code || missing) {
    bad = 1;
    PetscCall(PetscPrintf(PETSC_COMM_SELF, "[%d] %s returned %d (expected %d) with the message \"%s\"%s%s%s\n",
                          (int)ctx->rank, what, (int)ierr, (int)code, e->text, missing ? ", which must say \"" : "",
                          missing ? missing : "", missing ? "\"" : ""));
  }
  PetscCallMPI(MPI_Allreduce(&bad, &gbad, 1, MPIU_INT, MPI_MAX, ctx->comm));
  TCHECK(ctx->comm, gbad == 0, "%s: not the error expected on some rank (see above)", what);
  PetscFunctionReturn(0);
}

/* Calls an expression that must fail with the given PETSc error code and a message holding each of the strings
   that follow (error printing suppressed) */
#define EXPECT_ERROR(ctx, code, call, ...)                          \
  do {                                                              \
    const char    *must_[] = {__VA_ARGS__, NULL};                   \
    ErrorText      e_      = {""};                                  \
    PetscErrorCode ierr_;                                           \
    FS_TEST_CAPTURE(call, e_, ierr_);                               \
    PetscCall(CheckError((ctx), ierr_, (code), &e_, #call, must_)); \
  } while (0)

/* Loads dataset /particles/<name> of an HDF5 file with this rank's layout and compares exactly */
static PetscErrorCode CheckDataset(TestCtx *ctx, const char file[], PetscInt f, const char name[], PetscInt bs,
                                   PetscInt start, PetscInt nlocal)
{
  PetscViewer        viewer;
  Vec                v;
  const PetscScalar *a;
  PetscInt           bad = 0, gbad;

  PetscFunctionBegin;
  PetscCall(PetscViewerHDF5Open(ctx->comm, file, FILE_MODE_READ, &viewer));
  PetscCall(PetscViewerHDF5PushGroup(viewer, "/particles"));
  PetscCall(VecCreate(ctx->comm, &v));
  PetscCall(VecSetSizes(v, nlocal * bs, PETSC_DETERMINE));
  PetscCall(VecSetBlockSize(v, bs));
  PetscCall(VecSetType(v, VECSTANDARD));
  PetscCall(PetscObjectSetName((PetscObject)v, name));
  PetscCall(VecLoad(v, viewer));
  PetscCall(VecGetArrayRead(v, &a));
  for (PetscInt i = 0; i < nlocal; i++)
    for (PetscInt c = 0; c < bs; c++)
      if (a[i * bs + c] != Value(f, start + i, c)) bad++;
  PetscCall(VecRestoreArrayRead(v, &a));
  PetscCall(VecDestroy(&v));
  PetscCall(PetscViewerHDF5PopGroup(viewer));
  PetscCall(PetscViewerDestroy(&viewer));
  PetscCallMPI(MPI_Allreduce(&bad, &gbad, 1, MPIU_INT, MPI_SUM, ctx->comm));
  TCHECK(ctx->comm, gbad == 0, "%s:/particles/%s: %" PetscInt_FMT " values differ", file, name, gbad);
  PetscFunctionReturn(0);
}

static PetscErrorCode CheckSnapshotAttrs(TestCtx *ctx, const char file[], double t, PetscInt step, PetscInt dim,
                                         PetscInt N)
{
  PetscViewer viewer;
  double      rt;
  PetscInt    rstep, rdim, rN;

  PetscFunctionBegin;
  PetscCall(PetscViewerHDF5Open(ctx->comm, file, FILE_MODE_READ, &viewer));
  PetscCall(PetscViewerHDF5ReadAttribute(viewer, "/particles", "time", PETSC_DOUBLE, NULL, &rt));
  PetscCall(PetscViewerHDF5ReadAttribute(viewer, "/particles", "step", PETSC_INT, NULL, &rstep));
  PetscCall(PetscViewerHDF5ReadAttribute(viewer, "/particles", "dim", PETSC_INT, NULL, &rdim));
  PetscCall(PetscViewerHDF5ReadAttribute(viewer, "/particles", "nparticles", PETSC_INT, NULL, &rN));
  PetscCall(PetscViewerDestroy(&viewer));
  TCHECK(ctx->comm, rt == t && rstep == step && rdim == dim && rN == N,
         "%s: attributes time %g step %" PetscInt_FMT " dim %" PetscInt_FMT " N %" PetscInt_FMT, file, rt, rstep, rdim,
         rN);
  PetscFunctionReturn(0);
}

/* number of data rows of a CSV on rank 0, and the value of column col (0-based) in each */
static PetscErrorCode CountCSVRows(const char path[], PetscInt *rows)
{
  char *text, *p;

  PetscFunctionBegin;
  PetscCall(ReadText(path, &text));
  *rows = -1; /* header */
  for (p = text; *p; p++)
    if (*p == '\n') (*rows)++;
  PetscCall(PetscFree(text));
  PetscFunctionReturn(0);
}

static PetscErrorCode TestDirectory(TestCtx *ctx)
{
  char path[PETSC_MAX_PATH_LEN], msg[PETSC_MAX_PATH_LEN + 128];

  PetscFunctionBegin;
  PetscCall(PetscSNPrintf(path, sizeof(path), "%s/a/b//c/", ctx->dir));
  PetscCall(FSMakeDirectory(ctx->comm, path, "-fs_output_dir"));
  PetscCall(FSMakeDirectory(ctx->comm, path, NULL)); /* existing is fine */
  /* a directory below a regular file cannot be created */
  PetscCall(PetscSNPrintf(path, sizeof(path), "%s/plainfile", ctx->dir));
  if (ctx->rank == 0) {
    FILE *fp = fopen(path, "w");
    PetscCheck(fp, PETSC_COMM_SELF, PETSC_ERR_FILE_OPEN, "cannot create %s", path);
    fclose(fp);
  }
  PetscCallMPI(MPI_Barrier(ctx->comm));
  PetscCall(PetscSNPrintf(path, sizeof(path), "%s/plainfile/sub", ctx->dir));
  PetscCall(
      PetscSNPrintf(msg, sizeof(msg), "Cannot create or write output directory \"%s\" (option -fs_output_dir)", path));
  EXPECT_ERROR(ctx, PETSC_ERR_FILE_OPEN, FSMakeDirectory(ctx->comm, path, "-fs_output_dir"), msg, "Not a directory");
  PetscFunctionReturn(0);
}

static PetscErrorCode TestSnapshots(TestCtx *ctx)
{
  char             dir2[PETSC_MAX_PATH_LEN], dir3[PETSC_MAX_PATH_LEN], file[PETSC_MAX_PATH_LEN];
  FSSnapshotWriter w;
  PetscInt         nlocal = 3 + ctx->rank, start, N, count;
  PetscReal       *pos, *vel, *rho, *pos3, *vel3, *p3;
  const double     times[3] = {0.0, 0.1, 0.2};

  PetscFunctionBegin;
  PetscCallMPI(MPI_Scan(&nlocal, &start, 1, MPIU_INT, MPI_SUM, ctx->comm));
  start -= nlocal;
  PetscCallMPI(MPI_Allreduce(&nlocal, &N, 1, MPIU_INT, MPI_SUM, ctx->comm));
  PetscCall(PetscMalloc3(2 * nlocal, &pos, 2 * nlocal, &vel, nlocal, &rho));
  PetscCall(PetscMalloc3(3 * nlocal, &pos3, 3 * nlocal, &vel3, nlocal, &p3));
  PetscCall(FillField(0, start, nlocal, 2, pos));
  PetscCall(FillField(1, start, nlocal, 2, vel));
  PetscCall(FillField(2, start, nlocal, 1, rho));
  PetscCall(FillField(3, start, nlocal, 3, pos3));
  PetscCall(FillField(4, start, nlocal, 3, vel3));
  PetscCall(FillField(5, start, nlocal, 1, p3));

  /* 2-D: three snapshots */
  PetscCall(PetscSNPrintf(dir2, sizeof(dir2), "%s/snap2d", ctx->dir));
  PetscCall(FSSnapshotWriterCreate(ctx->comm, dir2, -1.0, &w));
  {
    /* the velocity given by a fill function, called once per snapshot on every rank (CheckDataset reads it back) */
    VelocityFill  vf    = {start, nlocal, 0};
    FSOutputField f2[3] = {{"position", 2, pos}, {"velocity", 2, NULL, FillVelocity, &vf}, {"rho", 1, rho}};

    for (PetscInt s = 0; s < 3; s++) PetscCall(FSSnapshotWriterWrite(w, times[s], 10 * s, 2, nlocal, 3, f2));
    TCHECK(ctx->comm, vf.calls == 3, "the velocity's fill function called %" PetscInt_FMT " times, expected 3",
           vf.calls);
    f2[1] = (FSOutputField){.name = "velocity", .bs = 2, .data = vel};
    char msg[PETSC_MAX_PATH_LEN + 128];

    /* invalid calls: missing position, bad bs, bad name; the messages name the file (the next snapshot) */
    PetscCall(PetscSNPrintf(msg, sizeof(msg), "\"%s/snapshot_000003.h5\"", dir2));
    EXPECT_ERROR(ctx, PETSC_ERR_ARG_WRONG, FSSnapshotWriterWrite(w, 1.0, 99, 2, nlocal, 2, f2 + 1), msg,
                 "a field \"position\" with bs = dim = 2 is required");
    f2[1].bs = 3;
    EXPECT_ERROR(ctx, PETSC_ERR_ARG_OUTOFRANGE, FSSnapshotWriterWrite(w, 1.0, 99, 2, nlocal, 3, f2), msg,
                 "field \"velocity\" has bs 3, expected 1 (scalar) or 2 (vector)");
    f2[1].bs   = 2;
    f2[1].name = "bad name";
    EXPECT_ERROR(ctx, PETSC_ERR_ARG_WRONG, FSSnapshotWriterWrite(w, 1.0, 99, 2, nlocal, 3, f2), msg,
                 "field name \"bad name\" may contain only letters, digits, '_', '-' and '.'");
  }
  PetscCall(FSSnapshotWriterGetCount(w, &count));
  TCHECK(ctx->comm, count == 3, "2-D count %" PetscInt_FMT ", expected 3", count);
  PetscCall(FSSnapshotWriterDestroy(&w));
  PetscCall(PetscSNPrintf(file, sizeof(file), "%s/snapshot_000001.h5", dir2));
  PetscCall(CheckSnapshotAttrs(ctx, file, times[1], 10, 2, N));
  PetscCall(CheckDataset(ctx, file, 0, "position", 2, start, nlocal));
  PetscCall(CheckDataset(ctx, file, 1, "velocity", 2, start, nlocal));
  PetscCall(CheckDataset(ctx, file, 2, "rho", 1, start, nlocal));

  /* restart at t = 0.1: snapshot 2 (t = 0.2) is dropped from the index and rewritten */
  PetscCall(FSSnapshotWriterCreate(ctx->comm, dir2, 0.1, &w));
  PetscCall(FSSnapshotWriterGetCount(w, &count));
  TCHECK(ctx->comm, count == 2, "restart count %" PetscInt_FMT ", expected 2", count);
  {
    FSOutputField f2[3] = {{"position", 2, pos}, {"velocity", 2, vel}, {"rho", 1, rho}};
    PetscCall(FSSnapshotWriterWrite(w, 0.15, 15, 2, nlocal, 3, f2));
  }
  PetscCall(FSSnapshotWriterGetCount(w, &count));
  TCHECK(ctx->comm, count == 3, "count after restart write %" PetscInt_FMT ", expected 3", count);
  PetscCall(FSSnapshotWriterDestroy(&w));
  PetscCall(PetscSNPrintf(file, sizeof(file), "%s/snapshot_000002.h5", dir2));
  PetscCall(CheckSnapshotAttrs(ctx, file, 0.15, 15, 2, N));
  if (ctx->rank == 0) {
    char    *text, expect[1024];
    PetscInt rows = 0;

    PetscCall(PetscSNPrintf(file, sizeof(file), "%s/snapshots.csv", dir2));
    PetscCall(CountCSVRows(file, &rows));
    TCHECK(PETSC_COMM_SELF, rows == 3, "snapshots.csv has %" PetscInt_FMT " rows, expected 3", rows);
    PetscCall(ReadText(file, &text));
    PetscCall(PetscSNPrintf(
        expect, sizeof(expect),
        "2,0.14999999999999999,15,snapshot_000002.h5,%" PetscInt_FMT ",2,position:2;velocity:2;rho:1\n", N));
    TCHECK(PETSC_COMM_SELF, strstr(text, expect) != NULL, "snapshots.csv lacks row \"%s\":\n%s", expect, text);
    TCHECK(PETSC_COMM_SELF, strstr(text, ",0.20000000000000001,") == NULL, "snapshots.csv still lists t = 0.2:\n%s",
           text);
    PetscCall(PetscFree(text));
    PetscCall(PetscSNPrintf(file, sizeof(file), "%s/particles.xdmf", dir2));
    PetscCall(ReadText(file, &text));
    TCHECK(PETSC_COMM_SELF,
           strstr(text, "snapshot_000002.h5:/particles/velocity") && strstr(text, "GeometryType=\"XY\"") &&
               !strstr(text, "Value=\"0.20000000000000001\""),
           "particles.xdmf unexpected:\n%s", text);
    PetscCall(PetscFree(text));
  }

  /* 3-D: one snapshot in a fresh directory; a restart without an index starts empty */
  PetscCall(PetscSNPrintf(dir3, sizeof(dir3), "%s/snap3d", ctx->dir));
  PetscCall(FSSnapshotWriterCreate(ctx->comm, dir3, 5.0, &w));
  PetscCall(FSSnapshotWriterGetCount(w, &count));
  TCHECK(ctx->comm, count == 0, "3-D count %" PetscInt_FMT ", expected 0", count);
  {
    FSOutputField f3[3] = {{"p", 1, p3}, {"position", 3, pos3}, {"velocity", 3, vel3}};
    PetscCall(FSSnapshotWriterWrite(w, 0.5, 5, 3, nlocal, 3, f3));
  }
  PetscCall(FSSnapshotWriterDestroy(&w));
  PetscCall(PetscSNPrintf(file, sizeof(file), "%s/snapshot_000000.h5", dir3));
  PetscCall(CheckSnapshotAttrs(ctx, file, 0.5, 5, 3, N));
  PetscCall(CheckDataset(ctx, file, 3, "position", 3, start, nlocal));
  PetscCall(CheckDataset(ctx, file, 4, "velocity", 3, start, nlocal));
  PetscCall(CheckDataset(ctx, file, 5, "p", 1, start, nlocal));
  PetscCall(PetscFree3(pos, vel, rho));
  PetscCall(PetscFree3(pos3, vel3, p3));
  PetscFunctionReturn(0);
}

static PetscErrorCode TestCheckpoint(TestCtx *ctx)
{
  char               dir[PETSC_MAX_PATH_LEN], path[PETSC_MAX_PATH_LEN], missing[PETSC_MAX_PATH_LEN];
  char               msg[PETSC_MAX_PATH_LEN + 128], sizes[128];
  FSCheckpointHeader hdr, rh;
  PetscInt           nlocal = 4 + 3 * ctx->rank, start, N, rN, rn, bad = 0, gbad;
  PetscMPIInt        nranks;
  PetscReal         *pos, *vel, *rho, *buf;

  PetscFunctionBegin;
  PetscCallMPI(MPI_Scan(&nlocal, &start, 1, MPIU_INT, MPI_SUM, ctx->comm));
  start -= nlocal;
  PetscCallMPI(MPI_Allreduce(&nlocal, &N, 1, MPIU_INT, MPI_SUM, ctx->comm));
  PetscCall(PetscMalloc4(2 * nlocal, &pos, 2 * nlocal, &vel, nlocal, &rho, 2 * N, &buf));
  PetscCall(FillField(10, start, nlocal, 2, pos));
  PetscCall(FillField(11, start, nlocal, 2, vel));
  PetscCall(FillField(12, start, nlocal, 1, rho));
  PetscCall(PetscMemzero(&hdr, sizeof(hdr)));
  hdr.time    = 1.0 / 7.0;
  hdr.dt      = 1e-5 / 3.0;
  hdr.step    = 12345;
  hdr.nglobal = 5;
  for (PetscInt i = 0; i < hdr.nglobal; i++) hdr.global[i] = Value(20, i, 0) * (i % 2 ? -1.0 : 1.0);
  PetscCall(PetscSNPrintf(dir, sizeof(dir), "%s/ckpt", ctx->dir));
  PetscCall(FSMakeDirectory(ctx->comm, dir, "-fs_checkpoint_dir"));
  PetscCall(PetscSNPrintf(path, sizeof(path), "%s/checkpoint.h5", dir));
  {
    FSOutputField f[3] = {{"position", 2, pos}, {"velocity", 2, vel}, {"rho", 1, rho}};
    PetscCall(FSCheckpointWrite(ctx->comm, path, &hdr, nlocal, 3, f));
  }

  /* header */
  PetscCall(FSCheckpointReadHeader(ctx->comm, path, &rh, &rN, &nranks));
  TCHECK(ctx->comm, rh.time == hdr.time && rh.dt == hdr.dt && rh.step == hdr.step && rh.nglobal == hdr.nglobal,
         "checkpoint header differs");
  for (PetscInt i = 0; i < hdr.nglobal; i++)
    TCHECK(ctx->comm, rh.global[i] == hdr.global[i], "checkpoint global[%" PetscInt_FMT "] differs", i);
  TCHECK(ctx->comm, rN == N && nranks == ctx->size, "checkpoint N %" PetscInt_FMT " nranks %d", rN, (int)nranks);

  /* same number of ranks: the original layout, values exact */
  PetscCall(FSCheckpointGetLocalSize(ctx->comm, path, &rn));
  TCHECK(ctx->comm, rn == nlocal, "local size %" PetscInt_FMT ", expected %" PetscInt_FMT, rn, nlocal);
  PetscCall(FSCheckpointReadField(ctx->comm, path, "velocity", 2, nlocal, NULL, buf));
  for (PetscInt i = 0; i < 2 * nlocal; i++)
    if (buf[i] != vel[i]) bad++;
  PetscCall(FSCheckpointReadField(ctx->comm, path, "position", 2, nlocal, NULL, buf));
  for (PetscInt i = 0; i < 2 * nlocal; i++)
    if (buf[i] != pos[i]) bad++;
  PetscCall(FSCheckpointReadField(ctx->comm, path, "rho", 1, nlocal, NULL, buf));
  for (PetscInt i = 0; i < nlocal; i++)
    if (buf[i] != rho[i]) bad++;
  PetscCallMPI(MPI_Allreduce(&bad, &gbad, 1, MPIU_INT, MPI_SUM, ctx->comm));
  TCHECK(ctx->comm, gbad == 0, "%" PetscInt_FMT " checkpoint values differ", gbad);

  /* another communicator size: even split in the written order */
  if (ctx->size > 1) {
    MPI_Comm    sub;
    PetscMPIInt color = ctx->rank < ctx->size - 1 ? 0 : MPI_UNDEFINED, srank, ssize;

    PetscCallMPI(MPI_Comm_split(ctx->comm, color, ctx->rank, &sub));
    if (sub != MPI_COMM_NULL) {
      PetscInt sstart, expect;

      PetscCallMPI(MPI_Comm_rank(sub, &srank));
      PetscCallMPI(MPI_Comm_size(sub, &ssize));
      PetscCall(FSCheckpointGetLocalSize(sub, path, &rn));
      expect = N / ssize + (srank < N % ssize ? 1 : 0);
      TCHECK(sub, rn == expect, "even split %" PetscInt_FMT ", expected %" PetscInt_FMT, rn, expect);
      PetscCallMPI(MPI_Scan(&rn, &sstart, 1, MPIU_INT, MPI_SUM, sub));
      sstart -= rn;
      PetscCall(FSCheckpointReadField(sub, path, "velocity", 2, rn, NULL, buf));
      bad = 0;
      for (PetscInt i = 0; i < rn; i++)
        for (PetscInt c = 0; c < 2; c++)
          if (buf[2 * i + c] != Value(11, sstart + i, c)) bad++;
      PetscCallMPI(MPI_Allreduce(&bad, &gbad, 1, MPIU_INT, MPI_SUM, sub));
      TCHECK(sub, gbad == 0, "%" PetscInt_FMT " values differ after an even split", gbad);
      PetscCallMPI(MPI_Comm_free(&sub));
    }
  }

  /* errors: each names the file, and the field and sizes where they are wrong */
  PetscCall(PetscSNPrintf(missing, sizeof(missing), "%s/no_such_checkpoint.h5", dir));
  PetscCall(PetscSNPrintf(msg, sizeof(msg), "Checkpoint \"%s\" does not exist or cannot be read", missing));
  EXPECT_ERROR(ctx, PETSC_ERR_FILE_OPEN, FSCheckpointReadHeader(ctx->comm, missing, &rh, NULL, NULL), msg);
  EXPECT_ERROR(ctx, PETSC_ERR_FILE_OPEN, FSCheckpointGetLocalSize(ctx->comm, missing, &rn), msg);
  EXPECT_ERROR(ctx, PETSC_ERR_FILE_OPEN, FSCheckpointReadField(ctx->comm, missing, "rho", 1, nlocal, NULL, buf), msg);
  PetscCall(PetscSNPrintf(msg, sizeof(msg), "Checkpoint \"%s\"", path));
  EXPECT_ERROR(ctx, PETSC_ERR_FILE_UNEXPECTED, FSCheckpointReadField(ctx->comm, path, "pressure", 1, nlocal, NULL, buf),
               msg, "has no field \"pressure\" (dataset /particles/pressure)");
  EXPECT_ERROR(ctx, PETSC_ERR_FILE_UNEXPECTED, FSCheckpointReadField(ctx->comm, path, "velocity", 3, nlocal, NULL, buf),
               msg, "field \"velocity\" has 2 components per particle, expected 3");
  PetscCall(PetscSNPrintf(sizes, sizeof(sizes),
                          "field \"rho\" holds %" PetscInt_FMT
                          " particles, but the local sizes add up to %" PetscInt_FMT,
                          N, N - ctx->size));
  EXPECT_ERROR(ctx, PETSC_ERR_FILE_UNEXPECTED, FSCheckpointReadField(ctx->comm, path, "rho", 1, nlocal - 1, NULL, buf),
               msg, sizes);
  /* a snapshot is not a checkpoint */
  PetscCall(PetscSNPrintf(missing, sizeof(missing), "%s/snap3d/snapshot_000000.h5", ctx->dir));
  PetscCall(
      PetscSNPrintf(msg, sizeof(msg), "Checkpoint \"%s\" has no /header group: not a flexslosh checkpoint", missing));
  EXPECT_ERROR(ctx, PETSC_ERR_FILE_UNEXPECTED, FSCheckpointReadHeader(ctx->comm, missing, &rh, NULL, NULL), msg);
  PetscCall(PetscFree4(pos, vel, rho, buf));
  PetscFunctionReturn(0);
}

static PetscErrorCode TestTimeSeries(TestCtx *ctx)
{
  char              path[PETSC_MAX_PATH_LEN], msg[PETSC_MAX_PATH_LEN + 128];
  const char *const names[2] = {"energy", "mass"};
  const char *const other[2] = {"energy", "volume"};
  FSTimeSeries      ts;
  PetscReal         v[2];

  PetscFunctionBegin;
  PetscCall(PetscSNPrintf(path, sizeof(path), "%s/series.csv", ctx->dir));
  PetscCall(FSTimeSeriesCreate(ctx->comm, path, 2, names, -1, &ts));
  for (PetscInt s = 0; s < 5; s++) {
    v[0] = 0.5 * s;
    v[1] = 1.0 + s;
    PetscCall(FSTimeSeriesAppend(ts, s, v));
  }
  PetscCall(FSTimeSeriesDestroy(&ts));
  /* simulate a crash in the middle of a row */
  if (ctx->rank == 0) {
    FILE *fp = fopen(path, "a");
    PetscCheck(fp, PETSC_COMM_SELF, PETSC_ERR_FILE_OPEN, "cannot append to %s", path);
    fputs("5,2.5000", fp);
    fclose(fp);
  }
  PetscCallMPI(MPI_Barrier(ctx->comm));
  /* restart at step 2: rows 3, 4 and the torn row go; row 2 is kept (the run that wrote the checkpoint wrote it)
     and the restarted run's row 2 is not written again */
  PetscCall(FSTimeSeriesCreate(ctx->comm, path, 2, names, 2, &ts));
  v[0] = 7.0;
  v[1] = 7.0;
  PetscCall(FSTimeSeriesAppend(ts, 2, v));
  v[0] = -1.0;
  v[1] = 42.0;
  PetscCall(FSTimeSeriesAppend(ts, 3, v));
  PetscCall(FSTimeSeriesDestroy(&ts));
  if (ctx->rank == 0) {
    char       *text;
    const char *expect = "step,energy,mass\n"
                         "0,0.0000000000e+00,1.0000000000e+00\n"
                         "1,5.0000000000e-01,2.0000000000e+00\n"
                         "2,1.0000000000e+00,3.0000000000e+00\n"
                         "3,-1.0000000000e+00,4.2000000000e+01\n";
    PetscCall(ReadText(path, &text));
    TCHECK(PETSC_COMM_SELF, !strcmp(text, expect), "series.csv after restart:\n%s", text);
    PetscCall(PetscFree(text));
  }
  /* changed columns cannot be appended on restart: the file and the header it would need */
  PetscCall(PetscSNPrintf(msg, sizeof(msg), "Time series \"%s\": its header is not \"step,energy,volume\"", path));
  EXPECT_ERROR(ctx, PETSC_ERR_FILE_UNEXPECTED, FSTimeSeriesCreate(ctx->comm, path, 2, other, 2, &ts), msg,
               "cannot append to it on restart");
  PetscFunctionReturn(0);
}

/* A deferred time series (FSTimeSeriesSetDeferred): a row that cannot be written (rank 0 under a file-size limit,
   EFBIG) is kept on rank 0, no row is written after it, and the error carried to every rank names the file */
static PetscErrorCode TestTimeSeriesDeferred(TestCtx *ctx)
{
  char              path[PETSC_MAX_PATH_LEN], msg[PETSC_MAX_PATH_LEN + 128];
  const char *const names[1] = {"x"};
  FSTimeSeries      ts;
  PetscReal         v[1] = {1.0};
  struct rlimit     old, lim;
  int               err = 0;
  PetscBool         torn;

  PetscFunctionBegin;
  PetscCall(PetscSNPrintf(path, sizeof(path), "%s/deferred.csv", ctx->dir));
  PetscCall(FSTimeSeriesCreate(ctx->comm, path, 1, names, -1, &ts));
  PetscCall(FSTimeSeriesSetDeferred(ts, PETSC_TRUE));
  PetscCall(FSTimeSeriesAppend(ts, 0, v));
  PetscCall(FSTimeSeriesAppend(ts, 1, v));
  if (ctx->rank == 0) { /* the file may grow by half a row more: the next row fails, and is cut off again */
    struct stat sb;
    TCHECK(PETSC_COMM_SELF, stat(path, &sb) == 0 && getrlimit(RLIMIT_FSIZE, &old) == 0, "cannot stat %s", path);
    (void)signal(SIGXFSZ, SIG_IGN);
    lim          = old;
    lim.rlim_cur = (rlim_t)sb.st_size + 10;
    TCHECK(PETSC_COMM_SELF, setrlimit(RLIMIT_FSIZE, &lim) == 0, "cannot set a file-size limit");
  }
  PetscCall(FSTimeSeriesAppend(ts, 2, v)); /* fails on rank 0: kept there, nothing broadcast */
  if (ctx->rank == 0) TCHECK(PETSC_COMM_SELF, setrlimit(RLIMIT_FSIZE, &old) == 0, "cannot restore the file-size limit");
  PetscCall(FSTimeSeriesAppend(ts, 3, v)); /* not written after a failure, though it could be now */
  PetscCall(FSTimeSeriesGetFailure(ts, &err, &torn));
  TCHECK(PETSC_COMM_SELF, ctx->rank ? err == 0 : err == EFBIG && !torn, "rank %d: failure %d, expected %d", ctx->rank,
         err, ctx->rank ? 0 : EFBIG);
  PetscCallMPI(MPI_Bcast(&err, 1, MPI_INT, 0, ctx->comm)); /* as the solver's step reduction carries it */
  PetscCall(PetscSNPrintf(msg, sizeof(msg), "Cannot write to time series \"%s\": %s", path, strerror(EFBIG)));
  EXPECT_ERROR(ctx, PETSC_ERR_FILE_WRITE, FSTimeSeriesRaiseFailure(ts, err, PETSC_FALSE), msg);
  PetscCall(FSTimeSeriesDestroy(&ts));
  if (ctx->rank == 0) {
    const char *expect = "step,x\n0,1.0000000000e+00\n1,1.0000000000e+00\n";
    char       *text;
    struct stat sb;
    PetscCall(ReadText(path, &text));
    TCHECK(PETSC_COMM_SELF, !strcmp(text, expect) && stat(path, &sb) == 0 && (size_t)sb.st_size == strlen(expect),
           "deferred.csv after a failed row (%zu bytes):\n%s", (size_t)sb.st_size, text);
    PetscCall(PetscFree(text));
  }
  PetscFunctionReturn(0);
}

static PetscErrorCode TestJSON(TestCtx *ctx)
{
  char            path[PETSC_MAX_PATH_LEN];
  FSJSON          js;
  const PetscReal arr[4] = {1.5, -2.0, NAN, 1e300};

  PetscFunctionBegin;
  PetscCall(PetscSNPrintf(path, sizeof(path), "%s/summary.json", ctx->dir));
  PetscCall(FSJSONCreate(ctx->comm, path, &js));
  PetscCall(FSJSONWriteString(js, "name", "tank \"A\"\\1\n\ttab\x01"));
  PetscCall(FSJSONWriteString(js, "dir", "/tmp/caf\xc3\xa9")); /* '/' and UTF-8 as they are */
  PetscCall(FSJSONWriteInt(js, "nparticles", (PetscInt64)12345678901LL));
  PetscCall(FSJSONBeginObject(js, "timing"));
  PetscCall(FSJSONWriteReal(js, "total", 0.25));
  PetscCall(FSJSONWriteReal(js, "bad", INFINITY));
  PetscCall(FSJSONBeginObject(js, "empty"));
  PetscCall(FSJSONEndObject(js));
  PetscCall(FSJSONBeginObject(js, "open"));
  PetscCall(FSJSONWriteBool(js, "ok", PETSC_TRUE));
  PetscCall(FSJSONWriteRealArray(js, "values", 4, arr));
  PetscCall(FSJSONWriteRealArray(js, "none", 0, NULL));
  PetscCall(FSJSONDestroy(&js)); /* closes "open" and "timing" */
  if (ctx->rank == 0) {
    char       *text;
    const char *expect = "{\n" /* json-c's pretty format: arrays one value a line, reals with a '.' or an exponent */
                         "  \"name\": \"tank \\\"A\\\"\\\\1\\n\\ttab\\u0001\",\n"
                         "  \"dir\": \"/tmp/caf\xc3\xa9\",\n"
                         "  \"nparticles\": 12345678901,\n"
                         "  \"timing\": {\n"
                         "    \"total\": 0.25,\n"
                         "    \"bad\": null,\n"
                         "    \"empty\": {\n"
                         "    },\n"
                         "    \"open\": {\n"
                         "      \"ok\": true,\n"
                         "      \"values\": [\n"
                         "        1.5,\n"
                         "        -2.0,\n"
                         "        null,\n"
                         "        1.0000000000000001e+300\n"
                         "      ],\n"
                         "      \"none\": [\n"
                         "      ]\n"
                         "    }\n"
                         "  }\n"
                         "}\n";
    PetscCall(ReadText(path, &text));
    TCHECK(PETSC_COMM_SELF, !strcmp(text, expect), "summary.json:\n%s", text);
    PetscCall(PetscFree(text));
  }
  PetscFunctionReturn(0);
}

int main(int argc, char **argv)
{
  TestCtx   ctx;
  PetscBool made = PETSC_FALSE; /* the folder is ours to remove at the end */

  PetscCall(PetscInitialize(&argc, &argv, NULL, "Unit test of the flexslosh output writers"));
  ctx.comm = PETSC_COMM_WORLD;
  PetscCall(PetscOptionsGetBool(NULL, NULL, "-verbose_errors", &verbose_errors_, NULL));
  PetscCallMPI(MPI_Comm_rank(ctx.comm, &ctx.rank));
  PetscCallMPI(MPI_Comm_size(ctx.comm, &ctx.size));
  if (argc > 1 && argv[1][0] != '-') PetscCall(PetscStrncpy(ctx.dir, argv[1], sizeof(ctx.dir)));
  else {
    if (ctx.rank == 0) {
      PetscCall(PetscStrncpy(ctx.dir, "/tmp/test_output_XXXXXX", sizeof(ctx.dir)));
      PetscCheck(mkdtemp(ctx.dir), PETSC_COMM_SELF, PETSC_ERR_FILE_OPEN, "mkdtemp failed");
    }
    PetscCallMPI(MPI_Bcast(ctx.dir, sizeof(ctx.dir), MPI_CHAR, 0, ctx.comm));
    made = PETSC_TRUE;
  }
  PetscCall(FSMakeDirectory(ctx.comm, ctx.dir, NULL));
  PetscCall(TestDirectory(&ctx));
  PetscCall(TestSnapshots(&ctx));
  PetscCall(TestCheckpoint(&ctx));
  PetscCall(TestTimeSeries(&ctx));
  PetscCall(TestTimeSeriesDeferred(&ctx));
  PetscCall(TestJSON(&ctx));
  PetscCall(PetscPrintf(ctx.comm, "test_output: OK (%d ranks, output in %s%s)\n", (int)ctx.size, ctx.dir,
                        made ? ", removed" : ""));
  PetscCallMPI(MPI_Barrier(ctx.comm));
  if (made && ctx.rank == 0) PetscCall(FSTestRemoveTree(ctx.dir));
  PetscCall(PetscFinalize());
  return 0;
}
