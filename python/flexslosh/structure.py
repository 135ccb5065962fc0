"""Structure models written in Python, registered in the C core's structure registry.

A model is a subclass of ``Structure``; ``register_structure("name", cls)`` registers it through
FSStructureRegisterCallbacks, so ``-fs_structure name`` selects it like the built-in ``msd`` and
``modal``. Its DOFs are part of the TS state, advanced by the same integrator as the liquid; they
live on rank 0, where ``rhs``, ``motion``, ``column_values`` and ``energy`` are called (``setup`` and
``initial_state`` run on every rank). An exception raised in a method becomes a PETSc error whose
message carries the exception's type and text (and Python prints its traceback)::

    class Spring(flexslosh.Structure):
        ndof = 2
        def setup(self, ctx):
            self.k = ctx.options.getReal("my_k", 100.0)
            self.min_period = 2 * math.pi / math.sqrt(self.k)
        def initial_state(self):
            return [0.01, 0.0]
        def rhs(self, t, y, loads):
            return [y[1], loads.force[1] - self.k * y[0]]
        def motion(self, y, ydot):
            return flexslosh.TankMotion(disp=(0, y[0], 0), vel=(0, y[1], 0), acc=(0, ydot[1], 0))

    flexslosh.register_structure("spring1", Spring)
    Solver({"fs_case": "beam", "fs_structure": "spring1"}).run()

``MassSpringDamper`` is the Python twin of the built-in ``msd`` (src/structure/impls/msd.c), with the
same options and formulas.
"""
from __future__ import annotations

import itertools
import math
import sys
import traceback
from abc import ABC, abstractmethod
from dataclasses import dataclass
from typing import Any, Callable, Sequence

import numpy as np

from .solver import initialize

__all__ = ["Structure", "Loads", "TankMotion", "StructureContext", "MassSpringDamper", "register_structure"]


@dataclass
class Loads:
    """The liquid's loads on the tank's reference point (FSLoads): force (3, global axes) and moment
    (3, about the reference point). Zero without a coupling."""

    force: np.ndarray
    moment: np.ndarray


@dataclass
class TankMotion:
    """The rigid motion of the tank's reference point (FSTankMotion): displacement, velocity and
    acceleration (3 each), and the rotation about z: angle, rate, angular acceleration."""

    disp: Sequence[float] = (0.0, 0.0, 0.0)
    vel: Sequence[float] = (0.0, 0.0, 0.0)
    acc: Sequence[float] = (0.0, 0.0, 0.0)
    angle: float = 0.0
    rate: float = 0.0
    angacc: float = 0.0


@dataclass
class StructureContext:
    """What ``Structure.setup`` knows of the run.

    Attributes:
        name: the name the model was registered under.
        liquid_mass: the mass of the liquid the structure carries (2-D mass times -fs_tank_width when
            coupled, else 0; FSSolverGetLiquidMass).
        options: PETSc's options database (petsc4py PETSc.Options), to read the model's options.
        solver: the address of the FSSolver.
    """

    name: str
    liquid_mass: float
    options: Any
    solver: int = 0


class Structure(ABC):
    """A structure model carrying the tank (the Python side of FSStructureOps).

    Attributes to set, in the class or in ``setup``:
        ndof: the number of DOFs of the state y (> 0).
        min_period: the shortest period the model resolves (s); a run without particles takes
            -fs_structure_cfl times it as its time step (0: none, then -ts_dt is needed).
        columns: names of the model's own timeseries.csv columns (values from ``column_values``).
    """

    ndof: int = 0
    min_period: float = 0.0
    columns: Sequence[str] = ()

    def setup(self, ctx: StructureContext) -> None:
        """Reads the model's options and sets ndof, min_period and columns (every rank)."""

    @abstractmethod
    def initial_state(self) -> Sequence[float]:
        """The initial state y0 (ndof values)."""

    @abstractmethod
    def rhs(self, t: float, y: np.ndarray, loads: Loads) -> Sequence[float]:
        """dy/dt at time t for state y under the liquid's loads (rank 0)."""

    @abstractmethod
    def motion(self, y: np.ndarray, ydot: np.ndarray) -> TankMotion:
        """The tank's motion from the state and its rate (rank 0)."""

    def energy(self, y: np.ndarray) -> Sequence[float] | None:
        """Optional: (kinetic, potential, damping power >= 0) at state y, for energy.csv (rank 0)."""
        return None

    def column_values(self, t: float, y: np.ndarray, ydot: np.ndarray) -> Sequence[float]:
        """The values of ``columns`` (rank 0)."""
        return ()


class MassSpringDamper(Structure):
    """The cantilever as a mass-spring-damper at the tank, m w'' + c w' + K w = F: the built-in ``msd``
    (src/structure/impls/msd.c) written in Python, with its options (-fs_beam_*, -fs_msd_*) and formulas,
    so that both give the same run to round-off. State (w, w')."""

    ndof = 2

    def setup(self, ctx: StructureContext) -> None:
        o = ctx.options
        E, I, L = o.getReal("fs_beam_E", 210e9), o.getReal("fs_beam_I", 5.57e-7), o.getReal("fs_beam_length", 2.48)
        mlin = o.getReal("fs_beam_mass_per_length", 13.04)
        a = o.getReal("fs_beam_tank_position", L)
        tank, ballast = o.getReal("fs_beam_tank_mass", 0.0), o.getReal("fs_beam_ballast_mass", 0.0)
        payload = o.getReal("fs_beam_payload_mass", 0.0)
        if payload > 0:
            if payload < ctx.liquid_mass:
                raise ValueError(f"-fs_beam_payload_mass {payload} kg is less than the liquid's mass {ctx.liquid_mass} kg")
            ballast = payload - ctx.liquid_mass
        xi = o.getReal("fs_beam_damping", 0.015)
        o.getReal("fs_beam_tank_inertia", 0.0)  # read and unused, as msd.c does: no rotation (the seed's "no rolling")
        self.preload = o.getReal("fs_beam_preload", 0.0)
        force, xf = o.getReal("fs_beam_force", 0.0), o.getReal("fs_beam_force_position", a)
        fraction = o.getReal("fs_msd_beam_mass_fraction", 33.0 / 140.0)
        mass, stiffness = o.getReal("fs_msd_mass", 0.0), o.getReal("fs_msd_stiffness", 0.0)

        def influence(x, xf):  # the massless cantilever's deflection at x under a unit force at xf
            lo, hi = min(x, xf), max(x, xf)
            return lo * lo * (3 * hi - lo) / (6 * E * I)

        self.m = mass if mass > 0 else fraction * mlin * L + tank + ballast
        self.K = stiffness if stiffness > 0 else 3 * E * I / (a * a * a)
        self.omega = math.sqrt(self.K / self.m)
        self.c = 2 * xi * self.omega * self.m
        self.force_eq = force * influence(xf, a) / influence(a, a)
        self.min_period = 2 * math.pi / self.omega

    def initial_state(self):
        return [self.preload, 0.0]

    def rhs(self, t, y, loads):
        return [y[1], (loads.force[1] + self.force_eq - self.c * y[1] - self.K * y[0]) / self.m]

    def motion(self, y, ydot):
        return TankMotion(disp=(0.0, y[0], 0.0), vel=(0.0, y[1], 0.0), acc=(0.0, ydot[1], 0.0))

    def energy(self, y):
        return (0.5 * self.m * y[1] * y[1], 0.5 * self.K * y[0] * y[0] - self.force_eq * y[0], self.c * y[1] * y[1])


# ---------------------------------------------------------------------------- the callbacks
# The C registry calls the binding's extern "Python" functions fs_py_structure_* (their table,
# FSStructureCallbacks, is filled in C: python/ffi_build.py), attached to the functions below with
# ffi.def_extern on the first registration. ctx and impl are integer keys stored as void *.

_factories: dict[int, tuple[str, Callable[[], Structure]]] = {}  # registration id -> (name, factory)
_instances: dict[int, tuple[str, Structure]] = {}               # instance id (the C side's impl) -> (name, model)
_ids = itertools.count(1)
_attached = False  # whether the callbacks are attached to the binding


def _guarded(fn):
    """A callback's body: 0 on success; an exception's type and text go to FSStructureCallbacksSetError."""

    def call(*args):
        try:
            fn(*args)
            return 0
        except BaseException as exc:  # a crossing into C: nothing may escape
            traceback.print_exc(file=sys.stderr)
            msg = f"{type(exc).__name__}: {exc}"
            initialize().lib.FSStructureCallbacksSetError(msg.encode(errors="replace"))
            return 1

    call.__name__ = fn.__name__
    return call


def _key(ptr) -> int:
    return initialize().address(ptr)


def _array(ptr, n: int) -> np.ndarray:
    return initialize().array(ptr, n)


def _store(ptr, n: int, values, what: str) -> None:
    """Copies what a callback returned (what: its name) into the C array ptr of n reals: a sequence (or array) of n
    numbers. Anything else is an error that says what came back: None (a forgotten return), a single number, values
    that are not numbers, or another count."""
    core = initialize()
    if values is None:
        raise TypeError(f"{what} returned None, expected a sequence of {n} numbers (a missing return statement?)")
    try:
        v = np.ascontiguousarray(values, dtype=core.real).ravel()
    except (TypeError, ValueError) as exc:
        raise TypeError(f"{what} returned {type(values).__name__} {values!r:.80}, expected a sequence of {n} numbers "
                        f"({exc})") from None
    if v.shape != (n,):
        got = "a single number" if np.ndim(values) == 0 else f"{v.size} values"
        raise ValueError(f"{what} returned {got}, expected {n}")
    if n:
        core.ffi.memmove(ptr, v, v.nbytes)


@_guarded
def _create(ctx, st, impl):
    name, factory = _factories[_key(ctx)]
    obj = factory()
    if not isinstance(obj, Structure):
        raise TypeError(f"structure {name}: the factory returned {type(obj).__name__}, not a flexslosh.Structure")
    key = next(_ids)
    _instances[key] = (name, obj)
    impl[0] = initialize().ffi.cast("void *", key)


@_guarded
def _setup(impl, st, ndof, min_period):
    core, (name, obj) = initialize(), _instances[_key(impl)]
    solver, mass = core.ffi.new("FSSolver *"), core.ffi.new("PetscReal *")
    core.call("FSStructureGetSolver", st, solver)
    core.call("FSSolverGetLiquidMass", solver[0], mass)
    obj.setup(StructureContext(name=name, liquid_mass=mass[0], options=core.PETSc.Options(), solver=core.address(solver[0])))
    n = int(obj.ndof)
    if n <= 0:
        raise ValueError(f"{type(obj).__name__}.ndof is {obj.ndof}: set it (> 0) in the class or in setup()")
    for col in obj.columns:
        core.call("FSStructureAddColumn", st, str(col).encode())
    ndof[0], min_period[0] = n, float(obj.min_period)


@_guarded
def _initial(impl, n, y):
    _store(y, n, _instances[_key(impl)][1].initial_state(), "initial_state()")


@_guarded
def _rhs(impl, t, n, y, loads, ydot):
    L = Loads(np.array(list(loads.force)), np.array(list(loads.moment)))
    _store(ydot, n, _instances[_key(impl)][1].rhs(t, _array(y, n), L), "rhs()")


@_guarded
def _motion(impl, n, y, ydot, out):
    m = _instances[_key(impl)][1].motion(_array(y, n), _array(ydot, n))
    for name in ("disp", "vel", "acc"):
        v = np.asarray(getattr(m, name), dtype=float).ravel()
        if v.shape != (3,):
            raise ValueError(f"motion().{name} has {v.size} values, expected 3")
        setattr(out, name, v.tolist())
    out.angle, out.rate, out.angacc = float(m.angle), float(m.rate), float(m.angacc)


@_guarded
def _columns(impl, t, n, y, ydot, ncol, vals):
    _store(vals, ncol, _instances[_key(impl)][1].column_values(t, _array(y, n), _array(ydot, n)), "column_values()")


@_guarded
def _energy(impl, n, y, E):
    e = _instances[_key(impl)][1].energy(_array(y, n))
    if e is not None:
        _store(E, 3, e, "energy()")


@_guarded
def _destroy(impl):
    _instances.pop(_key(impl), None)


def _attach() -> None:
    """Attaches the callbacks above to the binding's extern "Python" functions (once)."""
    global _attached
    if not _attached:
        ffi = initialize().ffi
        for fn in (_create, _setup, _initial, _rhs, _motion, _columns, _energy, _destroy):
            # error=1: what C gets should an exception escape _guarded after all
            ffi.def_extern(name="fs_py_structure" + fn.__name__, error=1)(fn)
        _attached = True


def register_structure(name: str, model: type[Structure] | Callable[[], Structure], description: str | None = None) -> None:
    """Registers a Python structure model under name (-fs_structure name), through the C core's registry
    (FSStructureRegisterCallbacks). model: a Structure subclass, or any callable returning a new Structure;
    it is called once for every solver that uses the model. Registering a name again replaces it."""
    core = initialize()
    _attach()
    key = next(_ids)

    _factories[key] = (name, model)
    desc = description or f"Python structure {getattr(model, '__qualname__', repr(model))}"
    core.call("FSStructureRegisterCallbacks", name.encode(), desc.encode(), core.lib.fs_py_structure_callbacks(),
              core.ffi.cast("void *", key))
