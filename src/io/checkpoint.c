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
   Version 3 adds a checksum to every dataset and to the header, the string attribute "checksum",
   "sum64:" and 16 hex digits (FSCheckpointSum()): the sum modulo 2^64 over the dataset's values of a 64-bit
   mix of each value's bits and its index in the dataset (particle-major), so that each rank sums its own
   part and the ranks add their sums: it depends on the values and their places only, not on how many ranks
   wrote or read them. The header's covers its attributes and /particles.nparticles (FSCheckpointHeaderSum()).
   A flipped bit changes the sum but with a chance of 2^-64.

   The file is written as "<path>.tmp" and renamed into place by rank 0 once complete. Reading
   on the same number of ranks restores the original distribution (FSCheckpointGetLocalSize());
   on another number the particles are split evenly, keeping their order. Every value read is checked
   before it is used: its type, its range (finite; sizes, counts and ids integers in range; the time step
   able to advance the time) and its consistency with the rest of the file (sizes against counts, the
   checksums), an error naming the file, the dataset or attribute, the value and what was expected.
   Versions 1 (no set-up record) and 2 (no checksums) are still read, without the checksums' protection.
*/
#include <errno.h>
#include <stdint.h>
#include <string.h>
#include <petscvec.h>
#include <petscviewerhdf5.h>
#include <petsclayouthdf5.h> /* PetscViewerHDF5ReadSizes() */
#include "fsoutput.h"

#if defined(PETSC_USE_COMPLEX)
#  error "flexslosh output wraps PetscReal arrays as PetscScalar: a real PETSc build is required"
#endif

#define FS_CHECKPOINT_FORMAT  "flexslosh-checkpoint"
#define FS_CHECKPOINT_VERSION 3  /* 2: the set-up record; 3: the checksums */
#define FS_CHECKSUM_LEN       32 /* "sum64:" + 16 hex digits + NUL, with room */

/* FSMix64 - splitmix64's finalizer: every bit of z changes about half of the bits of the result */
static inline uint64_t FSMix64(uint64_t z)
{
  z += 0x9e3779b97f4a7c15ULL;
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
  return z ^ (z >> 31);
}

/* FSSumTerm - the checksum's term of the value whose bits are bits at index i */
static inline uint64_t FSSumTerm(uint64_t i, uint64_t bits) { return FSMix64(bits ^ FSMix64(i)); }

/* FSRealBits - the bits of a float64 */
static inline uint64_t FSRealBits(PetscReal v)
{
  double   d = (double)v;
  uint64_t b;
  memcpy(&b, &d, sizeof(b));
  return b;
}

/*
   FSCheckpointSum - the checksum of a dataset whose values lie on the ranks of comm in rank order, n on this
   rank: the sum (mod 2^64) of FSSumTerm(i, bits of value i) over the dataset's indices i, the same on every
   rank, however many ranks hold the values (collective)
*/
static PetscErrorCode FSCheckpointSum(MPI_Comm comm, PetscInt n, const PetscReal v[], uint64_t *sum)
{
  PetscInt64  first = 0, n64 = n;
  PetscMPIInt rank;
  uint64_t    mine = 0;

  PetscFunctionBegin;
  PetscCallMPI(MPI_Comm_rank(comm, &rank));
  PetscCallMPI(MPI_Exscan(&n64, &first, 1, MPIU_INT64, MPI_SUM, comm));
  if (!rank) first = 0; /* MPI_Exscan leaves rank 0's undefined */
  for (PetscInt i = 0; i < n; i++) mine += FSSumTerm((uint64_t)(first + i), FSRealBits(v[i]));
  PetscCallMPI(MPI_Allreduce(&mine, sum, 1, MPI_UINT64_T, MPI_SUM, comm));
  PetscFunctionReturn(0);
}

/* FSStringBits - FNV-1a over the bytes of a string, for the header's checksum */
static uint64_t FSStringBits(const char s[])
{
  uint64_t h = 0xcbf29ce484222325ULL;
  for (const unsigned char *c = (const unsigned char *)s; c && *c; c++) h = (h ^ *c) * 0x100000001b3ULL;
  return h;
}

/* The header's values, as written or read */
typedef struct {
  PetscInt64 version, step, nglobal, nparticles, nranks, nfields, pnparticles; /* pnparticles: /particles' */
  double     time, dt;
  char       format[64];
  char      *setup; /* NULL: none */
} FSHeaderValues;

/*
   FSCheckpointHeaderSum - the header's checksum: the sum of FSSumTerm(k, item k) over its items in this order:
   version, step, nglobal, nparticles, nranks, nfields, /particles.nparticles (as 64-bit integers), the bits of
   time and dt, FSStringBits() of format and of setup ("" when absent)
*/
static void FSCheckpointHeaderSum(const FSHeaderValues *h, char text[FS_CHECKSUM_LEN])
{
  const uint64_t item[] = {(uint64_t)h->version,
                           (uint64_t)h->step,
                           (uint64_t)h->nglobal,
                           (uint64_t)h->nparticles,
                           (uint64_t)h->nranks,
                           (uint64_t)h->nfields,
                           (uint64_t)h->pnparticles,
                           FSRealBits(h->time),
                           FSRealBits(h->dt),
                           FSStringBits(h->format),
                           FSStringBits(h->setup ? h->setup : "")};
  uint64_t       sum    = 0;

  for (size_t k = 0; k < sizeof(item) / sizeof(item[0]); k++) sum += FSSumTerm(k, item[k]);
  snprintf(text, FS_CHECKSUM_LEN, "sum64:%016llx", (unsigned long long)sum);
}

/* FSNum - a value for the messages as C prints it with %g ("nan", "-1", "5e+306"; PETSc's %g adds a dot to "-1.") */
typedef struct {
  char s[32];
} FSNumText;

static FSNumText FSNum(double v)
{
  FSNumText t;
  snprintf(t.s, sizeof(t.s), "%g", v);
  return t;
}

/* FSChecksumText - a checksum as stored */
static void FSChecksumText(uint64_t sum, char text[FS_CHECKSUM_LEN])
{
  snprintf(text, FS_CHECKSUM_LEN, "sum64:%016llx", (unsigned long long)sum);
}

/* The checksum of the dataset <group>/<name> just written, nlocal values from each rank in rank order (collective) */
static PetscErrorCode FSCheckpointWriteSum(PetscViewer viewer, MPI_Comm comm, const char group[], const char name[],
                                           PetscInt nlocal, const PetscReal values[])
{
  char     dset[PETSC_MAX_PATH_LEN], text[FS_CHECKSUM_LEN];
  uint64_t sum;

  PetscFunctionBegin;
  PetscCall(FSCheckpointSum(comm, nlocal, values, &sum));
  FSChecksumText(sum, text);
  PetscCall(PetscSNPrintf(dset, sizeof(dset), "%s/%s", group, name));
  PetscCall(PetscViewerHDF5WriteAttribute(viewer, dset, "checksum", PETSC_STRING, text));
  PetscFunctionReturn(0);
}

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
  PetscCall(FSCheckpointWriteSum(viewer, comm, group, name, nlocal, values));
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
  /* each field's checksum; a field given by its fill function is filled again, on every rank (it may be collective) */
  {
    PetscReal *buf;
    PetscInt   most = 0;
    for (PetscInt f = 0; f < nfields; f++)
      if (!fields[f].data) most = PetscMax(most, nlocal * fields[f].bs);
    PetscCall(PetscMalloc1(most + 1, &buf));
    for (PetscInt f = 0; f < nfields; f++) {
      const PetscReal *data = fields[f].data;
      if (!data) {
        PetscCall((*fields[f].fill)(fields[f].ctx, f, buf));
        data = buf;
      }
      PetscCall(FSCheckpointWriteSum(viewer, comm, "/particles", fields[f].name, nlocal * fields[f].bs, data));
    }
    PetscCall(PetscFree(buf));
  }
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
  /* an attribute is written collectively: the header is the same on every rank; no record is an empty one */
  PetscCall(PetscViewerHDF5WriteAttribute(viewer, "/header", "setup", PETSC_STRING, hdr->setup ? hdr->setup : ""));
  {
    FSHeaderValues h = {version, hdr->step, hdr->nglobal, N, nranks, nf, N, t, dt, FS_CHECKPOINT_FORMAT, NULL};
    char           text[FS_CHECKSUM_LEN];
    h.setup = (char *)(hdr->setup ? hdr->setup : "");
    FSCheckpointHeaderSum(&h, text);
    PetscCall(PetscViewerHDF5WriteAttribute(viewer, "/header", "checksum", PETSC_STRING, text));
  }
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
.  hdr     - time, dt, step, the nglobal (<= 64) global values, the set-up record (or NULL: an empty
            one) and the nlayout layout values (or none), identical on all ranks (rank 0's are written)
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

/* ------------------------------------------------------------------ reading */

/* HDF5's own error printing, off while a checkpoint is read: a damaged file is reported once, naming it */
typedef struct {
  H5E_auto2_t func;
  void       *data;
} FSH5Errors;

static void FSH5Quiet(FSH5Errors *e)
{
  H5Eget_auto2(H5E_DEFAULT, &e->func, &e->data);
  H5Eset_auto2(H5E_DEFAULT, NULL, NULL);
}

static void FSH5Restore(const FSH5Errors *e) { H5Eset_auto2(H5E_DEFAULT, e->func, e->data); }

/* FSCheckpointTry - runs call, a PETSc routine that reads the checkpoint path; an error in it (HDF5 refusing what the
   file holds) becomes one error on every rank that names the file and what was read (what) */
#define FSCheckpointTry(comm, path, what, call)                                                                   \
  do {                                                                                                            \
    FSH5Errors     e_;                                                                                            \
    PetscErrorCode ierr_;                                                                                         \
    int            bad_, any_;                                                                                    \
    FSH5Quiet(&e_);                                                                                               \
    PetscCall(PetscPushErrorHandler(PetscReturnErrorHandler, NULL));                                              \
    ierr_ = (call);                                                                                               \
    PetscCall(PetscPopErrorHandler());                                                                            \
    FSH5Restore(&e_);                                                                                             \
    bad_ = ierr_ != 0;                                                                                            \
    PetscCallMPI(MPI_Allreduce(&bad_, &any_, 1, MPI_INT, MPI_MAX, comm));                                         \
    PetscCheck(                                                                                                   \
        !any_, comm, PETSC_ERR_FILE_UNEXPECTED,                                                                   \
        "Checkpoint \"%s\": %s cannot be read: HDF5 refuses it (a damaged file, or one flexslosh did not write)", \
        path, what);                                                                                              \
  } while (0)

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
      FSH5Errors e;
      hid_t      fid;
      FSH5Quiet(&e);
      fid = H5Fopen(path, H5F_ACC_RDONLY, H5P_DEFAULT);
      if (fid >= 0) opens = H5Fclose(fid) >= 0;
      FSH5Restore(&e);
    }
    PetscCallMPI(MPI_Bcast(&opens, 1, MPI_INT, 0, comm));
    PetscCheck(opens, comm, PETSC_ERR_FILE_UNEXPECTED,
               "Checkpoint \"%s\" is damaged: HDF5 cannot open it (a truncated file, e.g. a copy or a run that was "
               "cut short)",
               path);
  }
  FSCheckpointTry(comm, path, "the file", PetscViewerHDF5Open(comm, path, FILE_MODE_READ, viewer));
  FSCheckpointTry(comm, path, "the group /header", PetscViewerHDF5HasGroup(*viewer, "/header", &has));
  if (!has) PetscCall(PetscViewerDestroy(viewer));
  PetscCheck(has, comm, PETSC_ERR_FILE_UNEXPECTED, "Checkpoint \"%s\" has no /header group: not a flexslosh checkpoint",
             path);
  PetscFunctionReturn(0);
}

/* Whether a dataset of an open checkpoint exists */
static PetscErrorCode FSCheckpointHasDataset(PetscViewer viewer, MPI_Comm comm, const char path[], const char dset[],
                                             PetscBool *has)
{
  PetscFunctionBegin;
  FSCheckpointTry(comm, path, dset, PetscViewerHDF5HasDataset(viewer, dset, has));
  PetscFunctionReturn(0);
}

typedef enum { FS_ATTR_INT, FS_ATTR_REAL, FS_ATTR_STRING } FSAttrKind;

/* an HDF5 type class in words, for the messages */
static const char *FSClassName(H5T_class_t c)
{
  switch (c) {
  case H5T_INTEGER: return "an integer";
  case H5T_FLOAT: return "a floating-point number";
  case H5T_STRING: return "a string";
  case H5T_COMPOUND: return "a compound";
  default: return "of another type";
  }
}

/*
   FSCheckpointAttr - reads the attribute name of obj (a group or a dataset) of an open checkpoint, on every rank: an
   integer (read as 64 bits, into *(PetscInt64 *)value), a number (an integer or a floating-point one, into
   *(double *)value) or a string (into *(char **)value, to PetscFree()). A missing attribute is an error when required
   (else *has is false); one of another type, that is not one value or that HDF5 cannot read is an error always; each
   names the file and the attribute, and the type found.
*/
static PetscErrorCode FSCheckpointAttr(PetscViewer viewer, MPI_Comm comm, const char path[], const char obj[],
                                       const char name[], FSAttrKind kind, PetscBool required, void *value,
                                       PetscBool *has)
{
  const char *want = kind == FS_ATTR_INT ? "an integer" : (kind == FS_ATTR_REAL ? "a number" : "a string");
  hid_t       fid, aid = -1, tid = -1, sid = -1;
  H5T_class_t cls  = H5T_NO_CLASS;
  hssize_t    npts = -1;
  FSH5Errors  e;
  int         st[2] = {0, 0}, all[2]; /* st[0]: 1 missing, 2 unreadable, 3 another type, 4 not one value; st[1]: cls */
  PetscInt64  i64   = 0;
  double      d     = 0;
  char       *str   = NULL;

  PetscFunctionBegin;
  if (has) *has = PETSC_FALSE;
  PetscCall(PetscViewerHDF5GetFileId(viewer, &fid));
  FSH5Quiet(&e);
  {
    const htri_t exists = H5Aexists_by_name(fid, obj, name, H5P_DEFAULT);
    if (exists == 0) st[0] = 1;
    else if (exists < 0 || (aid = H5Aopen_by_name(fid, obj, name, H5P_DEFAULT, H5P_DEFAULT)) < 0) st[0] = 2;
  }
  if (!st[0]) {
    tid  = H5Aget_type(aid);
    sid  = H5Aget_space(aid);
    cls  = tid >= 0 ? H5Tget_class(tid) : H5T_NO_CLASS;
    npts = sid >= 0 ? H5Sget_simple_extent_npoints(sid) : -1;
    if (tid < 0 || sid < 0) st[0] = 2;
    else if (!(kind == FS_ATTR_INT
                   ? cls == H5T_INTEGER
                   : (kind == FS_ATTR_REAL ? cls == H5T_INTEGER || cls == H5T_FLOAT : cls == H5T_STRING)))
      st[0] = 3;
    else if (npts != 1) st[0] = 4;
  }
  if (!st[0]) {
    if (kind == FS_ATTR_INT) {
      long long v = 0;
      if (H5Aread(aid, H5T_NATIVE_LLONG, &v) < 0) st[0] = 2;
      i64 = (PetscInt64)v;
    } else if (kind == FS_ATTR_REAL) {
      if (H5Aread(aid, H5T_NATIVE_DOUBLE, &d) < 0) st[0] = 2;
    } else {
      hid_t        mt  = H5Tcopy(H5T_C_S1);
      const htri_t var = H5Tis_variable_str(tid);
      if (var > 0) {
        char *p = NULL;
        if (H5Tset_size(mt, H5T_VARIABLE) < 0 || H5Aread(aid, mt, &p) < 0 || !p) st[0] = 2;
        else {
          PetscCall(PetscStrallocpy(p, &str));
          H5free_memory(p);
        }
      } else {
        const size_t size = H5Tget_size(tid); /* the file's string may fill it without a NUL: one more in memory */
        PetscCall(PetscCalloc1(size + 2, &str));
        if (var < 0 || !size || H5Tset_size(mt, size + 1) < 0 || H5Aread(aid, mt, str) < 0) st[0] = 2;
      }
      H5Tclose(mt);
    }
  }
  if (sid >= 0) H5Sclose(sid);
  if (tid >= 0) H5Tclose(tid);
  if (aid >= 0) H5Aclose(aid);
  FSH5Restore(&e);
  st[1] = (int)cls;
  PetscCallMPI(MPI_Allreduce(st, all, 2, MPI_INT, MPI_MAX, comm));
  if (all[0]) PetscCall(PetscFree(str));
  if (all[0] == 1 && !required) PetscFunctionReturn(0);
  PetscCheck(all[0] != 1, comm, PETSC_ERR_FILE_UNEXPECTED, "Checkpoint \"%s\": attribute %s.%s is missing", path, obj,
             name);
  PetscCheck(all[0] != 2, comm, PETSC_ERR_FILE_UNEXPECTED,
             "Checkpoint \"%s\": attribute %s.%s cannot be read: HDF5 refuses it (a damaged file)", path, obj, name);
  PetscCheck(all[0] != 3, comm, PETSC_ERR_FILE_UNEXPECTED, "Checkpoint \"%s\": attribute %s.%s is %s, expected %s",
             path, obj, name, FSClassName((H5T_class_t)all[1]), want);
  PetscCheck(all[0] != 4, comm, PETSC_ERR_FILE_UNEXPECTED,
             "Checkpoint \"%s\": attribute %s.%s holds %lld values, expected one (%s)", path, obj, name,
             (long long)npts, want);
  if (kind == FS_ATTR_INT) *(PetscInt64 *)value = i64;
  else if (kind == FS_ATTR_REAL) *(double *)value = d;
  else *(char **)value = str;
  if (has) *has = PETSC_TRUE;
  PetscFunctionReturn(0);
}

/*
   FSCheckpointVerifySum - compares the checksum computed from what was read of item (a dataset, or "the header") with
   the one stored in the attribute obj.checksum. A checkpoint of format version 3 or later must have it; an older one
   has none (nothing to compare) and must not have one (its version would then be damaged).
*/
static PetscErrorCode FSCheckpointVerifySum(PetscViewer viewer, MPI_Comm comm, const char path[], PetscInt64 version,
                                            const char obj[], const char item[], const char computed[])
{
  char     *stored = NULL;
  PetscBool has, same;

  PetscFunctionBegin;
  PetscCall(FSCheckpointAttr(viewer, comm, path, obj, "checksum", FS_ATTR_STRING, PETSC_FALSE, &stored, &has));
  if (!has) {
    PetscCheck(version < 3, comm, PETSC_ERR_FILE_UNEXPECTED,
               "Checkpoint \"%s\": %s has no checksum (attribute %s.checksum), which format version %" PetscInt64_FMT
               " always has: the file is damaged; restart from another checkpoint",
               path, item, obj, version);
    PetscFunctionReturn(0);
  }
  PetscCall(PetscStrcmp(stored, computed, &same));
  if (!same || version < 3) {
    char s[FS_CHECKSUM_LEN];
    PetscCall(PetscStrncpy(s, stored, sizeof(s)));
    PetscCall(PetscFree(stored));
    PetscCheck(version >= 3, comm, PETSC_ERR_FILE_UNEXPECTED,
               "Checkpoint \"%s\" has checksums but says format version %" PetscInt64_FMT
               " (/header.version), which has none: the version is damaged; restart from another checkpoint",
               path, version);
    SETERRQ(
        comm, PETSC_ERR_FILE_UNEXPECTED,
        "Checkpoint \"%s\": %s does not match its checksum (%.40s stored in %s.checksum, %s computed from the values "
        "read): the file is damaged (a flipped bit, a bad copy); restart from another checkpoint",
        path, item, s, obj, computed);
  }
  PetscCall(PetscFree(stored));
  PetscFunctionReturn(0);
}

/*
   FSCheckpointDatasetCheck - a dataset of an open checkpoint holds numbers (integers or floating-point), an error
   naming it otherwise
*/
static PetscErrorCode FSCheckpointDatasetCheck(PetscViewer viewer, MPI_Comm comm, const char path[], const char dset[])
{
  hid_t       fid, did, tid = -1;
  H5T_class_t cls = H5T_NO_CLASS;
  FSH5Errors  e;
  int         c, all;

  PetscFunctionBegin;
  PetscCall(PetscViewerHDF5GetFileId(viewer, &fid));
  FSH5Quiet(&e);
  did = H5Dopen2(fid, dset, H5P_DEFAULT);
  if (did >= 0) tid = H5Dget_type(did);
  if (tid >= 0) cls = H5Tget_class(tid);
  if (tid >= 0) H5Tclose(tid);
  if (did >= 0) H5Dclose(did);
  FSH5Restore(&e);
  c = cls == H5T_INTEGER || cls == H5T_FLOAT ? 0 : (cls == H5T_NO_CLASS ? -1 : (int)cls + 1);
  PetscCallMPI(MPI_Allreduce(&c, &all, 1, MPI_INT, MPI_MAX, comm));
  PetscCheck(all >= 0, comm, PETSC_ERR_FILE_UNEXPECTED,
             "Checkpoint \"%s\": dataset %s cannot be read: HDF5 refuses it (a damaged file)", path, dset);
  PetscCheck(all == 0, comm, PETSC_ERR_FILE_UNEXPECTED,
             "Checkpoint \"%s\": dataset %s does not hold numbers: its values are %s, expected integers or "
             "floating-point numbers",
             path, dset, FSClassName((H5T_class_t)(all - 1)));
  PetscFunctionReturn(0);
}

/*
   FSCheckpointCheckValues - the n*bs values of dataset dset that this rank read (those of its n particles, which follow
   the other ranks' in rank order) are finite and within range (NULL: finite is enough); else an error on every rank
   naming the file, the dataset, the first value out of range (its particle and component in the file) and what was
   expected.
*/
static PetscErrorCode FSCheckpointCheckValues(MPI_Comm comm, const char path[], const char dset[], PetscInt bs,
                                              PetscInt n, const PetscReal v[], const FSCheckpointRange *range)
{
  PetscInt64  first = 0, nv = (PetscInt64)n * bs, bad = INT64_MAX, gbad;
  PetscMPIInt rank;
  uint64_t    bits = 0, gbits;

  PetscFunctionBegin;
  PetscCallMPI(MPI_Comm_rank(comm, &rank));
  PetscCallMPI(MPI_Exscan(&nv, &first, 1, MPIU_INT64, MPI_SUM, comm));
  if (!rank) first = 0;
  for (PetscInt64 i = 0; i < nv && bad == INT64_MAX; i++) {
    const PetscReal x  = v[i];
    const PetscInt  c  = (PetscInt)(i % bs);
    PetscBool       ok = (PetscBool)!PetscIsInfOrNanReal(x);
    if (ok && range) {
      if (range->lo) ok = (PetscBool)(range->open ? x > range->lo[c] : x >= range->lo[c]);
      if (ok && range->hi) ok = (PetscBool)(range->open ? x < range->hi[c] : x <= range->hi[c]);
      if (ok && range->integer) ok = (PetscBool)(x == PetscFloorReal(x));
    }
    if (!ok) {
      bad  = first + i;
      bits = FSRealBits(x);
    }
  }
  PetscCallMPI(MPI_Allreduce(&bad, &gbad, 1, MPIU_INT64, MPI_MIN, comm));
  if (gbad == INT64_MAX) PetscFunctionReturn(0);
  if (bad != gbad) bits = 0; /* the value, from the rank that holds it */
  PetscCallMPI(MPI_Allreduce(&bits, &gbits, 1, MPI_UINT64_T, MPI_SUM, comm));
  {
    double x;
    char   where[64] = "";
    memcpy(&x, &gbits, sizeof(x));
    if (bs > 1) PetscCall(PetscSNPrintf(where, sizeof(where), "[%" PetscInt64_FMT "]", gbad % bs));
    SETERRQ(comm, PETSC_ERR_FILE_UNEXPECTED, "Checkpoint \"%s\": %s[%" PetscInt64_FMT "]%s is %s: expected %s", path,
            dset, gbad / bs, where, FSNum(x).s, range && range->expect ? range->expect : "a finite number");
  }
}

/*
   The dataset <group>/<name>, at most cap values, into values on every rank (read on rank 0); *n its size. Its
   checksum is verified and its values must be finite.
*/
static PetscErrorCode FSCheckpointReadArray(PetscViewer viewer, MPI_Comm comm, const char path[], PetscInt64 version,
                                            const char group[], const char name[], PetscInt cap, PetscReal values[],
                                            PetscInt *n)
{
  PetscMPIInt rank;
  Vec         v;
  char        dset[PETSC_MAX_PATH_LEN], text[FS_CHECKSUM_LEN];
  uint64_t    sum;

  PetscFunctionBegin;
  PetscCallMPI(MPI_Comm_rank(comm, &rank));
  PetscCall(PetscSNPrintf(dset, sizeof(dset), "%s/%s", group, name));
  PetscCall(FSCheckpointDatasetCheck(viewer, comm, path, dset));
  PetscCall(PetscViewerHDF5PushGroup(viewer, group));
  FSCheckpointTry(comm, path, dset, PetscViewerHDF5ReadSizes(viewer, name, NULL, n));
  PetscCheck(*n >= 0 && *n <= cap, comm, PETSC_ERR_FILE_UNEXPECTED,
             "Checkpoint \"%s\": %s has %" PetscInt_FMT " values, at most %" PetscInt_FMT " expected", path, dset, *n,
             cap);
  PetscCall(VecCreateMPI(comm, rank == 0 ? *n : 0, *n, &v));
  PetscCall(PetscObjectSetName((PetscObject)v, name));
  FSCheckpointTry(comm, path, dset, VecLoad(v, viewer));
  PetscCall(PetscViewerHDF5PopGroup(viewer));
  if (rank == 0) {
    const PetscScalar *a;
    PetscCall(VecGetArrayRead(v, &a));
    for (PetscInt i = 0; i < *n; i++) values[i] = PetscRealPart(a[i]);
    PetscCall(VecRestoreArrayRead(v, &a));
  }
  PetscCall(VecDestroy(&v));
  PetscCall(FSCheckpointSum(comm, rank == 0 ? *n : 0, values, &sum));
  FSChecksumText(sum, text);
  PetscCall(FSCheckpointVerifySum(viewer, comm, path, version, dset, dset, text));
  PetscCall(FSCheckpointCheckValues(comm, path, dset, 1, rank == 0 ? *n : 0, values, NULL));
  PetscCallMPI(MPI_Bcast(values, (PetscMPIInt)*n, MPIU_REAL, 0, comm));
  PetscFunctionReturn(0);
}

/*
   FSCheckpointReadHeaderValues - the attributes of /header (and /particles.nparticles) of an open checkpoint, each
   checked for its type and range, the header's checksum verified (format version 3), and the number of datasets in
   /particles against nfields. Free h->setup with PetscFree().
*/
static PetscErrorCode FSCheckpointReadHeaderValues(PetscViewer viewer, MPI_Comm comm, const char path[],
                                                   FSHeaderValues *h)
{
  char     *format = NULL;
  PetscBool same;

  PetscFunctionBegin;
  PetscCall(PetscMemzero(h, sizeof(*h)));
  PetscCall(FSCheckpointAttr(viewer, comm, path, "/header", "version", FS_ATTR_INT, PETSC_TRUE, &h->version, NULL));
  PetscCheck(h->version >= 1 && h->version <= FS_CHECKPOINT_VERSION, comm, PETSC_ERR_FILE_UNEXPECTED,
             "Checkpoint \"%s\" has format version %" PetscInt64_FMT "; this build reads versions 1 to %d", path,
             h->version, FS_CHECKPOINT_VERSION);
  PetscCall(FSCheckpointAttr(viewer, comm, path, "/header", "format", FS_ATTR_STRING, PETSC_TRUE, &format, NULL));
  PetscCall(PetscStrcmp(format, FS_CHECKPOINT_FORMAT, &same));
  if (same) PetscCall(PetscStrncpy(h->format, format, sizeof(h->format)));
  else {
    char f[64];
    PetscCall(PetscStrncpy(f, format, sizeof(f)));
    PetscCall(PetscFree(format));
    SETERRQ(comm, PETSC_ERR_FILE_UNEXPECTED, "Checkpoint \"%s\": attribute /header.format is \"%s\", expected \"%s\"",
            path, f, FS_CHECKPOINT_FORMAT);
  }
  PetscCall(PetscFree(format));
  PetscCall(FSCheckpointAttr(viewer, comm, path, "/header", "time", FS_ATTR_REAL, PETSC_TRUE, &h->time, NULL));
  PetscCall(FSCheckpointAttr(viewer, comm, path, "/header", "dt", FS_ATTR_REAL, PETSC_TRUE, &h->dt, NULL));
  PetscCall(FSCheckpointAttr(viewer, comm, path, "/header", "step", FS_ATTR_INT, PETSC_TRUE, &h->step, NULL));
  PetscCall(FSCheckpointAttr(viewer, comm, path, "/header", "nglobal", FS_ATTR_INT, PETSC_TRUE, &h->nglobal, NULL));
  PetscCall(
      FSCheckpointAttr(viewer, comm, path, "/header", "nparticles", FS_ATTR_INT, PETSC_TRUE, &h->nparticles, NULL));
  PetscCall(FSCheckpointAttr(viewer, comm, path, "/header", "nranks", FS_ATTR_INT, PETSC_TRUE, &h->nranks, NULL));
  PetscCall(FSCheckpointAttr(viewer, comm, path, "/header", "nfields", FS_ATTR_INT, PETSC_TRUE, &h->nfields, NULL));
  /* the set-up record: from version 2 on (version 2's writer could leave it out: FSCheckpointReadSetUp() refuses
     that), always from version 3 on */
  PetscCall(FSCheckpointAttr(viewer, comm, path, "/header", "setup", FS_ATTR_STRING, (PetscBool)(h->version >= 3),
                             &h->setup, NULL));
  PetscCall(
      FSCheckpointAttr(viewer, comm, path, "/particles", "nparticles", FS_ATTR_INT, PETSC_TRUE, &h->pnparticles, NULL));
  {
    char text[FS_CHECKSUM_LEN];
    FSCheckpointHeaderSum(h, text);
    PetscCall(FSCheckpointVerifySum(viewer, comm, path, h->version, "/header", "the header (the attributes of /header)",
                                    text));
  }
  /* the values: each in its range, and consistent */
  PetscCheck(!PetscIsInfOrNanReal(h->time) && h->time >= 0, comm, PETSC_ERR_FILE_UNEXPECTED,
             "Checkpoint \"%s\": attribute /header.time is %s: expected a finite number >= 0", path, FSNum(h->time).s);
  PetscCheck(!PetscIsInfOrNanReal(h->dt) && h->dt > 0, comm, PETSC_ERR_FILE_UNEXPECTED,
             "Checkpoint \"%s\": attribute /header.dt is %s: expected a positive finite number", path, FSNum(h->dt).s);
  PetscCheck(h->time + h->dt > h->time, comm, PETSC_ERR_FILE_UNEXPECTED,
             "Checkpoint \"%s\": attributes /header.time %s and /header.dt %s: the time step is below the time's "
             "resolution (time + dt == time), so the run could not advance: expected a time step that counts",
             path, FSNum(h->time).s, FSNum(h->dt).s);
  PetscCheck(h->step >= 0 && h->step <= PETSC_MAX_INT, comm, PETSC_ERR_FILE_UNEXPECTED,
             "Checkpoint \"%s\": attribute /header.step is %" PetscInt64_FMT ": expected an integer in [0, %d]", path,
             h->step, (int)PETSC_MAX_INT);
  PetscCheck(h->step > 0 || h->time == 0, comm, PETSC_ERR_FILE_UNEXPECTED,
             "Checkpoint \"%s\": attribute /header.time is %s at step 0: expected 0", path, FSNum(h->time).s);
  PetscCheck(h->nglobal >= 0 && h->nglobal <= 64, comm, PETSC_ERR_FILE_UNEXPECTED,
             "Checkpoint \"%s\": attribute /header.nglobal is %" PetscInt64_FMT ": expected an integer in [0, 64]",
             path, h->nglobal);
  PetscCheck(h->nparticles >= 0 && h->nparticles < PETSC_MAX_INT, comm, PETSC_ERR_FILE_UNEXPECTED,
             "Checkpoint \"%s\": attribute /header.nparticles is %" PetscInt64_FMT ": expected an integer in [0, %d]",
             path, h->nparticles, (int)PETSC_MAX_INT - 1);
  PetscCheck(h->pnparticles == h->nparticles, comm, PETSC_ERR_FILE_UNEXPECTED,
             "Checkpoint \"%s\": attribute /particles.nparticles is %" PetscInt64_FMT
             " but /header.nparticles is %" PetscInt64_FMT ": expected the same number",
             path, h->pnparticles, h->nparticles);
  PetscCheck(h->nranks >= 1 && h->nranks <= PETSC_MPI_INT_MAX, comm, PETSC_ERR_FILE_UNEXPECTED,
             "Checkpoint \"%s\": attribute /header.nranks is %" PetscInt64_FMT ": expected an integer in [1, %d]", path,
             h->nranks, (int)PETSC_MPI_INT_MAX);
  {
    hid_t      fid;
    H5G_info_t info;
    FSH5Errors e;
    herr_t     st;
    long long  links;
    PetscCall(PetscViewerHDF5GetFileId(viewer, &fid));
    FSH5Quiet(&e);
    st = H5Gget_info_by_name(fid, "/particles", &info, H5P_DEFAULT);
    FSH5Restore(&e);
    links = st < 0 ? -1 : (long long)info.nlinks;
    PetscCheck(links >= 0, comm, PETSC_ERR_FILE_UNEXPECTED,
               "Checkpoint \"%s\": the group /particles cannot be read: HDF5 refuses it (a damaged file)", path);
    /* fewer: the field missing is named where it is read (FSCheckpointReadField()) */
    PetscCheck(h->nfields >= 1 && h->nfields >= links, comm, PETSC_ERR_FILE_UNEXPECTED,
               "Checkpoint \"%s\": attribute /header.nfields is %" PetscInt64_FMT
               " but /particles holds %lld datasets: expected as many",
               path, h->nfields, links);
  }
  PetscFunctionReturn(0);
}

/* Header of an open checkpoint, checked (FSCheckpointReadHeaderValues()), with its global values; any output may be
   NULL */
static PetscErrorCode FSCheckpointReadHeader_Viewer(PetscViewer viewer, MPI_Comm comm, const char path[],
                                                    FSCheckpointHeader *hdr, PetscInt *N, PetscInt *nranks,
                                                    PetscInt64 *version)
{
  FSHeaderValues     v;
  FSCheckpointHeader h;

  PetscFunctionBegin;
  PetscCall(FSCheckpointReadHeaderValues(viewer, comm, path, &v));
  PetscCall(PetscFree(v.setup));
  PetscCall(PetscMemzero(&h, sizeof(h)));
  h.time    = (PetscReal)v.time;
  h.dt      = (PetscReal)v.dt;
  h.step    = (PetscInt)v.step;
  h.nglobal = (PetscInt)v.nglobal;
  h.version = (PetscInt)v.version;
  if (hdr && h.nglobal > 0) {
    PetscBool has;
    PetscInt  n;

    PetscCall(FSCheckpointHasDataset(viewer, comm, path, "/header/global", &has));
    PetscCheck(has, comm, PETSC_ERR_FILE_UNEXPECTED,
               "Checkpoint \"%s\": dataset /header/global is missing (nglobal = %" PetscInt_FMT ")", path, h.nglobal);
    PetscCall(FSCheckpointReadArray(viewer, comm, path, v.version, "/header", "global", h.nglobal, h.global, &n));
    PetscCheck(n == h.nglobal, comm, PETSC_ERR_FILE_UNEXPECTED,
               "Checkpoint \"%s\": /header/global has %" PetscInt_FMT " values, nglobal says %" PetscInt_FMT, path, n,
               h.nglobal);
  }
  if (hdr) *hdr = h;
  if (N) *N = (PetscInt)v.nparticles;
  if (nranks) *nranks = (PetscInt)v.nranks;
  if (version) *version = v.version;
  PetscFunctionReturn(0);
}

/*@C
   FSCheckpointReadHeader - Reads the header of a checkpoint.

   Collective

   Input Parameters:
+  comm - communicator
-  path - the checkpoint file

   Output Parameters:
+  hdr               - time, dt, step, nglobal and global[], and the file's format version (may be NULL)
.  nglobal_particles - total number of particles (may be NULL)
-  nranks_written    - number of ranks that wrote the checkpoint (may be NULL)

   Notes:
   A missing file raises PETSC_ERR_FILE_OPEN, a file that is not a checkpoint of this format
   PETSC_ERR_FILE_UNEXPECTED; the message names the file. So does every value that is not of its type or
   range (a time that is not finite or negative, a time step that is not positive or cannot advance the
   time, a negative step or count, global values that are not finite) and a header or global values that
   do not match their checksum.
@*/
PetscErrorCode FSCheckpointReadHeader(MPI_Comm comm, const char path[], FSCheckpointHeader *hdr,
                                      PetscInt *nglobal_particles, PetscMPIInt *nranks_written)
{
  PetscViewer viewer;
  PetscInt    nr;

  PetscFunctionBegin;
  PetscCall(FSCheckpointOpen(comm, path, &viewer));
  PetscCall(FSCheckpointReadHeader_Viewer(viewer, comm, path, hdr, nglobal_particles, &nr, NULL));
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
   rank order, cover the particles in the order they were written. The writers' counts (/layout/nlocal)
   are checked in any case: one per writing rank, integers in [0, N] that add up to N.
@*/
PetscErrorCode FSCheckpointGetLocalSize(MPI_Comm comm, const char path[], PetscInt *nlocal)
{
  PetscViewer viewer;
  PetscMPIInt rank, size;
  PetscInt    N, nr, n;
  PetscInt64  version, sum = 0;
  PetscBool   has;
  PetscReal  *counts;

  PetscFunctionBegin;
  PetscCheck(nlocal, comm, PETSC_ERR_ARG_NULL, "FSCheckpointGetLocalSize: nlocal is required");
  PetscCallMPI(MPI_Comm_rank(comm, &rank));
  PetscCallMPI(MPI_Comm_size(comm, &size));
  PetscCall(FSCheckpointOpen(comm, path, &viewer));
  PetscCall(FSCheckpointReadHeader_Viewer(viewer, comm, path, NULL, &N, &nr, &version));
  PetscCall(FSCheckpointHasDataset(viewer, comm, path, "/layout/nlocal", &has));
  PetscCheck(has, comm, PETSC_ERR_FILE_UNEXPECTED, "Checkpoint \"%s\": dataset /layout/nlocal is missing", path);
  PetscCall(PetscViewerHDF5PushGroup(viewer, "/layout"));
  FSCheckpointTry(comm, path, "/layout/nlocal", PetscViewerHDF5ReadSizes(viewer, "nlocal", NULL, &n));
  PetscCall(PetscViewerHDF5PopGroup(viewer));
  PetscCheck(n == nr, comm, PETSC_ERR_FILE_UNEXPECTED,
             "Checkpoint \"%s\": /layout/nlocal has %" PetscInt_FMT " entries, nranks is %" PetscInt_FMT, path, n, nr);
  PetscCall(PetscMalloc1(nr, &counts));
  PetscCall(FSCheckpointReadArray(viewer, comm, path, version, "/layout", "nlocal", nr, counts, &n));
  for (PetscInt r = 0; r < nr; r++) {
    PetscCheck(counts[r] >= 0 && counts[r] <= N && counts[r] == PetscFloorReal(counts[r]), comm,
               PETSC_ERR_FILE_UNEXPECTED,
               "Checkpoint \"%s\": /layout/nlocal[%" PetscInt_FMT "] is %s: expected an integer in [0, %" PetscInt_FMT
               "] (the particles rank %" PetscInt_FMT " wrote)",
               path, r, FSNum((double)counts[r]).s, N, r);
    sum += (PetscInt64)counts[r];
  }
  PetscCheck(sum == N, comm, PETSC_ERR_FILE_UNEXPECTED,
             "Checkpoint \"%s\": /layout/nlocal sums to %" PetscInt64_FMT ", nparticles is %" PetscInt_FMT, path, sum,
             N);
  if (nr == (PetscInt)size) *nlocal = (PetscInt)counts[rank];
  else *nlocal = N / size + ((PetscInt)rank < N % size ? 1 : 0);
  PetscCall(PetscFree(counts));
  PetscCall(PetscViewerDestroy(&viewer));
  PetscFunctionReturn(0);
}

/*@C
   FSCheckpointReadField - Reads one particle field of a checkpoint into a local array, and checks it.

   Collective

   Input Parameters:
+  comm   - communicator
.  path   - the checkpoint file
.  name   - field name (dataset /particles/<name>)
.  bs     - components per particle expected
.  nlocal - particles to read on this rank (e.g. from FSCheckpointGetLocalSize()); rank r gets the
            particles that follow those of ranks 0..r-1, in the order they were written
-  range  - what the values may be besides finite (NULL: any finite value)

   Output Parameter:
.  data - nlocal*bs values

   Notes:
   A missing file is PETSC_ERR_FILE_OPEN; a missing field, a bs that differs from the file's, a
   sum of nlocal that differs from the number of particles in the file, values that are not numbers, do
   not match the field's checksum, are not finite or lie outside range are PETSC_ERR_FILE_UNEXPECTED, naming
   the file, the dataset and (for a value) the particle, the value and what was expected.
@*/
PetscErrorCode FSCheckpointReadField(MPI_Comm comm, const char path[], const char name[], PetscInt bs, PetscInt nlocal,
                                     const FSCheckpointRange *range, PetscReal data[])
{
  PetscViewer        viewer;
  char               dset[PETSC_MAX_PATH_LEN], text[FS_CHECKSUM_LEN];
  PetscBool          has;
  PetscInt           fbs, flen, N;
  PetscInt64         version;
  Vec                v;
  const PetscScalar *a;
  uint64_t           sum;

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
  PetscCall(FSCheckpointReadHeader_Viewer(viewer, comm, path, NULL, NULL, NULL, &version));
  PetscCall(FSCheckpointHasDataset(viewer, comm, path, dset, &has));
  if (!has) PetscCall(PetscViewerDestroy(&viewer));
  PetscCheck(has, comm, PETSC_ERR_FILE_UNEXPECTED, "Checkpoint \"%s\" has no field \"%s\" (dataset %s)", path, name,
             dset);
  PetscCall(FSCheckpointDatasetCheck(viewer, comm, path, dset));
  PetscCall(PetscViewerHDF5PushGroup(viewer, "/particles"));
  FSCheckpointTry(comm, path, dset, PetscViewerHDF5ReadSizes(viewer, name, &fbs, &flen));
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
  FSCheckpointTry(comm, path, dset, VecLoad(v, viewer));
  PetscCall(PetscViewerHDF5PopGroup(viewer));
  /* VecLoad may replace the Vec's array, so read into a Vec of our own and copy out */
  PetscCall(VecGetArrayRead(v, &a));
  for (PetscInt i = 0; i < nlocal * bs; i++) data[i] = PetscRealPart(a[i]);
  PetscCall(VecRestoreArrayRead(v, &a));
  PetscCall(VecDestroy(&v));
  PetscCall(FSCheckpointSum(comm, nlocal * bs, data, &sum));
  FSChecksumText(sum, text);
  PetscCall(FSCheckpointVerifySum(viewer, comm, path, version, dset, dset, text));
  PetscCall(PetscViewerDestroy(&viewer));
  PetscCall(FSCheckpointCheckValues(comm, path, dset, bs, nlocal, data, range));
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
  PetscCall(FSCheckpointHasDataset(viewer, comm, path, dset, has));
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
   attribute. The record is covered by the header's checksum (version 3).
@*/
PetscErrorCode FSCheckpointReadSetUp(MPI_Comm comm, const char path[], char **setup)
{
  PetscViewer    viewer;
  FSHeaderValues v;

  PetscFunctionBegin;
  PetscCheck(setup, comm, PETSC_ERR_ARG_NULL, "FSCheckpointReadSetUp: setup is required");
  *setup = NULL;
  PetscCall(FSCheckpointOpen(comm, path, &viewer));
  PetscCall(FSCheckpointReadHeaderValues(viewer, comm, path, &v));
  PetscCall(PetscViewerDestroy(&viewer));
  PetscCheck(v.setup || v.version < 2, comm, PETSC_ERR_FILE_UNEXPECTED,
             "Checkpoint \"%s\": attribute /header.setup is missing", path);
  *setup = v.setup;
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
   More than cap values, values that are not finite or do not match their checksum are errors naming the file.
@*/
PetscErrorCode FSCheckpointReadLayout(MPI_Comm comm, const char path[], PetscInt cap, PetscReal layout[], PetscInt *n)
{
  PetscViewer viewer;
  PetscBool   has;
  PetscInt64  version;

  PetscFunctionBegin;
  *n = 0;
  PetscCall(FSCheckpointOpen(comm, path, &viewer));
  PetscCall(FSCheckpointReadHeader_Viewer(viewer, comm, path, NULL, NULL, NULL, &version));
  PetscCall(FSCheckpointHasDataset(viewer, comm, path, "/layout/domain", &has));
  if (has) PetscCall(FSCheckpointReadArray(viewer, comm, path, version, "/layout", "domain", cap, layout, n));
  PetscCall(PetscViewerDestroy(&viewer));
  PetscFunctionReturn(0);
}
