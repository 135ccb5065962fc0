static const char help[] = "flexslosh: liquid sloshing in tanks on flexible structures (delta-LES-SPH, PETSc TS).\n"
                           "  flexslosh -options_file cases/taylor_green.opts [-fs_dx 0.01 -ts_type ssp ...]\n"
                           "  -fs_case_view lists the cases, -fs_terms_view the physics terms, -fs_view the set-up.\n"
                           "  Options given but never used are reported at the end (-fs_options_left 0: not).\n\n";

#include <flexslosh.h>

int main(int argc, char **argv)
{
  FSSolver  solver;
  PetscBool help_only; /* -help lists the options (the solver's, its terms', its cases' and its TS's) and stops */

  PetscFunctionBeginUser;
  PetscCall(PetscInitialize(&argc, &argv, NULL, help));
  PetscCall(FSCheckPlugins(PETSC_COMM_WORLD));
  PetscCall(FSSolverCreate(PETSC_COMM_WORLD, &solver));
  PetscCall(FSSolverSetFromOptions(solver));
  PetscCall(PetscOptionsHasHelp(NULL, &help_only));
  if (!help_only) {
    PetscCall(FSSolverSetUp(solver));
    PetscCall(PetscObjectViewFromOptions((PetscObject)solver, NULL, "-fs_view"));
    PetscCall(FSSolverSolve(solver));
  }
  PetscCall(FSSolverDestroy(&solver));
  if (!help_only) PetscCall(FSOptionsLeft(PETSC_COMM_WORLD, 0, NULL)); /* a misspelt option: a warning */
  PetscCall(PetscFinalize());
  return 0;
}
