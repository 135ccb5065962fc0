/*
   Structure models defined by callbacks: FSStructureRegisterCallbacks(name, description, callbacks, ctx)
   registers a model whose operations call the function pointers given, through the same registry as
   the built-in models (-fs_structure name selects it). The Python package registers its Structure
   classes so (flexslosh.register_structure); a C program can build models at run time the same way.

   Each FSStructure of such a model gets its own instance: create(ctx, st, &impl) makes it (without
   create the instance is ctx itself), and every other callback receives it. A callback returns 0, or
   non-zero after FSStructureCallbacksSetError(message): the message becomes a PETSc error naming the
   model and the callback, so an exception raised in Python ends as an error, not a crash. A non-zero
   return without a message is passed on as the callback's own PETSc error.
*/
#include <flexslosh.h>

typedef struct _n_FSCallbackEntry {
  char                       name[64];
  FSStructureCallbacks       cb;
  void                      *ctx;
  struct _n_FSCallbackEntry *next;
} FSCallbackEntry;

/* the registered callbacks by name; like the registry, allocated with calloc and never freed */
static FSCallbackEntry *FSCallbackEntries;
static char             FSCallbackMessage[1024];

typedef struct {
  FSStructureCallbacks cb;
  void                *impl;
  PetscBool            created; /* impl comes from cb.create (destroyed with cb.destroy) */
} Callbacks;

/*
   FSStructureCallbacksSetError - the message of the error a callback is about to return (for example
   a Python exception's type and text). The model's operation then raises a PETSc error with it.

   Not collective

   Input Parameter:
.  message - the text

.seealso: FSStructureRegisterCallbacks()
*/
PetscErrorCode FSStructureCallbacksSetError(const char message[])
{
  PetscFunctionBegin;
  PetscCall(PetscStrncpy(FSCallbackMessage, message ? message : "", sizeof(FSCallbackMessage)));
  PetscFunctionReturn(0);
}

/* a callback's status: its message as a new error, or its own PETSc error passed on */
static PetscErrorCode CallbackCheck(FSStructure st, const char op[], PetscErrorCode ierr)
{
  char msg[sizeof(FSCallbackMessage)];

  PetscFunctionBegin;
  if (!ierr) PetscFunctionReturn(0);
  if (FSCallbackMessage[0]) {
    PetscCall(PetscStrncpy(msg, FSCallbackMessage, sizeof(msg)));
    FSCallbackMessage[0] = 0;
    SETERRQ(PETSC_COMM_SELF, PETSC_ERR_USER, "Structure %s: its %s callback failed: %s", st->name, op, msg);
  }
  PetscCall(ierr);
  PetscFunctionReturn(0);
}

static PetscErrorCode SetUp(FSStructure st)
{
  Callbacks *c    = (Callbacks *)st->data;
  PetscInt   ndof = -1;
  PetscReal  T    = 0;

  PetscFunctionBegin;
  PetscCall(CallbackCheck(st, "setup", (*c->cb.setup)(c->impl, st, &ndof, &T)));
  PetscCheck(ndof >= 0, st->comm, PETSC_ERR_ARG_OUTOFRANGE,
             "Structure %s: its setup callback gave %" PetscInt_FMT " DOFs: expected a non-negative number", st->name,
             ndof);
  PetscCheck(T >= 0, st->comm, PETSC_ERR_ARG_OUTOFRANGE,
             "Structure %s: its setup callback gave the shortest period %g: expected a non-negative number (0: none)",
             st->name, (double)T);
  st->ndof       = ndof;
  st->min_period = T;
  PetscFunctionReturn(0);
}

static PetscErrorCode Initial(FSStructure st, PetscReal y[])
{
  Callbacks *c = (Callbacks *)st->data;

  PetscFunctionBegin;
  PetscCall(PetscArrayzero(y, st->ndof));
  if (c->cb.initial) PetscCall(CallbackCheck(st, "initial", (*c->cb.initial)(c->impl, st->ndof, y)));
  PetscFunctionReturn(0);
}

static PetscErrorCode RHS(FSStructure st, PetscReal t, const PetscReal y[], const FSLoads *loads, PetscReal ydot[])
{
  Callbacks *c = (Callbacks *)st->data;

  PetscFunctionBegin;
  PetscCall(CallbackCheck(st, "rhs", (*c->cb.rhs)(c->impl, t, st->ndof, y, loads, ydot)));
  PetscFunctionReturn(0);
}

static PetscErrorCode Motion(FSStructure st, PetscReal t, const PetscReal y[], const PetscReal ydot[], FSTankMotion *m)
{
  Callbacks *c = (Callbacks *)st->data;

  PetscFunctionBegin;
  PetscCall(PetscMemzero(m, sizeof(*m)));
  PetscCall(CallbackCheck(st, "motion", (*c->cb.motion)(c->impl, st->ndof, y, ydot, m)));
  PetscFunctionReturn(0);
}

static PetscErrorCode Columns(FSStructure st, PetscReal t, const PetscReal y[], const PetscReal ydot[],
                              PetscReal vals[])
{
  Callbacks *c = (Callbacks *)st->data;

  PetscFunctionBegin;
  PetscCall(CallbackCheck(st, "columns", (*c->cb.columns)(c->impl, t, st->ndof, y, ydot, st->ncolumns, vals)));
  PetscFunctionReturn(0);
}

static PetscErrorCode Energy(FSStructure st, const PetscReal y[], PetscReal E[3])
{
  Callbacks *c = (Callbacks *)st->data;

  PetscFunctionBegin;
  E[0] = E[1] = E[2] = 0;
  PetscCall(CallbackCheck(st, "energy", (*c->cb.energy)(c->impl, st->ndof, y, E)));
  PetscFunctionReturn(0);
}

static PetscErrorCode View(FSStructure st, PetscViewer viewer)
{
  PetscFunctionBegin;
  PetscCall(PetscViewerASCIIPrintf(viewer, "defined by callbacks: %" PetscInt_FMT " DOFs, shortest period %g s\n",
                                   st->ndof, (double)st->min_period));
  PetscFunctionReturn(0);
}

static PetscErrorCode Destroy(FSStructure st)
{
  Callbacks *c = (Callbacks *)st->data;

  PetscFunctionBegin;
  if (c->created && c->cb.destroy) PetscCall(CallbackCheck(st, "destroy", (*c->cb.destroy)(c->impl)));
  PetscCall(PetscFree(st->data));
  PetscFunctionReturn(0);
}

/* the creation routine of every callback model: finds the callbacks registered under the structure's name */
static PetscErrorCode FSStructureCreate_Callbacks(FSStructure st)
{
  FSCallbackEntry *e = FSCallbackEntries;
  Callbacks       *c;

  PetscFunctionBegin;
  while (e && strcmp(e->name, st->name)) e = e->next;
  PetscCheck(e, st->comm, PETSC_ERR_PLIB, "Structure %s has no registered callbacks", st->name);
  PetscCall(PetscNew(&c));
  c->cb           = e->cb; /* a copy: registering the name again does not change this instance */
  c->impl         = e->ctx;
  st->data        = c;
  st->ops.setup   = SetUp;
  st->ops.initial = Initial;
  st->ops.rhs     = RHS;
  st->ops.motion  = Motion;
  st->ops.columns = e->cb.columns ? Columns : NULL;
  st->ops.energy  = e->cb.energy ? Energy : NULL;
  st->ops.view    = View;
  st->ops.destroy = Destroy;
  st->rank0       = PETSC_TRUE; /* a callback may keep state of its own or print: it runs once, on rank 0 */
  if (e->cb.create) {
    PetscCall(CallbackCheck(st, "create", (*e->cb.create)(e->ctx, st, &c->impl)));
    c->created = PETSC_TRUE;
  }
  PetscFunctionReturn(0);
}

/*
   FSStructureRegisterCallbacks - registers a structure model whose operations are the callbacks given,
   under a name for -fs_structure, as FSStructureRegister() does for models written in C.

   Not collective

   Input Parameters:
+  name        - the name used in -fs_structure
.  description - one line (-fs_structure_view)
.  cb          - the callbacks (copied); setup, rhs and motion are required
-  ctx         - passed to cb->create, or, without create, the instance every callback receives

   Notes:
   The callbacks are called on the ranks FSStructureCallbacks says; they must stay valid while a
   solver uses the model. Registering a name again replaces its callbacks for the structures created
   afterwards.

.seealso: FSStructureRegister(), FSStructureCallbacksSetError(), FSStructureAddColumn()
*/
PetscErrorCode FSStructureRegisterCallbacks(const char name[], const char description[], const FSStructureCallbacks *cb,
                                            void *ctx)
{
  FSCallbackEntry *e = FSCallbackEntries, *last = NULL;

  PetscFunctionBegin;
  PetscCheck(cb && cb->setup && cb->rhs && cb->motion, PETSC_COMM_SELF, PETSC_ERR_ARG_NULL,
             "Structure %s: the callbacks setup, rhs and motion are required", name);
  for (; e; last = e, e = e->next)
    if (!strcmp(e->name, name)) break;
  if (!e) {
    e = (FSCallbackEntry *)calloc(1, sizeof(*e));
    PetscCheck(e, PETSC_COMM_SELF, PETSC_ERR_MEM, "Out of memory registering %s", name);
    if (last) last->next = e;
    else FSCallbackEntries = e;
  }
  PetscCall(PetscStrncpy(e->name, name, sizeof(e->name)));
  e->cb  = *cb;
  e->ctx = ctx;
  PetscCall(FSStructureRegister(name, description, FSStructureCreate_Callbacks));
  PetscFunctionReturn(0);
}
