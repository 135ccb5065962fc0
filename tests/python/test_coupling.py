"""The liquid in the tank coupled with the structure (issue 5): loads to the structure and the tank's
motion back to the liquid at every stage of the integrator."""
import numpy as np
import pytest

from conftest import (REPO_ROOT, last_snapshot, read_series, read_snapshot, read_summary, rel_max_diff, run_flexslosh,
                      snapshot_files)

# the seed's rectangular tank at 50 % fill on the mass-spring-damper beam; coarse liquid (H/dx = 6)
COUPLED = ["-fs_case", "tank", "-fs_structure", "msd", "-fs_dx", 0.005, "-fs_output_interval", 0]
M_STRUCT, K = 7.62281, 23006.0  # msd defaults of the seed's beam (-fs_view): moving mass and stiffness


def crossings(t, w):
    """Times where w crosses zero upwards (linear interpolation)."""
    i = np.nonzero((w[:-1] < 0) & (w[1:] >= 0))[0]
    return t[i] - w[i] * (t[i + 1] - t[i]) / (w[i + 1] - w[i])


def test_liquid_at_rest_does_not_drive_the_beam(tmp_path):
    """Liquid at rest in the undeflected tank: its weight is part of the static equilibrium, so the
    beam stays still: the tip within 0.5 % of the static deflection the weight would cause (measured
    0.39 %), the loads within 15 % of the weight (measured 13 %: the liquid settling from its lattice)."""
    out = tmp_path / "rest"
    run_flexslosh(COUPLED + ["-ts_max_time", 0.15, "-fs_output_dir", out], cwd=tmp_path, timeout=300)
    s = read_series(out)
    weight = s["mass"][0] * 0.1 * 9.81  # 2-D mass per unit width x the tank's width (0.1 m)
    assert np.abs(s["tip_displacement"]).max() < 0.005 * weight / K
    assert np.abs(s["load_force_y"]).max() < 0.15 * weight  # dynamic part of the loads only


def test_liquid_adds_its_mass_to_the_vertical_oscillation(tmp_path):
    """Free decay from a 1 cm preload: the tank moves vertically, far below the liquid's acoustic
    modes and without exciting sloshing, so the liquid moves with it as a rigid mass: the period is
    2 pi sqrt((m + M_liquid)/K) (12 % longer than the dry one). Without the coupling (-fs_coupling 0)
    the period is the dry one. Measured: wet +0.038 %, dry +0.011 % (the damping's 1/sqrt(1 - xi^2))."""
    periods = {}
    for coupling in (1, 0):
        out = tmp_path / f"c{coupling}"
        run_flexslosh(COUPLED + ["-fs_beam_preload", 0.01, "-fs_coupling", coupling, "-ts_max_time", 0.36,
                                 "-fs_output_dir", out], cwd=tmp_path, timeout=300)
        s = read_series(out)
        z = crossings(s["time"], s["tip_displacement"])
        assert len(z) >= 2
        periods[coupling] = np.diff(z).mean()
        mliq = s["mass"][0] * 0.1
    wet = 2 * np.pi * np.sqrt((M_STRUCT + mliq) / K)
    dry = 2 * np.pi * np.sqrt(M_STRUCT / K)
    assert periods[1] == pytest.approx(wet, rel=1e-3), (periods, wet, dry)
    assert periods[0] == pytest.approx(dry, rel=3e-4), (periods, wet, dry)


@pytest.mark.parametrize("model", ["msd", "modal"])
def test_coupled_ranks_agree(tmp_path, model):
    """The coupled tank and beam on 1 and 3 ranks: the same particles and structure after 60 steps."""
    runs = {}
    for n in (1, 3):
        out = tmp_path / f"r{n}"
        run_flexslosh(["-fs_case", "tank", "-fs_structure", model, "-fs_dx", 0.005, "-fs_beam_preload", 0.01,
                       "-ts_max_steps", 60, "-fs_output_interval", 0, "-fs_output_dir", out],
                      nranks=n, cwd=tmp_path, timeout=300)
        runs[n] = (last_snapshot(out), read_series(out))
    (a, sa), (b, sb) = runs[1], runs[3]
    assert np.array_equal(a["id"], b["id"])
    for f in ("position", "velocity", "density"):
        assert rel_max_diff(a[f], b[f]) < 1e-10, f
    for c in ("tip_displacement", "tip_acceleration", "load_force_y"):
        assert np.abs(sa[c] - sb[c]).max() <= 1e-9 * np.abs(sa[c]).max(), c


@pytest.mark.parametrize("args,expect", [
    (["-fs_tank_width", -0.1], ["-fs_tank_width", "-0.1", "positive"]),
    (["-fs_tank_reference", 0.35], ["-fs_tank_reference", "two values"]),
    (["-fs_tank_reference", "0.35,1e300"], ["-fs_tank_reference", "its y must lie in"]),
])
def test_bad_coupling_options(tmp_path, args, expect):
    from conftest import petsc_error_message

    proc = run_flexslosh(COUPLED + ["-ts_max_steps", 1, "-fs_output_dir", tmp_path / "o"] + args, cwd=tmp_path, check=False)
    assert proc.returncode != 0
    msg = petsc_error_message(proc.stdout)
    for e in expect:
        assert e in msg, msg


def test_coupled_restart_is_exact(tmp_path):
    """A coupled run restarted from a checkpoint (particles, structure DOFs, dissipated energies)
    continues exactly as the uninterrupted run."""
    base = COUPLED + ["-fs_beam_preload", 0.01, "-fs_checkpoint_interval", 20]
    a, b = tmp_path / "A", tmp_path / "B"
    run_flexslosh(base + ["-ts_max_steps", 40, "-fs_output_dir", a], cwd=tmp_path, timeout=300)
    run_flexslosh(base + ["-ts_max_steps", 40, "-fs_restart", a / "checkpoint_000020.h5", "-fs_output_dir", b],
                  cwd=tmp_path, timeout=300)
    sa, sb = read_series(a), read_series(b)
    assert sb["step"][-1] == 40
    for c in ("tip_displacement", "tip_velocity", "kinetic_energy", "load_force_y"):
        assert sa[c][-1] == sb[c][-1], c
    pa, pb = last_snapshot(a), last_snapshot(b)
    assert np.array_equal(pa["position"], pb["position"])


def momentum_balance_error(out, width=0.1, ref=(0.35, 0.0), g=-9.81):
    """Newton's second law for the liquid in the absolute frame, from a coupled run's output. With R,
    M_R the walls' force and moment (about the tank's reference point x_ref) on the liquid per unit
    width, M its mass, w the tank's width, the structure receives the loads -w R - M g (global axes)
    and -w M_R - the weight's moment at rest (the static loads it does not see), so
      w dP_abs/dt = w (M g + R) = -load_force,
      w dH/dt = w (R(theta) S) x g + w M_R - w V_ref x P_abs = w (R(theta) S - S(0)) x g - load_moment_z - w V_ref x P_abs,
    H = sum m (X - X_ref) x V the absolute angular momentum about the moving reference point. From the
    tank-frame columns: P_abs = M V_ref + R(theta) (P + omega e_z x S), P = (momentum_x, momentum_y),
    S = sum m r (r = x - x_ref) the first moment, S(t) = S(0) + int P dt (dx/dt = u), V_ref = (0,
    tip_velocity); H = (R(theta) S) x V_ref + sum m r x u + omega sum m |r|^2 from the snapshots. The
    masses: the lattice's particles all have the volume dx^2, so m is proportional to the first
    snapshot's density. Returns the largest |w (P_abs(t) - P_abs(0)) + int load_force dt| over the run
    for x and y, and the largest |w (H(t) - H(0)) - int (dH/dt) dt| at the snapshots, each over the
    largest |w (P_abs(t) - P_abs(0))| (|w (H(t) - H(0))|); the integrals by the trapezoidal rule."""
    s = read_series(out)
    t, M = s["time"], s["mass"][0]
    snaps = [read_snapshot(f) for f in snapshot_files(out)]
    m = M * snaps[0]["density"] / snaps[0]["density"].sum()
    ref = np.array(ref)

    def cross(a, b):
        return a[0] * b[1] - a[1] * b[0]

    def integral(y):
        return np.concatenate([[0.0], np.cumsum(0.5 * (y[1:] + y[:-1]) * np.diff(t))])

    S0 = (m[:, None] * (snaps[0]["position"] - ref)).sum(axis=0)
    P = np.stack([s["momentum_x"], s["momentum_y"]])
    S = S0[:, None] + np.stack([integral(p) for p in P])
    th, om = s["tank_rotation"], s["tank_rotation_rate"]

    def turn(v):
        return np.stack([np.cos(th) * v[0] - np.sin(th) * v[1], np.sin(th) * v[0] + np.cos(th) * v[1]])

    Vref = np.stack([0 * t, s["tip_velocity"]])
    Pabs = M * Vref + turn(np.stack([P[0] - om * S[1], P[1] + om * S[0]]))
    errs = []
    for k, axis in enumerate("xy"):
        change = width * (Pabs[k] - Pabs[k, 0])
        errs.append(np.abs(change + integral(s[f"load_force_{axis}"])).max() / np.abs(change).max())
    RS = turn(S)
    dHdt = width * cross(RS - S0[:, None], [0, g]) - s["load_moment_z"] - width * cross(Vref, Pabs)
    H, expect = [], []
    for snap in snaps:
        k = np.argmin(np.abs(t - snap.attrs["time"]))
        assert abs(t[k] - snap.attrs["time"]) < 1e-9
        r, u = snap["position"] - ref, snap["velocity"]
        H.append(width * (cross(RS[:, k], Vref[:, k]) + (m * (r[:, 0] * u[:, 1] - r[:, 1] * u[:, 0])).sum()
                          + om[k] * (m * (r * r).sum(axis=1)).sum()))
        expect.append(integral(dHdt)[k])
    H = np.array(H) - H[0]
    errs.append(np.abs(H - np.array(expect)).max() / np.abs(H).max())
    return errs


@pytest.mark.parametrize("model", ["msd", "modal"])
def test_reaction_loads_balance_the_liquids_momentum(tmp_path, model):
    """The loads the structure receives are the reaction of the walls' forces on the liquid: the
    liquid's absolute momentum and angular momentum (from the tank-frame columns, the tank's motion and
    the snapshots) change by the time integral of minus those loads, plus gravity's moment
    (momentum_balance_error). A free decay from 5 mm (no wall bounces, which change the momentum between
    steps), 0.2 s (the wet period is 0.19 s); the modal beam with 2 modes turns the tank (its x momentum
    comes from the rotation alone). Measured (largest error / largest change): msd y 0.33 % (x and the
    moment are zero by symmetry); modal x 0.29 %, y 0.35 %, moment 0.59 %, the trapezoidal rule's error
    on the printed rows (the loads are those of each step's last stage; y: 0.11 %, 0.05 % at -fs_cfl 0.5,
    0.25). Checked by changing FSCouplingComputeLoads: loads of the wrong sign miss by 200 % (moment)
    to 1800 % (y), a moment 10 % too large by 10 %, a vertical force 2 % too large by 16 % (the weight is
    in it); the wall-pressure integral (-fs_coupling_loads walls) by 210 % (x), 4.7 % (y) and 8 %
    (moment): it is not the reaction, and that energy shows in work_coupling (-0.1 % of the initial
    energy), which the reaction's budget has none of. The whole system's budget closes: residual_total
    3.5e-5 (msd), 4.2e-5 and 4.0e-5 (modal, walls) of the initial energy."""
    runs = {}
    for loads in ("reaction", "walls") if model == "modal" else ("reaction",):
        out = tmp_path / loads
        run_flexslosh(["-fs_case", "tank", "-fs_structure", model] + ["-fs_modal_modes", 2] * (model == "modal") +
                      ["-fs_dx", 0.005, "-fs_beam_preload", 0.005, "-ts_max_time", 0.2, "-fs_output_interval", 0.02,
                       "-fs_coupling_loads", loads, "-fs_output_dir", out], cwd=tmp_path, timeout=300)
        assert read_summary(out)["wall_bounces"] == 0
        e = np.genfromtxt(out / "energy.csv", delimiter=",", names=True)
        E0 = e["E_struct_elastic"][0]
        assert np.abs(e["residual_total"]).max() < 6e-5 * E0, loads
        runs[loads] = (momentum_balance_error(out), e["work_coupling"][-1] / E0)
    err = runs["reaction"][0]
    print(f"{model}: momentum balance error x {err[0]:.2e}, y {err[1]:.2e}, moment {err[2]:.2e}")
    assert err[1] < 0.005, err
    if model == "modal":
        assert err[0] < 0.005 and err[2] < 0.008, err
        walls_err, walls_work = runs["walls"]
        print(f"walls: x {walls_err[0]:.2e}, y {walls_err[1]:.2e}, moment {walls_err[2]:.2e}, work_coupling {walls_work:.2e}")
        assert walls_err[0] > 0.5 and walls_err[1] > 0.02 and walls_err[2] > 0.04, walls_err
        assert abs(walls_work) > 5e-4, walls_work


@pytest.mark.parametrize("model", ["msd", "modal"])
def test_empty_tank_is_the_solid_mass(tmp_path, model):
    """-fs_fill 0, the 0 % point of a fill sweep: no liquid, the payload (3.36 kg) all ballast, so the
    coupled case is the beam with the 5 kg tank and 3.36 kg of ballast at its tip, released from 4 cm,
    xi = 1.5 %: checked against the exact references computed here, not against another run.
    msd: the exact damped oscillator with m = 33/140 m L + 5 + 3.36 kg and K = 3 EI/L^3 (measured
    2.8e-5 of the preload over 0.5 s: RK4 at dt = T/50). modal: q1 is a damped oscillator at the first
    frequency of the clamped beam with the tip mass 8.36 kg and rotary inertia 0.344 kg m^2
    (tip_mass_roots of test_structure.py, 5.99667 Hz), released from rest (measured 9.4e-9 of q1(0):
    the FE frequency is 7e-10 off). Checked by changing the source: a ballast 1 % light (0.2 % of the
    moving mass) misses by 1.4 % with both models, the msd's beam share 1/4 instead of 33/140 by 19 %."""
    from test_structure import EI, MLIN, L, msd_exact, tip_mass_roots

    out = tmp_path / "empty"
    run_flexslosh(["-options_file", REPO_ROOT / "cases/coupled_rectangular.opts", "-fs_structure", model, "-fs_fill", 0,
                   "-ts_max_time", 0.5, "-fs_output_dir", out], cwd=tmp_path)
    s, st = read_series(out), read_summary(out)["structure"]
    t = s["time"]
    assert s["mass"][0] == 0 and t[-1] == pytest.approx(0.5) and len(t) > 20
    tip_mass, inertia, xi = 5.0 + 3.36, 0.344, 0.015
    if model == "msd":
        omega = np.sqrt(3 * EI / L ** 3 / (33 / 140 * MLIN * L + tip_mass))
        err = np.abs(s["tip_displacement"] - msd_exact(t, 0.04, omega, xi)).max() / 0.04
        assert err < 4e-5, err
    else:
        beta = tip_mass_roots(tip_mass / (MLIN * L), inertia / (MLIN * L ** 3), 1)[0]
        omega = beta ** 2 * np.sqrt(EI / (MLIN * L ** 4))
        q = s["q1"]
        assert q[0] == pytest.approx(0.04, rel=0.01)  # most of the static shape is the first mode
        err = np.abs(q - q[0] * msd_exact(t, 1.0, omega, xi)).max() / q[0]
        assert err < 2e-8, err
