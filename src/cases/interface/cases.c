/* The registry of cases (set-ups): -fs_case <name>. */
#include "solver/solverimpl.h"

static FSRegistry FSCases; /* src/sys/registry.c */

PETSC_EXTERN PetscErrorCode FSCaseCreate_TaylorGreen(FSSolver, FSCaseOps *);
PETSC_EXTERN PetscErrorCode FSCaseCreate_Shear(FSSolver, FSCaseOps *);
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
  PetscCall(FSCaseRegister("taylor_green", "Taylor-Green vortices in a periodic box (2-D, or extruded in 3-D); exact viscous decay", FSCaseCreate_TaylorGreen));
  PetscCall(FSCaseRegister("tank", "liquid at rest in a fixed tank: rectangular, baffled (the seed's) or from a file; hydrostatic start, wall loads", FSCaseCreate_Tank));
  PetscCall(FSCaseRegister("dam_break", "2-D dam break (Martin & Moyce 1952): a column a wide and 2a high collapses in a tank; surge front and column height", FSCaseCreate_DamBreak));
  PetscCall(FSCaseRegister("standing_wave", "linear standing wave (sloshing mode) in a rectangular tank with free-slip walls; linear theory's period and viscous decay", FSCaseCreate_StandingWave));
  PetscCall(FSCaseRegister("beam", "the dry structure alone, no liquid: free decay, static load (-fs_structure msd|modal, -fs_beam_*)", FSCaseCreate_Beam));
  PetscCall(FSCaseRegister("shear", "periodic shear flow u = U sin(2 pi y/L) in 2-D or 3-D; exact viscous decay", FSCaseCreate_Shear));
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
   FSCaseHelpAll - with -help, lists the options of every registered case besides the selected one,
   leaving the solver's parameters as the selected case set them.
*/
PetscErrorCode FSCaseHelpAll(FSSolver s, PetscOptionItems *PetscOptionsObject)
{
  FSCaseOps keepops = s->caseops;
  void     *keepdata = s->casedata;
  PetscReal keep[8] = {s->rho0, s->c0, s->nu, s->gravity[0], s->gravity[1], s->gravity[2], s->dx, s->final_time};

  PetscFunctionBegin;
  for (FSRegistryEntry *info = FSCases.first; info; info = info->next) {
    FSCaseCreateFn create;
    FSCaseOps      ops;
    if (!strcmp(info->name, s->casename)) continue;
    PetscCall(FSRegistryFind(&FSCases, info->name, (void (**)(void)) & create));
    PetscCall(PetscMemzero(&ops, sizeof(ops)));
    s->casedata = NULL;
    PetscCall((*create)(s, &ops));
    if (ops.setfromoptions) PetscCall((*ops.setfromoptions)(s, PetscOptionsObject));
    PetscCall(PetscFree(s->casedata));
  }
  s->caseops  = keepops;
  s->casedata = keepdata;
  s->rho0 = keep[0]; s->c0 = keep[1]; s->nu = keep[2];
  s->gravity[0] = keep[3]; s->gravity[1] = keep[4]; s->gravity[2] = keep[5];
  s->dx = keep[6]; s->final_time = keep[7];
  PetscFunctionReturn(0);
}
