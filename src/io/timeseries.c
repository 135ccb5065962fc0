/*
   FSTimeSeries: a CSV file with a header "step,<names...>" and one row per output step, written
   by rank 0. Each row is formatted in memory and written with one write to the unbuffered stream, so a
   crash leaves only complete lines (at worst a torn last line, which a restart drops); a row that cannot
   be written whole (a full disk) is cut off again, so the file keeps only whole rows. The outcome of a write is
   broadcast from rank 0, or (FSTimeSeriesSetDeferred()) left for the caller to carry on a collective of its own.
*/
#define _POSIX_C_SOURCE 200809L
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <errno.h>
#include <sys/stat.h>
#include <unistd.h>
#include "fsoutput.h"

struct _n_FSTimeSeries {
  MPI_Comm    comm;
  PetscMPIInt rank;
  FILE       *fp; /* rank 0 only, opened for appending */
  PetscInt    ncols;
  char        path[PETSC_MAX_PATH_LEN];
  char       *row;       /* rank 0: buffer for one formatted row */
  size_t      rowlen;    /* its size */
  off_t       size;      /* rank 0: the file's length after its last whole row */
  PetscInt    kept;      /* a restart's step whose row the file kept (not written again), or -1 */
  PetscBool   deferred;  /* FSTimeSeriesSetDeferred(): the outcome of a write is not broadcast */
  int         failed[2]; /* rank 0, deferred: the first failed write's errno and whether its torn row stayed */
  PetscBool   raised;    /* FSTimeSeriesRaiseFailure() raised a failure */
};

/* Header line (without newline) in a PetscMalloc'ed string */
static PetscErrorCode FSTimeSeriesBuildHeader(MPI_Comm comm, const char path[], PetscInt ncols,
                                              const char *const names[], char **header)
{
  size_t len = 5, l;

  PetscFunctionBegin;
  for (PetscInt c = 0; c < ncols; c++) {
    PetscCheck(names[c] && names[c][0], comm, PETSC_ERR_ARG_WRONG,
               "Time series \"%s\": column %" PetscInt_FMT " has no name", path, c);
    PetscCheck(!strpbrk(names[c], ",\"\n\r"), comm, PETSC_ERR_ARG_WRONG,
               "Time series \"%s\": column name \"%s\" contains a comma, quote or newline", path, names[c]);
    PetscCall(PetscStrlen(names[c], &l));
    len += l + 1;
  }
  PetscCall(PetscMalloc1(len + 1, header));
  PetscCall(PetscStrcpy(*header, "step"));
  for (PetscInt c = 0; c < ncols; c++) {
    PetscCall(PetscStrcat(*header, ","));
    PetscCall(PetscStrcat(*header, names[c]));
  }
  PetscFunctionReturn(0);
}

/*
   Rank 0: keep the header and the complete rows with step <= restart_step of an existing file, writing them to
   "<path>.tmp" and renaming it over path; *kept says whether a row of restart_step was among them (the run that wrote
   the checkpoint wrote it: a restart cannot recompute the loads of that step's last stage, so it keeps it). Sets
   *ioerr (errno) or *badheader on failure.
*/
static PetscErrorCode FSTimeSeriesTruncate(const char path[], const char header[], PetscInt restart_step, int *ioerr,
                                           PetscBool *badheader, PetscBool *kept)
{
  char     tmp[PETSC_MAX_PATH_LEN];
  FILE    *in, *out;
  FSFileId id;
  char    *line = NULL;
  size_t   cap  = 0;
  ssize_t  n;
  long     lineno = 0;

  PetscFunctionBegin;
  *ioerr     = 0;
  *badheader = PETSC_FALSE;
  *kept      = PETSC_FALSE;
  PetscCall(PetscSNPrintf(tmp, sizeof(tmp), "%s.tmp", path));
  in = fopen(path, "r");
  if (!in) {
    *ioerr = errno ? errno : EIO;
    PetscFunctionReturn(0);
  }
  if ((*ioerr = FSFileCreate_Private(tmp, &out, &id))) {
    (void)fclose(in);
    PetscFunctionReturn(0);
  }
  while ((n = getline(&line, &cap, in)) > 0) {
    lineno++;
    if (line[n - 1] != '\n') break; /* torn last line of a crashed run */
    if (lineno == 1) {
      line[n - 1] = '\0';
      if (n > 1 && line[n - 2] == '\r') line[n - 2] = '\0';
      if (strcmp(line, header)) {
        *badheader = PETSC_TRUE;
        break;
      }
      if (fprintf(out, "%s\n", header) < 0) *ioerr = errno ? errno : EIO;
    } else {
      char *end;
      long  step = strtol(line, &end, 10);

      if (end == line || *end != ',') continue; /* not a data row */
      if (step > (long)restart_step) continue;
      if (fputs(line, out) == EOF) *ioerr = errno ? errno : EIO;
      if (step == (long)restart_step) *kept = PETSC_TRUE;
    }
    if (*ioerr) break;
  }
  free(line); /* allocated by getline() */
  if (ferror(in) && !*ioerr) *ioerr = EIO;
  (void)fclose(in);
  if (fclose(out) != 0 && !*ioerr) *ioerr = errno ? errno : EIO;
  if (lineno == 0 && !*ioerr && !*badheader) {
    /* empty file: start again with just the header */
    if ((*ioerr = FSFileCreate_Private(tmp, &out, &id)) == 0 && fprintf(out, "%s\n", header) < 0)
      *ioerr = errno ? errno : EIO;
    if (out && fclose(out) != 0 && !*ioerr) *ioerr = errno ? errno : EIO;
  }
  if (*ioerr || *badheader) {
    (void)remove(tmp);
    PetscFunctionReturn(0);
  }
  *ioerr = FSFileReplace_Private(tmp, path, &id);
  PetscFunctionReturn(0);
}

/*@C
   FSTimeSeriesCreate - Opens a CSV time series "step,<names...>" written by rank 0.

   Collective

   Input Parameters:
+  comm         - communicator; only rank 0 writes
.  path         - the CSV file
.  ncols        - number of value columns
.  names        - their names (no commas, quotes or newlines)
-  restart_step - < 0: a new file (an existing one is truncated); >= 0: a restart at this step: an
                  existing file keeps its header and the rows with step <= restart_step (rewritten
                  through "<path>.tmp" and a rename), then rows are appended (a kept row of
                  restart_step is not appended again); a missing file is created

   Output Parameter:
.  ts - the time series

   Notes:
   On restart the existing header must equal the new one, otherwise PETSC_ERR_FILE_UNEXPECTED is
   raised (columns would not line up). Errors are raised on every rank.
@*/
PetscErrorCode FSTimeSeriesCreate(MPI_Comm comm, const char path[], PetscInt ncols, const char *const names[],
                                  PetscInt restart_step, FSTimeSeries *ts)
{
  FSTimeSeries w;
  char        *header;
  int          st[3] = {0, 0, 0}; /* errno, bad header, the row of restart_step kept */

  PetscFunctionBegin;
  PetscCheck(path && ts, comm, PETSC_ERR_ARG_NULL, "FSTimeSeriesCreate: path and output handle are required");
  PetscCheck(ncols >= 0, comm, PETSC_ERR_ARG_OUTOFRANGE, "Time series \"%s\": ncols %" PetscInt_FMT " must be >= 0",
             path, ncols);
  PetscCheck(names || ncols == 0, comm, PETSC_ERR_ARG_NULL, "Time series \"%s\": no column names", path);
  PetscCheck(strlen(path) + 5 < PETSC_MAX_PATH_LEN, comm, PETSC_ERR_ARG_SIZ, "Time series path too long: \"%s\"", path);
  PetscCall(FSTimeSeriesBuildHeader(comm, path, ncols, names, &header));
  PetscCall(PetscNew(&w));
  w->comm  = comm;
  w->ncols = ncols;
  PetscCall(PetscStrcpy(w->path, path));
  PetscCallMPI(MPI_Comm_rank(comm, &w->rank));
  if (w->rank == 0) {
    PetscBool exists = PETSC_FALSE, bad = PETSC_FALSE, kept = PETSC_FALSE;

    if (restart_step >= 0) PetscCall(PetscTestFile(path, 'r', &exists));
    if (exists) {
      PetscCall(FSTimeSeriesTruncate(path, header, restart_step, &st[0], &bad, &kept));
      st[1] = bad ? 1 : 0;
      st[2] = kept ? 1 : 0;
      if (!st[0] && !bad) st[0] = FSFileOpenAppend_Private(path, &w->fp);
    } else { /* a new file, not written through a link (FSFileCreate_Private()) */
      st[0] = FSFileCreate_Private(path, &w->fp, NULL);
      if (!st[0] && (fprintf(w->fp, "%s\n", header) < 0 || fflush(w->fp) != 0)) st[0] = errno ? errno : EIO;
    }
    if (!st[0] && !st[1] && w->fp) { /* unbuffered: a row goes out whole or is cut off again (FSTimeSeriesAppend) */
      struct stat sb;

      if (fflush(w->fp) != 0 || setvbuf(w->fp, NULL, _IONBF, 0) != 0 || fstat(fileno(w->fp), &sb) != 0)
        st[0] = errno ? errno : EIO;
      else w->size = sb.st_size;
    }
    w->rowlen = 32 + 32 * (size_t)ncols;
    PetscCall(PetscMalloc1(w->rowlen, &w->row));
  }
  PetscCallMPI(MPI_Bcast(st, 3, MPI_INT, 0, comm));
  w->kept = st[2] ? restart_step : -1;
  if (st[0] || st[1]) {
    char expected[256];

    PetscCall(PetscStrncpy(expected, header, sizeof(expected)));
    PetscCall(PetscFree(header));
    if (w->fp) (void)fclose(w->fp);
    PetscCall(PetscFree(w->row));
    PetscCall(PetscFree(w));
    PetscCheck(!st[1], comm, PETSC_ERR_FILE_UNEXPECTED,
               "Time series \"%s\": its header is not \"%s\" (columns changed?); cannot append to it on restart", path,
               expected);
    SETERRQ(comm, PETSC_ERR_FILE_OPEN, "Cannot open time series \"%s\" for writing: %s", path, strerror(st[0]));
  }
  PetscCall(PetscFree(header));
  *ts = w;
  PetscFunctionReturn(0);
}

/* Rank 0: one row, formatted and written with one fwrite to the unbuffered stream; st: errno, and whether the torn row
   could not be cut off */
static PetscErrorCode FSTimeSeriesWriteRow(FSTimeSeries ts, PetscInt step, const PetscReal values[], int st[2])
{
  size_t off;
  int    n;

  PetscFunctionBegin;
  PetscCheck(values || ts->ncols == 0, PETSC_COMM_SELF, PETSC_ERR_ARG_NULL, "Time series \"%s\": no values", ts->path);
  n = snprintf(ts->row, ts->rowlen, "%" PetscInt_FMT, step);
  PetscCheck(n > 0 && (size_t)n < ts->rowlen, PETSC_COMM_SELF, PETSC_ERR_PLIB, "Time series row buffer too small");
  off = (size_t)n;
  for (PetscInt c = 0; c < ts->ncols; c++) {
    n = snprintf(ts->row + off, ts->rowlen - off, ",%.10e", (double)values[c]);
    PetscCheck(n > 0 && (size_t)n < ts->rowlen - off, PETSC_COMM_SELF, PETSC_ERR_PLIB,
               "Time series row buffer too small");
    off += (size_t)n;
  }
  PetscCheck(off + 1 < ts->rowlen, PETSC_COMM_SELF, PETSC_ERR_PLIB, "Time series row buffer too small");
  ts->row[off]     = '\n';
  ts->row[off + 1] = '\0';
  errno            = 0;
  if (fwrite(ts->row, 1, off + 1, ts->fp) != off + 1 || fflush(ts->fp) != 0) {
    st[0] = errno ? errno : EIO;
    clearerr(ts->fp);
    st[1] = ftruncate(fileno(ts->fp), ts->size) != 0; /* no torn row: the file ends at its last whole row */
  } else ts->size += (off_t)(off + 1);
  PetscFunctionReturn(0);
}

/*@C
   FSTimeSeriesAppend - Appends one row: step, then the values with "%.10e".

   Collective (rank 0 writes; the outcome is broadcast, so a failure is raised on every rank), or not collective
   once FSTimeSeriesSetDeferred() deferred the outcome

   Input Parameters:
+  ts     - the time series
.  step   - step number written in the first column
-  values - ncols values (read on rank 0 only)

   Notes:
   The row is written with one fwrite to the unbuffered stream; when it cannot be written whole (a full
   disk), the file is cut back to its last whole row and the error names the file. Deferred, the failure is
   kept on rank 0 (FSTimeSeriesGetFailure()) and no row is written after it, so the file ends at its last whole row.
@*/
PetscErrorCode FSTimeSeriesAppend(FSTimeSeries ts, PetscInt step, const PetscReal values[])
{
  int st[2] = {0, 0}; /* errno, the torn row could not be cut off */

  PetscFunctionBegin;
  PetscCheck(ts, PETSC_COMM_SELF, PETSC_ERR_ARG_NULL, "Null FSTimeSeries");
  if (step == ts->kept) { /* a restart's first row: the file has it from the run that wrote the checkpoint */
    ts->kept = -1;
    PetscFunctionReturn(0);
  }
  if (ts->deferred) { /* rank 0 keeps the outcome; after a failure the file stays as it is */
    if (ts->rank == 0 && !ts->failed[0]) PetscCall(FSTimeSeriesWriteRow(ts, step, values, ts->failed));
    PetscFunctionReturn(0);
  }
  if (ts->rank == 0) PetscCall(FSTimeSeriesWriteRow(ts, step, values, st));
  PetscCallMPI(MPI_Bcast(st, 2, MPI_INT, 0, ts->comm));
  PetscCall(FSTimeSeriesRaiseFailure(ts, st[0], (PetscBool)(st[1] != 0)));
  PetscFunctionReturn(0);
}

/*@C
   FSTimeSeriesSetDeferred - whether FSTimeSeriesAppend() broadcasts the outcome of rank 0's write (the default) or
   keeps it on rank 0 for the caller to carry on a collective it takes anyway (FSTimeSeriesGetFailure()) and raise on
   every rank (FSTimeSeriesRaiseFailure()): a row then costs no collective.

   Not Collective (the same on every rank)

   Input Parameters:
+  ts       - the time series
-  deferred - PETSC_TRUE to defer
@*/
PetscErrorCode FSTimeSeriesSetDeferred(FSTimeSeries ts, PetscBool deferred)
{
  PetscFunctionBegin;
  ts->deferred = deferred;
  PetscFunctionReturn(0);
}

/*@C
   FSTimeSeriesGetFailure - rank 0's first failed write of a deferred time series (FSTimeSeriesSetDeferred()).

   Not Collective

   Input Parameter:
.  ts - the time series

   Output Parameters:
+  err  - its errno, 0 when every row was written (always 0 on the other ranks)
-  torn - whether the torn row could not be cut off (may be NULL)
@*/
PetscErrorCode FSTimeSeriesGetFailure(FSTimeSeries ts, int *err, PetscBool *torn)
{
  PetscFunctionBegin;
  *err = ts->failed[0];
  if (torn) *torn = (PetscBool)(ts->failed[1] != 0);
  PetscFunctionReturn(0);
}

/*@C
   FSTimeSeriesRaiseFailure - raises the error of a failed write (errno err, as rank 0's FSTimeSeriesGetFailure() gave
   it, carried to every rank) naming the file; nothing when err is 0.

   Not Collective (called on every rank with the same err, it raises the error on every rank)
@*/
PetscErrorCode FSTimeSeriesRaiseFailure(FSTimeSeries ts, int err, PetscBool torn)
{
  PetscFunctionBegin;
  if (err) ts->raised = PETSC_TRUE;
  PetscCheck(!err, ts->comm, PETSC_ERR_FILE_WRITE, "Cannot write to time series \"%s\": %s%s", ts->path, strerror(err),
             torn ? " (and its last row could not be cut off)" : "");
  PetscFunctionReturn(0);
}

/*@C
   FSTimeSeriesDestroy - Closes the time series.

   Not Collective

   Input Parameter:
.  ts - the time series (set to NULL)

   Notes:
   A deferred failure (FSTimeSeriesSetDeferred()) that was never raised is printed to stderr by rank 0.
@*/
PetscErrorCode FSTimeSeriesDestroy(FSTimeSeries *ts)
{
  int err = 0;

  PetscFunctionBegin;
  if (!ts || !*ts) PetscFunctionReturn(0);
  if ((*ts)->failed[0] &&
      !(*ts)->raised) /* deferred, and the run ended before it was carried to the ranks: said here */
    PetscCall(PetscFPrintf(PETSC_COMM_SELF, PETSC_STDERR, "Error: cannot write to time series \"%s\": %s%s\n",
                           (*ts)->path, strerror((*ts)->failed[0]),
                           (*ts)->failed[1] ? " (and its last row could not be cut off)" : ""));
  if ((*ts)->fp && fclose((*ts)->fp) != 0) err = errno ? errno : EIO;
  (*ts)->fp = NULL;
  PetscCheck(!err, PETSC_COMM_SELF, PETSC_ERR_FILE_WRITE, "Cannot close time series \"%s\": %s", (*ts)->path,
             strerror(err));
  PetscCall(PetscFree((*ts)->row));
  PetscCall(PetscFree(*ts));
  PetscFunctionReturn(0);
}
