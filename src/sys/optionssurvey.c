/*
   The options every object of flexslosh reads, collected from PETSc's -help table, and the registered names
   nearest to a misspelt one.

   A survey pushes a scratch options database holding only -help (and the survey's own settings, e.g. -fs_dim 3),
   replaces PetscHelpPrintf with a collector and has every registered object read its options (the solver's
   FSSolverOptionsSurvey(): the same routines as -help runs). Each line of the help table that names an option
   ("  -fs_dx <0.02 : 0.02>: ...") is recorded with the object that was reading then (FSOptionsSurveyOwner(): the
   solver, "case tank", "term shifting", ...). Nothing of the run is touched: the scratch database is popped and
   PetscHelpPrintf restored at the end, and the help table itself is printed nowhere.

   PETSc prints an options block's help once per process and block title (PetscOptionsBegin() records the titles
   printed); the blocks a survey opens again call FSOptionsSurveyBlock() to be printed all the same.
*/
#include "sys/fssys.h"
#include <ctype.h>
#include <stdarg.h>

struct _n_FSOptionsTable {
  FSOptionsEntry *entry;
  PetscInt        n, max;
};

static struct {
  PetscBool      active;
  char           owner[96];
  FSOptionsTable table;
  PetscErrorCode (*printf_saved)(MPI_Comm, const char[], ...);
  PetscOptions db;
} Survey;

/* Add - one entry of the table (an option seen twice under the same owner is kept once) */
static PetscErrorCode Add(const char name[], PetscBool prefix)
{
  FSOptionsTable t = Survey.table;

  PetscFunctionBegin;
  for (PetscInt k = 0; k < t->n; k++)
    if (!strcmp(t->entry[k].name, name) && !strcmp(t->entry[k].owner, Survey.owner)) PetscFunctionReturn(0);
  if (t->n == t->max) {
    FSOptionsEntry *e;
    t->max = t->max ? 2 * t->max : 256;
    PetscCall(PetscCalloc1(t->max, &e));
    if (t->n) PetscCall(PetscArraycpy(e, t->entry, t->n));
    PetscCall(PetscFree(t->entry));
    t->entry = e;
  }
  PetscCall(PetscStrncpy(t->entry[t->n].name, name, sizeof(t->entry[0].name)));
  PetscCall(PetscStrncpy(t->entry[t->n].owner, Survey.owner, sizeof(t->entry[0].owner)));
  t->entry[t->n].prefix = prefix;
  t->n++;
  PetscFunctionReturn(0);
}

/* Collect - PetscHelpPrintf during a survey: each line "  -NAME..." of the text records NAME (fs_ options only) */
static PetscErrorCode Collect(MPI_Comm comm, const char format[], ...)
{
  char    text[4096];
  va_list ap;

  PetscFunctionBegin;
  (void)comm;
  va_start(ap, format);
  (void)vsnprintf(text, sizeof(text), format, ap);
  va_end(ap);
  for (const char *line = text; line && *line; line = strchr(line, '\n') ? strchr(line, '\n') + 1 : NULL) {
    const char *c = line;
    char        name[64];
    size_t      n = 0;
    while (*c == ' ' || *c == '\t') c++;
    if (*c++ != '-') continue;
    while ((isalnum((unsigned char)*c) || *c == '_') && n + 1 < sizeof(name))
      name[n++] = (char)tolower((unsigned char)*c++);
    name[n] = 0;
    if (n > 3 && !strncmp(name, "fs_", 3)) PetscCall(Add(name, PETSC_FALSE));
  }
  PetscFunctionReturn(0);
}

/*
   FSOptionsSurveyBegin - starts a survey: a scratch options database holding -help and the settings given is
   PETSc's default database, and the help table goes into a table of options instead of the terminal.

   Not collective (every rank runs the same survey)

   Input Parameter:
.  settings - options for the objects surveyed, e.g. "-fs_dim 3" (NULL: none)
*/
PetscErrorCode FSOptionsSurveyBegin(const char settings[])
{
  PetscFunctionBegin;
  PetscCheck(!Survey.active, PETSC_COMM_SELF, PETSC_ERR_ORDER, "A survey of the options is already running");
  if (!Survey.table) PetscCall(PetscNew(&Survey.table));
  PetscCall(PetscOptionsCreate(&Survey.db));
  PetscCall(PetscOptionsInsertString(Survey.db, "-help"));
  if (settings) PetscCall(PetscOptionsInsertString(Survey.db, settings));
  PetscCall(PetscOptionsPush(Survey.db));
  Survey.printf_saved = PetscHelpPrintf;
  PetscHelpPrintf     = Collect;
  Survey.active       = PETSC_TRUE;
  Survey.owner[0]     = 0;
  PetscFunctionReturn(0);
}

/*
   FSOptionsSurveyEnd - ends a survey: the run's options database and PetscHelpPrintf are restored. The table
   keeps growing over several surveys until FSOptionsSurveyTake() hands it over.
*/
PetscErrorCode FSOptionsSurveyEnd(void)
{
  PetscFunctionBegin;
  if (!Survey.active) PetscFunctionReturn(0);
  Survey.active   = PETSC_FALSE;
  PetscHelpPrintf = Survey.printf_saved;
  PetscCall(PetscOptionsPop());
  PetscCall(PetscOptionsDestroy(&Survey.db));
  PetscFunctionReturn(0);
}

/* FSOptionsSurveyTake - the table the surveys collected, handed to the caller (FSOptionsTableDestroy() frees it) */
PetscErrorCode FSOptionsSurveyTake(FSOptionsTable *table)
{
  PetscFunctionBegin;
  if (!Survey.table) PetscCall(PetscNew(&Survey.table));
  *table       = Survey.table;
  Survey.table = NULL;
  PetscFunctionReturn(0);
}

/* FSOptionsSurveyActive - whether a survey is running (the objects read their options for it, not for a run) */
PetscBool FSOptionsSurveyActive(void) { return Survey.active; }

/*
   FSOptionsSurveyOwner - during a survey, the object whose options are read from now on: kind and name, e.g.
   ("term", "shifting"); kind NULL: the solver itself. Outside a survey it does nothing.
*/
PetscErrorCode FSOptionsSurveyOwner(const char kind[], const char name[])
{
  PetscFunctionBegin;
  if (!Survey.active) PetscFunctionReturn(0);
  if (kind)
    PetscCall(PetscSNPrintf(Survey.owner, sizeof(Survey.owner), "%s%s%s", kind, name ? " " : "", name ? name : ""));
  else Survey.owner[0] = 0;
  PetscFunctionReturn(0);
}

/*
   FSOptionsSurveyPrefix - during a survey, records that the current owner's PETSc objects read every option
   beginning with prefix (e.g. "-fs_modal_eps_": the modal beam's SLEPc eigensolver). Outside a survey it does
   nothing.
*/
PetscErrorCode FSOptionsSurveyPrefix(const char prefix[])
{
  char name[64];

  PetscFunctionBegin;
  if (!Survey.active) PetscFunctionReturn(0);
  PetscCall(PetscStrncpy(name, prefix[0] == '-' ? prefix + 1 : prefix, sizeof(name)));
  for (char *c = name; *c; c++) *c = (char)tolower((unsigned char)*c);
  PetscCall(Add(name, PETSC_TRUE));
  PetscFunctionReturn(0);
}

/*
   FSOptionsSurveyBlock - during a survey, makes the options block print its help (PETSc prints a block's help
   once per process and title: a survey opens blocks a run has already opened). Call it right after
   PetscOptionsBegin(). Outside a survey it does nothing.
*/
PetscErrorCode FSOptionsSurveyBlock(PetscOptionItems *items)
{
  PetscFunctionBegin;
  if (Survey.active) items->alreadyprinted = PETSC_FALSE;
  PetscFunctionReturn(0);
}

/* FSOptionsTableGet - the entries of a table */
PetscErrorCode FSOptionsTableGet(FSOptionsTable table, PetscInt *n, const FSOptionsEntry **entry)
{
  PetscFunctionBegin;
  *n     = table ? table->n : 0;
  *entry = table ? table->entry : NULL;
  PetscFunctionReturn(0);
}

/* FSOptionsTableDestroy - frees a table of FSOptionsSurveyTake() */
PetscErrorCode FSOptionsTableDestroy(FSOptionsTable *table)
{
  PetscFunctionBegin;
  if (!*table) PetscFunctionReturn(0);
  PetscCall(PetscFree((*table)->entry));
  PetscCall(PetscFree(*table));
  PetscFunctionReturn(0);
}

/*
   FSOptionsDistance - the edit distance between two option names, case-insensitive (optimal string alignment:
   insertions, deletions, substitutions and transpositions of neighbours each count 1). Names of at most 63
   characters; longer ones count as far apart.
*/
PetscInt FSOptionsDistance(const char a[], const char b[])
{
  PetscInt  d[64][64];
  const int n = (int)strlen(a), m = (int)strlen(b);

  if (n > 63 || m > 63) return PETSC_MAX_INT;
  for (int i = 0; i <= n; i++) d[i][0] = i;
  for (int j = 0; j <= m; j++) d[0][j] = j;
  for (int i = 1; i <= n; i++)
    for (int j = 1; j <= m; j++) {
      const int ca = tolower((unsigned char)a[i - 1]), cb = tolower((unsigned char)b[j - 1]);
      PetscInt  v = PetscMin(d[i - 1][j] + 1, d[i][j - 1] + 1);
      v           = PetscMin(v, d[i - 1][j - 1] + (ca != cb));
      if (i > 1 && j > 1 && ca == tolower((unsigned char)b[j - 2]) && tolower((unsigned char)a[i - 2]) == cb)
        v = PetscMin(v, d[i - 2][j - 2] + 1);
      d[i][j] = v;
    }
  return d[n][m];
}
