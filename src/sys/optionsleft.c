/*
   Options given but never used: a misspelt option (-fs_dx_ 0.1) would otherwise be ignored in
   silence. PETSc lists them at PetscFinalize() only with -options_left; flexslosh warns by default.
*/
#include "sys/fssys.h"

/*@C
   FSOptionsLeft - Warns about the options of PETSc's database that were given but never used.

   Collective

   Input Parameters:
+  comm  - the communicator of the run (rank 0 prints)
.  n     - the number of names, or 0 for every option of the database
-  names - the options to check (without the leading '-'), e.g. those a driver set; NULL with n = 0

   Options Database Keys:
+  -fs_options_left <true> - warn (false: silence the warnings)
-  -options_left <bool>    - PETSc's own report at PetscFinalize(): when given, true or false, it replaces
                             this one, which then prints nothing

   Notes:
   Call it at the end of a run, after the options were read (the executable calls it before
   PetscFinalize(), the Python package when a Solver is destroyed). Each unused option is one line
   "Warning: option -NAME [VALUE] was given but never used ...". Options are read on rank 0 as on the
   others, so rank 0's list is reported.

.seealso: FSSolverSetFromOptions()
@*/
PetscErrorCode FSOptionsLeft(MPI_Comm comm, PetscInt n, const char *const names[])
{
  PetscBool set, warn = PETSC_TRUE, petsc;
  PetscInt  N;
  char    **left, **values;

  PetscFunctionBegin;
  PetscCall(PetscOptionsGetBool(NULL, NULL, "-options_left", &petsc, &set));
  if (set) PetscFunctionReturn(0); /* PETSc reports them, or was told not to */
  PetscCall(PetscOptionsGetBool(NULL, NULL, "-fs_options_left", &warn, NULL));
  if (!warn) PetscFunctionReturn(0);
  PetscCall(PetscOptionsLeftGet(NULL, &N, &left, &values));
  for (PetscInt k = 0; k < N; k++) {
    PetscBool mine = (PetscBool)(n == 0);
    for (PetscInt j = 0; j < n && !mine; j++) {
      const char *name = names[j][0] == '-' ? names[j] + 1 : names[j];
      PetscCall(PetscStrcasecmp(name, left[k], &mine));
    }
    if (!mine) continue;
    PetscCall(PetscPrintf(comm,
                          "Warning: option -%s%s%s was given but never used (misspelt, or not an option of this "
                          "set-up); -fs_options_left 0 silences this warning\n",
                          left[k], values[k] ? " " : "", values[k] ? values[k] : ""));
  }
  PetscCall(PetscOptionsLeftRestore(NULL, &N, &left, &values));
  PetscFunctionReturn(0);
}
