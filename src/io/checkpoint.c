/*
   Checkpoints: everything needed to restart a run, in one HDF5 file.

   Layout (all reals float64):
     /particles/<field>   dataset (N,) for bs = 1, (N, bs) for bs > 1, particles in rank order;
                          group attribute nparticles (int)
     /header              group; attributes format = "flexslosh-checkpoint", version (int),
                          time, dt (double), step, nglobal, nparticles, nranks, nfields (int),
                          setup (string, version 2: the run's set-up, one "name=value" a line)
     /header/global       dataset (nglobal,): the replicated global values (absent if nglobal = 0)
     /layout/nlocal       dataset (nranks,): particles owned by each writing rank
     /layout/domain       dataset (nlayout,): the writers' split of the domain (FSCheckpointHeader's layout;
                          absent when nlayout = 0), for a restart on as many ranks

   The file is written as "<path>.tmp" and renamed into place by rank 0 once complete. Reading
   on the same number of ranks restores the original distribution (FSCheckpointGetLocalSize());
   on another number the particles are split evenly, keeping their order. Version 1 (no set-up record)
   is still read.
*/
#include <errno.h>
#include <string.h>
#include <petscvec.h>
#include <petscviewerhdf5.h>
#include <petsclayouthdf5.h> /* PetscViewerHDF5ReadSizes() */
#include "fsoutput.h"

#if defined(PETSC_USE_COMPLEX)
#  error "flexslosh output wraps PetscReal arrays as PetscScalar: a real PETSc build is required"
#endif

#define FS_CHECKPOINT_FORMAT  "flexslosh-checkpoint"
#define FS_CHECKPOINT_VERSION 2 /* 2: the set-up record */

/* The dataset <group>/<name> of n values: nlocal of them from each rank, in rank order (collective) */
static PetscErrorCode FSCheckpointWriteArray(PetscViewer viewer, MPI_Comm comm, const char group[], const char name[],
                                             PetscInt nlocal, PetscInt n, const PetscReal values[])
{
  Vec v;

  PetscFunctionBegin;
  PetscCall(VecCreateMPIWithArray(comm, 1, nlocal, n, (const PetscScalar *)values, &v));
  PetscCall(PetscObjectSetName((PetscObject)v, name));
  PetscCall(PetscViewerHDF5PushGroup(viewer, group));
  PetscCall(VecView(v, viewer));
  PetscCall(PetscViewerHDF5PopGroup(viewer));
  PetscCall(VecDestroy(&v));
  PetscFunctionReturn(0);
}

/* The HDF5 file of a checkpoint, written to tmp, created first as id (collective) */
static PetscErrorCode FSCheckpointWriteHDF5(MPI_Comm comm, const char tmp[], FSFileId *id,
                                            const FSCheckpointHeader *hdr, double t, double dt, PetscInt N,
                                            PetscInt nlocal, PetscInt nfields, const FSOutputField fields[])
{
  PetscViewer viewer;
  PetscMPIInt rank, size;
  PetscInt    nranks, nf = nfields, version = FS_CHECKPOINT_VERSION;
  PetscReal   mine = (PetscReal)nlocal;

  PetscFunctionBegin;
  PetscCallMPI(MPI_Comm_rank(comm, &rank));
  PetscCallMPI(MPI_Comm_size(comm, &size));
  nranks = size;
  PetscCall(FSFileCreateShared_Private(comm, tmp, id)); /* HDF5 would follow a link under the name */
  PetscCall(PetscViewerHDF5Open(comm, tmp, FILE_MODE_WRITE, &viewer));
  /* particle fields */
  PetscCall(PetscViewerHDF5WriteGroup(viewer, "/particles"));
  PetscCall(PetscViewerHDF5PushGroup(viewer, "/particles"));
  PetscCall(FSViewFields_Private(viewer, comm, nlocal, nfields, fields));
  PetscCall(PetscViewerHDF5WriteAttribute(viewer, "/particles", "nparticles", PETSC_INT, &N));
  PetscCall(PetscViewerHDF5PopGroup(viewer));
  /* header */
  PetscCall(PetscViewerHDF5WriteGroup(viewer, "/header"));
  PetscCall(PetscViewerHDF5WriteAttribute(viewer, "/header", "format", PETSC_STRING, FS_CHECKPOINT_FORMAT));
  PetscCall(PetscViewerHDF5WriteAttribute(viewer, "/header", "version", PETSC_INT, &version));
  PetscCall(PetscViewerHDF5WriteAttribute(viewer, "/header", "time", PETSC_DOUBLE, &t));
  PetscCall(PetscViewerHDF5WriteAttribute(viewer, "/header", "dt", PETSC_DOUBLE, &dt));
  PetscCall(PetscViewerHDF5WriteAttribute(viewer, "/header", "step", PETSC_INT, &hdr->step));
  PetscCall(PetscViewerHDF5WriteAttribute(viewer, "/header", "nglobal", PETSC_INT, &hdr->nglobal));
  PetscCall(PetscViewerHDF5WriteAttribute(viewer, "/header", "nparticles", PETSC_INT, &N));
  PetscCall(PetscViewerHDF5WriteAttribute(viewer, "/header", "nranks", PETSC_INT, &nranks));
  PetscCall(PetscViewerHDF5WriteAttribute(viewer, "/header", "nfields", PETSC_INT, &nf));
  if (hdr->setup) /* an attribute is written collectively: the header is the same on every rank */
    PetscCall(PetscViewerHDF5WriteAttribute(viewer, "/header", "setup", PETSC_STRING, hdr->setup));
  if (hdr->nglobal > 0)
    PetscCall(FSCheckpointWriteArray(viewer, comm, "/header", "global", rank == 0 ? hdr->nglobal : 0, hdr->nglobal,
                                     hdr->global));
  /* layout: one entry per rank, and the split of the domain */
  PetscCall(FSCheckpointWriteArray(viewer, comm, "/layout", "nlocal", 1, size, &mine));
  if (hdr->nlayout > 0)
    PetscCall(FSCheckpointWriteArray(viewer, comm, "/layout", "domain", rank == 0 ? hdr->nlayout : 0, hdr->nlayout,
                                     hdr->layout));
  PetscCall(PetscViewerDestroy(&viewer));
  PetscFunctionReturn(0);
}

/*@C
   FSCheckpointWrite - Writes a checkpoint: the header, the global values, the particle layout and
   all particle fields.

   Collective

   Input Parameters:
+  comm    - communicator of the particles
.  path    - the checkpoint file (written as "<path>.tmp", then renamed)
.  hdr     - time, dt, step, the nglobal (<= 64) global values, the set-up record (or NULL) and the nlayout
            layout values (or none), identical on all ranks (rank 0's are written)
.  nlocal  - number of particles on this rank
.  nfields - number of fields
-  fields  - the fields (any bs >= 1); names as for snapshots

   Notes:
   See the file comment of checkpoint.c for the layout.
@*/
PetscErrorCode FSCheckpointWrite(MPI_Comm comm, const char path[], const FSCheckpointHeader *hdr, PetscInt nlocal,
                                 PetscInt nfields, const FSOutputField fields[])
{
  char           tmp[PETSC_MAX_PATH_LEN];
  PetscInt       N;
  double         t, dt;
  int            syserr;
  PetscErrorCode ierr;
  FSFileId       id;

  PetscFunctionBegin;
  PetscCheck(path && hdr, comm, PETSC_ERR_ARG_NULL, "FSCheckpointWrite: path and header are required");
  PetscCheck(strlen(path) + 5 < sizeof(tmp), comm, PETSC_ERR_ARG_SIZ, "Checkpoint path too long: \"%s\"", path);
  PetscCall(PetscSNPrintf(tmp, sizeof(tmp), "%s.tmp", path));
  PetscCheck(hdr->nglobal >= 0 && hdr->nglobal <= (PetscInt)(sizeof(hdr->global) / sizeof(hdr->global[0])), comm,
             PETSC_ERR_ARG_OUTOFRANGE, "Checkpoint \"%s\": nglobal %" PetscInt_FMT " must be in [0, %d]", path,
             hdr->nglobal, (int)(sizeof(hdr->global) / sizeof(hdr->global[0])));
  PetscCall(FSCheckFields_Private(comm, path, 0, nlocal, nfields, fields));
  PetscCallMPI(MPI_Allreduce(&nlocal, &N, 1, MPIU_INT, MPI_SUM, comm));
  t  = (double)hdr->time;
  dt = (double)hdr->dt;

  /* a failed write (a full disk) is an error naming the file; the checkpoints written before stay as they are */
  PetscCall(PetscPushErrorHandler(PetscReturnErrorHandler, NULL));
  errno  = 0;
  ierr   = FSCheckpointWriteHDF5(comm, tmp, &id, hdr, t, dt, N, nlocal, nfields, fields);
  syserr = errno;
  PetscCall(PetscPopErrorHandler());
  PetscCall(FSWriteCheck_Private(ierr, syserr, path));
  PetscCallMPI(MPI_Barrier(comm)); /* every rank has closed the file before it is renamed */
  PetscCall(FSRenameFile_Private(comm, tmp, path, &id));
  PetscFunctionReturn(0);
}

/* Opens an existing checkpoint for reading; a missing file is PETSC_ERR_FILE_OPEN on every rank */
static PetscErrorCode FSCheckpointOpen(MPI_Comm comm, const char path[], PetscViewer *viewer)
{
  PetscBool exists, has;

  PetscFunctionBegin;
  PetscCheck(path, comm, PETSC_ERR_ARG_NULL, "Checkpoint path is required");
  PetscCall(FSTestFile_Private(comm, path, &exists));
  PetscCheck(exists, comm, PETSC_ERR_FILE_OPEN, "Checkpoint \"%s\" does not exist or cannot be read", path);
  { /* an HDF5 file at all? (HDF5's own error would not name it) */
    PetscMPIInt rank;
    int         ishdf5 = 0;
    PetscCallMPI(MPI_Comm_rank(comm, &rank));
    if (!rank) ishdf5 = H5Fis_hdf5(path) > 0;
    PetscCallMPI(MPI_Bcast(&ishdf5, 1, MPI_INT, 0, comm));
    PetscCheck(ishdf5, comm, PETSC_ERR_FILE_UNEXPECTED,
               "Checkpoint \"%s\" is not an HDF5 file: give a checkpoint_NNNNNN.h5 that flexslosh wrote", path);
  }
  { /* can HDF5 open it? A truncated file is refused here, quietly, instead of in every rank's H5Fopen */
    PetscMPIInt rank;
    int         opens = 0;
    PetscCallMPI(MPI_Comm_rank(comm, &rank));
    if (!rank) {
      H5E_auto2_t func;
      void       *data;
      hid_t       fid;
      H5Eget_auto2(H5E_DEFAULT, &func, &data);
      H5Eset_auto2(H5E_DEFAULT, NULL, NULL);
      fid = H5Fopen(path, H5F_ACC_RDONLY, H5P_DEFAULT);
      if (fid >= 0) opens = H5Fclose(fid) >= 0;
      H5Eset_auto2(H5E_DEFAULT, func, data);
    }
    PetscCallMPI(MPI_Bcast(&opens, 1, MPI_INT, 0, comm));
    PetscCheck(opens, comm, PETSC_ERR_FILE_UNEXPECTED,
               "Checkpoint \"%s\" is damaged: HDF5 cannot open it (a truncated file, e.g. a copy or a run that was "
               "cut short)",
               path);
  }
  PetscCall(PetscViewerHDF5Open(comm, path, FILE_MODE_READ, viewer));
  PetscCall(PetscViewerHDF5HasGroup(*viewer, "/header", &has));
  if (!has) PetscCall(PetscViewerDestroy(viewer));
  PetscCheck(has, comm, PETSC_ERR_FILE_UNEXPECTED, "Checkpoint \"%s\" has no /header group: not a flexslosh checkpoint",
             path);
  PetscFunctionReturn(0);
}

/* Reads a required attribute of /header; its absence is PETSC_ERR_FILE_UNEXPECTED naming the file */
static PetscErrorCode FSCheckpointReadAttr(PetscViewer viewer, MPI_Comm comm, const char path[], const char name[],
                                           PetscDataType type, void *value)
{
  PetscBool has;

  PetscFunctionBegin;
  PetscCall(PetscViewerHDF5HasAttribute(viewer, "/header", name, &has));
  PetscCheck(has, comm, PETSC_ERR_FILE_UNEXPECTED, "Checkpoint \"%s\": attribute /header.%s is missing", path, name);
  PetscCall(PetscViewerHDF5ReadAttribute(viewer, "/header", name, type, NULL, value));
  PetscFunctionReturn(0);
}

/* The dataset <group>/<name>, at most cap values, into values on every rank (read on rank 0); *n its size */
static PetscErrorCode FSCheckpointReadArray(PetscViewer viewer, MPI_Comm comm, const char path[], const char group[],
                                            const char name[], PetscInt cap, PetscReal values[], PetscInt *n)
{
  PetscMPIInt rank;
  Vec         v;

  PetscFunctionBegin;
  PetscCallMPI(MPI_Comm_rank(comm, &rank));
  PetscCall(PetscViewerHDF5PushGroup(viewer, group));
  PetscCall(PetscViewerHDF5ReadSizes(viewer, name, NULL, n));
  PetscCheck(*n >= 0 && *n <= cap, comm, PETSC_ERR_FILE_UNEXPECTED,
             "Checkpoint \"%s\": %s/%s has %" PetscInt_FMT " values, at most %" PetscInt_FMT " expected", path, group,
             name, *n, cap);
  PetscCall(VecCreateMPI(comm, rank == 0 ? *n : 0, *n, &v));
  PetscCall(PetscObjectSetName((PetscObject)v, name));
  PetscCall(VecLoad(v, viewer));
  PetscCall(PetscViewerHDF5PopGroup(viewer));
  if (rank == 0) {
    const PetscScalar *a;
    PetscCall(VecGetArrayRead(v, &a));
    for (PetscInt i = 0; i < *n; i++) values[i] = PetscRealPart(a[i]);
    PetscCall(VecRestoreArrayRead(v, &a));
  }
  PetscCall(VecDestroy(&v));
  PetscCallMPI(MPI_Bcast(values, (PetscMPIInt)*n, MPIU_REAL, 0, comm));
  PetscFunctionReturn(0);
}

/* Header of an open checkpoint; any output may be NULL */
static PetscErrorCode FSCheckpointReadHeader_Viewer(PetscViewer viewer, MPI_Comm comm, const char path[],
                                                    FSCheckpointHeader *hdr, PetscInt *N, PetscInt *nranks)
{
  PetscInt           version, np, nr;
  double             t, dt;
  FSCheckpointHeader h;

  PetscFunctionBegin;
  PetscCall(PetscMemzero(&h, sizeof(h)));
  PetscCall(FSCheckpointReadAttr(viewer, comm, path, "version", PETSC_INT, &version));
  PetscCheck(version >= 1 && version <= FS_CHECKPOINT_VERSION, comm, PETSC_ERR_FILE_UNEXPECTED,
             "Checkpoint \"%s\" has format version %" PetscInt_FMT "; this build reads versions 1 to %d", path, version,
             FS_CHECKPOINT_VERSION);
  PetscCall(FSCheckpointReadAttr(viewer, comm, path, "time", PETSC_DOUBLE, &t));
  PetscCall(FSCheckpointReadAttr(viewer, comm, path, "dt", PETSC_DOUBLE, &dt));
  PetscCall(FSCheckpointReadAttr(viewer, comm, path, "step", PETSC_INT, &h.step));
  PetscCall(FSCheckpointReadAttr(viewer, comm, path, "nglobal", PETSC_INT, &h.nglobal));
  PetscCall(FSCheckpointReadAttr(viewer, comm, path, "nparticles", PETSC_INT, &np));
  PetscCall(FSCheckpointReadAttr(viewer, comm, path, "nranks", PETSC_INT, &nr));
  h.time = (PetscReal)t;
  h.dt   = (PetscReal)dt;
  PetscCheck(h.nglobal >= 0 && h.nglobal <= (PetscInt)(sizeof(h.global) / sizeof(h.global[0])), comm,
             PETSC_ERR_FILE_UNEXPECTED, "Checkpoint \"%s\": nglobal %" PetscInt_FMT " outside [0, %d]", path, h.nglobal,
             (int)(sizeof(h.global) / sizeof(h.global[0])));
  PetscCheck(np >= 0 && nr >= 1, comm, PETSC_ERR_FILE_UNEXPECTED,
             "Checkpoint \"%s\": invalid nparticles %" PetscInt_FMT " or nranks %" PetscInt_FMT, path, np, nr);
  if (hdr && h.nglobal > 0) {
    PetscBool has;
    PetscInt  n;

    PetscCall(PetscViewerHDF5HasDataset(viewer, "/header/global", &has));
    PetscCheck(has, comm, PETSC_ERR_FILE_UNEXPECTED,
               "Checkpoint \"%s\": dataset /header/global is missing (nglobal = %" PetscInt_FMT ")", path, h.nglobal);
    PetscCall(FSCheckpointReadArray(viewer, comm, path, "/header", "global", h.nglobal, h.global, &n));
    PetscCheck(n == h.nglobal, comm, PETSC_ERR_FILE_UNEXPECTED,
               "Checkpoint \"%s\": /header/global has %" PetscInt_FMT " values, nglobal says %" PetscInt_FMT, path, n,
               h.nglobal);
  }
  if (hdr) *hdr = h;
  if (N) *N = np;
  if (nranks) *nranks = nr;
  PetscFunctionReturn(0);
}

/*@C
   FSCheckpointReadHeader - Reads the header of a checkpoint.

   Collective

   Input Parameters:
+  comm - communicator
-  path - the checkpoint file

   Output Parameters:
+  hdr               - time, dt, step, nglobal and global[] (may be NULL)
.  nglobal_particles - total number of particles (may be NULL)
-  nranks_written    - number of ranks that wrote the checkpoint (may be NULL)

   Notes:
   A missing file raises PETSC_ERR_FILE_OPEN, a file that is not a checkpoint of this format
   PETSC_ERR_FILE_UNEXPECTED; the message names the file.
@*/
PetscErrorCode FSCheckpointReadHeader(MPI_Comm comm, const char path[], FSCheckpointHeader *hdr,
                                      PetscInt *nglobal_particles, PetscMPIInt *nranks_written)
{
  PetscViewer viewer;
  PetscInt    nr;

  PetscFunctionBegin;
  PetscCall(FSCheckpointOpen(comm, path, &viewer));
  PetscCall(FSCheckpointReadHeader_Viewer(viewer, comm, path, hdr, nglobal_particles, &nr));
  PetscCall(PetscViewerDestroy(&viewer));
  if (nranks_written) *nranks_written = (PetscMPIInt)nr;
  PetscFunctionReturn(0);
}

/*@C
   FSCheckpointGetLocalSize - Number of particles this rank should read from a checkpoint.

   Collective

   Input Parameters:
+  comm - communicator
-  path - the checkpoint file

   Output Parameter:
.  nlocal - this rank's share

   Notes:
   On as many ranks as wrote the checkpoint, each rank gets back the particles it wrote; otherwise
   N/size each, the remainder going one each to the first ranks. Either way the shares, taken in
   rank order, cover the particles in the order they were written.
@*/
PetscErrorCode FSCheckpointGetLocalSize(MPI_Comm comm, const char path[], PetscInt *nlocal)
{
  PetscViewer viewer;
  PetscMPIInt rank, size;
  PetscInt    N, nr;

  PetscFunctionBegin;
  PetscCheck(nlocal, comm, PETSC_ERR_ARG_NULL, "FSCheckpointGetLocalSize: nlocal is required");
  PetscCallMPI(MPI_Comm_rank(comm, &rank));
  PetscCallMPI(MPI_Comm_size(comm, &size));
  PetscCall(FSCheckpointOpen(comm, path, &viewer));
  PetscCall(FSCheckpointReadHeader_Viewer(viewer, comm, path, NULL, &N, &nr));
  if (nr == (PetscInt)size) {
    PetscBool          has;
    PetscInt           n, sum;
    Vec                v;
    const PetscScalar *a;

    PetscCall(PetscViewerHDF5HasDataset(viewer, "/layout/nlocal", &has));
    PetscCheck(has, comm, PETSC_ERR_FILE_UNEXPECTED, "Checkpoint \"%s\": dataset /layout/nlocal is missing", path);
    PetscCall(PetscViewerHDF5PushGroup(viewer, "/layout"));
    PetscCall(PetscViewerHDF5ReadSizes(viewer, "nlocal", NULL, &n));
    PetscCheck(n == nr, comm, PETSC_ERR_FILE_UNEXPECTED,
               "Checkpoint \"%s\": /layout/nlocal has %" PetscInt_FMT " entries, nranks is %" PetscInt_FMT, path, n,
               nr);
    PetscCall(VecCreateMPI(comm, 1, size, &v));
    PetscCall(PetscObjectSetName((PetscObject)v, "nlocal"));
    PetscCall(VecLoad(v, viewer));
    PetscCall(PetscViewerHDF5PopGroup(viewer));
    PetscCall(VecGetArrayRead(v, &a));
    *nlocal = (PetscInt)PetscRealPart(a[0]);
    PetscCall(VecRestoreArrayRead(v, &a));
    PetscCall(VecDestroy(&v));
    PetscCallMPI(MPI_Allreduce(nlocal, &sum, 1, MPIU_INT, MPI_SUM, comm));
    PetscCheck(sum == N, comm, PETSC_ERR_FILE_UNEXPECTED,
               "Checkpoint \"%s\": /layout/nlocal sums to %" PetscInt_FMT ", nparticles is %" PetscInt_FMT, path, sum,
               N);
  } else {
    *nlocal = N / size + ((PetscInt)rank < N % size ? 1 : 0);
  }
  PetscCall(PetscViewerDestroy(&viewer));
  PetscFunctionReturn(0);
}

/*@C
   FSCheckpointReadField - Reads one particle field of a checkpoint into a local array.

   Collective

   Input Parameters:
+  comm   - communicator
.  path   - the checkpoint file
.  name   - field name (dataset /particles/<name>)
.  bs     - components per particle expected
-  nlocal - particles to read on this rank (e.g. from FSCheckpointGetLocalSize()); rank r gets the
            particles that follow those of ranks 0..r-1, in the order they were written

   Output Parameter:
.  data - nlocal*bs values

   Notes:
   A missing file is PETSC_ERR_FILE_OPEN; a missing field, a bs that differs from the file's, or a
   sum of nlocal that differs from the number of particles in the file is PETSC_ERR_FILE_UNEXPECTED.
@*/
PetscErrorCode FSCheckpointReadField(MPI_Comm comm, const char path[], const char name[], PetscInt bs, PetscInt nlocal,
                                     PetscReal data[])
{
  PetscViewer        viewer;
  char               dset[PETSC_MAX_PATH_LEN];
  PetscBool          has;
  PetscInt           fbs, flen, N;
  Vec                v;
  const PetscScalar *a;

  PetscFunctionBegin;
  PetscCheck(path && name, comm, PETSC_ERR_ARG_NULL, "FSCheckpointReadField: path and field name are required");
  PetscCheck(bs >= 1, comm, PETSC_ERR_ARG_OUTOFRANGE,
             "Checkpoint \"%s\": field \"%s\" requested with bs %" PetscInt_FMT ", expected >= 1", path, name, bs);
  PetscCheck(nlocal >= 0, comm, PETSC_ERR_ARG_OUTOFRANGE, "Checkpoint \"%s\": nlocal %" PetscInt_FMT " must be >= 0",
             path, nlocal);
  PetscCheck(data || nlocal * bs == 0, PETSC_COMM_SELF, PETSC_ERR_ARG_NULL,
             "Checkpoint \"%s\": no array to read field \"%s\" into", path, name);
  PetscCall(PetscSNPrintf(dset, sizeof(dset), "/particles/%s", name));
  PetscCallMPI(MPI_Allreduce(&nlocal, &N, 1, MPIU_INT, MPI_SUM, comm));
  PetscCall(FSCheckpointOpen(comm, path, &viewer));
  PetscCall(PetscViewerHDF5HasDataset(viewer, dset, &has));
  if (!has) PetscCall(PetscViewerDestroy(&viewer));
  PetscCheck(has, comm, PETSC_ERR_FILE_UNEXPECTED, "Checkpoint \"%s\" has no field \"%s\" (dataset %s)", path, name,
             dset);
  PetscCall(PetscViewerHDF5PushGroup(viewer, "/particles"));
  PetscCall(PetscViewerHDF5ReadSizes(viewer, name, &fbs, &flen));
  if (fbs != bs || flen != N * bs) PetscCall(PetscViewerDestroy(&viewer));
  PetscCheck(fbs == bs, comm, PETSC_ERR_FILE_UNEXPECTED,
             "Checkpoint \"%s\": field \"%s\" has %" PetscInt_FMT " components per particle, expected %" PetscInt_FMT,
             path, name, fbs, bs);
  PetscCheck(flen == N * bs, comm, PETSC_ERR_FILE_UNEXPECTED,
             "Checkpoint \"%s\": field \"%s\" holds %" PetscInt_FMT
             " particles, but the local sizes add up to %" PetscInt_FMT,
             path, name, flen / bs, N);
  PetscCall(VecCreate(comm, &v));
  PetscCall(VecSetSizes(v, nlocal * bs, PETSC_DETERMINE));
  PetscCall(VecSetBlockSize(v, bs));
  PetscCall(VecSetType(v, VECSTANDARD));
  PetscCall(PetscObjectSetName((PetscObject)v, name));
  PetscCall(VecLoad(v, viewer));
  PetscCall(PetscViewerHDF5PopGroup(viewer));
  PetscCall(PetscViewerDestroy(&viewer));
  /* VecLoad may replace the Vec's array, so read into a Vec of our own and copy out */
  PetscCall(VecGetArrayRead(v, &a));
  for (PetscInt i = 0; i < nlocal * bs; i++) data[i] = PetscRealPart(a[i]);
  PetscCall(VecRestoreArrayRead(v, &a));
  PetscCall(VecDestroy(&v));
  PetscFunctionReturn(0);
}

/*@C
   FSCheckpointHasField - Whether a checkpoint holds a particle field (a field added to the format
   later is missing from older checkpoints).

   Collective

   Input Parameters:
+  comm - communicator
.  path - the checkpoint file
-  name - field name (dataset /particles/<name>)

   Output Parameter:
.  has - PETSC_TRUE if the dataset exists
@*/
PetscErrorCode FSCheckpointHasField(MPI_Comm comm, const char path[], const char name[], PetscBool *has)
{
  PetscViewer viewer;
  char        dset[PETSC_MAX_PATH_LEN];

  PetscFunctionBegin;
  PetscCheck(path && name && has, comm, PETSC_ERR_ARG_NULL, "FSCheckpointHasField: path, name and has are required");
  PetscCall(PetscSNPrintf(dset, sizeof(dset), "/particles/%s", name));
  PetscCall(FSCheckpointOpen(comm, path, &viewer));
  PetscCall(PetscViewerHDF5HasDataset(viewer, dset, has));
  PetscCall(PetscViewerDestroy(&viewer));
  PetscFunctionReturn(0);
}

/*@C
   FSCheckpointReadSetUp - Reads the record of the set-up of the run that wrote a checkpoint.

   Collective

   Input Parameters:
+  comm - communicator
-  path - the checkpoint file

   Output Parameter:
.  setup - the record as written (FSCheckpointHeader's setup), the same on every rank; free it with
           PetscFree(). NULL for a checkpoint of format version 1, written before the record existed.

   Notes:
   A checkpoint of version 2 without the record is PETSC_ERR_FILE_UNEXPECTED, naming the file and the
   attribute.
@*/
PetscErrorCode FSCheckpointReadSetUp(MPI_Comm comm, const char path[], char **setup)
{
  PetscViewer viewer;
  PetscInt    version;

  PetscFunctionBegin;
  PetscCheck(setup, comm, PETSC_ERR_ARG_NULL, "FSCheckpointReadSetUp: setup is required");
  *setup = NULL;
  PetscCall(FSCheckpointOpen(comm, path, &viewer));
  PetscCall(FSCheckpointReadAttr(viewer, comm, path, "version", PETSC_INT, &version));
  if (version >= 2) PetscCall(FSCheckpointReadAttr(viewer, comm, path, "setup", PETSC_STRING, setup));
  PetscCall(PetscViewerDestroy(&viewer));
  PetscFunctionReturn(0);
}

/*@C
   FSCheckpointReadLayout - Reads the writers' split of the domain (/layout/domain) of a checkpoint.

   Collective

   Input Parameters:
+  comm - communicator
.  path - the checkpoint file
-  cap  - room in layout

   Output Parameters:
+  layout - the values, the same on every rank
-  n      - their number; 0 when the checkpoint has none (written before the layout was kept, or without it)

   Notes:
   More than cap values is an error naming the file.
@*/
PetscErrorCode FSCheckpointReadLayout(MPI_Comm comm, const char path[], PetscInt cap, PetscReal layout[], PetscInt *n)
{
  PetscViewer viewer;
  PetscBool   has;

  PetscFunctionBegin;
  *n = 0;
  PetscCall(FSCheckpointOpen(comm, path, &viewer));
  PetscCall(PetscViewerHDF5HasDataset(viewer, "/layout/domain", &has));
  if (has) PetscCall(FSCheckpointReadArray(viewer, comm, path, "/layout", "domain", cap, layout, n));
  PetscCall(PetscViewerDestroy(&viewer));
  PetscFunctionReturn(0);
}
