/*
   FSJSON: a small streaming JSON writer for run summaries. Rank 0 writes "<path>.tmp"; the other
   ranks do nothing. The document is one top-level object; members are written in call order with
   commas and nesting tracked here, strings are escaped and non-finite reals become null.
   FSJSONDestroy closes every open object and renames the file into place.
*/
#include <stdio.h>
#include <string.h>
#include <errno.h>
#include "fsoutput.h"

#define FS_JSON_MAX_DEPTH 32

struct _n_FSJSON {
  MPI_Comm    comm;
  PetscMPIInt rank;
  FILE       *fp;                       /* rank 0 only */
  char        path[PETSC_MAX_PATH_LEN]; /* final name */
  char        tmp[PETSC_MAX_PATH_LEN];  /* "<path>.tmp" */
  PetscInt    depth;                    /* number of open objects (1 = only the root) */
  PetscBool   first[FS_JSON_MAX_DEPTH]; /* no member written yet at this level */
};

static PetscErrorCode FSJSONCheckIO(FSJSON js, int status)
{
  PetscFunctionBegin;
  PetscCheck(status >= 0 && !ferror(js->fp), PETSC_COMM_SELF, PETSC_ERR_FILE_WRITE, "Error writing JSON file \"%s\": %s", js->tmp, strerror(errno));
  PetscFunctionReturn(0);
}

static PetscErrorCode FSJSONIndent(FSJSON js)
{
  PetscFunctionBegin;
  for (PetscInt i = 0; i < js->depth; i++) PetscCall(FSJSONCheckIO(js, fputs("  ", js->fp)));
  PetscFunctionReturn(0);
}

static PetscErrorCode FSJSONPutString(FSJSON js, const char s[])
{
  const unsigned char *c;

  PetscFunctionBegin;
  PetscCall(FSJSONCheckIO(js, fputc('"', js->fp)));
  for (c = (const unsigned char *)s; *c; c++) {
    int st;

    switch (*c) {
    case '"':
      st = fputs("\\\"", js->fp);
      break;
    case '\\':
      st = fputs("\\\\", js->fp);
      break;
    case '\n':
      st = fputs("\\n", js->fp);
      break;
    case '\r':
      st = fputs("\\r", js->fp);
      break;
    case '\t':
      st = fputs("\\t", js->fp);
      break;
    case '\b':
      st = fputs("\\b", js->fp);
      break;
    case '\f':
      st = fputs("\\f", js->fp);
      break;
    default:
      if (*c < 0x20) st = fprintf(js->fp, "\\u%04x", (unsigned)*c);
      else st = fputc(*c, js->fp); /* bytes >= 0x80 pass through: UTF-8 is assumed */
    }
    PetscCall(FSJSONCheckIO(js, st));
  }
  PetscCall(FSJSONCheckIO(js, fputc('"', js->fp)));
  PetscFunctionReturn(0);
}

/* separator, indentation and "key": for the next member of the innermost open object */
static PetscErrorCode FSJSONBeginMember(FSJSON js, const char key[])
{
  PetscFunctionBegin;
  PetscCheck(key && key[0], PETSC_COMM_SELF, PETSC_ERR_ARG_NULL, "JSON \"%s\": every member of an object needs a non-empty key", js->path);
  PetscCall(FSJSONCheckIO(js, fputs(js->first[js->depth - 1] ? "\n" : ",\n", js->fp)));
  js->first[js->depth - 1] = PETSC_FALSE;
  PetscCall(FSJSONIndent(js));
  PetscCall(FSJSONPutString(js, key));
  PetscCall(FSJSONCheckIO(js, fputs(": ", js->fp)));
  PetscFunctionReturn(0);
}

static PetscErrorCode FSJSONPutReal(FSJSON js, PetscReal v)
{
  PetscFunctionBegin;
  if (PetscIsInfOrNanReal(v)) PetscCall(FSJSONCheckIO(js, fputs("null", js->fp)));
  else PetscCall(FSJSONCheckIO(js, fprintf(js->fp, "%.17g", (double)v)));
  PetscFunctionReturn(0);
}

/*@C
   FSJSONCreate - Starts a JSON document (one top-level object) written by rank 0 to "<path>.tmp".

   Collective

   Input Parameters:
+  comm - communicator; only rank 0 writes, the other ranks' calls are no-ops
-  path - final file name; the document appears there when FSJSONDestroy() renames it

   Output Parameter:
.  js - the writer

   Notes:
   A failure to open the file is raised on every rank.
@*/
PetscErrorCode FSJSONCreate(MPI_Comm comm, const char path[], FSJSON *js)
{
  FSJSON w;
  int    err = 0;

  PetscFunctionBegin;
  PetscCheck(path && js, comm, PETSC_ERR_ARG_NULL, "FSJSONCreate: path and output handle are required");
  PetscCall(PetscNew(&w));
  w->comm = comm;
  PetscCallMPI(MPI_Comm_rank(comm, &w->rank));
  PetscCheck(strlen(path) + 5 < sizeof(w->tmp), comm, PETSC_ERR_ARG_SIZ, "JSON path too long: \"%s\"", path);
  PetscCall(PetscStrcpy(w->path, path));
  PetscCall(PetscSNPrintf(w->tmp, sizeof(w->tmp), "%s.tmp", path));
  if (w->rank == 0) {
    w->fp = fopen(w->tmp, "w");
    if (!w->fp) err = errno ? errno : EIO;
    else if (fputc('{', w->fp) == EOF) err = errno ? errno : EIO;
  }
  PetscCallMPI(MPI_Bcast(&err, 1, MPI_INT, 0, comm));
  if (err) {
    if (w->fp) (void)fclose(w->fp);
    PetscCall(PetscFree(w));
    SETERRQ(comm, PETSC_ERR_FILE_OPEN, "Cannot open JSON file \"%s.tmp\" for writing: %s", path, strerror(err));
  }
  w->depth    = 1;
  w->first[0] = PETSC_TRUE;
  *js         = w;
  PetscFunctionReturn(0);
}

/*@C
   FSJSONBeginObject - Opens a nested object as member key of the current object.

   Not Collective (rank 0 writes, other ranks return at once)

   Input Parameters:
+  js  - the writer
-  key - member name (non-empty)

   Notes:
   Close it with FSJSONEndObject(); at most 31 levels of nesting.
@*/
PetscErrorCode FSJSONBeginObject(FSJSON js, const char key[])
{
  PetscFunctionBegin;
  PetscCheck(js, PETSC_COMM_SELF, PETSC_ERR_ARG_NULL, "Null FSJSON");
  if (js->rank != 0) PetscFunctionReturn(0);
  PetscCheck(js->depth < FS_JSON_MAX_DEPTH, PETSC_COMM_SELF, PETSC_ERR_ARG_OUTOFRANGE, "JSON \"%s\": objects nested deeper than %d", js->path, FS_JSON_MAX_DEPTH - 1);
  PetscCall(FSJSONBeginMember(js, key));
  PetscCall(FSJSONCheckIO(js, fputc('{', js->fp)));
  js->first[js->depth] = PETSC_TRUE;
  js->depth++;
  PetscFunctionReturn(0);
}

/*@C
   FSJSONEndObject - Closes the innermost object opened with FSJSONBeginObject().

   Not Collective

   Input Parameter:
.  js - the writer

   Notes:
   The top-level object is closed by FSJSONDestroy(); closing it here is an error.
@*/
PetscErrorCode FSJSONEndObject(FSJSON js)
{
  PetscFunctionBegin;
  PetscCheck(js, PETSC_COMM_SELF, PETSC_ERR_ARG_NULL, "Null FSJSON");
  if (js->rank != 0) PetscFunctionReturn(0);
  PetscCheck(js->depth > 1, PETSC_COMM_SELF, PETSC_ERR_ARG_WRONGSTATE, "JSON \"%s\": FSJSONEndObject() without a matching FSJSONBeginObject()", js->path);
  js->depth--;
  if (!js->first[js->depth]) {
    PetscCall(FSJSONCheckIO(js, fputc('\n', js->fp)));
    PetscCall(FSJSONIndent(js));
  }
  PetscCall(FSJSONCheckIO(js, fputc('}', js->fp)));
  PetscFunctionReturn(0);
}

/*@C
   FSJSONWriteString - Writes member key with a string value (escaped as JSON requires).

   Not Collective

   Input Parameters:
+  js    - the writer
.  key   - member name
-  value - the string; NULL writes null
@*/
PetscErrorCode FSJSONWriteString(FSJSON js, const char key[], const char value[])
{
  PetscFunctionBegin;
  PetscCheck(js, PETSC_COMM_SELF, PETSC_ERR_ARG_NULL, "Null FSJSON");
  if (js->rank != 0) PetscFunctionReturn(0);
  PetscCall(FSJSONBeginMember(js, key));
  if (value) PetscCall(FSJSONPutString(js, value));
  else PetscCall(FSJSONCheckIO(js, fputs("null", js->fp)));
  PetscFunctionReturn(0);
}

/*@C
   FSJSONWriteInt - Writes member key with an integer value.

   Not Collective

   Input Parameters:
+  js    - the writer
.  key   - member name
-  value - the value
@*/
PetscErrorCode FSJSONWriteInt(FSJSON js, const char key[], PetscInt64 value)
{
  PetscFunctionBegin;
  PetscCheck(js, PETSC_COMM_SELF, PETSC_ERR_ARG_NULL, "Null FSJSON");
  if (js->rank != 0) PetscFunctionReturn(0);
  PetscCall(FSJSONBeginMember(js, key));
  PetscCall(FSJSONCheckIO(js, fprintf(js->fp, "%" PetscInt64_FMT, value)));
  PetscFunctionReturn(0);
}

/*@C
   FSJSONWriteReal - Writes member key with a real value (17 significant digits, so it reads back
   exactly); NaN and infinities are written as null.

   Not Collective

   Input Parameters:
+  js    - the writer
.  key   - member name
-  value - the value
@*/
PetscErrorCode FSJSONWriteReal(FSJSON js, const char key[], PetscReal value)
{
  PetscFunctionBegin;
  PetscCheck(js, PETSC_COMM_SELF, PETSC_ERR_ARG_NULL, "Null FSJSON");
  if (js->rank != 0) PetscFunctionReturn(0);
  PetscCall(FSJSONBeginMember(js, key));
  PetscCall(FSJSONPutReal(js, value));
  PetscFunctionReturn(0);
}

/*@C
   FSJSONWriteRealArray - Writes member key with an array of reals (non-finite entries as null).

   Not Collective

   Input Parameters:
+  js     - the writer
.  key    - member name
.  n      - number of values (0 writes [])
-  values - the values
@*/
PetscErrorCode FSJSONWriteRealArray(FSJSON js, const char key[], PetscInt n, const PetscReal values[])
{
  PetscFunctionBegin;
  PetscCheck(js, PETSC_COMM_SELF, PETSC_ERR_ARG_NULL, "Null FSJSON");
  if (js->rank != 0) PetscFunctionReturn(0);
  PetscCheck(n >= 0, PETSC_COMM_SELF, PETSC_ERR_ARG_OUTOFRANGE, "JSON \"%s\": negative array length %" PetscInt_FMT " for \"%s\"", js->path, n, key ? key : "");
  PetscCheck(values || n == 0, PETSC_COMM_SELF, PETSC_ERR_ARG_NULL, "JSON \"%s\": no values for \"%s\"", js->path, key ? key : "");
  PetscCall(FSJSONBeginMember(js, key));
  PetscCall(FSJSONCheckIO(js, fputc('[', js->fp)));
  for (PetscInt i = 0; i < n; i++) {
    if (i) PetscCall(FSJSONCheckIO(js, fputs(", ", js->fp)));
    PetscCall(FSJSONPutReal(js, values[i]));
  }
  PetscCall(FSJSONCheckIO(js, fputc(']', js->fp)));
  PetscFunctionReturn(0);
}

/*@C
   FSJSONWriteBool - Writes member key with true or false.

   Not Collective

   Input Parameters:
+  js    - the writer
.  key   - member name
-  value - the value
@*/
PetscErrorCode FSJSONWriteBool(FSJSON js, const char key[], PetscBool value)
{
  PetscFunctionBegin;
  PetscCheck(js, PETSC_COMM_SELF, PETSC_ERR_ARG_NULL, "Null FSJSON");
  if (js->rank != 0) PetscFunctionReturn(0);
  PetscCall(FSJSONBeginMember(js, key));
  PetscCall(FSJSONCheckIO(js, fputs(value ? "true" : "false", js->fp)));
  PetscFunctionReturn(0);
}

/*@C
   FSJSONDestroy - Closes all open objects, closes the file and renames "<path>.tmp" to path.

   Collective

   Input Parameter:
.  js - the writer (set to NULL)

   Notes:
   A write or rename failure is raised on every rank.
@*/
PetscErrorCode FSJSONDestroy(FSJSON *js)
{
  FSJSON w;
  int    err = 0;

  PetscFunctionBegin;
  if (!js || !*js) PetscFunctionReturn(0);
  w = *js;
  if (w->rank == 0) {
    while (w->depth > 1) PetscCall(FSJSONEndObject(w));
    if (fputs(w->first[0] ? "}\n" : "\n}\n", w->fp) == EOF || ferror(w->fp)) err = errno ? errno : EIO;
    if (fclose(w->fp) != 0 && !err) err = errno ? errno : EIO;
    w->fp = NULL;
    if (!err && rename(w->tmp, w->path) != 0) err = errno ? errno : EIO;
  }
  PetscCallMPI(MPI_Bcast(&err, 1, MPI_INT, 0, w->comm));
  PetscCheck(!err, w->comm, PETSC_ERR_FILE_WRITE, "Cannot finish JSON file \"%s\" (written as \"%s\"): %s", w->path, w->tmp, strerror(err));
  PetscCall(PetscFree(*js));
  PetscFunctionReturn(0);
}
