/* Term "gravity": the body force g (option -fs_gravity), D u_i/Dt += g (seed Eq. 4). */
#include <flexslosh.h>

static void Source(FSTerm t, const FSParticles *P, PetscInt i, FSRate *rate)
{
  (void)t;
  (void)i;
  for (PetscInt d = 0; d < P->dim; d++) rate->du[d] += P->gravity[d];
}

PETSC_EXTERN PetscErrorCode FSTermCreate_Gravity(FSTerm t)
{
  PetscFunctionBegin;
  t->ops.source = Source;
  PetscFunctionReturn(0);
}
