"""The liquid in the tank coupled with the structure (issue 5): loads to the structure and the tank's
motion back to the liquid at every stage of the integrator."""
import numpy as np
import pytest

from conftest import last_snapshot, read_series, rel_max_diff, run_flexslosh

# the seed's rectangular tank at 50 % fill on the mass-spring-damper beam; coarse liquid (H/dx = 6)
COUPLED = ["-fs_case", "tank", "-fs_structure", "msd", "-fs_dx", 0.005, "-fs_output_interval", 0]
M_STRUCT, K = 7.62281, 23006.0  # msd defaults of the seed's beam (-fs_view): moving mass and stiffness


def crossings(t, w):
    """Times where w crosses zero upwards (linear interpolation)."""
    i = np.nonzero((w[:-1] < 0) & (w[1:] >= 0))[0]
    return t[i] - w[i] * (t[i + 1] - t[i]) / (w[i + 1] - w[i])


def test_liquid_at_rest_does_not_drive_the_beam(tmp_path):
    """Liquid at rest in the undeflected tank: its weight is part of the static equilibrium, so the
    beam stays still (tip within 2 % of the static deflection the weight would cause)."""
    out = tmp_path / "rest"
    run_flexslosh(COUPLED + ["-ts_max_time", 0.15, "-fs_output_dir", out], cwd=tmp_path, timeout=300)
    s = read_series(out)
    weight = s["mass"][0] * 0.1 * 9.81  # 2-D mass per unit width x the tank's width (0.1 m)
    assert np.abs(s["tip_displacement"]).max() < 0.02 * weight / K
    assert np.abs(s["load_force_y"]).max() < 0.2 * weight  # dynamic part of the loads only


def test_liquid_adds_its_mass_to_the_vertical_oscillation(tmp_path):
    """Free decay from a 1 cm preload: the tank moves vertically, far below the liquid's acoustic
    modes and without exciting sloshing, so the liquid moves with it as a rigid mass: the period is
    2 pi sqrt((m + M_liquid)/K) (12 % longer than the dry one). Without the coupling (-fs_coupling 0)
    the period is the dry one."""
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
    assert periods[1] == pytest.approx(wet, rel=0.01), (periods, wet, dry)
    assert periods[0] == pytest.approx(dry, rel=0.005), (periods, wet, dry)


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


def test_reaction_loads_conserve_the_coupled_energy(tmp_path):
    """With the default reaction loads the coupling neither creates nor destroys energy (work_coupling
    is zero and the whole system's residual is the integrator's); the wall-pressure integral
    (-fs_coupling_loads walls) gives the modal beam a moment that is not the reaction and does work."""
    import numpy as np

    work = {}
    for loads in ("reaction", "walls"):
        out = tmp_path / loads
        run_flexslosh(["-fs_case", "tank", "-fs_structure", "modal", "-fs_dx", 0.005, "-fs_beam_preload", 0.01,
                       "-ts_max_time", 0.1, "-fs_output_interval", 0, "-fs_coupling_loads", loads, "-fs_output_dir", out],
                      cwd=tmp_path, timeout=300)
        e = np.genfromtxt(out / "energy.csv", delimiter=",", names=True)
        E0 = e["E_struct_elastic"][0]
        work[loads] = e["work_coupling"][-1] / E0
        assert np.abs(e["residual_total"]).max() < 1e-4 * E0, loads
    assert work["reaction"] == 0.0
    assert abs(work["walls"]) > 1e-3, work


@pytest.mark.parametrize("model", ["msd", "modal"])
def test_empty_tank_is_the_solid_mass(tmp_path, model):
    """-fs_fill 0, the 0 % point of a fill sweep: no liquid, the payload all ballast, so the coupled case
    is the structure alone with that ballast (cases/beam_free_decay_*.opts): the same tip history."""
    from conftest import REPO_ROOT

    empty, solid = tmp_path / "empty", tmp_path / "solid"
    run_flexslosh(["-options_file", REPO_ROOT / "cases/coupled_rectangular.opts", "-fs_structure", model, "-fs_fill", 0,
                   "-ts_max_time", 0.5, "-fs_output_dir", empty], cwd=tmp_path)
    run_flexslosh(["-options_file", REPO_ROOT / f"cases/beam_free_decay_{model}.opts", "-ts_max_time", 0.5,
                   "-fs_output_dir", solid], cwd=tmp_path)
    e, s = read_series(empty), read_series(solid)
    assert e["mass"][0] == 0 and len(e["time"]) == len(s["time"]) > 20
    np.testing.assert_allclose(e["time"], s["time"], rtol=1e-12)
    assert rel_max_diff(e["tip_displacement"], s["tip_displacement"]) < 1e-12
