/*
   An example plug-in structure built as its own shared library (libfsspring.so), loaded at run time:
     flexslosh -dll_append /path/to/libfsspring.so -fs_case beam -fs_structure spring -fs_spring_frequency 2
   Structure "spring": the tank on an undamped linear spring, w'' = -omega^2 w + F_y/m, released from
   w(0) = -fs_spring_amplitude at rest: w(t) = A cos(omega t). The entry point must be named after
   the file: libfsspring.so -> PetscDLLibraryRegister_fsspring.
*/
#include <flexslosh.h>

typedef struct {
  PetscReal f, m, A;
} Spring;

static PetscErrorCode SetFromOptions(FSStructure st, PetscOptionItems *PetscOptionsObject)
{
  Spring *p = (Spring *)st->data;

  PetscFunctionBegin;
  PetscOptionsHeadBegin(PetscOptionsObject, "Structure spring (plug-in libfsspring)");
  PetscCall(PetscOptionsReal("-fs_spring_frequency", "Natural frequency (Hz)", "", p->f, &p->f, NULL));
  PetscCheck(p->f > 0, st->comm, PETSC_ERR_ARG_OUTOFRANGE, "-fs_spring_frequency %g must be positive", (double)p->f);
  PetscCall(PetscOptionsReal("-fs_spring_mass", "Moving mass (kg)", "", p->m, &p->m, NULL));
  PetscCheck(p->m > 0, st->comm, PETSC_ERR_ARG_OUTOFRANGE, "-fs_spring_mass %g must be positive", (double)p->m);
  PetscCall(PetscOptionsReal("-fs_spring_amplitude", "Initial deflection (m)", "", p->A, &p->A, NULL));
  PetscOptionsHeadEnd();
  PetscFunctionReturn(0);
}

static PetscErrorCode SetUp(FSStructure st)
{
  Spring *p = (Spring *)st->data;

  PetscFunctionBegin;
  st->ndof       = 2;
  st->min_period = 1 / p->f;
  PetscFunctionReturn(0);
}

static PetscErrorCode Initial(FSStructure st, PetscReal y[])
{
  Spring *p = (Spring *)st->data;

  PetscFunctionBegin;
  y[0] = p->A;
  y[1] = 0;
  PetscFunctionReturn(0);
}

static PetscErrorCode RHS(FSStructure st, PetscReal t, const PetscReal y[], const FSLoads *loads, PetscReal ydot[])
{
  Spring         *p = (Spring *)st->data;
  const PetscReal w = 2 * PETSC_PI * p->f;

  PetscFunctionBegin;
  ydot[0] = y[1];
  ydot[1] = -w * w * y[0] + loads->force[1] / p->m;
  PetscFunctionReturn(0);
}

static PetscErrorCode Motion(FSStructure st, PetscReal t, const PetscReal y[], const PetscReal ydot[], FSTankMotion *m)
{
  PetscFunctionBegin;
  PetscCall(PetscMemzero(m, sizeof(*m)));
  m->disp[1] = y[0];
  m->vel[1]  = y[1];
  m->acc[1]  = ydot[1];
  PetscFunctionReturn(0);
}

static PetscErrorCode Destroy(FSStructure st)
{
  PetscFunctionBegin;
  PetscCall(PetscFree(st->data));
  PetscFunctionReturn(0);
}

static PetscErrorCode CreateSpring(FSStructure st)
{
  Spring *p;

  PetscFunctionBegin;
  PetscCall(PetscNew(&p));
  p->f                   = 1.0;
  p->m                   = 1.0;
  p->A                   = 0.01;
  st->data               = p;
  st->ops.setfromoptions = SetFromOptions;
  st->ops.setup          = SetUp;
  st->ops.initial        = Initial;
  st->ops.rhs            = RHS;
  st->ops.motion         = Motion;
  st->ops.destroy        = Destroy;
  PetscFunctionReturn(0);
}

/* The entry point PETSc calls when it loads libfsspring.so. */
PETSC_EXTERN PetscErrorCode PetscDLLibraryRegister_fsspring(void)
{
  PetscFunctionBegin;
  PetscCall(FSStructureRegister("spring", "undamped linear oscillator (example plug-in, -fs_spring_*)", CreateSpring));
  PetscFunctionReturn(0);
}
