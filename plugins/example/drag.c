/*
   An example plug-in term built as its own shared library (libfsdrag.so) and loaded at run time:
     flexslosh -dll_append /path/to/libfsdrag.so -fs_terms continuity,delta,pressure,viscosity,drag -fs_drag_rate 2
   Term "drag": a linear drag D u_i/Dt += -k u_i with k = -fs_drag_rate (1/s). Kinetic energy then
   decays at an extra rate 2k, which the test suite checks on the Taylor-Green vortex.
   The entry point must be named after the file: libfsdrag.so -> PetscDLLibraryRegister_fsdrag.
*/
#include <flexslosh.h>

typedef struct {
  PetscReal k;
} Drag;

static void Source(FSTerm t, const FSParticles *P, PetscInt i, FSRate *rate)
{
  const Drag      *ctx = (const Drag *)t->data;
  const PetscReal *r   = &P->rec[i * P->stride];
  PetscReal        pw  = 0;
  for (PetscInt d = 0; d < P->dim; d++) {
    rate->du[d] -= ctx->k * r[P->dim + d];
    pw -= ctx->k * r[P->dim + d] * r[P->dim + d];
  }
  t->power += r[2 * P->dim + 1] * pw;
}

static PetscErrorCode SetFromOptions(FSTerm t, PetscOptionItems *PetscOptionsObject)
{
  Drag *ctx = (Drag *)t->data;

  PetscFunctionBegin;
  PetscOptionsHeadBegin(PetscOptionsObject, "Term drag (plug-in libfsdrag)");
  PetscCall(PetscOptionsReal("-fs_drag_rate", "Linear drag rate k (1/s)", "", ctx->k, &ctx->k, NULL));
  PetscOptionsHeadEnd();
  PetscCheck(ctx->k >= 0, PETSC_COMM_WORLD, PETSC_ERR_ARG_OUTOFRANGE, "-fs_drag_rate %g must be non-negative",
             (double)ctx->k);
  PetscFunctionReturn(0);
}

static PetscErrorCode Destroy(FSTerm t)
{
  PetscFunctionBegin;
  PetscCall(PetscFree(t->data));
  PetscFunctionReturn(0);
}

static PetscErrorCode CreateDrag(FSTerm t)
{
  Drag *ctx;

  PetscFunctionBegin;
  PetscCall(PetscNew(&ctx));
  ctx->k                = 1.0;
  t->data               = ctx;
  t->has_power          = PETSC_TRUE;
  t->ops.source         = Source;
  t->ops.setfromoptions = SetFromOptions;
  t->ops.destroy        = Destroy;
  PetscFunctionReturn(0);
}

/* The entry point PETSc calls when it loads libfsdrag.so. */
PETSC_EXTERN PetscErrorCode PetscDLLibraryRegister_fsdrag(void)
{
  PetscFunctionBegin;
  PetscCall(FSTermRegister("drag", "linear drag -k u (example plug-in, -fs_drag_rate)", CreateDrag));
  PetscFunctionReturn(0);
}
