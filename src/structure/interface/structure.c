/*
   FSStructure: the structure that carries the tank, and its registry (-fs_structure <name>), as
   TSRegister does for TS types. Built-in models register in FSStructureRegisterAll; plug-ins call
   FSStructureRegister from their PetscDLLibraryRegister_<name>() entry point, which runs inside
   PetscInitialize: the list is created lazily and never reset.
*/
#include "structure/fsstructure.h"
#include "sys/fssys.h"

static FSRegistry FSStructures; /* src/sys/registry.c */

PETSC_EXTERN PetscErrorCode FSStructureCreate_MSD(FSStructure);
PETSC_EXTERN PetscErrorCode FSStructureCreate_Modal(FSStructure);
PETSC_EXTERN PetscErrorCode FSStructureCreate_Prescribed(FSStructure);

/*
   FSStructureRegister - adds a structure model to the registry.

   Not collective

   Input Parameters:
+  name        - the name used in -fs_structure
.  description - one line
-  create      - the routine that fills the structure's ops and data (options are read later, by ops.setfromoptions)

   Notes: may be called before FSInitializePackage (from a plug-in's entry point). Registering a
   name twice replaces the earlier routine. "none" is reserved (no structure).
*/
PetscErrorCode FSStructureRegister(const char name[], const char description[], FSStructureCreateFn create)
{
  PetscFunctionBegin;
  PetscCheck(strcmp(name, "none"), PETSC_COMM_SELF, PETSC_ERR_ARG_WRONG,
             "The structure name \"none\" is reserved (no structure)");
  PetscCall(FSRegistryAdd(&FSStructures, name, description, (void (*)(void))create));
  PetscFunctionReturn(0);
}

/* FSStructureListView - prints every registered structure model with its description (-fs_structure_view). */
PetscErrorCode FSStructureListView(PetscViewer viewer)
{
  PetscFunctionBegin;
  PetscCall(FSRegistryView(&FSStructures, viewer, "structure models", "select with -fs_structure name (or none)"));
  PetscFunctionReturn(0);
}

PetscErrorCode FSStructureFind(const char name[], FSStructureCreateFn *create)
{
  PetscFunctionBegin;
  PetscCall(FSStructureRegisterAll());
  PetscCall(FSRegistryFind(&FSStructures, name, (void (**)(void))create));
  PetscFunctionReturn(0);
}

/*
   FSStructureCreate - creates the structure model registered under name for a solver.

   Collective on the solver
*/
PetscErrorCode FSStructureCreate(FSSolver s, const char name[], FSStructure *st)
{
  FSStructureCreateFn create;
  FSStructure         t;
  MPI_Comm            comm = PetscObjectComm((PetscObject)s);

  PetscFunctionBegin;
  PetscCall(FSStructureFind(name, &create));
  if (!create) {
    char known[2048];
    PetscCall(FSRegistryNames(&FSStructures, known, sizeof(known)));
    SETERRQ(comm, PETSC_ERR_ARG_UNKNOWN_TYPE,
            "Unknown structure \"%s\" given to -fs_structure: the registered models are none%s (load plug-ins with "
            "-dll_append, list with -fs_structure_view)",
            name, known);
  }
  PetscCall(PetscNew(&t));
  PetscCall(PetscStrncpy(t->name, name, sizeof(t->name)));
  t->solver = s;
  t->comm   = comm;
  PetscCall((*create)(t));
  *st = t;
  PetscFunctionReturn(0);
}

PetscErrorCode FSStructureDestroy(FSStructure *st)
{
  PetscFunctionBegin;
  if (!*st) PetscFunctionReturn(0);
  if ((*st)->ops.destroy) PetscCall((*(*st)->ops.destroy)(*st));
  PetscCall(PetscFree(*st));
  PetscFunctionReturn(0);
}

/* FSStructureGetSolver - the solver a structure belongs to. */
PetscErrorCode FSStructureGetSolver(FSStructure st, FSSolver *s)
{
  PetscFunctionBegin;
  *s = st->solver;
  PetscFunctionReturn(0);
}

/*
   FSStructureAddColumn - adds a column of the model's own to the time series (called from the
   model's setup; its value comes from ops.columns).
*/
PetscErrorCode FSStructureAddColumn(FSStructure st, const char name[])
{
  PetscFunctionBegin;
  PetscCheck(st->ncolumns < FS_STRUCTURE_MAX_COLUMNS, st->comm, PETSC_ERR_ARG_OUTOFRANGE,
             "Structure %s: more than %d time-series columns", st->name, FS_STRUCTURE_MAX_COLUMNS);
  PetscCall(PetscStrncpy(st->column[st->ncolumns++], name, sizeof(st->column[0])));
  PetscFunctionReturn(0);
}

/*
   FSStructureHelpAll - with -help, lists the options of every registered structure model besides
   the selected one. Called inside the solver's options block.
*/
PetscErrorCode FSStructureHelpAll(FSSolver s, FSStructure selected, PetscOptionItems *PetscOptionsObject)
{
  PetscFunctionBegin;
  for (FSRegistryEntry *info = FSStructures.first; info; info = info->next) {
    FSStructure st;
    if (selected && !strcmp(selected->name, info->name)) continue;
    PetscCall(FSStructureCreate(s, info->name, &st));
    PetscCall(FSOptionsSurveyOwner("structure model", info->name));
    if (st->ops.setfromoptions) PetscCall((*st->ops.setfromoptions)(st, PetscOptionsObject));
    PetscCall(FSOptionsSurveyOwner(NULL, NULL));
    PetscCall(FSStructureDestroy(&st));
  }
  PetscFunctionReturn(0);
}

/*
   FSStructureRegisterAll - registers the built-in structure models (idempotent).
*/
PetscErrorCode FSStructureRegisterAll(void)
{
  static PetscBool done = PETSC_FALSE;

  PetscFunctionBegin;
  if (done) PetscFunctionReturn(0);
  done = PETSC_TRUE;
  PetscCall(FSStructureRegister(
      "msd",
      "cantilever as a mass-spring-damper at the tank, K = 3 EI/a^3 (seed Eqs. 16-17), options -fs_beam_*, -fs_msd_*",
      FSStructureCreate_MSD));
  PetscCall(FSStructureRegister("modal",
                                "modal Euler-Bernoulli cantilever, modes of Hermite finite elements with the tank by "
                                "SLEPc (seed Eqs. 18-27), options -fs_beam_*, -fs_modal_*",
                                FSStructureCreate_Modal));
  PetscCall(FSStructureRegister("prescribed",
                                "the tank moved by a given motion: translation and roll about z, sums of sines, "
                                "polynomials or time-series files, options -fs_motion_*",
                                FSStructureCreate_Prescribed));
  PetscFunctionReturn(0);
}
