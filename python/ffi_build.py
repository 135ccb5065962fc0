"""Generates the C source of the flexslosh package's binding, the cffi extension module _flexslosh_cffi.

    /usr/bin/python3 python/ffi_build.py OUT.c

cffi in API mode ("out of line"): the declarations below (CDEF) say what Python may call, and the
generated C source compiles them against include/flexslosh.h itself, so the C compiler, not this file,
decides every size and layout. python/CMakeLists.txt runs this script and compiles OUT.c with
-Werror=incompatible-pointer-types and its kin, so a declaration here that drifts from the header is a
build error, not a corrupted call:
  - PetscInt, PetscReal, ... are `int...` / `float...`: their size is the compiler's;
  - FSLoads and FSTankMotion end with `...;`: cffi takes their layout from the compiler and checks the
    type of every field it names (a field renamed, removed or retyped in the header fails to compile);
  - every function declared from the header is also assigned to a pointer of the type declared here
    (PROTOTYPE_CHECKS), which fails unless the two types are the same;
  - the FSStructureCallbacks table is filled in C with the extern "Python" callbacks, so each of them is
    checked against the member it fills.
"""
from __future__ import annotations

import re
import sys

import cffi

MODULE = "_flexslosh_cffi"

# What Python calls in libflexslosh and PETSc, as declared in include/flexslosh.h and PETSc's headers.
HEADER_FUNCTIONS = """
PetscErrorCode FSInitializePackage(void);
PetscErrorCode FSSolverSetFromOptions(FSSolver);
PetscErrorCode FSSolverSetUp(FSSolver);
PetscErrorCode FSSolverSetOptionsChecked(FSSolver, PetscInt, const char *const[]);
PetscErrorCode FSSolverStep(FSSolver);
PetscErrorCode FSSolverSolve(FSSolver);
PetscErrorCode FSSolverDestroy(FSSolver *);
PetscErrorCode FSSolverGetTS(FSSolver, TS *);
PetscErrorCode FSSolverGetSwarm(FSSolver, DM *);
PetscErrorCode FSSolverGetTime(FSSolver, PetscReal *, PetscInt *);
PetscErrorCode FSSolverGetDimension(FSSolver, PetscInt *);
PetscErrorCode FSSolverGetLocalSize(FSSolver, PetscInt *);
PetscErrorCode FSSolverGetField(FSSolver, const char[], PetscInt *, PetscInt *, const PetscReal *[]);
PetscErrorCode FSSolverRestoreField(FSSolver, const char[], PetscInt *, PetscInt *, const PetscReal *[]);
PetscErrorCode FSSolverGetWallLoads(FSSolver, PetscInt *, const char *[], const PetscReal *[]);
PetscErrorCode FSSolverGetEnergy(FSSolver, PetscInt *, const char *[], PetscReal[]);
PetscErrorCode FSSolverGetProbes(FSSolver, PetscInt *, const char *[], PetscInt[], PetscReal[]);
PetscErrorCode FSSolverGetLiquidMass(FSSolver, PetscReal *);
PetscErrorCode FSSolverGetStructureState(FSSolver, PetscInt *, PetscReal[]);
PetscErrorCode FSSolverGetTankMotion(FSSolver, FSTankMotion *);
PetscErrorCode FSStructureGetSolver(FSStructure, FSSolver *);
PetscErrorCode FSStructureAddColumn(FSStructure, const char[]);
PetscErrorCode FSStructureCallbacksSetError(const char[]);
PetscErrorCode FSStructureRegisterCallbacks(const char[], const char[], const FSStructureCallbacks *, void *);
PetscErrorCode FSSolverWriteCheckpoint(FSSolver);
PetscErrorCode PetscErrorMessage(int, const char *[], char **);
PetscErrorCode PetscOptionsDestroy(PetscOptions *);
"""

# The helpers of PREAMBLE: what cffi cannot declare portably (MPI_Comm by value, a function pointer
# taking one, Python objects), written in C so that the compiler checks their calls too.
HELPER_FUNCTIONS = """
PetscErrorCode fs_py_load_plugins(const MPI_Comm *);
PetscErrorCode fs_py_solver_create(const MPI_Comm *, FSSolver *);
PetscErrorCode fs_py_options_insert_file(const MPI_Comm *, PetscOptions, const char[], PetscBool);
PetscErrorCode fs_py_options_left(const MPI_Comm *, PetscInt, char *[]);
PetscErrorCode fs_py_options_copy_default(PetscOptions *);
int fs_py_depth(void);
int fs_py_enter(PetscOptions);
void fs_py_leave(int);
int fs_py_entered(PetscOptions);
const FSStructureCallbacks *fs_py_structure_callbacks(void);
int fs_py_wrap_ts(TS, void *, void *);
int fs_py_wrap_dm(DM, void *, void *);
int fs_py_gil_held(void);
"""

# The callbacks of a Python structure model (flexslosh.structure defines them with ffi.def_extern).
CALLBACKS = """
extern "Python" PetscErrorCode fs_py_structure_create(void *, FSStructure, void **);
extern "Python" PetscErrorCode fs_py_structure_setup(void *, FSStructure, PetscInt *, PetscReal *);
extern "Python" PetscErrorCode fs_py_structure_initial(void *, PetscInt, PetscReal[]);
extern "Python" PetscErrorCode fs_py_structure_rhs(void *, PetscReal, PetscInt, const PetscReal[], const FSLoads *, PetscReal[]);
extern "Python" PetscErrorCode fs_py_structure_motion(void *, PetscInt, const PetscReal[], const PetscReal[], FSTankMotion *);
extern "Python" PetscErrorCode fs_py_structure_columns(void *, PetscReal, PetscInt, const PetscReal[], const PetscReal[], PetscInt, PetscReal[]);
extern "Python" PetscErrorCode fs_py_structure_energy(void *, PetscInt, const PetscReal[], PetscReal[3]);
extern "Python" PetscErrorCode fs_py_structure_destroy(void *);
"""

CDEF = """
typedef int... PetscInt;
typedef int... PetscErrorCode;
typedef int... PetscBool;
typedef float... PetscReal;
typedef ... MPI_Comm;
typedef ... *TS;
typedef ... *DM;
typedef ... *FSSolver;
typedef ... *FSStructure;
typedef ... *PetscOptions;
typedef struct { PetscReal force[3], moment[3]; ...; } FSLoads;
typedef struct { PetscReal disp[3], vel[3], acc[3]; PetscReal angle, rate, angacc; PetscReal rotated, Q[9], w[3], dw[3]; ...; } FSTankMotion;
typedef struct { ...; } FSStructureCallbacks;
#define FS_ENERGY_MAX_COLUMNS ...
#define FS_PROBE_MAX_VALUES ...
extern PetscBool PetscInitializeCalled;
""" + HEADER_FUNCTIONS + HELPER_FUNCTIONS + CALLBACKS

PREAMBLE = r"""
#include <flexslosh.h>
#include <petsc4py/petsc4py.h>

/* -- the helpers ---------------------------------------------------------------------------------- */
/* MPI_Comm is a pointer in Open MPI and an int in MPICH: Python hands in the address of the handle
   (mpi4py's MPI._addressof(comm)) and C reads it with its own type. */
static PetscErrorCode fs_py_load_plugins(const MPI_Comm *comm) { return FSLoadPlugins(*comm); }
static PetscErrorCode fs_py_solver_create(const MPI_Comm *comm, FSSolver *s) { return FSSolverCreate(*comm, s); }
static PetscErrorCode fs_py_options_insert_file(const MPI_Comm *comm, PetscOptions options, const char file[],
                                                PetscBool require)
{
  return PetscOptionsInsertFile(*comm, options, file, require);
}
static PetscErrorCode fs_py_options_left(const MPI_Comm *comm, PetscInt n, char *names[])
{
  return FSOptionsLeft(*comm, n, (const char *const *)names);
}

/* A solver's own options database: a new one holding what the default database (the command line given
   to petsc4py.init, PETSC_OPTIONS, flexslosh.set_options) holds now, as "-name value" items; PETSc keeps
   no -options_file or -prefix_push items (it reads them as it inserts), so the copy reads as the original. */
static PetscErrorCode fs_py_options_copy_default(PetscOptions *options)
{
  char *all;

  PetscFunctionBegin;
  *options = NULL;
  PetscCall(PetscOptionsGetAll(NULL, &all));
  PetscCall(PetscOptionsCreate(options)); /* the caller destroys it, also after an error below */
  PetscCall(PetscOptionsInsertString(*options, all));
  PetscCall(PetscFree(all));
  PetscFunctionReturn(0);
}

/* -- the calls' context: a solver's options and the error handler -------------------------------------
   Each call into the C core for a solver runs with that solver's options database pushed as PETSc's
   default (PetscOptionsPush: every PetscOptionsGet...(NULL, ...) of the core and of PETSc reads it) and
   FSErrorHandler pushed (its short report; FSErrorTraceHandler, PETSc's full one, with -fs_error_trace in the
   database). fs_py_enter(options) pushes both and records them; fs_py_leave(depth) pops what
   was recorded above depth (fs_py_depth() before the call), so a KeyboardInterrupt raised anywhere
   between Python's two calls leaves nothing pushed. A database already in force (a callback of the
   solver's own call calling the solver again) is not pushed again; one deeper in the stack (solver A's
   callback calling B, calling back into A) is refused (-1): PETSc's stack of databases is a linked list
   through the databases themselves, which a second push of the same one would tie into a loop. */
#define FS_PY_MAX_DEPTH 64
static struct {
  PetscOptions options; /* the database in force (NULL: the one below, or PETSc's own) */
  PetscBool    pushed;  /* whether this entry pushed it */
} fs_py_stack[FS_PY_MAX_DEPTH];
static int fs_py_ndepth = 0;

static int fs_py_depth(void) { return fs_py_ndepth; }

static PetscOptions fs_py_current(void)
{
  for (int k = fs_py_ndepth - 1; k >= 0; k--)
    if (fs_py_stack[k].options) return fs_py_stack[k].options;
  return NULL;
}

/* whether options is pushed by a call in progress */
static int fs_py_entered(PetscOptions options)
{
  for (int k = 0; k < fs_py_ndepth; k++)
    if (options && fs_py_stack[k].options == options) return 1;
  return 0;
}

static int fs_py_enter(PetscOptions options)
{
  PetscBool push = (PetscBool)(options && options != fs_py_current());
  if (fs_py_ndepth == FS_PY_MAX_DEPTH || (push && fs_py_entered(options))) return -1;
  if (push && PetscOptionsPush(options)) return -2;
  PetscBool trace = PETSC_FALSE; /* -fs_error_trace: PETSc's full report of each error instead of the short one */
  if (PetscOptionsGetBool(NULL, NULL, "-fs_error_trace", &trace, NULL) || /* the database now in force */
      PetscPushErrorHandler(trace ? FSErrorTraceHandler : FSErrorHandler, NULL)) {
    if (push) (void)PetscOptionsPop();
    return -2;
  }
  fs_py_stack[fs_py_ndepth].options = options;
  fs_py_stack[fs_py_ndepth].pushed  = push;
  fs_py_ndepth++;
  return 0;
}

static void fs_py_leave(int depth)
{
  while (fs_py_ndepth > depth && fs_py_ndepth > 0) {
    fs_py_ndepth--;
    (void)PetscPopErrorHandler();
    if (fs_py_stack[fs_py_ndepth].pushed) (void)PetscOptionsPop();
  }
}

/* The petsc4py object of a PETSc object, an instance of type: a subclass of petsc4py's PETSc.TS or
   PETSc.DMSwarm (flexslosh.solver's, which check that the solver still lives). It is made as
   PyPetscTS_New / PyPetscDM_New make theirs (petsc4py's C API): the new, empty object gets the handle
   and its own reference to the PETSc object, so the Python object and the C core each destroy theirs.
   cffi has no PyObject * type to return it as, so the caller hands in a Python list by its address
   (id(list), CPython's object address; the caller keeps the list alive during the call) and the new
   object is appended to it; on failure the Python exception is appended instead and -1 returned, so
   that no exception is left pending here. */
static int fs_py_wrap(PetscObject obj, PyTypeObject *(*base)(void), void *type, void *out)
{
  PyGILState_STATE gil = PyGILState_Ensure(); /* held anyway (see below); cheap and safe either way */
  PyObject *list = (PyObject *)out, *res = NULL;
  int       ok   = -1;
  if (!PyList_Check(list)) PyErr_SetString(PyExc_TypeError, "fs_py_wrap: a list is needed");
  else if (import_petsc4py() == 0) {
    if (!PyType_Check((PyObject *)type) || !PyType_IsSubtype((PyTypeObject *)type, base()))
      PyErr_SetString(PyExc_TypeError, "fs_py_wrap: the type must be a subclass of the object's petsc4py class");
    else if ((res = PyObject_CallNoArgs((PyObject *)type)) != NULL) {
      PetscObject *slot = ((PyPetscObjectObject *)res)->obj; /* the handle's place: &self.ts, &self.dm */
      if (!slot || *slot) PyErr_SetString(PyExc_RuntimeError, "fs_py_wrap: the new petsc4py object is not empty");
      else if (PetscObjectReference(obj))
        PyErr_SetString(PyExc_RuntimeError, "fs_py_wrap: PetscObjectReference failed");
      else {
        *slot = obj;
        ok    = PyList_Append(list, res);
      }
    }
  }
  Py_XDECREF(res);
  if (ok) {
    PyObject *etype, *value, *tb;
    PyErr_Fetch(&etype, &value, &tb);
    PyErr_NormalizeException(&etype, &value, &tb);
    if (value && tb) PyException_SetTraceback(value, tb);
    if (value) PyList_Append(list, value);
    Py_XDECREF(etype); Py_XDECREF(value); Py_XDECREF(tb);
    ok = -1;
  }
  PyGILState_Release(gil);
  return ok;
}
static PyTypeObject *fs_py_ts_type(void) { return &PyPetscTS_Type; }
static PyTypeObject *fs_py_dm_type(void) { return &PyPetscDM_Type; }
static int fs_py_wrap_ts(TS ts, void *type, void *out) { return fs_py_wrap((PetscObject)ts, fs_py_ts_type, type, out); }
static int fs_py_wrap_dm(DM dm, void *type, void *out) { return fs_py_wrap((PetscObject)dm, fs_py_dm_type, type, out); }

/* The Python structure model: the extern "Python" callbacks (defined by cffi below, declared here as
   cffi's documentation says) in the table the C registry calls; each initializer is checked against
   the member's type in flexslosh.h. */
@CALLBACK_DECLARATIONS@
static const FSStructureCallbacks fs_py_callbacks = {
  .create = fs_py_structure_create, .setup = fs_py_structure_setup, .initial = fs_py_structure_initial,
  .rhs = fs_py_structure_rhs, .motion = fs_py_structure_motion, .columns = fs_py_structure_columns,
  .energy = fs_py_structure_energy, .destroy = fs_py_structure_destroy,
};
static const FSStructureCallbacks *fs_py_structure_callbacks(void) { return &fs_py_callbacks; }

/* -- the checks of the declarations ---------------------------------------------------------------- */
__attribute__((unused)) static void fs_py_prototype_checks(void)
{
@PROTOTYPE_CHECKS@
}

/* -- the GIL ------------------------------------------------------------------------------------------
   cffi's wrappers release the GIL around every call (Py_BEGIN_ALLOW_THREADS ... Py_END_ALLOW_THREADS
   in the code generated below). The C core must not run without it: PETSc prints through petsc4py's
   PetscVFPrintf, which writes to Python's sys.stdout when it was replaced (pytest, notebooks) and does
   not take the GIL itself, and PETSc objects are shared with petsc4py. So, as ctypes.PyDLL did, the
   calls keep it: the two macros are emptied for the wrappers below (this preamble precedes them).
   fs_py_gil_held() lets the package check, when it loads the module, that this took effect. The
   extern "Python" callbacks take the GIL themselves (PyGILState_Ensure), which is reentrant. */
#undef Py_BEGIN_ALLOW_THREADS
#undef Py_END_ALLOW_THREADS
#define Py_BEGIN_ALLOW_THREADS {
#define Py_END_ALLOW_THREADS }
static int fs_py_gil_held(void) { return PyGILState_Check(); }
"""

_PROTOTYPE = re.compile(r"^(?P<ret>[\w ]*?\w)\s*(?P<ptr>\**)\s*(?P<name>\w+)\((?P<args>.*)\);$")


def _prototype_checks(decls: str) -> str:
    """For each declaration `R f(A);`: a pointer of type R (*)(A) initialized with f, which compiles only
    if f's type in the header is the same."""
    lines = []
    for decl in filter(None, (d.strip() for d in decls.splitlines())):
        m = _PROTOTYPE.match(decl)
        if not m:
            raise ValueError(f"ffi_build.py: cannot read the declaration {decl!r}")
        lines.append(f"  {{ {m['ret']} {m['ptr']}(*p)({m['args']}) = {m['name']}; (void)p; }}")
    return "\n".join(lines)


def _callback_declarations(decls: str) -> str:
    return "\n".join("static " + d.strip()[len('extern "Python" '):] for d in decls.splitlines() if d.strip())


def make_ffi() -> cffi.FFI:
    ffi = cffi.FFI()
    ffi.cdef(CDEF)
    source = (PREAMBLE.replace("@PROTOTYPE_CHECKS@", _prototype_checks(HEADER_FUNCTIONS))
                      .replace("@CALLBACK_DECLARATIONS@", _callback_declarations(CALLBACKS)))
    ffi.set_source(MODULE, source)
    return ffi


if __name__ == "__main__":
    if len(sys.argv) != 2:
        sys.exit(__doc__)
    make_ffi().emit_c_code(sys.argv[1])
