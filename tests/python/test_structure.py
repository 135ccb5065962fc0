"""Structure models (issue 4): mass-spring-damper and modal Euler-Bernoulli beam, alone (-fs_case beam)
and inside the TS state of a liquid run; static test, modes, free decay, integrator orders, bad input,
MPI, restart, plug-in structure, output."""
import re

import numpy as np
import pytest

from conftest import (REPO_ROOT, TG, assert_no_crash, petsc_error_message, read_series, read_summary, run_flexslosh)

# The seed's beam (section III.A) and the solid-mass configuration of its Fig. 5 (cases/beam_free_decay_*.opts)
E, I, L, MLIN = 210e9, 5.57e-7, 2.48, 13.04
EI = E * I
TANK, BALLAST, J = 5.0, 3.36, 0.344
KL_EXACT = [1.875104069, 4.694091133, 7.854757438, 10.995540734, 14.137168391]
BEAM = ["-fs_case", "beam", "-fs_output_interval", "0"]
SOLID = ["-fs_beam_tank_mass", TANK, "-fs_beam_ballast_mass", BALLAST, "-fs_beam_tank_inertia", J]


def beam_run(tmp_path, name, args, nranks=1, check=True):
    d = tmp_path / name
    proc = run_flexslosh(BEAM + ["-fs_output_dir", d] + [str(a) for a in args], nranks=nranks, cwd=tmp_path, check=check)
    return d, proc


# ------------------------------------------------------------------ exact references


def tip_mass_det(beta, mu, j):
    """Determinant of the clamped-free beam with a tip mass mu m L and rotary inertia j m L^3 at x = L:
    phi = A (cosh - cos)(beta x/L) + B (sinh - sin)(beta x/L) (clamped at 0); at the tip
    EI phi'' = J omega^2 phi' and EI phi''' = -M omega^2 phi (from the Lagrangian's boundary terms),
    with omega^2 = beta^4 EI/(m L^4)."""
    ch, c, sh, s = np.cosh(beta), np.cos(beta), np.sinh(beta), np.sin(beta)
    b3 = beta ** 3
    r1 = ((ch + c) - j * b3 * (sh + s), (sh + s) - j * b3 * (ch - c))
    r2 = ((sh - s) + mu * beta * (ch - c), (ch + c) + mu * beta * (sh - s))
    return r1[0] * r2[1] - r1[1] * r2[0]


def tip_mass_roots(mu, j, n, bmax=20.0):
    grid = np.linspace(0.05, bmax, 40000)
    vals = [tip_mass_det(b, mu, j) for b in grid]
    roots = []
    for k in range(len(grid) - 1):
        if np.sign(vals[k]) != np.sign(vals[k + 1]):
            lo, hi = grid[k], grid[k + 1]
            for _ in range(80):
                mid = 0.5 * (lo + hi)
                if np.sign(tip_mass_det(mid, mu, j)) == np.sign(tip_mass_det(lo, mu, j)):
                    lo = mid
                else:
                    hi = mid
            roots.append(0.5 * (lo + hi))
            if len(roots) == n:
                break
    return roots


def msd_exact(t, w0, omega, xi):
    wd = omega * np.sqrt(1 - xi ** 2)
    return np.exp(-xi * omega * t) * (w0 * np.cos(wd * t) + xi * omega * w0 / wd * np.sin(wd * t))


def peaks(t, y):
    """Local maxima of a sampled signal, refined by a parabola through the three samples."""
    out_t, out_y = [], []
    for k in range(1, len(y) - 1):
        if y[k] > y[k - 1] and y[k] >= y[k + 1]:
            h = t[k + 1] - t[k]
            a = 0.5 * (y[k + 1] - 2 * y[k] + y[k - 1])
            b = 0.5 * (y[k + 1] - y[k - 1])
            dx = -b / (2 * a) if a != 0 else 0.0
            out_t.append(t[k] + dx * h)
            out_y.append(y[k] - b * b / (4 * a) if a != 0 else y[k])
    return np.array(out_t), np.array(out_y)


def check_exact_root_sanity():
    assert tip_mass_roots(0, 0, 5) == pytest.approx(KL_EXACT, rel=1e-8)


# ------------------------------------------------------------------ modes


def test_exact_characteristic_equation_reduces_to_the_bare_beam():
    check_exact_root_sanity()
    # a heavy tip mass: first frequency tends to that of a spring 3EI/L^3 with M + 33/140 m L
    mu = 50.0
    beta = tip_mass_roots(mu, 0, 1)[0]
    omega = beta ** 2 * np.sqrt(EI / (MLIN * L ** 4))
    assert omega == pytest.approx(np.sqrt(3 * EI / L ** 3 / ((mu + 33 / 140) * MLIN * L)), rel=1e-3)
    # rotary inertia lowers the first frequency
    assert tip_mass_roots(1.0, 0.1, 1)[0] < tip_mass_roots(1.0, 0.0, 1)[0]


def test_bare_cantilever_kL(tmp_path):
    d, proc = beam_run(tmp_path, "bare", ["-fs_modal_elements", 60, "-fs_modal_modes", 5, "-fs_modal_view", "-ts_max_steps", 1])
    st = read_summary(d)["structure"]
    kl = np.array(st["kL"])
    err = np.abs(kl / KL_EXACT - 1)
    print(f"k_n L relative errors (60 elements): {err}")
    assert err.max() < 1e-5, f"k_n L relative errors {err}"
    f_exact = np.array(KL_EXACT) ** 2 * np.sqrt(EI / (MLIN * L ** 4)) / (2 * np.pi)
    assert np.abs(np.array(st["frequencies_hz"]) / f_exact - 1).max() < 2e-5
    # -fs_modal_view prints the table
    assert re.search(r"^\s+1\s+8\.61\d+\s+54\.1\d+\s+1\.8751040", proc.stdout, re.M), proc.stdout
    # modal mass of a bare cantilever's mode scaled to a unit tip deflection is m L / 4
    assert st["modal_mass"][0] == pytest.approx(MLIN * L / 4, rel=1e-6)


def test_tip_mass_and_inertia_first_frequencies(tmp_path):
    d, _ = beam_run(tmp_path, "tip", SOLID + ["-fs_modal_elements", 80, "-fs_modal_modes", 3, "-ts_max_steps", 1])
    st = read_summary(d)["structure"]
    mu, j = (TANK + BALLAST) / (MLIN * L), J / (MLIN * L ** 3)
    betas = tip_mass_roots(mu, j, 3)
    f_exact = np.array(betas) ** 2 * np.sqrt(EI / (MLIN * L ** 4)) / (2 * np.pi)
    f = np.array(st["frequencies_hz"])
    print(f"tip mass + inertia: f = {f}, exact {f_exact}, relative errors {f / f_exact - 1}")
    assert f[0] == pytest.approx(f_exact[0], rel=1e-7), (f, f_exact)
    assert np.abs(f / f_exact - 1).max() < 1e-5, (f, f_exact)


# ------------------------------------------------------------------ static test (seed Fig. 3)


@pytest.mark.parametrize("model", ["msd", "modal"])
def test_static_tip_deflection(tmp_path, model):
    """10 kg hung at the tip, heavily damped (xi = 0.9): the tip settles at F L^3/(3 EI).
    modal: 3 modes within 1 %, its finite-element static solution (Hermite cubics: exact for a point
    load) to 1e-10. msd: its spring is defined as 3 EI/L^3, so its own static deflection says nothing;
    the run settles instead at the static deflection of the modal model's finite elements, computed from
    the FE stiffness matrix (measured 1.4e-10 apart: the CSV's 11 digits and the FE solve), and its whole
    history is the exact step response of the damped oscillator with m = 33/140 m L + 10 kg, K =
    3 EI/L^3, c = 2 xi omega m computed here (measured 2.1e-6 of the static deflection: RK4 at dt = T/50)."""
    F = -10 * 9.81
    exact = F * L ** 3 / (3 * EI)
    args = ["-fs_beam_tank_mass", 10, "-fs_beam_force", F, "-fs_beam_damping", 0.9]
    modes = ["-fs_modal_modes", 3]  # the modal model's own: an option of a model not in use is refused
    d, _ = beam_run(tmp_path, model, ["-fs_structure", model, "-ts_max_time", 2] + args + modes * (model == "modal"))
    s, st = read_series(d), read_summary(d)["structure"]
    assert s["tip_displacement"][0] == 0.0
    assert s["tip_displacement"][-1] == pytest.approx(st["static_tip_deflection"], rel=1e-6)
    if model == "modal":
        assert st["static_tip_deflection"] == pytest.approx(exact, rel=1e-2)  # 3 modes
        assert st["static_tip_deflection_fe"] == pytest.approx(exact, rel=1e-10)
        return
    fe_dir, _ = beam_run(tmp_path, "fe", ["-fs_structure", "modal", "-ts_max_steps", 1] + args + modes)
    fe = read_summary(fe_dir)["structure"]["static_tip_deflection_fe"]
    assert s["tip_displacement"][-1] == pytest.approx(fe, rel=1e-9)
    K, m, xi = 3 * EI / L ** 3, 33 / 140 * MLIN * L + 10, 0.9
    omega = np.sqrt(K / m)
    step = F / K * (1 - msd_exact(s["time"], 1.0, omega, xi))
    assert np.abs(s["tip_displacement"] - step).max() < 3e-6 * abs(F / K)


def test_static_deflection_converges_with_modes(tmp_path):
    F = -98.1
    exact = F * L ** 3 / (3 * EI)
    errs = []
    for n in (1, 2, 3, 5, 8):
        d, _ = beam_run(tmp_path, f"n{n}", ["-fs_beam_tank_mass", 10, "-fs_beam_force", F, "-fs_modal_modes", n, "-ts_max_steps", 1])
        errs.append(abs(read_summary(d)["structure"]["static_tip_deflection"] / exact - 1))
    print(f"static tip deflection, relative error with 1, 2, 3, 5, 8 modes: {errs}")
    assert all(b < a for a, b in zip(errs, errs[1:])), errs
    assert errs[-1] < 2e-3, errs


# ------------------------------------------------------------------ free decay (seed Fig. 5)


@pytest.fixture(scope="module")
def decay(tmp_path_factory):
    out = {}
    for model in ("msd", "modal"):
        d = tmp_path_factory.mktemp(model)
        run_flexslosh(["-options_file", REPO_ROOT / "cases" / f"beam_free_decay_{model}.opts", "-fs_output_dir", d,
                       "-ts_max_time", 2.0, "-fs_structure_cfl", 0.01, "-fs_output_interval", 0.5], cwd=d)
        out[model] = d
    return out


@pytest.mark.parametrize("model,column", [("msd", "tip_displacement"), ("modal", "q1")])
def test_log_decrement_gives_back_xi_and_period(decay, model, column):
    s, st = read_series(decay[model]), read_summary(decay[model])["structure"]
    tp, ap = peaks(s["time"], s[column])
    assert len(ap) >= 8
    delta = np.log(ap[:-1] / ap[1:])
    zeta = delta / np.sqrt(4 * np.pi ** 2 + delta ** 2)
    print(f"{model}: damping ratio per cycle {zeta.min():.6f}..{zeta.max():.6f}, period {np.mean(np.diff(tp)):.6f}")
    assert np.abs(zeta / 0.015 - 1).max() < 1e-6, zeta  # measured 2.1e-7 (msd), 4e-10 (modal)
    f1 = st["frequencies_hz"][0]
    period = np.mean(np.diff(tp))
    assert period == pytest.approx(1 / (f1 * np.sqrt(1 - 0.015 ** 2)), rel=1e-6)  # measured 8e-8, 7e-10
    if model == "msd":  # the whole history against the exact solution
        w = msd_exact(s["time"], 0.04, st["omega"], 0.015)
        assert np.abs(s["tip_displacement"] - w).max() < 5e-6 * 0.04  # RK4 at dt = T/100 over 12 periods: 3.2e-6


def test_free_decay_output(decay):
    s = read_series(decay["modal"])
    assert s["tip_displacement"][0] == pytest.approx(0.04, rel=3e-5)  # 5 modes of the static shape: -1.6e-5
    assert s["tip_velocity"][0] == 0.0
    acc = s["tip_acceleration"]
    assert np.isfinite(acc).all() and np.abs(acc).max() > 9.81  # several g at the release
    for c in ("tank_rotation", "tank_rotation_rate", "tank_angular_acceleration", "load_force_y", "load_moment_z", "q5"):
        assert c in s
    assert np.all(s["load_force_y"] == 0)  # no liquid
    st = read_summary(decay["modal"])["structure"]
    assert st["model"] == "modal" and len(st["frequencies_hz"]) == 5 and len(st["modal_mass"]) == 5
    # the deflected shape at the snapshot times: x, w, rotation at the nodes; the last node is the tip
    shapes = sorted(decay["modal"].glob("beam_shape_*.csv"))
    assert len(shapes) == 5  # t = 0, 0.5, 1, 1.5, 2
    last = np.loadtxt(shapes[-1], delimiter=",", skiprows=2)
    assert last[0, 0] == 0 and last[-1, 0] == pytest.approx(L)
    assert last[-1, 1] == pytest.approx(s["tip_displacement"][-1], rel=1e-8, abs=1e-14)
    assert last[-1, 2] == pytest.approx(s["tank_rotation"][-1], rel=1e-8, abs=1e-14)


# ------------------------------------------------------------------ integrator orders


def msd_error(tmp_path, name, args, tend=0.5):
    d, _ = beam_run(tmp_path, name, ["-fs_structure", "msd"] + SOLID + ["-fs_beam_preload", 0.04, "-ts_max_time", tend] + args)
    s, st = read_series(d), read_summary(d)["structure"]
    w = msd_exact(s["time"][-1], 0.04, st["omega"], 0.015)
    return abs(st["final_state"][0] - w), len(s["time"]) - 1  # the summary has all the digits


@pytest.mark.parametrize("name,args,order", [("rk4", [], 4), ("ssp", ["-ts_type", "ssp"], 2), ("rk5dp_fixed", ["-ts_type", "rk", "-ts_rk_type", "5dp", "-ts_adapt_type", "none"], 5)])
def test_fixed_step_convergence_order(tmp_path, name, args, order):
    # 2.125 periods of the solid-mass configuration (msd) in n steps of equal size. The run ends half-way
    # between a peak and a zero crossing, where both the amplitude and the phase errors show (on a linear
    # oscillator they may differ in order: for 5dp the amplitude error is O(dt^5), the phase error O(dt^6))
    T = 0.16561
    steps = (40, 80, 160)
    errs = [msd_error(tmp_path, f"{name}{k}", args + ["-ts_dt", 2.125 * T / n], tend=2.125 * T)[0] for k, n in enumerate(steps)]
    rates = np.log2(np.array(errs[:-1]) / np.array(errs[1:]))
    print(f"{name}: errors {errs}, observed orders {rates}")
    assert np.all(np.abs(rates - order) < 0.3), (errs, rates)


def test_adaptive_rk5dp_converges_at_fifth_order(tmp_path):
    res = [msd_error(tmp_path, f"tol{k}", ["-ts_type", "rk", "-ts_rk_type", "5dp", "-ts_adapt_type", "basic", "-fs_structure_cfl", 1,
                                           "-ts_rtol", tol, "-ts_atol", tol]) for k, tol in enumerate((1e-5, 1e-7, 1e-9))]
    errs, steps = np.array([r[0] for r in res]), np.array([r[1] for r in res])
    assert np.all(np.diff(steps) > 0) and np.all(np.diff(errs) < 0), res
    order = -np.polyfit(np.log(steps), np.log(errs), 1)[0]
    print(f"rk5dp adaptive: steps {steps}, errors {errs}, observed order {order:.2f}")
    assert 4.0 < order < 6.5, (res, order)


# ------------------------------------------------------------------ MPI, restart, liquid + structure


@pytest.mark.parametrize("model", ["msd", "modal"])
def test_one_and_two_ranks_same_structure_history(tmp_path, model):
    args = ["-fs_structure", model] + SOLID + ["-fs_beam_preload", 0.04, "-ts_max_steps", 200]
    d1, _ = beam_run(tmp_path, "r1", args)
    d2, _ = beam_run(tmp_path, "r2", args, nranks=2)
    assert (d1 / "timeseries.csv").read_text() == (d2 / "timeseries.csv").read_text()


def test_liquid_and_structure_on_two_ranks(tmp_path):
    args = TG + ["-fs_dx", 0.04, "-fs_structure", "msd"] + SOLID + ["-fs_beam_preload", 0.04, "-ts_max_steps", 20]
    out = {}
    for n in (1, 2):
        d = tmp_path / f"n{n}"
        run_flexslosh(args + ["-fs_output_dir", d], nranks=n, cwd=tmp_path)
        out[n] = read_series(d)
    for c in ("tip_displacement", "tip_velocity", "tip_acceleration"):
        assert np.array_equal(out[1][c], out[2][c]), c
    assert np.allclose(out[1]["kinetic_energy"], out[2]["kinetic_energy"], rtol=1e-12)
    # the structure's time step limit applies to the liquid run too: dt <= 0.02 T
    assert out[1]["dt"].max() <= 0.02 * 0.1656 * 1.01


@pytest.mark.parametrize("case", ["beam_modal", "tg_msd"])
def test_restart_with_structure_is_exact(tmp_path, case):
    if case == "beam_modal":
        args = BEAM + SOLID + ["-fs_beam_preload", 0.04]
    else:
        args = TG + ["-fs_dx", 0.04, "-fs_structure", "msd"] + SOLID + ["-fs_beam_preload", 0.04]
    a, b = tmp_path / "A", tmp_path / "B"
    run_flexslosh(args + ["-ts_max_steps", 40, "-fs_checkpoint_interval", 20, "-fs_output_dir", a], cwd=tmp_path)
    run_flexslosh(args + ["-ts_max_steps", 40, "-fs_restart", a / "checkpoint_000020.h5", "-fs_output_dir", b], cwd=tmp_path)
    sa, sb = read_series(a), read_series(b)
    assert list(sb["step"]) == list(range(20, 41))
    for name in sa:
        assert np.array_equal(sa[name][20:], sb[name]), name
    assert read_summary(a)["structure"]["final_state"] == read_summary(b)["structure"]["final_state"]
    # another structure cannot continue this checkpoint
    proc = run_flexslosh(args + ["-fs_structure", "none" if case == "tg_msd" else "msd", "-ts_max_steps", 40,
                                 "-fs_restart", a / "checkpoint_000020.h5", "-fs_output_dir", tmp_path / "C"], cwd=tmp_path, check=False)
    assert_no_crash(proc)
    assert "-fs_structure" in petsc_error_message(proc.stdout)


# ------------------------------------------------------------------ registry, plug-in


def test_structure_view_lists_models(run):
    proc = run(["-fs_structure_view", "-ts_max_steps", "0", "-fs_output", "0"])
    assert re.search(r"Registered structure models \(3\)", proc.stdout), proc.stdout
    for name in ("msd", "modal", "prescribed"):
        assert re.search(rf"^\s+{name}\s{{2,}}", proc.stdout, re.M), name


def test_plugin_structure(tmp_path):
    lib = REPO_ROOT / "build" / "libfsspring.so"
    from conftest import build_dir
    lib = build_dir() / "libfsspring.so"
    assert lib.exists(), f"{lib} not built"
    proc = run_flexslosh(["-dll_append", lib, "-fs_structure_view", "-ts_max_steps", "0", "-fs_output", "0"], cwd=tmp_path)
    assert re.search(r"Registered structure models \(4\)", proc.stdout) and re.search(r"^\s+spring\s{2,}", proc.stdout, re.M)
    d, _ = beam_run(tmp_path, "spring", ["-dll_append", lib, "-fs_structure", "spring", "-fs_spring_frequency", 2,
                                         "-fs_spring_amplitude", 0.01, "-ts_max_time", 1.0, "-fs_structure_cfl", 0.005])
    s = read_series(d)
    assert np.abs(s["tip_displacement"] - 0.01 * np.cos(4 * np.pi * s["time"])).max() < 1e-7
    proc = run_flexslosh(BEAM + ["-fs_structure", "spring", "-ts_max_steps", 1, "-fs_output", 0], cwd=tmp_path, check=False)
    assert_no_crash(proc)
    msg = petsc_error_message(proc.stdout)
    assert '"spring"' in msg and "-dll_append" in msg, msg


# ------------------------------------------------------------------ bad input

BAD = {
    "E_zero": (["-fs_beam_E", "0"], [r"-fs_beam_E 0\b", "positive"]),
    "I_negative": (["-fs_beam_I", "-1e-7"], [r"-fs_beam_I -1e-07\b", "positive"]),
    "length_zero": (["-fs_beam_length", "0"], [r"-fs_beam_length 0\b", "positive"]),
    "mass_per_length_zero": (["-fs_beam_mass_per_length", "0"], [r"-fs_beam_mass_per_length 0\b", "positive"]),
    "tank_mass_negative": (["-fs_beam_tank_mass", "-2"], [r"-fs_beam_tank_mass -2\b", "non-negative"]),
    "msd_mass_negative": (["-fs_structure", "msd", "-fs_msd_mass", "-1"], [r"-fs_msd_mass -1\b", "non-negative"]),
    "damping_one": (["-fs_beam_damping", "1"], [r"-fs_beam_damping 1\b", r"\[0, 1\)"]),
    "damping_negative": (["-fs_beam_damping", "-0.1"], [r"-fs_beam_damping -0.1\b", r"\[0, 1\)"]),
    "modal_damping_one": (["-fs_modal_damping", "0.02,1.5"], [r"-fs_modal_damping value 1.5\b", r"\[0, 1\)"]),
    "too_many_modes": (["-fs_modal_elements", "3", "-fs_modal_modes", "7"], [r"-fs_modal_modes 7\b", "-fs_modal_elements", "at most 6"]),
    "load_point_outside": (["-fs_beam_force", "10", "-fs_beam_force_position", "3"], [r"-fs_beam_force_position 3\b", "outside the beam"]),
    "tank_outside": (["-fs_beam_tank_position", "-0.5"], [r"-fs_beam_tank_position -0.5\b", "outside the beam"]),
    "unknown_structure": (["-fs_structure", "wing"], ["-fs_structure", '"wing"', "msd"]),
    "beam_without_structure": (["-fs_structure", "none"], ["beam", "-fs_structure none"]),
    "structure_cfl": (["-fs_structure_cfl", "0"], [r"-fs_structure_cfl 0\b", "range"]),
}


@pytest.mark.parametrize("name", list(BAD))
def test_bad_structure_option(tmp_path, name):
    args, patterns = BAD[name]
    d, proc = beam_run(tmp_path, "out", args + ["-ts_max_steps", 2], check=False)
    assert_no_crash(proc)
    msg = petsc_error_message(proc.stdout)
    for pat in patterns:
        assert re.search(pat, msg), f"{pat!r} not in the error message:\n{msg}"
    assert not (d / "summary.json").exists()


def test_modal_time_step_advice(tmp_path):
    """At set-up, a mode whose period sets the time step below the liquid's acoustic step is named, with the
    number of modes that the liquid's step resolves and the -fs_structure_cfl that would; no warning otherwise."""
    base = ["-options_file", REPO_ROOT / "cases" / "coupled_rectangular.opts", "-fs_structure", "modal", "-fs_dx",
            "0.01", "-fs_geometry_view", "-fs_output_dir", tmp_path / "o"]
    out = run_flexslosh(base, cwd=tmp_path).stdout
    assert re.search(r"Warning: the structure modal's shortest period sets the time step: [\d.]+ Hz \(mode 5 of 5\)"
                     r".*-fs_structure_cfl 0\.02 of it is .* times shorter than the liquid's acoustic step 0\.001 s.*"
                     r"-fs_modal_modes \d.*raise -fs_structure_cfl to 0\.34", out), out
    assert "shortest period sets" not in run_flexslosh(base + ["-fs_structure_cfl", "0.4"], cwd=tmp_path).stdout
