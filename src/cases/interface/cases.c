/* The registry of cases (set-ups): -fs_case <name>. */
#include <flexslosh.h>
#include "sys/fssys.h"
#include "cases/fscases.h"

static FSRegistry FSCases; /* src/sys/registry.c */

PETSC_EXTERN PetscErrorCode FSCaseCreate_TaylorGreen(FSSolver, FSCaseOps *);
PETSC_EXTERN PetscErrorCode FSCaseCreate_Shear(FSSolver, FSCaseOps *);
PETSC_EXTERN PetscErrorCode FSCaseCreate_Channel(FSSolver, FSCaseOps *);
PETSC_EXTERN PetscErrorCode FSCaseCreate_Drop(FSSolver, FSCaseOps *);
PETSC_EXTERN PetscErrorCode FSCaseCreate_Beam(FSSolver, FSCaseOps *);
PETSC_EXTERN PetscErrorCode FSCaseCreate_Tank(FSSolver, FSCaseOps *);
PETSC_EXTERN PetscErrorCode FSCaseCreate_DamBreak(FSSolver, FSCaseOps *);
PETSC_EXTERN PetscErrorCode FSCaseCreate_StandingWave(FSSolver, FSCaseOps *);

/*
   FSCaseRegister - adds a case (a set-up routine) to the registry.

   Input Parameters:
+  name        - the name used in -fs_case
.  description - one line
-  create      - fills the case's ops
*/
PetscErrorCode FSCaseRegister(const char name[], const char description[], FSCaseCreateFn create)
{
  PetscFunctionBegin;
  PetscCall(FSRegistryAdd(&FSCases, name, description, (void (*)(void))create));
  PetscFunctionReturn(0);
}

/* FSCaseRegisterAll - registers the built-in cases (idempotent). */
PetscErrorCode FSCaseRegisterAll(void)
{
  static PetscBool done = PETSC_FALSE;

  PetscFunctionBegin;
  if (done) PetscFunctionReturn(0);
  done = PETSC_TRUE;
  PetscCall(FSCaseRegister("taylor_green",
                           "Taylor-Green vortices in a periodic box (2-D, or extruded in 3-D); exact viscous decay",
                           FSCaseCreate_TaylorGreen));
  PetscCall(FSCaseRegister(
      "tank",
      "liquid at rest in a fixed tank: rectangular, baffled (the seed's) or from a file; hydrostatic start, wall loads",
      FSCaseCreate_Tank));
  PetscCall(FSCaseRegister("dam_break",
                           "2-D dam break (Martin & Moyce 1952): a column a wide and 2a high collapses in a tank; "
                           "surge front and column height",
                           FSCaseCreate_DamBreak));
  PetscCall(FSCaseRegister("standing_wave",
                           "linear standing wave (sloshing mode) in a rectangular tank with free-slip walls; linear "
                           "theory's period and viscous decay",
                           FSCaseCreate_StandingWave));
  PetscCall(FSCaseRegister(
      "beam", "the dry structure alone, no liquid: free decay, static load (-fs_structure msd|modal, -fs_beam_*)",
      FSCaseCreate_Beam));
  PetscCall(FSCaseRegister("shear", "periodic shear flow u = U sin(2 pi y/L) in 2-D or 3-D; exact viscous decay",
                           FSCaseCreate_Shear));
  PetscCall(FSCaseRegister("channel",
                           "plane channel flow between two walls, periodic along x (and z), driven by a body force: "
                           "Poiseuille start-up with -fs_walls_noslip floor,lid",
                           FSCaseCreate_Channel));
  PetscCall(
      FSCaseRegister("drop",
                     "a free drop without walls or gravity (square or ellipse; 2-D or 3-D) for the surface tension "
                     "term: Laplace pressure and oscillation",
                     FSCaseCreate_Drop));
  PetscFunctionReturn(0);
}

PetscErrorCode FSCaseFind(const char name[], FSCaseCreateFn *create)
{
  PetscFunctionBegin;
  PetscCall(FSCaseRegisterAll());
  PetscCall(FSRegistryFind(&FSCases, name, (void (**)(void))create));
  PetscFunctionReturn(0);
}

/* FSCaseListView - prints every registered case with its description. */
PetscErrorCode FSCaseListView(PetscViewer viewer)
{
  PetscFunctionBegin;
  PetscCall(FSRegistryView(&FSCases, viewer, "cases", "select with -fs_case name"));
  PetscFunctionReturn(0);
}

/*
   FSCaseHelpAll - with -help, lists the options of every registered case besides the selected one.
   Each case is created and reads its options on a scratch solver of its own, so that the run's
   solver keeps the parameters its case set. Called inside the solver's options block.

   Collective

   Input Parameters:
+  s                  - the run's solver (its communicator)
.  selected           - the name of the run's case, whose options the solver lists itself
-  PetscOptionsObject - the solver's options block
*/
PetscErrorCode FSCaseHelpAll(FSSolver s, const char selected[], PetscOptionItems *PetscOptionsObject)
{
  PetscFunctionBegin;
  for (FSRegistryEntry *info = FSCases.first; info; info = info->next) {
    FSCaseCreateFn create;
    FSCaseOps      ops;
    FSSolver       scratch;
    if (!strcmp(info->name, selected)) continue;
    PetscCall(FSRegistryFind(&FSCases, info->name, (void (**)(void)) & create));
    PetscCall(PetscMemzero(&ops, sizeof(ops)));
    PetscCall(FSSolverCreate(PetscObjectComm((PetscObject)s), &scratch));
    PetscCall((*create)(scratch, &ops));
    PetscCall(FSOptionsSurveyOwner("case", info->name));
    if (ops.setfromoptions) PetscCall((*ops.setfromoptions)(scratch, PetscOptionsObject));
    PetscCall(FSOptionsSurveyOwner(NULL, NULL));
    PetscCall(FSSolverDestroy(&scratch));
  }
  PetscFunctionReturn(0);
}
