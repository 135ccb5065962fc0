/*
   The record of what defines a run, written into its checkpoints, and the check that a restart
   (-fs_restart) continues the same run: every item of the checkpoint's record is compared with this
   run's, and every difference is listed in one error unless -fs_restart_allow_changes names it.

   The record is text, one "name=value" a line:
     - the values the run uses, however they were given (options file, command line, a case's default):
       version, -fs_dim, -fs_case, -fs_dx, -fs_h_over_dx, -fs_rho0, -fs_c0, -fs_nu, -fs_gravity,
       -fs_background_pressure, -fs_terms (the terms created), -fs_structure, structure_dofs, coupling,
       walls_geometry (FSBoundaryGetGeometryHash()), -ts_type and -ts_rk_type;
     - every other option of PETSc's database as given (the case's, the structure's, the terms' and the
       integrator's parameters), except those that never define the run (FSSetUpAllowedByDefault) and
       those a value above covers (the walls' files are compared through the walls' hash).
*/
#include <ctype.h>
#include <strings.h>
#include "solver/solverimpl.h"
#include "boundary/fsboundary.h"

/* options that never define the run: they may change on restart (a '*' matches any characters) */
static const char *const FSSetUpAllowedByDefault[] = {"fs_output",
                                                      "fs_output_dir",
                                                      "fs_output_name",
                                                      "fs_error_trace",
                                                      "fs_output_interval",
                                                      "fs_checkpoint_interval",
                                                      "fs_restart",
                                                      "fs_restart_allow_changes",
                                                      "fs_progress",
                                                      "fs_progress_interval",
                                                      "fs_probes",
                                                      "fs_probe_interval",
                                                      "fs_series_interval",
                                                      "fs_geometry_view",
                                                      "fs_max_density_variation",
                                                      "fs_options_left",
                                                      "fs_options_check",
                                                      "*_view",
                                                      "*_view_*",
                                                      "ts_max_time",
                                                      "ts_max_steps",
                                                      "ts_exact_final_time",
                                                      "ts_monitor*",
                                                      "ts_adapt_monitor",
                                                      "log_*",
                                                      "options_*",
                                                      "help",
                                                      "info*",
                                                      "malloc*",
                                                      "memory_*",
                                                      "on_error_*",
                                                      "error_output_*",
                                                      "no_signal_handler",
                                                      "history",
                                                      "dll_append*",
                                                      "viewer_*",
                                                      "fp_trap",
                                                      "check_pointer_intensity",
                                                      "objects_dump"};

/* options whose effect a derived item of the record compares */
static const char *const FSSetUpCovered[] = {
    "fs_dim",       "fs_case", "fs_dx",      "fs_h_over_dx",           "fs_rho0",
    "fs_c0",        "fs_nu",   "fs_gravity", "fs_background_pressure", "fs_terms",
    "fs_structure", "ts_type", "ts_rk_type", "fs_tank_file",           "fs_tank_stl"};

/* options that may differ between the ranks of one run: each process's own diagnostics (PETSc's profiles and
   memory reports, -log_view, -memory_view, are collective: not these), and the files every rank reads, whose paths
   may be a node's own (where they are read, a file some rank cannot open is an error) */
static const char *const FSRankLocal[] = {"info*",       "history",      "malloc_debug",   "malloc_dump",
                                          "malloc_test", "on_error_*",   "error_output_*", "no_signal_handler",
                                          "fp_trap",     "objects_dump", "options_left",   "check_pointer_intensity",
                                          "dll_append",  "fs_tank_file", "fs_tank_stl",    "fs_motion_*_file"};

typedef struct {
  char  *text;
  size_t len, cap;
} FSText;

static PetscErrorCode FSTextAppend(FSText *t, const char a[], size_t n)
{
  PetscFunctionBegin;
  if (t->len + n + 1 > t->cap) {
    char *grown;
    t->cap = PetscMax(2 * t->cap, t->len + n + 256);
    PetscCall(PetscMalloc1(t->cap, &grown));
    if (t->len) PetscCall(PetscArraycpy(grown, t->text, t->len));
    PetscCall(PetscFree(t->text));
    t->text = grown;
  }
  if (n) PetscCall(PetscArraycpy(t->text + t->len, a, n));
  t->len += n;
  t->text[t->len] = 0;
  PetscFunctionReturn(0);
}

/* adds the line name=value */
static PetscErrorCode FSTextItem(FSText *t, const char name[], const char value[])
{
  PetscFunctionBegin;
  PetscCall(FSTextAppend(t, name, strlen(name)));
  PetscCall(FSTextAppend(t, "=", 1));
  PetscCall(FSTextAppend(t, value, strlen(value)));
  PetscCall(FSTextAppend(t, "\n", 1));
  PetscFunctionReturn(0);
}

/* the shortest decimal form of x that reads back as x */
static void FSFormatReal(PetscReal x, char buf[32])
{
  for (int p = 6; p <= 17; p++) {
    snprintf(buf, 32, "%.*g", p, (double)x);
    if (strtod(buf, NULL) == (double)x) return;
  }
}

static PetscErrorCode FSTextRealItem(FSText *t, const char name[], PetscInt n, const PetscReal x[])
{
  char value[256] = "", buf[32];

  PetscFunctionBegin;
  for (PetscInt k = 0; k < n; k++) {
    FSFormatReal(x[k], buf);
    if (k) PetscCall(PetscStrlcat(value, ",", sizeof(value)));
    PetscCall(PetscStrlcat(value, buf, sizeof(value)));
  }
  PetscCall(FSTextItem(t, name, value));
  PetscFunctionReturn(0);
}

/* whether name (without its leading '-') matches pattern, where a '*' matches any characters */
static PetscBool FSMatch(const char *pattern, const char *name)
{
  if (*pattern == '-') pattern++;
  if (*name == '-') name++;
  for (; *pattern; pattern++, name++) {
    if (*pattern == '*') {
      for (;; name++) {
        if (FSMatch(pattern + 1, name)) return PETSC_TRUE;
        if (!*name) return PETSC_FALSE;
      }
    }
    if (!*name || tolower((unsigned char)*pattern) != tolower((unsigned char)*name)) return PETSC_FALSE;
  }
  return (PetscBool) !*name;
}

static PetscBool FSMatchAny(const char *const list[], size_t n, const char name[])
{
  for (size_t k = 0; k < n; k++)
    if (FSMatch(list[k], name)) return PETSC_TRUE;
  return PETSC_FALSE;
}

/* whether the comma-separated list of -fs_restart_allow_changes ("all" is "*") lets name change */
static PetscBool FSAllowedByUser(const char allow[], const char name[])
{
  char item[256];

  while (*allow) {
    size_t n = strcspn(allow, ", ");
    if (n && n < sizeof(item)) {
      memcpy(item, allow, n);
      item[n] = 0;
      if (!strcmp(item, "all") || FSMatch(item, name)) return PETSC_TRUE;
    }
    allow += n;
    allow += strspn(allow, ", ");
  }
  return PETSC_FALSE;
}

static PetscErrorCode FSTextBcast(MPI_Comm, FSText *);

/* whether an option is left out of the record of what defines the run: it may change on restart, or an item of
   its own compares it */
static PetscBool FSSkipForRestart(const char name[])
{
  return (PetscBool)(FSMatchAny(FSSetUpAllowedByDefault, PETSC_STATIC_ARRAY_LENGTH(FSSetUpAllowedByDefault), name) ||
                     FSMatchAny(FSSetUpCovered, PETSC_STATIC_ARRAY_LENGTH(FSSetUpCovered), name));
}

/* whether an option is left out of the comparison between the ranks (FSRankLocal) */
static PetscBool FSSkipForRanks(const char name[])
{
  return FSMatchAny(FSRankLocal, PETSC_STATIC_ARRAY_LENGTH(FSRankLocal), name);
}

/* the options of the database as "-name=value" items of PetscOptionsGetAll(), but those skip() leaves out */
static PetscErrorCode FSRecordOptions(FSText *t, PetscBool (*skip)(const char[]))
{
  char  *all, *tok, *save = NULL, name[256] = "";
  FSText value = {NULL, 0, 0};

  PetscFunctionBegin;
  PetscCall(PetscOptionsGetAll(NULL, &all));
  for (tok = strtok_r(all, " ", &save);; tok = strtok_r(NULL, " ", &save)) {
    PetscBool isname = (PetscBool)(tok && tok[0] == '-' && (isalpha((unsigned char)tok[1]) || tok[1] == '_'));
    if ((isname || !tok) && name[0]) { /* the item before is complete */
      if (!skip(name)) PetscCall(FSTextItem(t, name, value.text ? value.text : ""));
      name[0]   = 0;
      value.len = 0;
      if (value.text) value.text[0] = 0;
    }
    if (!tok) break;
    if (isname) PetscCall(PetscStrncpy(name, tok, sizeof(name)));
    else if (name[0]) { /* a value, or one more word of it */
      if (value.len) PetscCall(FSTextAppend(&value, " ", 1));
      PetscCall(FSTextAppend(&value, tok, strlen(tok)));
    }
  }
  PetscCall(PetscFree(value.text));
  PetscCall(PetscFree(all));
  PetscFunctionReturn(0);
}

/*
   FSSolverSetUpRecord - builds the record of what defines the run (the file comment) into s->mon.setup,
   for the checkpoints and the check of a restart. Called by FSSolverSetUp() once the walls, the
   structure and the TS are set up, before a checkpoint is loaded.

   Collective (the record is rank 0's, broadcast)
*/
PetscErrorCode FSSolverSetUpRecord(FSSolver s)
{
  MPI_Comm comm = PetscObjectComm((PetscObject)s);
  FSText   t    = {NULL, 0, 0};
  char     buf[1024];

  PetscFunctionBegin;
  PetscCall(PetscFree(s->mon.setup));
  PetscCall(FSTextItem(&t, "version", FLEXSLOSH_VERSION));
  PetscCall(PetscSNPrintf(buf, sizeof(buf), "%" PetscInt_FMT, s->opt.dim));
  PetscCall(FSTextItem(&t, "-fs_dim", buf));
  PetscCall(FSTextItem(&t, "-fs_case", s->opt.casename));
  PetscCall(FSTextRealItem(&t, "-fs_dx", 1, &s->opt.dx));
  PetscCall(FSTextRealItem(&t, "-fs_h_over_dx", 1, &s->opt.h_over_dx));
  PetscCall(FSTextRealItem(&t, "-fs_rho0", 1, &s->opt.rho0));
  PetscCall(FSTextRealItem(&t, "-fs_c0", 1, &s->opt.c0));
  PetscCall(FSTextRealItem(&t, "-fs_nu", 1, &s->opt.nu));
  PetscCall(FSTextRealItem(&t, "-fs_gravity", s->opt.dim, s->opt.gravity));
  PetscCall(FSTextRealItem(&t, "-fs_background_pressure", 1, &s->opt.background_pressure));
  buf[0] = 0;
  for (PetscInt k = 0; k < s->terms.nterms; k++) {
    if (k) PetscCall(PetscStrlcat(buf, ",", sizeof(buf)));
    PetscCall(PetscStrlcat(buf, s->terms.term[k]->name, sizeof(buf)));
  }
  PetscCall(FSTextItem(&t, "-fs_terms", buf));
  PetscCall(FSTextItem(&t, "-fs_structure", s->structure ? s->structure->name : "none"));
  PetscCall(PetscSNPrintf(buf, sizeof(buf), "%" PetscInt_FMT, s->structure ? s->structure->ndof : 0));
  PetscCall(FSTextItem(&t, "structure_dofs", buf));
  PetscCall(FSTextItem(&t, "coupling", s->structure && s->boundary && s->pw.nglobal_particles ? "yes" : "no"));
  if (s->boundary) PetscCall(FSBoundaryGetGeometryHash(s->boundary, buf, sizeof(buf)));
  else PetscCall(PetscStrncpy(buf, "none", sizeof(buf)));
  PetscCall(FSTextItem(&t, "walls_geometry", buf));
  if (s->ts) {
    TSType    type;
    PetscBool isrk;
    PetscCall(TSGetType(s->ts, &type));
    PetscCall(FSTextItem(&t, "-ts_type", type ? type : ""));
    PetscCall(PetscStrcmp(type, TSRK, &isrk));
    if (isrk) {
      TSRKType rk;
      PetscCall(TSRKGetType(s->ts, &rk));
      PetscCall(FSTextItem(&t, "-ts_rk_type", rk ? rk : ""));
    }
  }
  PetscCall(FSRecordOptions(&t, FSSkipForRestart));
  PetscCall(FSTextBcast(comm, &t)); /* rank 0's record */
  s->mon.setup = t.text;
  PetscFunctionReturn(0);
}

/* the value of name in a record (NULL: absent), with its length */
static const char *FSRecordFind(const char record[], const char name[], size_t *len)
{
  size_t n = strlen(name);

  for (const char *l = record; l && *l; l = strchr(l, '\n') ? strchr(l, '\n') + 1 : NULL) {
    if (!strncmp(l, name, n) && l[n] == '=') {
      *len = strcspn(l + n + 1, "\n");
      return l + n + 1;
    }
  }
  return NULL;
}

/* whether two values are the same: as text, as numbers, or as truth values */
static PetscBool FSValuesEqual(const char *a, size_t na, const char *b, size_t nb)
{
  static const char *const truth[] = {"", "1", "true", "yes", "on", "0", "false", "no", "off"};
  char                     x[256], y[256], *ex, *ey;
  int                      tx = -1, ty = -1;

  if (na == nb && !strncmp(a, b, na)) return PETSC_TRUE;
  if (na >= sizeof(x) || nb >= sizeof(y)) return PETSC_FALSE;
  memcpy(x, a, na);
  x[na] = 0;
  memcpy(y, b, nb);
  y[nb] = 0;
  if (na && nb) {
    double u = strtod(x, &ex), v = strtod(y, &ey);
    if (!*ex && !*ey) return (PetscBool)(u == v);
  }
  for (int k = 0; k < 9; k++) {
    if (!strcasecmp(x, truth[k])) tx = k < 5;
    if (!strcasecmp(y, truth[k])) ty = k < 5;
  }
  return (PetscBool)(tx >= 0 && tx == ty);
}

/* one line "  name: checkpoint's value -> this run's value" of the differences */
static PetscErrorCode FSTextDifference(FSText *t, const char *name, size_t nn, const char *a, size_t na, const char *b,
                                       size_t nb)
{
  const size_t cut = 60;

  PetscFunctionBegin;
  PetscCall(FSTextAppend(t, "  ", 2));
  PetscCall(FSTextAppend(t, name, nn));
  PetscCall(FSTextAppend(t, ": ", 2));
  if (a) PetscCall(FSTextAppend(t, a, PetscMin(na, cut)));
  else PetscCall(FSTextAppend(t, "(not set)", 9));
  if (a && na > cut) PetscCall(FSTextAppend(t, "...", 3));
  PetscCall(FSTextAppend(t, " -> ", 4));
  if (b) PetscCall(FSTextAppend(t, b, PetscMin(nb, cut)));
  else PetscCall(FSTextAppend(t, "(not set)", 9));
  if (b && nb > cut) PetscCall(FSTextAppend(t, "...", 3));
  PetscCall(FSTextAppend(t, "\n", 1));
  PetscFunctionReturn(0);
}

/* the items of record a that b lacks or holds with another value, unless allowed; names into list */
static PetscErrorCode FSRecordCompare(const char a[], const char b[], PetscBool afirst, const char allow[],
                                      FSText *diff, FSText *list, PetscInt *ndiff)
{
  PetscFunctionBegin;
  for (const char *l = a; l && *l; l = strchr(l, '\n') ? strchr(l, '\n') + 1 : NULL) {
    size_t      nn = strcspn(l, "="), na, nb = 0;
    const char *va = l + nn + 1, *vb;
    char        name[256];

    if (l[nn] != '=' || nn >= sizeof(name)) continue;
    memcpy(name, l, nn);
    name[nn] = 0;
    na       = strcspn(va, "\n");
    if (FSMatchAny(FSSetUpAllowedByDefault, PETSC_STATIC_ARRAY_LENGTH(FSSetUpAllowedByDefault), name) ||
        FSAllowedByUser(allow, name))
      continue;
    vb = FSRecordFind(b, name, &nb);
    if (!afirst && vb) continue; /* the second pass lists the items only b's side lacks */
    if (vb && FSValuesEqual(va, na, vb, nb)) continue;
    if (diff->len < 1400) {
      if (afirst) PetscCall(FSTextDifference(diff, l, nn, va, na, vb, nb));
      else PetscCall(FSTextDifference(diff, l, nn, vb, nb, va, na));
    }
    if (*ndiff) PetscCall(FSTextAppend(list, ",", 1));
    PetscCall(FSTextAppend(list, name[0] == '-' ? name + 1 : name, strlen(name[0] == '-' ? name + 1 : name)));
    (*ndiff)++;
  }
  PetscFunctionReturn(0);
}

/* rank 0's text on every rank */
static PetscErrorCode FSTextBcast(MPI_Comm comm, FSText *t)
{
  PetscMPIInt rank;
  size_t      len = t->len;

  PetscFunctionBegin;
  PetscCallMPI(MPI_Comm_rank(comm, &rank));
  PetscCallMPI(MPI_Bcast(&len, sizeof(len), MPI_BYTE, 0, comm));
  if (rank) {
    PetscCall(PetscFree(t->text));
    PetscCall(PetscMalloc1(len + 1, &t->text));
    t->cap = len + 1;
    t->len = len;
  }
  PetscCallMPI(MPI_Bcast(t->text, (PetscMPIInt)(len + 1), MPI_CHAR, 0, comm));
  PetscFunctionReturn(0);
}

/*
   FSSolverCheckSetUp - compares the record of the checkpoint given to -fs_restart with this run's and
   stops with one error listing every item that differs (name: the checkpoint's value -> this run's),
   except those -fs_restart_allow_changes names and those that never define the run.

   Collective (rank 0 decides and broadcasts the verdict)

   Input Parameters:
+  s      - the solver, its record built (FSSolverSetUpRecord())
-  record - the checkpoint's record (FSCheckpointReadSetUp()), NULL for a checkpoint of format version 1:
            refused unless -fs_restart_allow_changes all
*/
PetscErrorCode FSSolverCheckSetUp(FSSolver s, const char record[])
{
  MPI_Comm    comm = PetscObjectComm((PetscObject)s);
  FSText      diff = {NULL, 0, 0}, list = {NULL, 0, 0};
  PetscInt    ndiff = 0;
  PetscMPIInt rank;

  PetscFunctionBegin;
  if (!record) {
    PetscCheck(FSAllowedByUser(s->opt.allow_changes, "all"), comm, PETSC_ERR_FILE_UNEXPECTED,
               "Checkpoint \"%s\" has no record of its run's set-up (format version 1, written by an older flexslosh): "
               "it cannot be checked against this run. Restart it anyway with -fs_restart_allow_changes all",
               s->opt.restart);
    PetscCall(
        PetscPrintf(comm, "Warning: checkpoint %s has no record of its run's set-up: not checked\n", s->opt.restart));
    PetscFunctionReturn(0);
  }
  PetscCallMPI(MPI_Comm_rank(comm, &rank));
  if (!rank) {
    PetscCall(FSRecordCompare(record, s->mon.setup, PETSC_TRUE, s->opt.allow_changes, &diff, &list, &ndiff));
    PetscCall(FSRecordCompare(s->mon.setup, record, PETSC_FALSE, s->opt.allow_changes, &diff, &list, &ndiff));
    if (diff.len >= 1400) PetscCall(FSTextAppend(&diff, "  ...\n", 6));
    PetscCall(FSTextAppend(&diff, "", 0));
    PetscCall(FSTextAppend(&list, "", 0));
  }
  PetscCallMPI(MPI_Bcast(&ndiff, 1, MPIU_INT, 0, comm));
  if (!ndiff) {
    PetscCall(PetscFree(diff.text));
    PetscCall(PetscFree(list.text));
    PetscFunctionReturn(0);
  }
  PetscCall(FSTextBcast(comm, &diff)); /* every rank reports the same error */
  PetscCall(FSTextBcast(comm, &list));
  SETERRQ(comm, PETSC_ERR_ARG_INCOMP,
          "Checkpoint \"%s\" was written by a run set up differently; %" PetscInt_FMT
          " item(s) differ (the checkpoint's value -> this run's):\n%sRestart with the set-up that wrote it, or let "
          "these change with -fs_restart_allow_changes %s",
          s->opt.restart, ndiff, diff.text, list.text);
}

/* FNV-1a: a 64-bit hash of a text */
static uint64_t FSTextHash(const char *text, size_t len)
{
  uint64_t h = 14695981039346656037ULL;

  for (size_t k = 0; k < len; k++) {
    h ^= (unsigned char)text[k];
    h *= 1099511628211ULL;
  }
  return h;
}

/* the first item of record a that b lacks or (unless absent) holds with another value (NULL: none), and the number
   of such items */
static const char *FSRecordFirstDifference(const char a[], const char b[], PetscBool absent, PetscInt *ndiff)
{
  const char *first = NULL;

  *ndiff = 0;
  for (const char *l = a; l && *l; l = strchr(l, '\n') ? strchr(l, '\n') + 1 : NULL) {
    size_t      nn = strcspn(l, "="), nb = 0;
    const char *vb;
    char        name[256];

    if (l[nn] != '=' || nn >= sizeof(name)) continue;
    memcpy(name, l, nn);
    name[nn] = 0;
    vb       = FSRecordFind(b, name, &nb);
    if (vb && (absent || FSValuesEqual(l + nn + 1, strcspn(l + nn + 1, "\n"), vb, nb))) continue;
    if (!first) first = l;
    (*ndiff)++;
  }
  return first;
}

/* the value of the item at line l of a record, and the same item's in record b ("(not set)" where absent) */
static void FSRecordItemValues(const char *l, const char b[], char name[256], char va[128], char vb[128])
{
  size_t      nn = PetscMin(strcspn(l, "="), 255), na = strcspn(l + nn + 1, "\n"), nb = 0;
  const char *v;

  memcpy(name, l, nn);
  name[nn] = 0;
  snprintf(va, 128, "%.*s", (int)PetscMin(na, 100), l + nn + 1);
  v = FSRecordFind(b, name, &nb);
  if (v) snprintf(vb, 128, "%.*s", (int)PetscMin(nb, 100), v);
  else snprintf(vb, 128, "(not set)");
}

/*
   FSSolverCheckRanksAgree - stops the run when its ranks were given different options (the command lines of an
   MPMD launch, options files or PETSC_OPTIONS that differ between the ranks), which would otherwise leave them in
   different collectives (a hang, or an MPI error far from the cause). Every rank hashes its options database
   (PetscOptionsGetAll(), without each process's own diagnostics and the paths of the files every rank reads,
   FSRankLocal); one MPI_Allreduce of the hash's largest and smallest value compares them. Only when they differ
   rank 0 gathers the ranks' options and names the first option that differs, with both values.

   Collective

   Input Parameter:
.  s - the solver, before it reads its options (FSSolverSetFromOptions())

   Notes:
   Values that differ as text but not as numbers or truth values (0.02 and 2e-2) are the same.

.seealso: FSSolverSetFromOptions(), FSSolverCheckSetUp()
*/
PetscErrorCode FSSolverCheckRanksAgree(FSSolver s)
{
  MPI_Comm    comm = PetscObjectComm((PetscObject)s);
  FSText      t    = {NULL, 0, 0};
  PetscMPIInt size, rank, len, *lens = NULL, *displs = NULL;
  uint64_t    h[2];
  char       *all = NULL, verdict[1024] = "";

  PetscFunctionBegin;
  PetscCallMPI(MPI_Comm_size(comm, &size));
  if (size == 1) PetscFunctionReturn(0);
  PetscCallMPI(MPI_Comm_rank(comm, &rank));
  PetscCall(FSRecordOptions(&t, FSSkipForRanks));
  PetscCall(FSTextAppend(&t, "", 0)); /* a text, also without options */
  h[0] = FSTextHash(t.text, t.len);
  h[1] = ~h[0];
  PetscCallMPI(MPI_Allreduce(MPI_IN_PLACE, h, 2, MPI_UINT64_T, MPI_MAX, comm));
  if (h[0] == ~h[1]) { /* the largest hash is the smallest: every rank's is the same */
    PetscCall(PetscFree(t.text));
    PetscFunctionReturn(0);
  }
  PetscCall(PetscMPIIntCast(t.len + 1, &len));
  if (!rank) PetscCall(PetscMalloc2(size, &lens, size + 1, &displs));
  PetscCallMPI(MPI_Gather(&len, 1, MPI_INT, lens, 1, MPI_INT, 0, comm));
  if (!rank) {
    displs[0] = 0;
    for (PetscMPIInt r = 0; r < size; r++) displs[r + 1] = displs[r] + lens[r];
    PetscCall(PetscMalloc1(displs[size], &all));
  }
  PetscCallMPI(MPI_Gatherv(t.text, len, MPI_CHAR, all, lens, displs, MPI_CHAR, 0, comm));
  if (!rank) { /* the first rank whose options differ from rank 0's, and the first of them */
    PetscInt nranks = 0, ndiff = 0;
    char     first[768] = "";
    for (PetscMPIInt r = 1; r < size; r++) {
      const char *rec = all + displs[r], *l0, *l1;
      PetscInt    n0, n1;
      char        name[256], va[128], vb[128];
      l0 = FSRecordFirstDifference(t.text, rec, PETSC_FALSE, &n0); /* rank 0's items that rank r lacks or differ */
      l1 = FSRecordFirstDifference(rec, t.text, PETSC_TRUE, &n1);  /* rank r's items that rank 0 lacks */
      if (!l0 && !l1) continue;                                    /* the same values, written differently */
      if (!nranks++) {
        if (l0) FSRecordItemValues(l0, rec, name, va, vb);
        else FSRecordItemValues(l1, t.text, name, vb, va);
        PetscCall(PetscSNPrintf(first, sizeof(first), "%s is %s on rank 0 and %s on rank %d", name, va, vb, r));
        ndiff = n0 + n1;
      }
    }
    if (nranks)
      PetscCall(PetscSNPrintf(verdict, sizeof(verdict),
                              "The ranks were given different options: %s (%" PetscInt_FMT
                              " difference(s) with that rank; %" PetscInt_FMT
                              " rank(s) differ from rank 0). Every rank of a run must be given the same options: "
                              "check the command lines of an MPMD launch, the options files and PETSC_OPTIONS",
                              first, ndiff, nranks));
    PetscCall(PetscFree(all));
    PetscCall(PetscFree2(lens, displs));
  }
  PetscCall(PetscFree(t.text));
  PetscCallMPI(MPI_Bcast(verdict, (PetscMPIInt)sizeof(verdict), MPI_CHAR, 0, comm)); /* rank 0's, on every rank */
  PetscCheck(!verdict[0], comm, PETSC_ERR_ARG_INCOMP, "%s", verdict);
  PetscFunctionReturn(0);
}
