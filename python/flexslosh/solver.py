"""Drive the C core (libflexslosh) from Python through its PETSc objects.

``Solver`` wraps one FSSolver. PETSc is initialized through petsc4py, and libflexslosh is loaded into
the same process through the binding _flexslosh_cffi (a cffi extension module compiled against
include/flexslosh.h, built by CMake beside libflexslosh.so; python/ffi_build.py), so the C library and
petsc4py share one PETSc: the same objects. Each solver has its own options database, PETSc's default
during its calls (``Solver.options``). ``Solver.ts`` is the solver's
own TS and ``Solver.swarm`` its DMSwarm, as petsc4py objects::

    from flexslosh import Solver
    with Solver({"fs_case": "tank", "fs_dx": 0.01, "ts_max_time": 0.05, "fs_output": False}) as s:
        s.step(10)
        print(s.time, s.step_number, s.ts.getType(), s.swarm.getLocalSize())
        p = s.pressures(gather=True)          # on rank 0, sorted by particle id
        s.run()                               # to -ts_max_time

PETSc's errors in the C core raise ``FlexsloshError`` (a RuntimeError) with PETSc's message; PETSc
prints its usual error report too. The library and the binding are found in $FLEXSLOSH_BUILD, else in
<repo>/build. petsc4py and the binding are loaded on first use, not when ``flexslosh`` is imported.
"""
from __future__ import annotations

import atexit
import contextlib
import importlib.machinery
import importlib.util
import os
import signal
import sys
import threading
import weakref
from pathlib import Path
from typing import Any, Callable, Mapping

import numpy as np

__all__ = ["Solver", "SolverOptions", "FlexsloshError", "initialize", "library_path", "binding_path", "set_options"]

_MISSING = object()
_BINDING = "_flexslosh_cffi"  # the module python/ffi_build.py generates
_DESTROYED = "Solver has been destroyed"


class FlexsloshError(RuntimeError):
    """A PETSc error in the C core.

    Attributes:
        ierr: PETSc's error code.
        message: PETSc's message (the text given where the error was raised).
        call: the C function that returned it.
    """

    def __init__(self, ierr: int, message: str, call: str):
        self.ierr, self.message, self.call = ierr, message, call
        super().__init__(f"{call}: {message} (PETSc error {ierr})")


def _build_dir() -> Path:
    env = os.environ.get("FLEXSLOSH_BUILD")
    return Path(env) if env else Path(__file__).resolve().parents[2] / "build"


def library_path() -> Path:
    """libflexslosh.so in $FLEXSLOSH_BUILD, else in the build directory of the checkout (<repo>/build)."""
    return _build_dir() / "libflexslosh.so"


def binding_path() -> Path:
    """The binding (_flexslosh_cffi.<this Python's extension suffix>) beside libflexslosh.so."""
    build = _build_dir()
    paths = [build / (_BINDING + suffix) for suffix in importlib.machinery.EXTENSION_SUFFIXES]
    return next((p for p in paths if p.exists()), paths[0])


def _load_binding(path: Path):
    """Imports the binding from path (once per process), RTLD_GLOBAL: libflexslosh's symbols are global,
    for plug-ins loaded later with -dll_append."""
    module = sys.modules.get(_BINDING)
    if module is None:
        spec = importlib.util.spec_from_file_location(_BINDING, path)
        flags = sys.getdlopenflags()
        sys.setdlopenflags(flags | os.RTLD_GLOBAL)
        try:
            module = importlib.util.module_from_spec(spec)  # dlopen happens here
            spec.loader.exec_module(module)
        finally:
            sys.setdlopenflags(flags)
        sys.modules[_BINDING] = module
    return module


_OPTIONS_FILE_DEPTH = 16


def options_file_cycle(words: list[str], _chain: tuple[tuple[str, str], ...] = ()) -> str | None:
    """The chain of options files that include themselves (or nest deeper than 16) among the files named
    after ``-options_file`` in words, followed as PETSc reads them ('#' starts a comment, each line its own
    words), as a message; None when there is none. PETSc 3.18 follows such a chain until the stack overflows
    (a segmentation fault), so the files are checked before PETSc reads them, as they are for a byte-order mark
    (PETSc took it for part of the first option; the flexslosh binary refuses it alike); a file that cannot be read
    is left to PETSc, which names it."""
    for i, word in enumerate(words[:-1]):
        if word != "-options_file":
            continue
        given = words[i + 1]
        try:
            real = os.path.realpath(given, strict=True)
        except OSError:
            continue
        chain = _chain + ((given, real),)
        first = next((k for k, (_, r) in enumerate(_chain) if r == real), None)
        if first is not None or len(chain) >= _OPTIONS_FILE_DEPTH:
            what = (f'options file "{given}" includes itself' if first is not None
                    else f"options files nested deeper than {_OPTIONS_FILE_DEPTH}")
            return what + ": " + " -> ".join(f"-options_file {g}" for g, _ in chain[first or 0:])
        try:
            data = Path(real).read_bytes()
        except OSError:
            continue
        marks = ((b"\xef\xbb\xbf", "EF BB BF, a UTF-8"), (b"\xff\xfe", "FF FE, a UTF-16"), (b"\xfe\xff", "FE FF, a UTF-16"))
        for mark, what in marks:
            if data.startswith(mark):
                return (f'options file "{given}" starts with the bytes {what} byte-order mark: save it as plain text, '
                        "ASCII or UTF-8 without the mark")
        text = data.replace(b"\0", b" ").decode("utf-8", "replace")
        for line in text.splitlines():
            found = options_file_cycle(line.split("#", 1)[0].split(), chain)
            if found:
                return found
    return None


class _Core:
    """petsc4py's PETSc module and the binding: its ``ffi`` (types, memory) and ``lib`` (the C functions
    of include/flexslosh.h and PETSc the package calls, and the helpers of python/ffi_build.py)."""

    # the functions that take an MPI_Comm, called through a helper of the binding that reads the
    # communicator from its address (errors keep the C function's name)
    _VIA_HELPER = {"FSLoadPlugins": "fs_py_load_plugins", "FSSolverCreate": "fs_py_solver_create",
                   "PetscOptionsInsertFile": "fs_py_options_insert_file", "FSOptionsLeft": "fs_py_options_left",
                   "PetscOptionsCreate": "fs_py_options_copy_default"}

    def __init__(self, argv):
        import petsc4py

        if "petsc4py.PETSc" not in sys.modules:
            cycle = options_file_cycle(list(argv or []) + os.environ.get("PETSC_OPTIONS", "").split())
            if cycle:
                raise ValueError(cycle)
            # the program's name: "-c" of python -c would read as an option (kept in every solver's database
            # and in its checkpoints' record of the set-up)
            name = sys.argv[0] if sys.argv and sys.argv[0] and not sys.argv[0].startswith("-") else "flexslosh"
            petsc4py.init(list(argv) if argv is not None else [name])
        from petsc4py import PETSc

        path, binding = library_path(), binding_path()
        if not path.exists():
            raise FileNotFoundError(
                f"libflexslosh.so not found at {path}: build the C core (cmake -S . -B build && cmake --build build) "
                "or set FLEXSLOSH_BUILD to the build directory")
        if not binding.exists():
            raise FileNotFoundError(
                f"the Python binding {binding.name} not found in {binding.parent}: build it with the C core "
                f"(cmake --build; it needs python3-cffi and python3-dev, for {sys.executable}) or set FLEXSLOSH_BUILD")
        self.PETSc = PETSc
        module = _load_binding(binding)
        self.ffi, self.lib = ffi, lib = module.ffi, module.lib
        # the calls keep the GIL, since PETSc may print through petsc4py's Python streams (sys.stdout
        # replaced, as under pytest) and callbacks into Python may happen at any time (ffi_build.py)
        if not lib.fs_py_gil_held():
            raise RuntimeError(f"{binding} releases the GIL in its calls: rebuild it (python/ffi_build.py)")
        if not lib.PetscInitializeCalled:
            raise RuntimeError(f"{path} does not see the PETSc petsc4py initialized: it must be built against the same PETSc "
                               f"({PETSc.__file__})")
        self.real = np.dtype(f"f{ffi.sizeof('PetscReal')}")  # PetscReal, as numpy sees it
        self.TS, self.Swarm = _wrapper_classes(PETSc)
        self.call("FSInitializePackage")

    def message(self, ierr: int) -> str:
        ffi = self.ffi
        text, specific = ffi.new("const char **"), ffi.new("char **")
        self.lib.PetscErrorMessage(ierr, text, specific)
        for p in (specific[0], text[0]):
            s = ffi.string(p) if p else b""
            if s:
                return s.decode(errors="replace").strip()
        return "unknown error"

    @contextlib.contextmanager
    def entered(self, options=None):
        """The context of a call into the C core: ``options`` (a solver's PetscOptions, or None) pushed as
        PETSc's default database, so that every option the core and PETSc read comes from it, and
        FSErrorHandler pushed (PETSc's error report, printed by rank 0 of the error's communicator, every
        error of the session in full; petsc4py's own handler prints nothing). Both are popped again on the
        way out, whatever interrupts it (the binding records what it pushed: ffi_build.py)."""
        lib = self.lib
        options = options if options is not None else self.ffi.NULL
        depth = lib.fs_py_depth()
        try:
            rc = lib.fs_py_enter(options)
            if rc == -1:
                raise RuntimeError("a Solver was called back from inside another solver's call while its own call is "
                                   "in progress (A -> B -> A): PETSc cannot stack its options database twice")
            if rc:
                raise RuntimeError("could not push the solver's options database and error handler")
            yield
        finally:
            lib.fs_py_leave(depth)

    def call(self, name: str, *args, options=None, label: str | None = None) -> None:
        """Calls a C function returning a PetscErrorCode in the context of ``entered(options)``; a non-zero
        code raises FlexsloshError on every rank that got it, naming the function (or ``label``)."""
        fn = getattr(self.lib, self._VIA_HELPER.get(name, name))
        with self.entered(options):
            ierr = fn(*args)
        if ierr:
            raise FlexsloshError(ierr, self.message(ierr), label or name)

    def comm(self, comm):
        """(mpi4py communicator, MPI_Comm * for the helpers) of comm: None (PETSC_COMM_WORLD), mpi4py or
        PETSc.Comm. The pointer points into the mpi4py object: keep that alive while it is used."""
        from mpi4py import MPI

        if comm is None:
            comm = self.PETSc.COMM_WORLD.tompi4py()
        elif isinstance(comm, self.PETSc.Comm):
            comm = comm.tompi4py()
        return comm, self.ffi.cast("MPI_Comm *", MPI._addressof(comm))

    def address(self, ptr) -> int:
        """The address a C pointer holds (0 for NULL)."""
        return int(self.ffi.cast("uintptr_t", ptr))

    def array(self, ptr, n: int) -> np.ndarray:
        """A copy of the n PetscReals at ptr."""
        if not n:
            return np.zeros(0)
        return np.frombuffer(self.ffi.buffer(ptr, n * self.real.itemsize), dtype=self.real).copy()

    def wrap(self, kind: str, obj):
        """The petsc4py object of a C PETSc object (kind "TS" or "DM"), an instance of the package's
        subclass of PETSc.TS or PETSc.DMSwarm (``_wrapper_classes``), made as petsc4py's C API makes its
        own (PyPetscTS_New): the wrapper takes its own reference, so the Python object and the C core each
        destroy theirs. The binding appends it to the list it is given (see ffi_build.py)."""
        out: list = []
        make, cls = {"TS": (self.lib.fs_py_wrap_ts, self.TS), "DM": (self.lib.fs_py_wrap_dm, self.Swarm)}[kind]
        if make(obj, self.ffi.cast("void *", id(cls)), self.ffi.cast("void *", id(out))):
            raise out[0] if out else RuntimeError(f"could not wrap the {kind} for petsc4py")
        return out[0]


def _wrapper_classes(PETSc):
    """The classes of a solver's TS and DMSwarm as petsc4py objects: PETSc.TS and PETSc.DMSwarm whose
    methods raise RuntimeError once the object is destroyed (by Solver.destroy or its own destroy), where
    petsc4py would hand PETSc the null handle (a segmentation fault in an optimized PETSc), and whose
    swarm fields are read-only arrays."""

    def guarded(base, what: str):
        allowed = frozenset({"handle", "destroy"})
        handle = PETSc.Object.handle

        def __getattribute__(self, name: str):
            if not name.startswith("__") and name not in allowed and not handle.__get__(self):
                raise RuntimeError(f"{_DESTROYED} (or this {what} was destroyed): the {what} of a flexslosh Solver "
                                   f"lives as long as the Solver; take solver.{what.lower()} from a live one")
            return base.__getattribute__(self, name)

        return __getattribute__

    class SolverTS(PETSc.TS):
        """The TS of a flexslosh Solver (petsc4py PETSc.TS): valid while the Solver lives; afterwards every
        method raises RuntimeError."""
        __getattribute__ = guarded(PETSc.TS, "TS")

    class SolverSwarm(PETSc.DMSwarm):
        """The particles' DMSwarm of a flexslosh Solver (petsc4py PETSc.DMSwarm): valid while the Solver lives
        (afterwards every method raises RuntimeError); its fields are read-only (``getField``)."""
        __getattribute__ = guarded(PETSc.DMSwarm, "Swarm")

        def getField(self, name: str) -> np.ndarray:
            """The field's values of this rank's particles as a read-only array over the swarm's memory; give
            the field back with restoreField(name). The swarm mirrors the solver's state, which lives in the
            TS's vector and is copied into the swarm after every step: a write here could not reach the
            particles (it would be overwritten at the next step, and the neighbour lists, the ghosts and the
            energy budget would not know of it), so writing raises ValueError instead of being lost."""
            values = PETSc.DMSwarm.getField(self, name)
            values.flags.writeable = False
            return values

    return SolverTS, SolverSwarm


_core: _Core | None = None
_live: "weakref.WeakSet[Solver]" = weakref.WeakSet()


def initialize(argv: list[str] | None = None) -> _Core:
    """Initializes PETSc through petsc4py (``petsc4py.init(argv)``; argv None: no command-line options,
    pass sys.argv to use the script's), loads libflexslosh and calls FSInitializePackage. Idempotent;
    when petsc4py.PETSc was imported before, its PETSc is used as it is."""
    global _core
    if _core is None:
        _core = _Core(argv)
        atexit.register(_destroy_all)  # after petsc4py's finalization was registered: runs before it
    return _core


def _destroy_all():
    if getattr(sys, "last_value", None) is not None and _core is not None and not _core.PETSc.Sys.isFinalized():
        world = _core.PETSc.COMM_WORLD
        if world.getSize() > 1:
            # an exception nobody caught ends this rank: the others may wait for it in a collective, and PETSc's
            # finalization would wait for them; end every rank now (mpi4py's own abort would come after it)
            sys.stdout.flush()
            sys.stderr.flush()
            world.tompi4py().Abort(1)
    for s in list(_live):
        s.destroy()


def _option_value(value) -> str:
    if isinstance(value, (bool, np.bool_)):
        return "" if value else "0"
    if isinstance(value, (list, tuple, np.ndarray)):
        return ",".join(_option_value(v) for v in value)
    if isinstance(value, (float, np.floating)):
        return repr(float(value))  # the shortest text that reads back as the same double
    return os.fspath(value) if isinstance(value, os.PathLike) else str(value)


def set_options(options: Mapping[str, Any]) -> None:
    """Puts options into PETSc's (global, prefix-free) options database, as on the command line: keys
    with or without the leading '-'; True sets a flag, False gives 0, sequences are comma separated,
    None removes the option. Every Solver created afterwards starts from a copy of that database (the
    solvers alive keep theirs)."""
    _set_into(initialize().PETSc.Options(), options)


def _set_into(opts, options: Mapping[str, Any]) -> None:
    """set_options into the petsc4py database opts."""
    for key, value in options.items():
        name = key if key.startswith("-") else "-" + key
        if value is None:
            opts.delValue(name)
        else:
            opts.setValue(name, _option_value(value))


class SolverOptions:
    """A Solver's own options database, with the methods of petsc4py's ``PETSc.Options`` (getString,
    getReal, getInt, getBool, getAll, hasName, setValue, delValue, insertString, view, ...), each called
    with that database in force (``PETSc.Options()`` then stands for it, as it does for a Python structure
    model's options during the solver's calls). Raises RuntimeError once the solver is destroyed."""

    def __init__(self, solver: "Solver"):
        self._solver = weakref.ref(solver)
        self._petsc = solver._core.PETSc.Options()  # no database of its own: PETSc's default, the solver's in a call

    def _database(self):
        solver = self._solver()
        if solver is None or not solver._opts[0]:
            raise RuntimeError(f"{_DESTROYED}: its options database went with it")
        return solver

    def __getattr__(self, name: str):
        if name in ("create", "destroy", "clear"):
            raise AttributeError(f"SolverOptions.{name}: the database lives and dies with its Solver")
        attr = getattr(self._petsc, name)
        if not callable(attr):
            return attr

        def method(*args, **kwargs):
            solver = self._database()
            with solver._core.entered(solver._opts[0]):
                return attr(*args, **kwargs)

        method.__doc__ = attr.__doc__
        method.__name__ = name
        return method

    def __repr__(self) -> str:
        return f"<SolverOptions of {self._solver()!r}>"


class _Interrupts:
    """Ctrl-C (SIGINT) held back during a run loop and delivered between two steps: the C core's calls keep
    the GIL and do not look at Python's signals, so a KeyboardInterrupt raised by Python's own handler waits
    for the call to end, which for FSSolverSolve is the run's. Inside ``with _Interrupts(comm) as i`` a
    SIGINT only sets a flag; ``i.pending()`` says whether one came (on a communicator of several ranks,
    whether one came to any rank: collective, so that every rank stops after the same step) and
    ``i.deliver()`` restores the previous handler and calls it (Python's default raises KeyboardInterrupt;
    a rank the signal did not reach raises KeyboardInterrupt itself). Outside the main thread (where Python
    receives no signals) or with SIGINT ignored, nothing changes."""

    def __init__(self, comm):
        self.comm, self.flag, self.frame, self.previous = comm, False, None, None
        self.installed = False

    def _handler(self, signum, frame):
        self.flag, self.frame = True, frame

    def __enter__(self) -> "_Interrupts":
        if threading.current_thread() is threading.main_thread():
            previous = signal.getsignal(signal.SIGINT)
            if previous not in (signal.SIG_IGN, None):
                self.previous = previous
                signal.signal(signal.SIGINT, self._handler)
                self.installed = True
        return self

    def _restore(self) -> None:
        if self.installed:
            signal.signal(signal.SIGINT, self.previous)
            self.installed = False

    def pending(self) -> bool:
        if self.comm is not None and self.comm.Get_size() > 1:
            from mpi4py import MPI

            return bool(self.comm.allreduce(int(self.flag), op=MPI.MAX))
        return self.flag

    def deliver(self) -> None:
        self._restore()
        if not self.flag:
            raise KeyboardInterrupt("interrupted on another rank")
        self.flag = False
        if self.previous is signal.SIG_DFL:
            signal.raise_signal(signal.SIGINT)
        elif callable(self.previous):
            self.previous(signal.SIGINT, self.frame)

    def __exit__(self, etype, value, tb) -> None:
        if etype is None and self.pending():
            self.deliver()  # came during the last step or the end of the run: the run is complete
        self._restore()


class Solver:
    """One flexslosh run (an FSSolver), driven from Python.

    Args:
        options: options of this solver, e.g. {"fs_case": "tank", "fs_dx": 0.01, "ts_max_time": 0.1} (keys
            and values as in ``set_options``); they win over the options file.
        options_file: a PETSc options file (as ``-options_file``), inserted first.
        comm: the run's communicator: None (PETSC_COMM_WORLD), an mpi4py communicator or a PETSc.Comm.

    Each solver has its own options database (``options``): a copy of PETSc's default database as it is
    when the solver is created (the script's command line given to petsc4py, PETSC_OPTIONS,
    ``set_options``), then the options file, then ``options``. It is PETSc's default database during every
    call into the C core for this solver, so the core and PETSc read it as the binary reads the command
    line, and no solver sees another's options. The solver reads its options at creation
    (FSSolverSetFromOptions); ``set_up`` builds the case (``step`` and ``run`` do it when needed). Field
    getters are collective: every rank of comm calls them. A ``Solver`` is a context manager; ``destroy``
    frees the C objects and the database, after which every use raises RuntimeError.
    """

    def __init__(self, options: Mapping[str, Any] | None = None, options_file: str | os.PathLike | None = None, comm=None):
        core = initialize()
        self._core, self._h = core, core.ffi.new("FSSolver *")  # NULL until created
        self._opts = core.ffi.new("PetscOptions *")  # the solver's database; NULL until created
        self._ts = self._swarm = None
        self._mine: list[str] = []  # the options the file and the dict set: checked for use by destroy
        self._created = False  # read its options: those it set and never used are reported by destroy
        self.comm, self._ccomm = core.comm(comm)
        if options_file is not None and not Path(options_file).is_file():
            raise FileNotFoundError(f"options file {options_file} not found")
        if options_file is not None:
            cycle = options_file_cycle(["-options_file", os.fspath(options_file)])
            if cycle:
                raise ValueError(cycle)
        core.call("PetscOptionsCreate", self._opts)  # a copy of PETSc's default database
        _live.add(self)
        try:
            opts = self.options
            before = opts.getAll()
            if options_file is not None:
                core.call("PetscOptionsInsertFile", self._ccomm, self._opts[0], os.fsencode(options_file), True)
            if options:
                with core.entered(self._opts[0]):
                    _set_into(core.PETSc.Options(), options)
            after = opts.getAll()
            self._mine = [k for k in after if before.get(k, _MISSING) != after[k]]
            if options_file is not None and "fs_output_name" not in after:  # output/<file's name>-<time stamp>
                with core.entered(self._opts[0]):
                    core.PETSc.Options().setValue("-fs_output_name", Path(options_file).stem)
            core.call("FSLoadPlugins", self._ccomm, options=self._opts[0])  # a -dll_append: its terms and structures
            core.call("FSSolverCreate", self._ccomm, self._h, options=self._opts[0])
            # the -fs_ options of the file and the dict that nothing reads are an error, with the nearest names: here
            # (misspelt ones, those of other cases, terms, structure models) and at set_up (the walls, the coupling)
            names = [core.ffi.new("char[]", k.encode()) for k in self._mine]
            self._call("FSSolverSetOptionsChecked", len(names), core.ffi.new("char *[]", names))
            self._call("FSSolverSetFromOptions")
            self._created = True
        except BaseException:
            self.destroy()
            raise

    # ------------------------------------------------------------------ life cycle

    def _call(self, name: str, *args, label: str | None = None) -> None:
        if not self._h[0]:
            raise RuntimeError(_DESTROYED)
        self._core.call(name, self._h[0], *args, options=self._opts[0], label=label)

    def set_up(self) -> "Solver":
        """Builds the case, the decomposition and the TS (FSSolverSetUp; idempotent)."""
        self._call("FSSolverSetUp")
        return self

    def _at_final_time(self) -> bool:
        ts = self.ts
        tmax = ts.getMaxTime()
        return ts.getTime() >= tmax - 1e-12 * max(1.0, abs(tmax))

    @property
    def finished(self) -> bool:
        """Whether the run reached -ts_max_time or -ts_max_steps (as FSSolverSolve decides)."""
        return self._at_final_time() or self.ts.getStepNumber() >= self.ts.getMaxSteps()

    def step(self, n: int = 1) -> "Solver":
        """Takes n time steps (FSSolverStep: the output and monitors of each step included; -ts_max_steps
        does not stop it, the final time does)."""
        for _ in range(n):
            if self._at_final_time():
                raise RuntimeError(f"the run is at its final time {self.ts.getMaxTime()} (-ts_max_time): raise it "
                                   "(solver.ts.setMaxTime) or use run(until=...)")
            self._call("FSSolverStep")
        return self

    def run(self, until: float | None = None, callback: Callable[["Solver"], Any] | None = None) -> "Solver":
        """Runs to -ts_max_time / -ts_max_steps, or to the time ``until`` (the last step shortened to land on
        it; -ts_max_time is restored after), writing the output as the executable does (FSSolverSolve's
        steps, then the last snapshot and summary.json). callback(solver), if given, is called after every
        step.

        Ctrl-C (SIGINT) stops the run after the step in progress (the steps are taken one call at a time):
        the output files then hold every step taken, as the binary's run to that step writes them, and a
        run with checkpoints (-fs_checkpoint_interval) writes one of that step (FSSolverWriteCheckpoint,
        for -fs_restart); then KeyboardInterrupt is raised. The solver stays usable: ``run()`` again goes
        on from there and its output continues the same files. An error raises FlexsloshError naming
        FSSolverSolve, whose steps these are."""
        ts = self.ts
        tmax = ts.getMaxTime()
        if until is not None:
            ts.setMaxTime(until)
        try:
            with _Interrupts(self.comm) as interrupts:
                self.set_up()
                stepping = not self._stops_at_set_up()  # an option: read once, not at every step
                while stepping:
                    if interrupts.pending():
                        self._write_interrupted()
                        interrupts.deliver()
                    if self.finished:
                        break
                    self._call("FSSolverStep", label="FSSolverSolve")  # its errors as FSSolverSolve's
                    if callback is not None:
                        callback(self)
                self._call("FSSolverSolve")  # after the loop: no step left, only the end of the output
        finally:
            if until is not None and self._h[0]:
                ts.setMaxTime(tmax)
        return self

    def _stops_at_set_up(self) -> bool:
        """-fs_geometry_view: FSSolverSolve takes no step."""
        return bool(self.options.getBool("fs_geometry_view", False))

    def _write_interrupted(self) -> None:
        """What an interrupted run leaves: the output files are written after every step (each row flushed);
        with -fs_checkpoint_interval, a checkpoint of the current step unless the run has just written one."""
        opts = self.options
        every = opts.getInt("fs_checkpoint_interval", 0)
        if every > 0 and opts.getBool("fs_output", True) and self.step_number % every:
            self._call("FSSolverWriteCheckpoint")

    def destroy(self) -> None:
        """Frees the C solver and the petsc4py wrappers of its TS and swarm (their methods raise
        RuntimeError afterwards), warns about the options this solver's file and dict set that were never
        used (a misspelt name; ``fs_options_left: False`` silences it) and frees its options database.
        Idempotent; also called at exit, before PETSc is finalized. Not from inside the solver's own call
        (a callback of its run)."""
        core = self._core
        if self._opts[0] and core.lib.fs_py_entered(self._opts[0]):
            raise RuntimeError("a Solver cannot be destroyed inside its own call (from a callback of its run)")
        _live.discard(self)
        if core.PETSc.Sys.isFinalized():
            self._h[0] = self._opts[0] = core.ffi.NULL
            return
        try:
            if self._h[0]:
                for obj in (self._ts, self._swarm):
                    if obj is not None:
                        obj.destroy()  # drops the Python side's reference only
                self._ts = self._swarm = None
                core.call("FSSolverDestroy", self._h, options=self._opts[0])
                if self._created:  # a misspelt option among this solver's: a warning (FSOptionsLeft)
                    names = [core.ffi.new("char[]", k.encode()) for k in self._mine]
                    core.call("FSOptionsLeft", self._ccomm, len(names), core.ffi.new("char *[]", names),
                              options=self._opts[0])
        finally:
            self._h[0] = core.ffi.NULL
            if self._opts[0]:
                core.call("PetscOptionsDestroy", self._opts)
                self._opts[0] = core.ffi.NULL

    def __enter__(self) -> "Solver":
        return self

    def __exit__(self, *exc) -> None:
        self.destroy()

    def __del__(self):
        try:
            self.destroy()
        except Exception:
            pass

    # ------------------------------------------------------------------ PETSc objects

    @property
    def handle(self) -> int:
        """The address of the FSSolver (0 once destroyed), for C code of one's own."""
        return self._core.address(self._h[0])

    def _wrapped(self, attr: str, getter: str, kind: str):
        out = self._core.ffi.new(f"{kind} *")
        self._call(getter, out)
        address = self._core.address(out[0])
        obj = getattr(self, attr)
        if obj is None or obj.handle != address:
            if obj is not None:
                obj.destroy()
            obj = self._core.wrap(kind, out[0]) if address else None
            setattr(self, attr, obj)
        return obj

    @property
    def ts(self):
        """The solver's TS as a petsc4py PETSc.TS (the same object: its time, step number, dt and options
        are the run's). Valid while the solver lives: afterwards its methods raise RuntimeError."""
        return self._wrapped("_ts", "FSSolverGetTS", "TS")

    @property
    def swarm(self):
        """The particles' DMSwarm as a petsc4py PETSc.DMSwarm (fields position, velocity, density, mass, id;
        local sizes change at every step), whose getField arrays are read-only (the swarm mirrors the TS's
        state: see _wrapper_classes). Sets the solver up. Valid while the solver lives: afterwards its
        methods raise RuntimeError."""
        self.set_up()
        return self._wrapped("_swarm", "FSSolverGetSwarm", "DM")

    @property
    def options(self) -> SolverOptions:
        """This solver's own options database (``SolverOptions``: petsc4py PETSc.Options's methods, no
        prefix), where its options file and dict went and from which the C core reads."""
        if not self._opts[0]:
            raise RuntimeError(_DESTROYED)
        return SolverOptions(self)

    def _new(self, ctype: str, *init):
        return self._core.ffi.new(ctype, *init)

    @property
    def time(self) -> float:
        t = self._new("PetscReal *")
        self._call("FSSolverGetTime", t, self._core.ffi.NULL)
        return t[0]

    @property
    def step_number(self) -> int:
        n = self._new("PetscInt *")
        self._call("FSSolverGetTime", self._core.ffi.NULL, n)
        return n[0]

    @property
    def dim(self) -> int:
        d = self._new("PetscInt *")
        self._call("FSSolverGetDimension", d)
        return d[0]

    @property
    def local_size(self) -> int:
        """The number of particles this rank owns."""
        n = self._new("PetscInt *")
        self._call("FSSolverGetLocalSize", n)
        return n[0]

    # ------------------------------------------------------------------ particle fields

    FIELDS = ("position", "velocity", "density", "mass", "pressure", "strain_rate", "turbulent_viscosity", "id", "rank")

    def _local_field(self, name: str) -> np.ndarray:
        n, bs, ptr = self._new("PetscInt *"), self._new("PetscInt *"), self._new("const PetscReal **")
        self.set_up()
        self._call("FSSolverGetField", name.encode(), n, bs, ptr)
        try:
            values = self._core.array(ptr[0], n[0] * bs[0])
        finally:
            NULL = self._core.ffi.NULL
            self._call("FSSolverRestoreField", name.encode(), NULL, NULL, ptr)
        return values.reshape(n[0], bs[0]) if bs[0] > 1 else values

    def field(self, name: str, gather: bool = False) -> np.ndarray | None:
        """One field of the particles (see FIELDS; pressure, strain_rate and turbulent_viscosity from a
        fresh right-hand side at the current state): this rank's particles in their local order, or with
        gather=True all of them on rank 0 sorted by particle id (None on the other ranks). Vectors have
        shape (n, dim). Collective."""
        values = self._local_field(name)
        if not gather:
            return values
        ids = self._local_field("id").astype(np.int64)
        return self._gather(ids, values)

    def _gather(self, ids: np.ndarray, values: np.ndarray) -> np.ndarray | None:
        comm = self.comm
        width = int(np.prod(values.shape[1:])) if values.ndim > 1 else 1
        counts = comm.gather(len(ids), root=0)
        root = comm.Get_rank() == 0
        all_ids = np.empty(sum(counts), dtype=np.int64) if root else None
        all_vals = np.empty(sum(counts) * width) if root else None
        comm.Gatherv(np.ascontiguousarray(ids), (all_ids, counts) if root else None, root=0)
        comm.Gatherv(np.ascontiguousarray(values, dtype=float).ravel(), (all_vals, [c * width for c in counts]) if root else None, root=0)
        if not root:
            return None
        order = np.argsort(all_ids, kind="stable")
        all_vals = all_vals.reshape((-1,) + values.shape[1:])
        return all_vals[order]

    def positions(self, gather: bool = False):
        return self.field("position", gather)

    def velocities(self, gather: bool = False):
        return self.field("velocity", gather)

    def densities(self, gather: bool = False):
        return self.field("density", gather)

    def pressures(self, gather: bool = False):
        return self.field("pressure", gather)

    def ids(self, gather: bool = False):
        """The particles' ids (local order; sorted on rank 0 with gather=True)."""
        ids = self._local_field("id").astype(np.int64)
        if not gather:
            return ids
        ordered = self._gather(ids, ids.astype(float))
        return None if ordered is None else ordered.astype(np.int64)

    # ------------------------------------------------------------------ loads, structure, energy

    def wall_loads(self) -> dict[str, dict[str, np.ndarray]]:
        """The liquid's load on each wall from the last right-hand side (the wall_* columns of
        timeseries.csv): {wall name: {"force": (3,), "moment": (3,)}}, every rank. Collective."""
        ffi = self._core.ffi
        n, loads = self._new("PetscInt *"), self._new("const PetscReal **")
        self._call("FSSolverGetWallLoads", n, ffi.NULL, ffi.NULL)
        names = self._new("const char *[]", max(n[0], 1))
        self._call("FSSolverGetWallLoads", n, names, loads)
        if not n[0]:
            return {}
        L = self._core.array(loads[0], 6 * n[0]).reshape(n[0], 6)
        return {ffi.string(names[w]).decode(): {"force": L[w, :3], "moment": L[w, 3:]} for w in range(n[0])}

    def structure_state(self) -> np.ndarray:
        """The structure's state (its DOFs) at the current state, every rank (empty without a structure). Collective."""
        ffi, n = self._core.ffi, self._new("PetscInt *")
        self._call("FSSolverGetStructureState", n, ffi.NULL)
        y = np.zeros(n[0], dtype=self._core.real)
        if n[0]:
            self._call("FSSolverGetStructureState", n, ffi.from_buffer("PetscReal[]", y, require_writable=True))
        return y

    def tank_motion(self) -> dict[str, Any]:
        """The tank's motion at the current state (FSSolverGetTankMotion): disp, vel, acc (3 each),
        angle, rate, angacc; zero without a structure. A 3-D tank turned about any axis (a prescribed
        pitch, yaw, axis or 6-DOF file) adds "rotation": Q (3x3, the tank's axes in the global ones),
        w and dw (its angular velocity and acceleration in the tank's axes). Collective."""
        m = self._new("FSTankMotion *")
        self._call("FSSolverGetTankMotion", m)
        out = {"disp": np.array(list(m.disp)), "vel": np.array(list(m.vel)), "acc": np.array(list(m.acc)),
               "angle": m.angle, "rate": m.rate, "angacc": m.angacc}
        if m.rotated:
            out["rotation"] = {"Q": np.array(list(m.Q)).reshape(3, 3), "w": np.array(list(m.w)),
                               "dw": np.array(list(m.dw))}
        return out

    def energy(self) -> dict[str, float]:
        """The energy budget of the current state: the columns of energy.csv, every rank. Collective."""
        ffi, cap = self._core.ffi, self._core.lib.FS_ENERGY_MAX_COLUMNS
        n, names, vals = self._new("PetscInt *"), self._new("const char *[]", cap), self._new("PetscReal[]", cap)
        self.set_up()
        self._call("FSSolverGetEnergy", n, names, vals)
        return {ffi.string(names[k]).decode(): vals[k] for k in range(n[0])}

    def probes(self) -> dict[str, Any]:
        """The probes and wave gauges of -fs_probes at the current state (the columns of probes.csv):
        {name: value} in the file's order, a probe's value a numpy array (pressure, velocity_x,
        velocity_y[, velocity_z][, filtered pressure: a probe with cutoff or rate]), a gauge's its
        elevation (float); {} without -fs_probes, every
        rank. Collective."""
        ffi, n = self._core.ffi, self._new("PetscInt *")
        self.set_up()
        self._call("FSSolverGetProbes", n, ffi.NULL, ffi.NULL, ffi.NULL)
        if not n[0]:
            return {}
        names, offsets = self._new("const char *[]", n[0]), self._new("PetscInt[]", n[0] + 1)
        vals = self._new("PetscReal[]", self._core.lib.FS_PROBE_MAX_VALUES * n[0])
        self._call("FSSolverGetProbes", n, names, offsets, vals)
        out: dict[str, Any] = {}
        for k in range(n[0]):
            v = np.array([vals[q] for q in range(offsets[k], offsets[k + 1])], dtype=self._core.real)
            out[ffi.string(names[k]).decode()] = float(v[0]) if v.size == 1 else v
        return out
