/*
   The registry of physics terms (as TSRegister does for TS types; the table is src/sys/registry.c).
   Built-in terms register in FSTermRegisterAll; plug-ins call FSTermRegister from their
   PetscDLLibraryRegister_<name>() entry point.
*/
#include "terms/fsterms.h"
#include "sys/fssys.h"

PETSC_EXTERN PetscErrorCode FSTermCreate_Continuity(FSTerm);
PETSC_EXTERN PetscErrorCode FSTermCreate_Delta(FSTerm);
PETSC_EXTERN PetscErrorCode FSTermCreate_Pressure(FSTerm);
PETSC_EXTERN PetscErrorCode FSTermCreate_Viscosity(FSTerm);
PETSC_EXTERN PetscErrorCode FSTermCreate_LESViscosity(FSTerm);
PETSC_EXTERN PetscErrorCode FSTermCreate_Gravity(FSTerm);
PETSC_EXTERN PetscErrorCode FSTermCreate_Shifting(FSTerm);
PETSC_EXTERN PetscErrorCode FSTermCreate_TensileControl(FSTerm);
PETSC_EXTERN PetscErrorCode FSTermCreate_SurfaceTension(FSTerm);
PETSC_EXTERN PetscErrorCode FSTermCreate_WallContinuity(FSTerm);
PETSC_EXTERN PetscErrorCode FSTermCreate_WallPressure(FSTerm);
PETSC_EXTERN PetscErrorCode FSTermCreate_WallViscosity(FSTerm);

static FSRegistry FSTerms; /* src/sys/registry.c */

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
  PetscFunctionBegin;
  PetscCall(FSRegistryAdd(&FSTerms, name, description, (void (*)(void))create));
  PetscFunctionReturn(0);
}

/* FSTermListView - prints every registered term with its description. */
PetscErrorCode FSTermListView(PetscViewer viewer)
{
  PetscFunctionBegin;
  PetscCall(FSRegistryView(&FSTerms, viewer, "physics terms", "select with -fs_terms name1,name2,..."));
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
  PetscCall(FSRegistryFind(&FSTerms, name, (void (**)(void)) & create));
  if (!create) {
    char known[2048];
    PetscCall(FSRegistryNames(&FSTerms, known, sizeof(known)));
    SETERRQ(PetscObjectComm((PetscObject)s), PETSC_ERR_ARG_UNKNOWN_TYPE,
            "Unknown physics term \"%s\" in -fs_terms: the registered terms are%s (load plug-ins with -dll_append, "
            "list with -fs_terms_view)",
            name, known);
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
PetscErrorCode FSTermHelpAll(FSSolver s, const FSTermSet *set, PetscOptionItems *PetscOptionsObject)
{
  PetscFunctionBegin;
  for (FSRegistryEntry *info = FSTerms.first; info; info = info->next) {
    PetscBool selected = PETSC_FALSE;
    FSTerm    t;
    for (PetscInt k = 0; k < set->nterms; k++)
      if (!strcmp(set->term[k]->name, info->name)) selected = PETSC_TRUE;
    if (selected) continue;
    PetscCall(FSTermCreate(s, info->name, &t));
    PetscCall(FSOptionsSurveyOwner("term", info->name));
    if (t->ops.setfromoptions) PetscCall((*t->ops.setfromoptions)(t, PetscOptionsObject));
    PetscCall(FSOptionsSurveyOwner(NULL, NULL));
    PetscCall(FSTermDestroy(&t));
  }
  PetscFunctionReturn(0);
}

/*
   FSTermRegisterAll - registers the built-in physics terms (idempotent).
*/
PetscErrorCode FSTermRegisterAll(void)
{
  static PetscBool done = PETSC_FALSE;

  PetscFunctionBegin;
  if (done) PetscFunctionReturn(0);
  done = PETSC_TRUE;
  PetscCall(FSTermRegister("continuity", "continuity equation -rho_i sum (u_j - u_i).gradW V_j (seed Eq. 4)",
                           FSTermCreate_Continuity));
  PetscCall(FSTermRegister("delta",
                           "delta-LES density diffusion with the renormalized density gradient (seed Eqs. 4-9)",
                           FSTermCreate_Delta));
  PetscCall(FSTermRegister("pressure", "pressure gradient, (p_i + p_j) form, linear equation of state (seed Eqs. 2, 4)",
                           FSTermCreate_Pressure));
  PetscCall(FSTermRegister("viscosity", "laminar viscosity K nu sum Pi_ij gradW V_j from -fs_nu (seed Eqs. 4, 5, 11)",
                           FSTermCreate_Viscosity));
  PetscCall(FSTermRegister("les_viscosity", "delta-LES turbulent (Smagorinsky) viscosity (seed Eqs. 11-13)",
                           FSTermCreate_LESViscosity));
  PetscCall(FSTermRegister("gravity", "body force -fs_gravity", FSTermCreate_Gravity));
  PetscCall(FSTermRegister("wall_continuity", "boundary-integral wall part of the continuity equation (seed Eq. 14)",
                           FSTermCreate_WallContinuity));
  PetscCall(FSTermRegister("wall_pressure",
                           "boundary-integral wall part of the pressure gradient; wall loads (seed Eqs. 14, 29)",
                           FSTermCreate_WallPressure));
  PetscCall(FSTermRegister("wall_viscosity", "wall shear stress on no-slip walls (-fs_walls_noslip)",
                           FSTermCreate_WallViscosity));
  PetscCall(FSTermRegister("shifting", "particle shifting of delta+-SPH (Sun et al. 2017), keeps the particles regular",
                           FSTermCreate_Shifting));
  PetscCall(FSTermRegister("tensile_control",
                           "tensile instability control of delta+-SPH (Sun et al. 2017): (p_j - p_i) where p_i < 0",
                           FSTermCreate_TensileControl));
  PetscCall(FSTermRegister("surface_tension",
                           "surface tension: pairwise cohesion calibrated to -fs_surface_tension_sigma, conserves "
                           "momentum",
                           FSTermCreate_SurfaceTension));
  PetscFunctionReturn(0);
}
