/* Package initialization: class id, log events, the built-in terms and cases, plug-in checks. */
#include "sys/fssys.h"
#include <dlfcn.h>

static PetscBool FSPackageInitialized = PETSC_FALSE;

PetscLogEvent FS_Structure, FS_Coupling;
PetscLogEvent FS_Step, FS_Neighbours, FS_Halo, FS_FirstPass, FS_PairPass, FS_WallPass, FS_Walls, FS_Migrate, FS_Output,
    FS_RHS, FS_Split, FS_FillPacking;

static PetscErrorCode FSFinalizePackageCallback(void)
{
  PetscFunctionBegin;
  FSPackageInitialized = PETSC_FALSE;
  PetscFunctionReturn(0);
}

/*
   FSInitializePackage - registers the FSSolver class, the log events, and the built-in terms and
   cases. Called by FSSolverCreate; idempotent.
*/
PetscErrorCode FSInitializePackage(void)
{
  PetscFunctionBegin;
  if (FSPackageInitialized) PetscFunctionReturn(0);
  FSPackageInitialized = PETSC_TRUE;
  PetscCall(PetscClassIdRegister("FSSolver", &FSSOLVER_CLASSID));
  PetscCall(PetscLogEventRegister("FSStep", FSSOLVER_CLASSID, &FS_Step));
  PetscCall(PetscLogEventRegister("FSRHS", FSSOLVER_CLASSID, &FS_RHS));
  PetscCall(PetscLogEventRegister("FSNeighbours", FSSOLVER_CLASSID, &FS_Neighbours));
  PetscCall(PetscLogEventRegister("FSHalo", FSSOLVER_CLASSID, &FS_Halo));
  PetscCall(PetscLogEventRegister("FSFirstPass", FSSOLVER_CLASSID, &FS_FirstPass));
  PetscCall(PetscLogEventRegister("FSPairPass", FSSOLVER_CLASSID, &FS_PairPass));
  PetscCall(PetscLogEventRegister("FSSplit", FSSOLVER_CLASSID, &FS_Split));
  PetscCall(PetscLogEventRegister("FSWallPass", FSSOLVER_CLASSID, &FS_WallPass));
  PetscCall(PetscLogEventRegister("FSWalls", FSSOLVER_CLASSID, &FS_Walls));
  PetscCall(PetscLogEventRegister("FSMigrate", FSSOLVER_CLASSID, &FS_Migrate));
  PetscCall(PetscLogEventRegister("FSOutput", FSSOLVER_CLASSID, &FS_Output));
  PetscCall(PetscLogEventRegister("FSStructure", FSSOLVER_CLASSID, &FS_Structure));
  PetscCall(PetscLogEventRegister("FSCoupling", FSSOLVER_CLASSID, &FS_Coupling));
  PetscCall(PetscLogEventRegister("FSFillPacking", FSSOLVER_CLASSID, &FS_FillPacking));
  PetscCall(FSTermRegisterAll());
  PetscCall(FSStructureRegisterAll());
  PetscCall(FSCaseRegisterAll());
  PetscCall(PetscRegisterFinalize(FSFinalizePackageCallback));
  PetscFunctionReturn(0);
}

PetscErrorCode FSFinalizePackage(void)
{
  PetscFunctionBegin;
  PetscCall(FSFinalizePackageCallback());
  PetscFunctionReturn(0);
}

/* the libraries given to -dll_append: loaded first if load (those PETSc has not loaded yet), then each
   checked for its entry point */
static PetscErrorCode FSPluginsProcess(MPI_Comm comm, PetscBool load)
{
  char     *paths[64];
  PetscInt  n = 64;
  PetscBool set;

  PetscFunctionBegin;
  PetscCall(PetscOptionsGetStringArray(NULL, NULL, "-dll_append", paths, &n, &set));
  if (!set) PetscFunctionReturn(0);
  for (PetscInt k = 0; k < n; k++) {
    char        base[PETSC_MAX_PATH_LEN], symbol[PETSC_MAX_PATH_LEN + 64], *dot;
    const char *slash = strrchr(paths[k], '/');
    void       *handle, *sym = NULL;
    if (load) PetscCall(PetscDLLibraryAppend(comm, &PetscDLLibrariesLoaded, paths[k]));
    PetscCall(PetscStrncpy(base, slash ? slash + 1 : paths[k], sizeof(base)));
    if (!strncmp(base, "lib", 3)) memmove(base, base + 3, strlen(base + 3) + 1);
    dot = strchr(base, '.');
    if (dot) *dot = 0;
    for (char *c = base; *c; c++)
      if (*c == '-') *c = '_';
    PetscCall(PetscSNPrintf(symbol, sizeof(symbol), "PetscDLLibraryRegister_%s", base));
    handle = dlopen(paths[k], RTLD_LAZY | RTLD_NOLOAD);
    if (!handle) {
      char full[PETSC_MAX_PATH_LEN + 8];
      PetscCall(PetscSNPrintf(full, sizeof(full), "%s.so", paths[k]));
      handle = dlopen(full, RTLD_LAZY | RTLD_NOLOAD);
    }
    PetscCheck(handle, comm, PETSC_ERR_FILE_OPEN,
               "Plug-in \"%s\" given to -dll_append was not loaded: check the path (it must be a shared library built "
               "against libflexslosh)",
               paths[k]);
    sym = dlsym(handle, symbol);
    dlclose(handle);
    PetscCheck(sym, comm, PETSC_ERR_ARG_WRONG,
               "Plug-in \"%s\" given to -dll_append has no entry point %s(): the function must be named after the file "
               "(lib<name>.so exports PetscDLLibraryRegister_<name>), so nothing was registered",
               paths[k], symbol);
    PetscCall(PetscFree(paths[k]));
  }
  PetscFunctionReturn(0);
}

/*
   FSCheckPlugins - checks every library given to -dll_append: PETSc loads a library silently even
   when it has no entry point named after its file, and then nothing is registered. This makes that
   a clear error.

   Collective
*/
PetscErrorCode FSCheckPlugins(MPI_Comm comm)
{
  PetscFunctionBegin;
  PetscCall(FSPluginsProcess(comm, PETSC_FALSE));
  PetscFunctionReturn(0);
}

/*@C
   FSLoadPlugins - loads the libraries given to -dll_append that PETSc has not loaded yet, then checks
   them all (FSCheckPlugins()). PetscInitialize() loads those given on the command line; a driver that
   sets options afterwards (the Python package's Solver options) calls this so that a -dll_append among
   them registers its terms and structures too. A library already loaded is not loaded again.

   Collective

   Input Parameter:
.  comm - the communicator of the run

.seealso: FSCheckPlugins(), FSTermRegister(), FSStructureRegister()
@*/
PetscErrorCode FSLoadPlugins(MPI_Comm comm)
{
  PetscFunctionBegin;
  PetscCall(FSPluginsProcess(comm, PETSC_TRUE));
  PetscFunctionReturn(0);
}
