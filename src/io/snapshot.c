/*
   FSSnapshotWriter: particle snapshots, one HDF5 file per output time, plus an XDMF file that
   lists them for ParaView and a CSV index that lets a restarted run continue the sequence.

   Layout of <dir>/snapshot_NNNNNN.h5 (NNNNNN: snapshot number, 6 digits):
     /particles                  group; attributes time (double), step (int), dim (int),
                                 nparticles (int)
     /particles/<field>          float64 dataset, shape (N,) when bs = 1, (N, bs) when bs > 1,
                                 particles in rank order (rank 0's first); "position" (bs = dim)
                                 is required and is the XDMF geometry
   <dir>/particles.xdmf          XDMF 3 temporal collection of all indexed snapshots
   <dir>/snapshots.csv           index: number,time,step,file,nparticles,dim,fields with fields
                                 written as name:bs;name:bs;...

   Every file is written as "<name>.tmp" and renamed into place. Only rank 0 touches the index
   and the XDMF file; errors there are broadcast so every rank raises them.
*/
#define _POSIX_C_SOURCE 200809L
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <errno.h>
#include <ctype.h>
#include <petscvec.h>
#include <petscviewerhdf5.h>
#include "fsoutput.h"

#if defined(PETSC_USE_COMPLEX)
#  error "flexslosh output wraps PetscReal arrays as PetscScalar: a real PETSc build is required"
#endif

#define FS_SNAPSHOT_INDEX  "snapshots.csv"
#define FS_SNAPSHOT_XDMF   "particles.xdmf"
#define FS_SNAPSHOT_HEADER "number,time,step,file,nparticles,dim,fields"
#define FS_FIELD_NAME_MAX  64

typedef struct {
  PetscInt  number;     /* the NNNNNN of snapshot_NNNNNN.h5 */
  PetscInt  step;       /* solver step */
  PetscInt  nparticles; /* global particle count */
  PetscInt  dim;        /* 2 or 3 */
  PetscReal time;
  char     *fields; /* "name:bs;name:bs;..." (PetscMalloc'ed) */
} FSSnapshotEntry;

struct _n_FSSnapshotWriter {
  MPI_Comm         comm;
  PetscMPIInt      rank;
  char             dir[PETSC_MAX_PATH_LEN];
  PetscInt         next;    /* number of the next snapshot (all ranks) */
  PetscInt         count;   /* entries in the index (all ranks) */
  PetscInt         nalloc;  /* capacity of entries (rank 0) */
  FSSnapshotEntry *entries; /* the index (rank 0) */
};

/*
   FSCheckFields_Private - Checks a field list before it is written: names made of letters, digits,
   '_', '-' or '.' (they become HDF5 dataset names and XDMF/CSV tokens), unique, bs >= 1 (and 1 or
   dim when dim > 0), data present when there are local values. file names the output in messages.
*/
PetscErrorCode FSCheckFields_Private(MPI_Comm comm, const char file[], PetscInt dim, PetscInt nlocal, PetscInt nfields,
                                     const FSOutputField fields[])
{
  PetscFunctionBegin;
  PetscCheck(nlocal >= 0, comm, PETSC_ERR_ARG_OUTOFRANGE, "Output \"%s\": nlocal %" PetscInt_FMT " must be >= 0", file,
             nlocal);
  PetscCheck(nfields >= 0, comm, PETSC_ERR_ARG_OUTOFRANGE, "Output \"%s\": nfields %" PetscInt_FMT " must be >= 0",
             file, nfields);
  PetscCheck(fields || nfields == 0, comm, PETSC_ERR_ARG_NULL, "Output \"%s\": no field list", file);
  for (PetscInt f = 0; f < nfields; f++) {
    const char *name = fields[f].name;
    size_t      len;

    PetscCheck(name && name[0], comm, PETSC_ERR_ARG_WRONG, "Output \"%s\": field %" PetscInt_FMT " has no name", file,
               f);
    PetscCall(PetscStrlen(name, &len));
    PetscCheck(len < FS_FIELD_NAME_MAX, comm, PETSC_ERR_ARG_WRONG,
               "Output \"%s\": field name \"%s\" is longer than %d characters", file, name, FS_FIELD_NAME_MAX - 1);
    for (size_t c = 0; c < len; c++) {
      unsigned char ch = (unsigned char)name[c];

      PetscCheck(isalnum(ch) || ch == '_' || ch == '-' || ch == '.', comm, PETSC_ERR_ARG_WRONG,
                 "Output \"%s\": field name \"%s\" may contain only letters, digits, '_', '-' and '.'", file, name);
    }
    PetscCheck(fields[f].bs >= 1, comm, PETSC_ERR_ARG_OUTOFRANGE,
               "Output \"%s\": field \"%s\" has bs %" PetscInt_FMT ", expected >= 1", file, name, fields[f].bs);
    PetscCheck(dim <= 0 || fields[f].bs == 1 || fields[f].bs == dim, comm, PETSC_ERR_ARG_OUTOFRANGE,
               "Output \"%s\": field \"%s\" has bs %" PetscInt_FMT ", expected 1 (scalar) or %" PetscInt_FMT
               " (vector)",
               file, name, fields[f].bs, dim);
    PetscCheck(fields[f].data || fields[f].fill || nlocal == 0, PETSC_COMM_SELF, PETSC_ERR_ARG_NULL,
               "Output \"%s\": field \"%s\" has no data", file, name);
    for (PetscInt g = 0; g < f; g++) {
      PetscBool same;

      PetscCall(PetscStrcmp(name, fields[g].name, &same));
      PetscCheck(!same, comm, PETSC_ERR_ARG_WRONG, "Output \"%s\": field \"%s\" given twice", file, name);
    }
  }
  PetscFunctionReturn(0);
}

/*
   FSViewFields_Private - Writes each field as a dataset named after it in the viewer's current
   group: the local array is wrapped (no copy) in an MPI Vec with the field's block size; a field given
   by its fill function is written into one buffer, the largest field's size, that the fields share.
*/
PetscErrorCode FSViewFields_Private(PetscViewer viewer, MPI_Comm comm, PetscInt nlocal, PetscInt nfields,
                                    const FSOutputField fields[])
{
  PetscReal *buf  = NULL;
  PetscInt   most = 0;

  PetscFunctionBegin;
  for (PetscInt f = 0; f < nfields; f++)
    if (!fields[f].data) most = PetscMax(most, nlocal * fields[f].bs);
  PetscCall(PetscMalloc1(most + 1, &buf));
  for (PetscInt f = 0; f < nfields; f++) {
    const PetscReal *data = fields[f].data;
    Vec              v;

    if (!data) { /* on every rank, none or not: a fill may be collective */
      PetscCall((*fields[f].fill)(fields[f].ctx, f, buf));
      data = buf;
    }
    PetscCall(
        VecCreateMPIWithArray(comm, fields[f].bs, nlocal * fields[f].bs, PETSC_DECIDE, (const PetscScalar *)data, &v));
    PetscCall(PetscObjectSetName((PetscObject)v, fields[f].name));
    PetscCall(VecView(v, viewer));
    PetscCall(VecDestroy(&v));
  }
  PetscCall(PetscFree(buf));
  PetscFunctionReturn(0);
}

/* Rank 0: room for one more index entry */
static PetscErrorCode FSSnapshotWriterGrow(FSSnapshotWriter w)
{
  FSSnapshotEntry *e;

  PetscFunctionBegin;
  if (w->count < w->nalloc) PetscFunctionReturn(0);
  w->nalloc = w->nalloc ? 2 * w->nalloc : 16;
  PetscCall(PetscMalloc1(w->nalloc, &e));
  if (w->count) PetscCall(PetscArraycpy(e, w->entries, w->count));
  PetscCall(PetscFree(w->entries));
  w->entries = e;
  PetscFunctionReturn(0);
}

/* Next "name:bs" token of a fields string; returns PETSC_FALSE at the end or on a malformed token */
static PetscBool FSNextFieldToken(const char **p, char name[FS_FIELD_NAME_MAX], PetscInt *bs)
{
  const char *s = *p, *colon, *end;
  char       *stop;
  long        b;
  size_t      len;

  if (!*s) return PETSC_FALSE;
  end   = strchr(s, ';');
  end   = end ? end : s + strlen(s);
  colon = memchr(s, ':', (size_t)(end - s));
  if (!colon) return PETSC_FALSE;
  len = (size_t)(colon - s);
  if (len == 0 || len >= FS_FIELD_NAME_MAX) return PETSC_FALSE;
  memcpy(name, s, len);
  name[len] = '\0';
  b         = strtol(colon + 1, &stop, 10);
  if (stop != end || b < 1) return PETSC_FALSE;
  *bs = (PetscInt)b;
  *p  = *end ? end + 1 : end;
  return PETSC_TRUE;
}

/* Rank 0: the entry's field list is well formed and contains position with bs = dim */
static PetscBool FSFieldsStringValid(const char fields[], PetscInt dim)
{
  const char *p = fields;
  char        name[FS_FIELD_NAME_MAX];
  PetscInt    bs;
  PetscBool   haspos = PETSC_FALSE;

  while (*p) {
    if (!FSNextFieldToken(&p, name, &bs)) return PETSC_FALSE;
    if (!strcmp(name, "position") && bs == dim) haspos = PETSC_TRUE;
  }
  return haspos;
}

/*
   Rank 0: reads <dir>/snapshots.csv and keeps the entries with time <= restart_time + 1e-12.
   *ioerr gets an errno value, *badline the number of a malformed line (0 if none).
*/
static PetscErrorCode FSSnapshotWriterLoadIndex(FSSnapshotWriter w, const char index[], PetscReal restart_time,
                                                int *ioerr, long *badline)
{
  FILE   *fp;
  char   *line = NULL;
  size_t  cap  = 0;
  ssize_t n;
  long    lineno = 0;

  PetscFunctionBegin;
  *ioerr   = 0;
  *badline = 0;
  fp       = fopen(index, "r");
  if (!fp) {
    *ioerr = errno ? errno : EIO;
    PetscFunctionReturn(0);
  }
  while ((n = getline(&line, &cap, fp)) > 0) {
    char     *p = line, *e;
    PetscReal time;
    long      number, step, np, dim;
    char     *file, *fields;

    lineno++;
    while (n > 0 && (line[n - 1] == '\n' || line[n - 1] == '\r')) line[--n] = '\0';
    if (lineno == 1) {
      if (strcmp(line, FS_SNAPSHOT_HEADER)) {
        *badline = lineno;
        break;
      }
      continue;
    }
    if (n == 0) continue;
    number = strtol(p, &e, 10);
    if (e == p || *e != ',') goto bad;
    p    = e + 1;
    time = (PetscReal)strtod(p, &e);
    if (e == p || *e != ',') goto bad;
    p    = e + 1;
    step = strtol(p, &e, 10);
    if (e == p || *e != ',') goto bad;
    file = e + 1;
    p    = strchr(file, ',');
    if (!p) goto bad;
    p++;
    np = strtol(p, &e, 10);
    if (e == p || *e != ',') goto bad;
    p   = e + 1;
    dim = strtol(p, &e, 10);
    if (e == p || *e != ',') goto bad;
    fields = e + 1;
    if (number < 0 || np < 0 || (dim != 2 && dim != 3) || !FSFieldsStringValid(fields, (PetscInt)dim)) goto bad;
    if (time > restart_time + 1e-12) continue;
    PetscCall(FSSnapshotWriterGrow(w));
    w->entries[w->count].number     = (PetscInt)number;
    w->entries[w->count].time       = time;
    w->entries[w->count].step       = (PetscInt)step;
    w->entries[w->count].nparticles = (PetscInt)np;
    w->entries[w->count].dim        = (PetscInt)dim;
    PetscCall(PetscStrallocpy(fields, &w->entries[w->count].fields));
    w->count++;
    if ((PetscInt)number + 1 > w->next) w->next = (PetscInt)number + 1;
    continue;
  bad:
    *badline = lineno;
    break;
  }
  free(line); /* allocated by getline() */
  if (ferror(fp) && !*ioerr && !*badline) *ioerr = EIO;
  (void)fclose(fp);
  PetscFunctionReturn(0);
}

/* Rank 0: writes the index CSV to "<index>.tmp" (created as id); returns an errno value in *ioerr */
static PetscErrorCode FSSnapshotWriterWriteIndex(FSSnapshotWriter w, const char tmp[], FSFileId *id, int *ioerr)
{
  FILE *fp;

  PetscFunctionBegin;
  if ((*ioerr = FSFileCreate_Private(tmp, &fp, id))) PetscFunctionReturn(0);
  if (fprintf(fp, "%s\n", FS_SNAPSHOT_HEADER) < 0) *ioerr = errno ? errno : EIO;
  for (PetscInt i = 0; i < w->count && !*ioerr; i++) {
    const FSSnapshotEntry *e = &w->entries[i];

    if (fprintf(fp,
                "%" PetscInt_FMT ",%.17g,%" PetscInt_FMT ",snapshot_%06" PetscInt_FMT ".h5,%" PetscInt_FMT
                ",%" PetscInt_FMT ",%s\n",
                e->number, (double)e->time, e->step, e->number, e->nparticles, e->dim, e->fields) < 0)
      *ioerr = errno ? errno : EIO;
  }
  if (fclose(fp) != 0 && !*ioerr) *ioerr = errno ? errno : EIO;
  PetscFunctionReturn(0);
}

/*
   Rank 0: writes the XDMF file to tmp (created as id); returns an errno value in *ioerr.

   Each snapshot is a Uniform grid with Polyvertex topology of N nodes and no connectivity
   DataItem (readers number the points 0..N-1), Geometry XY or XYZ from /particles/position, and
   one node-centred Attribute per other field whose DataItem has exactly the dataset's shape:
   "N" for scalars (PETSc writes bs = 1 fields as 1-D datasets) and "N bs" for vectors.

   2-D vectors are declared AttributeType="Vector" with Dimensions "N 2", i.e. stored as they are
   without padding or XDMF functions. ParaView 5.x reads them correctly: its Xdmf3 readers take the
   component count from the data (values / nodes = 2) and its "XDMF Reader" (Xdmf2) pads 2-D
   vectors with z = 0. We chose this over a Function/JOIN item with a zero column because JOIN's
   meaning differs between the Xdmf2 and Xdmf3 libraries, and over padding the HDF5 data because the
   datasets must keep their natural (N, 2) shape for the solver and Python tools. To glyph a 2-D
   vector in a reader that keeps 2 components, use a Calculator (v_X*iHat + v_Y*jHat).
*/
static PetscErrorCode FSSnapshotWriterWriteXDMF(FSSnapshotWriter w, const char tmp[], FSFileId *id, int *ioerr)
{
  FILE *fp;
  int   st = 0;

  PetscFunctionBegin;
  if ((*ioerr = FSFileCreate_Private(tmp, &fp, id))) PetscFunctionReturn(0);
  st |= fprintf(fp, "<?xml version=\"1.0\" ?>\n<Xdmf Version=\"3.0\">\n  <Domain>\n") < 0;
  st |= fprintf(fp, "    <Grid Name=\"particles\" GridType=\"Collection\" CollectionType=\"Temporal\">\n") < 0;
  for (PetscInt i = 0; i < w->count && !st; i++) {
    const FSSnapshotEntry *e = &w->entries[i];
    const char            *p = e->fields;
    char                   file[64], name[FS_FIELD_NAME_MAX];
    PetscInt               bs;

    PetscCall(PetscSNPrintf(file, sizeof(file), "snapshot_%06" PetscInt_FMT ".h5", e->number));
    st |= fprintf(fp, "      <Grid Name=\"snapshot_%06" PetscInt_FMT "\" GridType=\"Uniform\">\n", e->number) < 0;
    st |= fprintf(fp, "        <Time Value=\"%.17g\"/>\n", (double)e->time) < 0;
    st |= fprintf(fp,
                  "        <Topology TopologyType=\"Polyvertex\" NumberOfElements=\"%" PetscInt_FMT
                  "\" NodesPerElement=\"1\"/>\n",
                  e->nparticles) < 0;
    st |= fprintf(fp, "        <Geometry GeometryType=\"%s\">\n", e->dim == 2 ? "XY" : "XYZ") < 0;
    st |= fprintf(fp,
                  "          <DataItem Dimensions=\"%" PetscInt_FMT " %" PetscInt_FMT
                  "\" NumberType=\"Float\" Precision=\"%d\" Format=\"HDF\">%s:/particles/position</DataItem>\n",
                  e->nparticles, e->dim, (int)sizeof(PetscReal), file) < 0;
    st |= fprintf(fp, "        </Geometry>\n") < 0;
    while (FSNextFieldToken(&p, name, &bs)) {
      if (!strcmp(name, "position")) continue;
      st |= fprintf(fp, "        <Attribute Name=\"%s\" AttributeType=\"%s\" Center=\"Node\">\n", name,
                    bs == 1 ? "Scalar" : "Vector") < 0;
      if (bs == 1) st |= fprintf(fp, "          <DataItem Dimensions=\"%" PetscInt_FMT "\"", e->nparticles) < 0;
      else
        st |= fprintf(fp, "          <DataItem Dimensions=\"%" PetscInt_FMT " %" PetscInt_FMT "\"", e->nparticles, bs) <
              0;
      st |= fprintf(fp, " NumberType=\"Float\" Precision=\"%d\" Format=\"HDF\">%s:/particles/%s</DataItem>\n",
                    (int)sizeof(PetscReal), file, name) < 0;
      st |= fprintf(fp, "        </Attribute>\n") < 0;
    }
    st |= fprintf(fp, "      </Grid>\n") < 0;
  }
  st |= fprintf(fp, "    </Grid>\n  </Domain>\n</Xdmf>\n") < 0;
  if (st) *ioerr = errno ? errno : EIO;
  if (fclose(fp) != 0 && !*ioerr) *ioerr = errno ? errno : EIO;
  PetscFunctionReturn(0);
}

/* Rank 0: rewrites snapshots.csv and particles.xdmf (tmp + rename); *ioerr errno, *which 0 csv / 1 xdmf */
static PetscErrorCode FSSnapshotWriterFlushIndex(FSSnapshotWriter w, int *ioerr, int *which)
{
  char     path[PETSC_MAX_PATH_LEN], tmp[PETSC_MAX_PATH_LEN];
  FSFileId id;

  PetscFunctionBegin;
  *which = 0;
  PetscCall(PetscSNPrintf(path, sizeof(path), "%s/%s", w->dir, FS_SNAPSHOT_INDEX));
  PetscCall(PetscSNPrintf(tmp, sizeof(tmp), "%s.tmp", path));
  PetscCall(FSSnapshotWriterWriteIndex(w, tmp, &id, ioerr));
  if (!*ioerr) *ioerr = FSFileReplace_Private(tmp, path, &id);
  if (*ioerr) PetscFunctionReturn(0);
  *which = 1;
  PetscCall(PetscSNPrintf(path, sizeof(path), "%s/%s", w->dir, FS_SNAPSHOT_XDMF));
  PetscCall(PetscSNPrintf(tmp, sizeof(tmp), "%s.tmp", path));
  PetscCall(FSSnapshotWriterWriteXDMF(w, tmp, &id, ioerr));
  if (!*ioerr) *ioerr = FSFileReplace_Private(tmp, path, &id);
  PetscFunctionReturn(0);
}

/*@C
   FSSnapshotWriterCreate - Creates a writer of particle snapshots in a directory.

   Collective

   Input Parameters:
+  comm         - communicator of the particles
.  dir          - output directory (created if needed, see FSMakeDirectory())
-  restart_time - < 0: fresh run, the index starts empty and numbering at 0 (old snapshot files are
                  left alone; snapshots.csv and particles.xdmf are rewritten by the first
                  FSSnapshotWriterWrite()); >= 0: restart, <dir>/snapshots.csv is reloaded, entries
                  with time > restart_time + 1e-12 are dropped and numbering continues after the
                  last kept snapshot

   Output Parameter:
.  w - the writer

   Notes:
   A malformed snapshots.csv raises PETSC_ERR_FILE_UNEXPECTED; a restart without one starts empty.
@*/
PetscErrorCode FSSnapshotWriterCreate(MPI_Comm comm, const char dir[], PetscReal restart_time, FSSnapshotWriter *w)
{
  FSSnapshotWriter sw;
  char             index[PETSC_MAX_PATH_LEN];
  int              st[2] = {0, 0}; /* errno, bad line */
  PetscInt         counts[2];

  PetscFunctionBegin;
  PetscCheck(dir && w, comm, PETSC_ERR_ARG_NULL, "FSSnapshotWriterCreate: directory and output handle are required");
  PetscCheck(strlen(dir) + 32 < PETSC_MAX_PATH_LEN, comm, PETSC_ERR_ARG_SIZ, "Snapshot directory name too long: \"%s\"",
             dir);
  PetscCall(FSMakeDirectory(comm, dir, NULL));
  PetscCall(PetscNew(&sw));
  sw->comm = comm;
  PetscCallMPI(MPI_Comm_rank(comm, &sw->rank));
  PetscCall(PetscStrcpy(sw->dir, dir));
  PetscCall(PetscSNPrintf(index, sizeof(index), "%s/%s", dir, FS_SNAPSHOT_INDEX));
  if (restart_time >= 0 && sw->rank == 0) {
    PetscBool exists;

    PetscCall(PetscTestFile(index, 'r', &exists));
    if (exists) {
      long badline;

      PetscCall(FSSnapshotWriterLoadIndex(sw, index, restart_time, &st[0], &badline));
      st[1] = (int)badline;
    } else PetscCall(PetscInfo(NULL, "Restart: no snapshot index \"%s\"; starting an empty one\n", index));
  }
  PetscCallMPI(MPI_Bcast(st, 2, MPI_INT, 0, comm));
  if (st[0] || st[1]) {
    for (PetscInt i = 0; i < sw->count; i++) PetscCall(PetscFree(sw->entries[i].fields));
    PetscCall(PetscFree(sw->entries));
    PetscCall(PetscFree(sw));
    PetscCheck(!st[0], comm, PETSC_ERR_FILE_OPEN, "Cannot read snapshot index \"%s\": %s", index, strerror(st[0]));
    SETERRQ(comm, PETSC_ERR_FILE_UNEXPECTED,
            "Snapshot index \"%s\": line %d is malformed (expected header \"%s\" then rows of that form)", index, st[1],
            FS_SNAPSHOT_HEADER);
  }
  counts[0] = sw->count;
  counts[1] = sw->next;
  PetscCallMPI(MPI_Bcast(counts, 2, MPIU_INT, 0, comm));
  sw->count = counts[0];
  sw->next  = counts[1];
  *w        = sw;
  PetscFunctionReturn(0);
}

/* The HDF5 file of one snapshot, written to tmp, created first as id (collective) */
static PetscErrorCode FSSnapshotWriteHDF5(MPI_Comm comm, const char tmp[], FSFileId *id, double t, PetscInt step,
                                          PetscInt dim, PetscInt N, PetscInt nlocal, PetscInt nfields,
                                          const FSOutputField fields[])
{
  PetscViewer viewer;

  PetscFunctionBegin;
  PetscCall(FSFileCreateShared_Private(comm, tmp, id)); /* HDF5 would follow a link under the name */
  PetscCall(PetscViewerHDF5Open(comm, tmp, FILE_MODE_WRITE, &viewer));
  PetscCall(PetscViewerHDF5WriteGroup(viewer, "/particles"));
  PetscCall(PetscViewerHDF5PushGroup(viewer, "/particles"));
  PetscCall(FSViewFields_Private(viewer, comm, nlocal, nfields, fields));
  PetscCall(PetscViewerHDF5WriteAttribute(viewer, "/particles", "time", PETSC_DOUBLE, &t));
  PetscCall(PetscViewerHDF5WriteAttribute(viewer, "/particles", "step", PETSC_INT, &step));
  PetscCall(PetscViewerHDF5WriteAttribute(viewer, "/particles", "dim", PETSC_INT, &dim));
  PetscCall(PetscViewerHDF5WriteAttribute(viewer, "/particles", "nparticles", PETSC_INT, &N));
  PetscCall(PetscViewerHDF5PopGroup(viewer));
  PetscCall(PetscViewerDestroy(&viewer));
  PetscFunctionReturn(0);
}

/*@C
   FSSnapshotWriterWrite - Writes one snapshot file <dir>/snapshot_NNNNNN.h5 and updates the index
   and the XDMF file.

   Collective

   Input Parameters:
+  w       - the writer
.  time    - simulation time
.  step    - step number
.  dim     - spatial dimension, 2 or 3
.  nlocal  - number of particles on this rank
.  nfields - number of fields
-  fields  - the fields; one must be "position" with bs = dim; each bs is 1 or dim

   Notes:
   Datasets go to group /particles with shape (N,) for scalars and (N, dim) for vectors, N the sum of
   nlocal, in rank order. The group carries the attributes time, step, dim and nparticles.
   The file is written as "<file>.tmp" and renamed by rank 0 once complete.
@*/
PetscErrorCode FSSnapshotWriterWrite(FSSnapshotWriter w, PetscReal time, PetscInt step, PetscInt dim, PetscInt nlocal,
                                     PetscInt nfields, const FSOutputField fields[])
{
  char           file[PETSC_MAX_PATH_LEN], tmp[PETSC_MAX_PATH_LEN];
  PetscInt       N, number;
  PetscBool      haspos = PETSC_FALSE;
  double         t      = (double)time;
  int            st[2]  = {0, 0}, syserr;
  PetscErrorCode ierr;
  FSFileId       id;

  PetscFunctionBegin;
  PetscCheck(w, PETSC_COMM_SELF, PETSC_ERR_ARG_NULL, "Null FSSnapshotWriter");
  number = w->next;
  PetscCall(PetscSNPrintf(file, sizeof(file), "%s/snapshot_%06" PetscInt_FMT ".h5", w->dir, number));
  PetscCall(PetscSNPrintf(tmp, sizeof(tmp), "%s.tmp", file));
  PetscCheck(dim == 2 || dim == 3, w->comm, PETSC_ERR_ARG_OUTOFRANGE,
             "Snapshot \"%s\": dim %" PetscInt_FMT " must be 2 or 3", file, dim);
  PetscCall(FSCheckFields_Private(w->comm, file, dim, nlocal, nfields, fields));
  for (PetscInt f = 0; f < nfields; f++) {
    PetscBool same;

    PetscCall(PetscStrcmp(fields[f].name, "position", &same));
    if (same && fields[f].bs == dim) haspos = PETSC_TRUE;
  }
  PetscCheck(haspos, w->comm, PETSC_ERR_ARG_WRONG,
             "Snapshot \"%s\": a field \"position\" with bs = dim = %" PetscInt_FMT
             " is required (it is the XDMF geometry)",
             file, dim);
  PetscCallMPI(MPI_Allreduce(&nlocal, &N, 1, MPIU_INT, MPI_SUM, w->comm));

  /* a failed write (a full disk) is an error naming the file; the files written before stay as they are */
  PetscCall(PetscPushErrorHandler(PetscReturnErrorHandler, NULL));
  errno  = 0;
  ierr   = FSSnapshotWriteHDF5(w->comm, tmp, &id, t, step, dim, N, nlocal, nfields, fields);
  syserr = errno;
  PetscCall(PetscPopErrorHandler());
  PetscCall(FSWriteCheck_Private(ierr, syserr, file));
  PetscCallMPI(MPI_Barrier(w->comm)); /* every rank has closed the file before it is renamed */
  PetscCall(FSRenameFile_Private(w->comm, tmp, file, &id));

  if (w->rank == 0) {
    FSSnapshotEntry *e;
    size_t           len = 1;
    char            *s;

    /* a restarted run may write a number that a dropped entry had: drop any stale duplicate */
    for (PetscInt i = 0; i < w->count; i++) {
      if (w->entries[i].number >= number) {
        for (PetscInt j = i; j < w->count; j++) PetscCall(PetscFree(w->entries[j].fields));
        w->count = i;
        break;
      }
    }
    PetscCall(FSSnapshotWriterGrow(w));
    e             = &w->entries[w->count];
    e->number     = number;
    e->time       = time;
    e->step       = step;
    e->nparticles = N;
    e->dim        = dim;
    for (PetscInt f = 0; f < nfields; f++) len += strlen(fields[f].name) + 24;
    PetscCall(PetscMalloc1(len, &s));
    s[0] = '\0';
    for (PetscInt f = 0; f < nfields; f++) {
      size_t off = strlen(s);

      PetscCall(PetscSNPrintf(s + off, len - off, "%s%s:%" PetscInt_FMT, f ? ";" : "", fields[f].name, fields[f].bs));
    }
    e->fields = s;
    w->count++;
    PetscCall(FSSnapshotWriterFlushIndex(w, &st[0], &st[1]));
  }
  PetscCallMPI(MPI_Bcast(st, 2, MPI_INT, 0, w->comm));
  PetscCheck(!st[0], w->comm, PETSC_ERR_FILE_WRITE, "Cannot write \"%s/%s\": %s", w->dir,
             st[1] ? FS_SNAPSHOT_XDMF : FS_SNAPSHOT_INDEX, strerror(st[0]));
  PetscCallMPI(MPI_Bcast(&w->count, 1, MPIU_INT, 0, w->comm));
  w->next = number + 1;
  PetscFunctionReturn(0);
}

/*@C
   FSSnapshotWriterGetCount - Number of snapshots in the writer's index (kept from a restart plus
   written by this run).

   Not Collective

   Input Parameter:
.  w - the writer

   Output Parameter:
.  count - the number of indexed snapshots
@*/
PetscErrorCode FSSnapshotWriterGetCount(FSSnapshotWriter w, PetscInt *count)
{
  PetscFunctionBegin;
  PetscCheck(w && count, PETSC_COMM_SELF, PETSC_ERR_ARG_NULL, "FSSnapshotWriterGetCount: null argument");
  *count = w->count;
  PetscFunctionReturn(0);
}

/*@C
   FSSnapshotWriterDestroy - Frees the writer (the files are complete after each write).

   Not Collective

   Input Parameter:
.  w - the writer (set to NULL)
@*/
PetscErrorCode FSSnapshotWriterDestroy(FSSnapshotWriter *w)
{
  PetscFunctionBegin;
  if (!w || !*w) PetscFunctionReturn(0);
  for (PetscInt i = 0; i < (*w)->count && (*w)->entries; i++) PetscCall(PetscFree((*w)->entries[i].fields));
  PetscCall(PetscFree((*w)->entries));
  PetscCall(PetscFree(*w));
  PetscFunctionReturn(0);
}
