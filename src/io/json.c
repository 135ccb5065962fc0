/*
   FSJSON: the JSON run summaries, built with json-c (Debian libjson-c-dev). Rank 0 keeps the
   document, one top-level object, in memory (members in call order; a repeated key replaces the
   earlier value); the other ranks do nothing. FSJSONDestroy prints it (json-c's pretty format, two
   spaces per level) to "<path>.tmp", opened by FSJSONCreate so that an unwritable directory fails
   early, and renames that into place. Non-finite reals become null, as JSON has no NaN or Infinity;
   bytes of keys and strings that are not UTF-8 become U+FFFD, as a JSON text is UTF-8.
*/
#include <stdio.h>
#include <string.h>
#include <errno.h>
#include <json-c/json.h>
#include "fsoutput.h"

#define FS_JSON_MAX_DEPTH 32
#define FS_JSON_FORMAT    (JSON_C_TO_STRING_PRETTY | JSON_C_TO_STRING_SPACED | JSON_C_TO_STRING_NOSLASHESCAPE)

struct _n_FSJSON {
  MPI_Comm            comm;
  PetscMPIInt         rank;
  FILE               *fp;                       /* rank 0 only: "<path>.tmp", open from create to destroy */
  char                path[PETSC_MAX_PATH_LEN]; /* final name */
  char                tmp[PETSC_MAX_PATH_LEN];  /* "<path>.tmp" */
  FSFileId            id;                       /* rank 0: the file created under tmp */
  PetscInt            depth;                    /* number of open objects (1 = only the root) */
  struct json_object *open[FS_JSON_MAX_DEPTH];  /* rank 0 only: open[0] is the document, open[depth-1] the innermost */
};

/* the length of the valid UTF-8 sequence at s (1 to 4 bytes), 0 if it is not one (RFC 3629: no overlong
   forms, no surrogates, nothing past U+10FFFF) */
static size_t UTF8Length(const unsigned char *s)
{
  const unsigned char c = s[0];
  size_t              n;
  unsigned char       lo = 0x80, hi = 0xBF;
  if (c < 0x80) return 1;
  if (c >= 0xC2 && c <= 0xDF) n = 2;
  else if (c >= 0xE0 && c <= 0xEF) n = 3;
  else if (c >= 0xF0 && c <= 0xF4) n = 4;
  else return 0;
  if (c == 0xE0) lo = 0xA0;
  if (c == 0xED) hi = 0x9F;
  if (c == 0xF0) lo = 0x90;
  if (c == 0xF4) hi = 0x8F;
  if (s[1] < lo || s[1] > hi) return 0;
  for (size_t k = 2; k < n; k++)
    if (s[k] < 0x80 || s[k] > 0xBF) return 0;
  return n;
}

/* s with every byte that is not part of valid UTF-8 replaced by U+FFFD, in *out (to free), or *out = NULL
   when s is valid as it is: a JSON text is UTF-8, and an option's name or value (an options file with
   stray bytes) need not be */
static PetscErrorCode FSJSONValidText(const char s[], char **out)
{
  const unsigned char *u   = (const unsigned char *)s;
  size_t               bad = 0, at = 0;

  PetscFunctionBegin;
  *out = NULL;
  if (!s) PetscFunctionReturn(0);
  for (size_t k = 0, m; u[k]; k += m ? m : 1)
    if (!(m = UTF8Length(u + k))) bad++;
  if (!bad) PetscFunctionReturn(0);
  PetscCall(PetscMalloc1(strlen(s) + 2 * bad + 1, out));
  for (size_t k = 0, m; u[k]; k += m ? m : 1) {
    if ((m = UTF8Length(u + k))) memcpy(*out + at, s + k, m);
    else memcpy(*out + at, "\xEF\xBF\xBD", 3);
    at += m ? m : 3;
  }
  (*out)[at] = 0;
  PetscFunctionReturn(0);
}

/* adds value as member key of the innermost open object; takes value over even on error. value NULL
   is json-c's failure to allocate it, unless isnull says the member is null on purpose. */
static PetscErrorCode FSJSONAdd(FSJSON js, const char key[], struct json_object *value, PetscBool isnull)
{
  char *valid;

  PetscFunctionBegin;
  PetscCall(FSJSONValidText(key, &valid));
  if (valid) {
    PetscErrorCode ierr = FSJSONAdd(js, valid, value, isnull);
    PetscCall(PetscFree(valid));
    PetscCall(ierr);
    PetscFunctionReturn(0);
  }
  PetscCheck(value || isnull, PETSC_COMM_SELF, PETSC_ERR_MEM, "JSON \"%s\": out of memory for \"%s\"", js->path,
             key ? key : "");
  if (!key || !key[0]) json_object_put(value);
  PetscCheck(key && key[0], PETSC_COMM_SELF, PETSC_ERR_ARG_NULL,
             "JSON \"%s\": every member of an object needs a non-empty key", js->path);
  if (json_object_object_add(js->open[js->depth - 1], key, value) != 0) {
    json_object_put(value);
    SETERRQ(PETSC_COMM_SELF, PETSC_ERR_MEM, "JSON \"%s\": cannot add member \"%s\"", js->path, key);
  }
  PetscFunctionReturn(0);
}

/* a real as json-c's double (printed with 17 significant digits), or NULL (null) when not finite */
static struct json_object *FSJSONNewReal(PetscReal v)
{
  return PetscIsInfOrNanReal(v) ? NULL : json_object_new_double((double)v);
}

/*@C
   FSJSONCreate - Starts a JSON document (one top-level object) that rank 0 writes to path.

   Collective

   Input Parameters:
+  comm - communicator; only rank 0 builds and writes the document, the other ranks' calls are no-ops
-  path - final file name; the document appears there when FSJSONDestroy() renames "<path>.tmp"

   Output Parameter:
.  js - the writer

   Notes:
   "<path>.tmp" is opened here, so a failure to open it is raised at once, on every rank.
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
    err = FSFileCreate_Private(w->tmp, &w->fp, &w->id); /* not through a link under the name */
    if (!err && !(w->open[0] = json_object_new_object())) err = ENOMEM;
  }
  PetscCallMPI(MPI_Bcast(&err, 1, MPI_INT, 0, comm));
  if (err) {
    if (w->fp) {
      (void)fclose(w->fp);
      (void)remove(w->tmp);
    }
    PetscCall(PetscFree(w));
    SETERRQ(comm, PETSC_ERR_FILE_OPEN, "Cannot open JSON file \"%s.tmp\" for writing: %s", path, strerror(err));
  }
  w->depth = 1;
  *js      = w;
  PetscFunctionReturn(0);
}

/*@C
   FSJSONBeginObject - Opens a nested object as member key of the current object.

   Not Collective (rank 0 builds, other ranks return at once)

   Input Parameters:
+  js  - the writer
-  key - member name (non-empty)

   Notes:
   Close it with FSJSONEndObject(); at most 31 levels of nesting.
@*/
PetscErrorCode FSJSONBeginObject(FSJSON js, const char key[])
{
  struct json_object *obj;

  PetscFunctionBegin;
  PetscCheck(js, PETSC_COMM_SELF, PETSC_ERR_ARG_NULL, "Null FSJSON");
  if (js->rank != 0) PetscFunctionReturn(0);
  PetscCheck(js->depth < FS_JSON_MAX_DEPTH, PETSC_COMM_SELF, PETSC_ERR_ARG_OUTOFRANGE,
             "JSON \"%s\": objects nested deeper than %d", js->path, FS_JSON_MAX_DEPTH - 1);
  obj = json_object_new_object();
  PetscCall(FSJSONAdd(js, key, obj, PETSC_FALSE)); /* the parent owns obj now; it stays valid while the parent lives */
  js->open[js->depth++] = obj;
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
  PetscCheck(js->depth > 1, PETSC_COMM_SELF, PETSC_ERR_ARG_WRONGSTATE,
             "JSON \"%s\": FSJSONEndObject() without a matching FSJSONBeginObject()", js->path);
  js->open[--js->depth] = NULL;
  PetscFunctionReturn(0);
}

/*@C
   FSJSONWriteString - Writes member key with a string value (json-c escapes it).

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
  {
    char *valid;
    PetscCall(FSJSONValidText(value, &valid));
    PetscCall(FSJSONAdd(js, key, value ? json_object_new_string(valid ? valid : value) : NULL, (PetscBool)!value));
    PetscCall(PetscFree(valid));
  }
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
  PetscCall(FSJSONAdd(js, key, json_object_new_int64((int64_t)value), PETSC_FALSE));
  PetscFunctionReturn(0);
}

/*@C
   FSJSONWriteReal - Writes member key with a real value (17 significant digits, so it reads back
   exactly, with a decimal point or an exponent); NaN and infinities are written as null.

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
  PetscCall(FSJSONAdd(js, key, FSJSONNewReal(value), PetscIsInfOrNanReal(value)));
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
  struct json_object *arr;

  PetscFunctionBegin;
  PetscCheck(js, PETSC_COMM_SELF, PETSC_ERR_ARG_NULL, "Null FSJSON");
  if (js->rank != 0) PetscFunctionReturn(0);
  PetscCheck(n >= 0, PETSC_COMM_SELF, PETSC_ERR_ARG_OUTOFRANGE,
             "JSON \"%s\": negative array length %" PetscInt_FMT " for \"%s\"", js->path, n, key ? key : "");
  PetscCheck(values || n == 0, PETSC_COMM_SELF, PETSC_ERR_ARG_NULL, "JSON \"%s\": no values for \"%s\"", js->path,
             key ? key : "");
  arr = json_object_new_array_ext((int)n);
  PetscCheck(arr, PETSC_COMM_SELF, PETSC_ERR_MEM, "JSON \"%s\": out of memory for \"%s\"", js->path, key ? key : "");
  for (PetscInt i = 0; i < n; i++) {
    struct json_object *v = FSJSONNewReal(values[i]);

    if ((!v && !PetscIsInfOrNanReal(values[i])) || json_object_array_add(arr, v) != 0) {
      json_object_put(v);
      json_object_put(arr);
      SETERRQ(PETSC_COMM_SELF, PETSC_ERR_MEM, "JSON \"%s\": out of memory for \"%s\"", js->path, key ? key : "");
    }
  }
  PetscCall(FSJSONAdd(js, key, arr, PETSC_FALSE));
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
  PetscCall(FSJSONAdd(js, key, json_object_new_boolean(value ? 1 : 0), PETSC_FALSE));
  PetscFunctionReturn(0);
}

/*@C
   FSJSONDestroy - Closes all open objects, prints the document to "<path>.tmp" and renames it to path.

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
    const char *text = json_object_to_json_string_ext(w->open[0], FS_JSON_FORMAT); /* owned by the document */

    if (!text) err = ENOMEM;
    else if (fputs(text, w->fp) == EOF || fputc('\n', w->fp) == EOF || ferror(w->fp)) err = errno ? errno : EIO;
    if (fclose(w->fp) != 0 && !err) err = errno ? errno : EIO;
    w->fp = NULL;
    if (!err) err = FSFileReplace_Private(w->tmp, w->path, &w->id);
    (void)json_object_put(w->open[0]); /* frees the whole document */
  }
  PetscCallMPI(MPI_Bcast(&err, 1, MPI_INT, 0, w->comm));
  PetscCheck(!err, w->comm, PETSC_ERR_FILE_WRITE, "Cannot finish JSON file \"%s\" (written as \"%s\"): %s", w->path,
             w->tmp, strerror(err));
  PetscCall(PetscFree(*js));
  PetscFunctionReturn(0);
}
