/*
   The registry of physics terms (as TSRegister does for TS types). Built-in terms register in
   FSTermRegisterAll; plug-ins call FSTermRegister from their PetscDLLibraryRegister_<name>()
   entry point, which runs inside PetscInitialize: the list is therefore created lazily and
   never reset while the program runs.
*/
#include "fsimpl.h"

static PetscFunctionList FSTermList = NULL;

typedef struct _n_FSTermInfo {
  char                   name[64], description[256];
  struct _n_FSTermInfo  *next;
} FSTermInfo;
static FSTermInfo *FSTermInfos = NULL;

/*
   FSTermRegister - adds a physics term to the registry.

   Not collective

   Input Parameters:
+  name        - the name used in -fs_terms
.  description - one line saying what the term adds to the equations
-  create      - the routine that fills the term's ops, needs and data

   Notes: may be called before FSInitializePackage (from a plug-in's entry point).
   Registering a name twice replaces the earlier routine.
*/
PetscErrorCode FSTermRegister(const char name[], const char description[], FSTermCreateFn create)
{
  FSTermInfo *info;

  PetscFunctionBegin;
  PetscCall(PetscFunctionListAdd(&FSTermList, name, create));
  for (info = FSTermInfos; info; info = info->next)
    if (!strcmp(info->name, name)) break;
  if (!info) {
    /* plain calloc: this registry lives until the program ends, beyond PetscFinalize */
    info = (FSTermInfo *)calloc(1, sizeof(*info));
    PetscCheck(info, PETSC_COMM_SELF, PETSC_ERR_MEM, "Out of memory registering term %s", name);
    info->next  = FSTermInfos;
    FSTermInfos = info;
  }
  PetscCall(PetscStrncpy(info->name, name, sizeof(info->name)));
  PetscCall(PetscStrncpy(info->description, description ? description : "", sizeof(info->description)));
  PetscFunctionReturn(0);
}

/* FSTermListView - prints every registered term with its description. */
PetscErrorCode FSTermListView(PetscViewer viewer)
{
  PetscInt n = 0;
  FSTermInfo *info;

  PetscFunctionBegin;
  for (info = FSTermInfos; info; info = info->next) n++;
  PetscCall(PetscViewerASCIIPrintf(viewer, "Registered physics terms (%" PetscInt_FMT "), select with -fs_terms name1,name2,...:\n", n));
  /* print in registration order: the list is stored newest first */
  for (PetscInt k = n - 1; k >= 0; k--) {
    PetscInt m = 0;
    for (info = FSTermInfos; info && m < k; info = info->next) m++;
    PetscCall(PetscViewerASCIIPrintf(viewer, "  %-16s %s\n", info->name, info->description));
  }
  PetscFunctionReturn(0);
}

/*
   FSTermCreate - creates the term registered under name for a solver.

   Collective on the solver
*/
PetscErrorCode FSTermCreate(FSSolver s, const char name[], FSTerm *term)
{
  FSTermCreateFn create;
  FSTerm         t;

  PetscFunctionBegin;
  PetscCall(PetscFunctionListFind(FSTermList, name, &create));
  if (!create) {
    char        known[2048] = "";
    FSTermInfo *info;
    for (info = FSTermInfos; info; info = info->next) {
      PetscCall(PetscStrlcat(known, " ", sizeof(known)));
      PetscCall(PetscStrlcat(known, info->name, sizeof(known)));
    }
    SETERRQ(PetscObjectComm((PetscObject)s), PETSC_ERR_ARG_UNKNOWN_TYPE, "Unknown physics term \"%s\" in -fs_terms: the registered terms are%s (load plug-ins with -dll_append, list with -fs_terms_view)", name, known);
  }
  PetscCall(PetscNew(&t));
  PetscCall(PetscStrncpy(t->name, name, sizeof(t->name)));
  t->solver = s;
  PetscCall((*create)(t));
  *term = t;
  PetscFunctionReturn(0);
}

PetscErrorCode FSTermDestroy(FSTerm *term)
{
  PetscFunctionBegin;
  if (!*term) PetscFunctionReturn(0);
  if ((*term)->ops.destroy) PetscCall((*(*term)->ops.destroy)(*term));
  PetscCall(PetscFree(*term));
  PetscFunctionReturn(0);
}

/* FSTermGetSolver - the solver a term belongs to (to read its parameters). */
PetscErrorCode FSTermGetSolver(FSTerm t, FSSolver *s)
{
  PetscFunctionBegin;
  *s = t->solver;
  PetscFunctionReturn(0);
}

/*
   FSTermHelpAll - with -help, lists the options of every registered term that the run did not
   select, so that -help documents them all. Called inside the solver's options block.
*/
PetscErrorCode FSTermHelpAll(FSSolver s, PetscOptionItems *PetscOptionsObject)
{
  PetscFunctionBegin;
  for (FSTermInfo *info = FSTermInfos; info; info = info->next) {
    PetscBool selected = PETSC_FALSE;
    FSTerm    t;
    for (PetscInt k = 0; k < s->terms.nterms; k++)
      if (!strcmp(s->terms.term[k]->name, info->name)) selected = PETSC_TRUE;
    if (selected) continue;
    PetscCall(FSTermCreate(s, info->name, &t));
    if (t->ops.setfromoptions) PetscCall((*t->ops.setfromoptions)(t, PetscOptionsObject));
    PetscCall(FSTermDestroy(&t));
  }
  PetscFunctionReturn(0);
}
