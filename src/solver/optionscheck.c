/*
   The -fs_ options given but read by nothing, refused before the first step: a misspelt -fs_motion_roll_sine
   would otherwise leave the run without its roll, reported only at its end (FSOptionsLeft()).

   FSSolverSetFromOptions() and FSSolverSetUp() end with FSSolverCheckOptions(). When some -fs_ option of the
   database is still unused, a survey (src/sys/optionssurvey.c) collects every option each registered object
   reads (the -help table, in 2-D and 3-D), with the object reading it, and each unused option is classified:
   - in no object's table: unknown, an error naming the registered options nearest to it (edit distance);
   - an option of objects this run does not use (a term not in -fs_terms, another case, structure model or
     boundary method, the walls of a case without walls, the coupling without a structure): an error naming the
     object and the option that selects it;
   - an option of an object in use that this set-up does not read (e.g. -fs_tg_depth in 2-D): an error saying so;
   - an option under the prefix of an object's PETSc objects (-fs_modal_eps_*, read by SLEPc) of an object in
     use: left to the report at the end of the run, as PETSc's own options are.
   Options whose object is known only at set-up (the walls, a boundary method, the coupling) are judged there.
   Options without the fs_ prefix (-ts_*, -log_view, ...) are left to the end-of-run report.
*/
#include "solver/solverimpl.h"
#include "sys/fssys.h"
#include <ctype.h>

#define FS_CHECK_MAX_REPORTED 8 /* options named in one error */

/*
   FSSolverSetOptionsChecked - restricts the check of unused options (FSSolverCheckOptions()) to the options given,
   e.g. those a Python Solver's file and dict set (the others of its database came from the process's own and may
   be meant for other solvers).

   Logically collective

   Input Parameters:
+  s     - the solver
.  n     - the number of names (0: every option of the database, the default)
-  names - the options, with or without the leading '-'
*/
PetscErrorCode FSSolverSetOptionsChecked(FSSolver s, PetscInt n, const char *const names[])
{
  PetscFunctionBegin;
  for (PetscInt k = 0; k < s->nchecked; k++) PetscCall(PetscFree(s->checked[k]));
  PetscCall(PetscFree(s->checked));
  s->nchecked = 0;
  if (n <= 0) PetscFunctionReturn(0);
  PetscCall(PetscCalloc1(n, &s->checked));
  for (PetscInt k = 0; k < n; k++)
    PetscCall(PetscStrallocpy(names[k][0] == '-' ? names[k] + 1 : names[k], &s->checked[k]));
  s->nchecked = n;
  PetscFunctionReturn(0);
}

/* Survey - the table of every registered object's options, from its -help table in 2-D and in 3-D */
static PetscErrorCode Survey(FSSolver s, FSOptionsTable *table)
{
  const char *settings[] = {NULL, "-fs_dim 3"};

  PetscFunctionBegin;
  for (PetscInt k = 0; k < 2; k++) {
    FSSolver       scratch = NULL;
    PetscErrorCode ierr;
    PetscCall(FSOptionsSurveyBegin(settings[k]));
    ierr = FSSolverCreate(PetscObjectComm((PetscObject)s), &scratch);
    if (!ierr) ierr = FSSolverSetFromOptions(scratch);
    if (!ierr) ierr = FSSolverDestroy(&scratch);
    PetscCall(FSOptionsSurveyEnd()); /* the run's options back, whatever happened */
    PetscCall(ierr);
  }
  PetscCall(FSOptionsSurveyTake(table));
  PetscFunctionReturn(0);
}

/*
   InUse - whether the run uses the object owner ("" the solver, "case tank", "term delta", "structure model
   modal", "walls", "boundary method polygon", "coupling"): 1 yes, 0 no, -1 not known before the set-up.
   what gets the option that selects it, for the messages.
*/
static PetscErrorCode InUse(FSSolver s, const char owner[], PetscBool setup, PetscInt *use, char what[], size_t len)
{
  char        kind[32] = "", name[64] = "";
  const char *sp = strrchr(owner, ' ');

  PetscFunctionBegin;
  what[0] = 0;
  *use    = 1;
  if (!owner[0]) PetscFunctionReturn(0);
  if (sp && strncmp(owner, "walls", 5) && strncmp(owner, "coupling", 8)) {
    PetscCall(PetscStrncpy(kind, owner, PetscMin(sizeof(kind), (size_t)(sp - owner) + 1)));
    PetscCall(PetscStrncpy(name, sp + 1, sizeof(name)));
  } else PetscCall(PetscStrncpy(kind, owner, sizeof(kind)));
  if (!strcmp(kind, "case")) {
    PetscBool same;
    PetscCall(PetscStrcasecmp(name, s->opt.casename, &same));
    *use = same;
    PetscCall(PetscSNPrintf(what, len, "-fs_case is %s", s->opt.casename));
  } else if (!strcmp(kind, "term")) {
    size_t n = 0;
    *use     = 0;
    PetscCall(PetscSNPrintf(what, len, "-fs_terms is "));
    for (PetscInt t = 0; t < s->terms.nterms; t++) {
      PetscBool same;
      PetscCall(PetscStrcasecmp(name, s->terms.term[t]->name, &same));
      if (same) *use = 1;
      PetscCall(PetscStrlen(what, &n));
      PetscCall(PetscSNPrintf(what + n, len - n, "%s%s", t ? "," : "", s->terms.term[t]->name));
    }
  } else if (!strcmp(kind, "structure model")) {
    PetscBool same = PETSC_FALSE;
    if (s->structure) PetscCall(PetscStrcasecmp(name, s->structure->name, &same));
    *use = same;
    PetscCall(PetscSNPrintf(what, len, "-fs_structure is %s", s->opt.structname));
  } else if (!strcmp(kind, "walls")) {
    *use = setup ? (PetscInt)(s->boundary != NULL) : -1;
    PetscCall(PetscSNPrintf(what, len, "the case %s has no walls", s->opt.casename));
  } else if (!strcmp(kind, "boundary method")) {
    PetscBool same = PETSC_FALSE;
    if (s->boundary && ((PetscObject)s->boundary)->type_name)
      PetscCall(PetscStrcasecmp(name, ((PetscObject)s->boundary)->type_name, &same));
    *use = setup ? (PetscInt)same : -1;
    if (s->boundary && ((PetscObject)s->boundary)->type_name)
      PetscCall(PetscSNPrintf(what, len, "the walls' -fs_boundary is %s", ((PetscObject)s->boundary)->type_name));
    else PetscCall(PetscSNPrintf(what, len, "the case %s has no walls", s->opt.casename));
  } else if (!strcmp(kind, "coupling")) {
    *use = setup ? (PetscInt)(s->structure && s->boundary && s->pw.nglobal_particles > 0) : -1;
    PetscCall(PetscSNPrintf(what, len, "it needs a case with walls and liquid and a -fs_structure, here %s",
                            s->opt.structname));
  }
  PetscFunctionReturn(0);
}

/* Nearest - up to three registered options nearest to name, with their objects, as text for a message */
static PetscErrorCode Nearest(const char name[], PetscInt n, const FSOptionsEntry e[], char text[], size_t len)
{
  PetscInt best[3] = {-1, -1, -1}, dist[3] = {PETSC_MAX_INT, PETSC_MAX_INT, PETSC_MAX_INT}, nl, count = 0;
  size_t   l;

  PetscFunctionBegin;
  text[0] = 0;
  PetscCall(PetscStrlen(name, &l));
  nl = PetscMax(2, (PetscInt)l / 4); /* farther than this is no misspelling */
  for (PetscInt k = 0; k < n; k++) {
    PetscInt d = e[k].prefix ? PETSC_MAX_INT : FSOptionsDistance(name, e[k].name), dup = 0;
    if (d > nl) continue;
    for (PetscInt j = 0; j < 3; j++)
      if (best[j] >= 0 && !strcmp(e[best[j]].name, e[k].name)) dup = 1; /* one name, several objects: the first */
    if (dup) continue;
    for (PetscInt j = 0; j < 3; j++)
      if (d < dist[j]) {
        for (PetscInt i = 2; i > j; i--) {
          dist[i] = dist[i - 1];
          best[i] = best[i - 1];
        }
        dist[j] = d;
        best[j] = k;
        break;
      }
  }
  for (PetscInt j = 0; j < 3; j++) {
    size_t used;
    if (best[j] < 0 || dist[j] > dist[0] + 1) continue; /* the nearest, and those one edit farther */
    PetscCall(PetscStrlen(text, &used));
    PetscCall(PetscSNPrintf(text + used, len - used, "%s-%s (%s)", count++ ? ", " : "", e[best[j]].name,
                            e[best[j]].owner[0] ? e[best[j]].owner : "the solver"));
  }
  PetscFunctionReturn(0);
}

/* Classify - the line of the error for an unused option (empty: not an error, or not yet) */
static PetscErrorCode Classify(FSSolver s, PetscBool setup, const char name[], const char given[], PetscInt n,
                               const FSOptionsEntry e[], char line[], size_t len)
{
  PetscInt  owners = 0, inuse = 0, unknown = 0, prefixed = 0;
  char      objects[512] = "", selectors[512] = "", users[96] = "";
  PetscBool found = PETSC_FALSE;

  PetscFunctionBegin;
  line[0] = 0;
  for (PetscInt k = 0; k < n; k++) {
    PetscBool match;
    PetscInt  use;
    char      what[256];
    if (e[k].prefix) PetscCall(PetscStrncmp(name, e[k].name, strlen(e[k].name), &match));
    else PetscCall(PetscStrcasecmp(name, e[k].name, &match));
    if (!match) continue;
    found = PETSC_TRUE;
    PetscCall(InUse(s, e[k].owner, setup, &use, what, sizeof(what)));
    if (use < 0) unknown++;
    else if (use) {
      if (!inuse++) PetscCall(PetscStrncpy(users, e[k].owner[0] ? e[k].owner : "solver", sizeof(users)));
      if (e[k].prefix) prefixed++;
    } else if (!strstr(objects, e[k].owner)) {
      size_t used;
      PetscCall(PetscStrlen(objects, &used));
      PetscCall(PetscSNPrintf(objects + used, sizeof(objects) - used, "%sthe %s", owners ? " or " : "", e[k].owner));
      if (!strstr(selectors, what)) {
        PetscCall(PetscStrlen(selectors, &used));
        PetscCall(PetscSNPrintf(selectors + used, sizeof(selectors) - used, "%s%s", owners ? "; " : "", what));
      }
      owners++;
    }
  }
  if (!found) {
    char near[512];
    PetscCall(Nearest(name, n, e, near, sizeof(near)));
    if (near[0])
      PetscCall(PetscSNPrintf(line, len, "-%s is not an option of flexslosh: did you mean %s?", given, near));
    else PetscCall(PetscSNPrintf(line, len, "-%s is not an option of flexslosh (flexslosh -help lists them)", given));
  } else if (prefixed) { /* read by a PETSc object of an object in use: PETSc's report at the end names it */
  } else if (inuse) {
    PetscCall(PetscSNPrintf(line, len,
                            "-%s is an option of the %s that this set-up does not read (it is read only in some "
                            "set-ups of it, e.g. in 3-D; flexslosh -help lists it)",
                            given, users));
  } else if (!unknown && owners) {
    PetscCall(PetscSNPrintf(line, len, "-%s is an option of %s, which this run does not use (%s)", given, objects,
                            selectors));
  }
  PetscFunctionReturn(0);
}

/*
   FSSolverCheckOptions - refuses the -fs_ options of the database that nothing read (misspelt, or options of an
   object the run does not use), with an error naming each (at most 8) and the registered options nearest to an
   unknown one. FSSolverSetFromOptions() calls it (unknown options, options of other cases, terms and structure
   models), FSSolverSetUp() again once every object has read its options (the walls, the boundary method, the
   coupling too).

   Collective

   Input Parameters:
+  s     - the solver
-  setup - whether the set-up has read every option (FSSolverSetUp())

   Options Database Key:
.  -fs_options_check <true> - false: no check (the options nothing read are reported at the end of the run,
                              FSOptionsLeft())

   Notes:
   Options without the fs_ prefix are PETSc's (-ts_*, -log_view): they are left to the end-of-run report. The
   check costs nothing when every -fs_ option was read; otherwise it surveys the options every registered object
   reads (their -help table, 2-D and 3-D), plug-ins loaded with -dll_append included. An option that an object
   reads outside its options routine (a Python structure model's own, read in its setup) is known only when the
   object is in use.

.seealso: FSOptionsLeft(), FSSolverSetOptionsChecked()
*/
PetscErrorCode FSSolverCheckOptions(FSSolver s, PetscBool setup)
{
  MPI_Comm              comm = PetscObjectComm((PetscObject)s);
  PetscInt              N, nleft = 0, nerr        = 0, ntable;
  char                **left, **values, msg[8192] = "";
  PetscBool             help;
  FSOptionsTable        table = NULL;
  const FSOptionsEntry *entry;

  PetscFunctionBegin;
  if (FSOptionsSurveyActive() || !s->opt.options_check) PetscFunctionReturn(0);
  /* a structure model without an options routine (a Python model) reads its options at set-up: judged there */
  if (!setup && s->structure && !s->structure->ops.setfromoptions) PetscFunctionReturn(0);
  PetscCall(PetscOptionsHasHelp(NULL, &help));
  if (help) PetscFunctionReturn(0); /* -help reads every object's options and stops */
  PetscCall(PetscOptionsLeftGet(NULL, &N, &left, &values));
  for (PetscInt k = 0; k < N; k++) {
    PetscBool fs, mine = (PetscBool)(s->nchecked == 0);
    PetscCall(PetscStrncmp(left[k], "fs_", 3, &fs));
    for (PetscInt j = 0; j < s->nchecked && !mine; j++) PetscCall(PetscStrcasecmp(s->checked[j], left[k], &mine));
    if (fs && mine) left[nleft++] = left[k];
  }
  if (!nleft) {
    PetscCall(PetscOptionsLeftRestore(NULL, &N, &left, &values));
    PetscFunctionReturn(0);
  }
  PetscCall(Survey(s, &table));
  PetscCall(FSOptionsTableGet(table, &ntable, &entry));
  for (PetscInt k = 0; k < nleft; k++) {
    char   line[1024], name[64];
    size_t used;
    PetscCall(PetscStrncpy(name, left[k], sizeof(name)));
    for (char *c = name; *c; c++) *c = (char)tolower((unsigned char)*c);
    PetscCall(Classify(s, setup, name, left[k], ntable, entry, line, sizeof(line)));
    if (!line[0]) continue;
    if (nerr++ >= FS_CHECK_MAX_REPORTED) continue;
    PetscCall(PetscStrlen(msg, &used));
    PetscCall(PetscSNPrintf(msg + used, sizeof(msg) - used, "\n  %s", line));
  }
  PetscCall(PetscOptionsLeftRestore(NULL, &N, &left, &values));
  PetscCall(FSOptionsTableDestroy(&table));
  PetscCheck(!nerr, comm, PETSC_ERR_USER_INPUT,
             "%" PetscInt_FMT " option%s given that nothing reads:%s%s\nCorrect or remove %s before the run "
             "(-fs_options_check 0 lets it go on without %s, warned at its end)",
             nerr, nerr > 1 ? "s" : "", msg, nerr > FS_CHECK_MAX_REPORTED ? "\n  (and more)" : "",
             nerr > 1 ? "them" : "it", nerr > 1 ? "them" : "it");
  PetscFunctionReturn(0);
}
