/*
   Case "beam": the dry structure alone, with no liquid (no particles). The run advances only the
   structure's DOFs with the chosen integrator, its time step a fraction of the shortest period the
   structure resolves (-fs_structure_cfl) or -ts_dt. Uses: the static test (seed Fig. 3, with
   -fs_beam_force), the free decay of the solid-mass configuration (seed Fig. 5, with
   -fs_beam_preload), mode studies (-fs_modal_view). The structure defaults to "modal".
   The particle domain is a nominal unit box (no particle is created); the physics terms do nothing.
*/
#include <flexslosh.h>

static PetscErrorCode SetFromOptions(FSSolver s, PetscOptionItems *PetscOptionsObject)
{
  PetscReal g[3] = {0, 0, 0};

  PetscFunctionBegin;
  PetscCall(FSSolverSetDefaultPhysics(s, 1000.0, 20.0, 1e-6, g));
  PetscCall(FSSolverSetDefaultStructure(s, "modal"));
  PetscCall(FSSolverSetDefaultSpacing(s, 0.01));
  PetscCall(FSSolverSetDefaultFinalTime(s, 2.0));
  PetscFunctionReturn(0);
}

static PetscErrorCode SetUp(FSSolver s)
{
  PetscReal   lo[3] = {0, 0, 0}, hi[3] = {1, 1, 1};
  PetscBool   per[3] = {PETSC_FALSE, PETSC_FALSE, PETSC_FALSE};
  FSStructure st;

  PetscFunctionBegin;
  PetscCall(FSSolverGetStructure(s, &st));
  PetscCheck(st, PetscObjectComm((PetscObject)s), PETSC_ERR_ARG_WRONG,
             "Case beam computes the structure alone: it needs a structure, not -fs_structure none (msd or modal)");
  PetscCall(FSSolverSetDomain(s, lo, hi, per));
  PetscFunctionReturn(0);
}

PETSC_EXTERN PetscErrorCode FSCaseCreate_Beam(FSSolver s, FSCaseOps *ops)
{
  PetscFunctionBegin;
  PetscCall(FSSolverSetCaseData(s, NULL));
  ops->setfromoptions = SetFromOptions;
  ops->setup          = SetUp;
  PetscFunctionReturn(0);
}
