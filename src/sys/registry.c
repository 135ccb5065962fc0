/*
   The registration tables of flexslosh (terms, cases, structures), as TSRegister keeps TS types: the
   creation routines by name, with one-line descriptions, in registration order, for the listings
   (-fs_terms_view, ...), the error messages and -help. Plug-ins register from their
   PetscDLLibraryRegister_<name>() entry point, inside PetscInitialize, so a table is created on first
   use and never reset; its entries are allocated with plain calloc, not PetscMalloc, because they
   outlive PetscFinalize (so -malloc_dump does not list them).
*/
#include "sys/fssys.h"

/* FSRegistryAdd - adds (or replaces) name with its creation routine and description. */
PetscErrorCode FSRegistryAdd(FSRegistry *reg, const char name[], const char description[], void (*fn)(void))
{
  FSRegistryEntry *e, *last = NULL;

  PetscFunctionBegin;
  PetscCheck(strlen(name) < sizeof(e->name), PETSC_COMM_SELF, PETSC_ERR_ARG_OUTOFRANGE,
             "Cannot register \"%s\": a name has at most %zu characters", name, sizeof(e->name) - 1);
  for (e = reg->first; e; last = e, e = e->next)
    if (!strcmp(e->name, name)) break;
  if (!e) {
    e = (FSRegistryEntry *)calloc(1, sizeof(*e));
    PetscCheck(e, PETSC_COMM_SELF, PETSC_ERR_MEM, "Out of memory registering %s", name);
    if (last) last->next = e;
    else reg->first = e;
  }
  PetscCall(PetscStrncpy(e->name, name, sizeof(e->name)));
  PetscCall(PetscStrncpy(e->description, description ? description : "", sizeof(e->description)));
  e->create = fn;
  PetscFunctionReturn(0);
}

/* FSRegistryFind - the creation routine registered under name, or NULL. */
PetscErrorCode FSRegistryFind(FSRegistry *reg, const char name[], void (**fn)(void))
{
  PetscFunctionBegin;
  *fn = NULL;
  for (FSRegistryEntry *e = reg->first; e && name; e = e->next)
    if (!strcmp(e->name, name)) {
      *fn = e->create;
      break;
    }
  PetscFunctionReturn(0);
}

/* FSRegistryView - prints "Registered <what> (<count>), <how>:", then every name with its description. */
PetscErrorCode FSRegistryView(FSRegistry *reg, PetscViewer viewer, const char what[], const char how[])
{
  PetscInt n = 0;

  PetscFunctionBegin;
  for (FSRegistryEntry *e = reg->first; e; e = e->next) n++;
  PetscCall(PetscViewerASCIIPrintf(viewer, "Registered %s (%" PetscInt_FMT "), %s:\n", what, n, how));
  for (FSRegistryEntry *e = reg->first; e; e = e->next)
    PetscCall(PetscViewerASCIIPrintf(viewer, "  %-16s %s\n", e->name, e->description));
  PetscFunctionReturn(0);
}

/* FSRegistryNames - the registered names, separated by spaces (for error messages). */
PetscErrorCode FSRegistryNames(FSRegistry *reg, char names[], size_t len)
{
  PetscFunctionBegin;
  names[0] = 0;
  for (FSRegistryEntry *e = reg->first; e; e = e->next) {
    PetscCall(PetscStrlcat(names, " ", len));
    PetscCall(PetscStrlcat(names, e->name, len));
  }
  PetscFunctionReturn(0);
}
