"""Post-processing (flexslosh.output, flexslosh.figures, python3 -m flexslosh.plot) on real runs.

Two tiny runs, made once for the module: the beam alone with the solid mass (msd, 1 s, about 0.5 s
of wall time), whose damping is the model's own 1.5 %, so reading the columns wrong or finding the
peaks wrong fails the test; and the coupled rectangular tank at dx = 5 mm (840 particles, 0.25 s,
about 3 s), which has snapshots, an energy budget and one cycle of motion.
"""
import json
import struct
from pathlib import Path

import numpy as np
import pytest

from conftest import REPO_ROOT, plot_cli, run_flexslosh

from flexslosh import figures
from flexslosh.damping import damping_per_cycle, fit_envelope
from flexslosh.output import SNAPSHOT_FIELDS, read_csv, read_run, read_snapshot

ZETA = 0.015  # -fs_beam_damping of cases/beam_free_decay_msd.opts


@pytest.fixture(scope="module")
def beam_dir(tmp_path_factory):
    out = tmp_path_factory.mktemp("post") / "solid_mass"
    run_flexslosh(["-options_file", REPO_ROOT / "cases/beam_free_decay_msd.opts", "-ts_max_time", "1.0",
                   "-fs_output_dir", out])
    return out


@pytest.fixture(scope="module")
def tank_dir(tmp_path_factory):
    out = tmp_path_factory.mktemp("post") / "liquid"
    run_flexslosh(["-options_file", REPO_ROOT / "cases/coupled_rectangular.opts", "-fs_dx", "0.005",
                   "-ts_max_time", "0.25", "-fs_output_interval", "0.05", "-fs_output_dir", out])
    return out



def png_size(path):
    """(width, height) from a PNG's IHDR chunk, after checking the signature."""
    data = Path(path).read_bytes()
    assert data[:8] == b"\x89PNG\r\n\x1a\n", f"{path}: not a PNG"
    assert data[12:16] == b"IHDR", f"{path}: no IHDR chunk first"
    return struct.unpack(">II", data[16:24])


# ------------------------------------------------------------------ reading


def test_read_run_beam(beam_dir):
    run = read_run(beam_dir)
    ts = run.timeseries
    for col in ("step", "time", "dt", "tip_displacement", "tip_velocity", "tip_acceleration", "load_force_y"):
        assert col in ts, col
    n = len(ts["time"])
    assert n > 100 and all(len(v) == n for v in ts.values())
    assert ts["step"].dtype == np.int64 and np.array_equal(ts["step"], np.arange(n))
    assert ts["time"][0] == 0 and ts["time"][-1] == pytest.approx(1.0)
    assert ts["tip_displacement"][0] == pytest.approx(0.04)  # -fs_beam_preload
    assert {"E_struct_kin", "E_struct_elastic", "work_struct_damping"} <= set(run.energy)
    assert len(run.energy["time"]) == n
    assert run.summary["structure"]["model"] == "msd"
    assert run.particles == 0 and run.snapshots == [] and run.beam_shapes == []
    with pytest.raises(ValueError, match="timeseries.csv: no column 'q1'"):
        run.column("q1")


def test_damping_per_cycle_is_the_models(beam_dir):
    run = read_run(beam_dir)
    c = damping_per_cycle(run.timeseries["time"], run.timeseries["tip_displacement"])
    assert len(c.zeta) >= 5  # 6 Hz for 1 s
    assert np.allclose(c.zeta, ZETA, rtol=0.05), c.zeta
    omega = run.summary["structure"]["omega"]
    assert np.allclose(c.period, 2 * np.pi / (omega * np.sqrt(1 - ZETA**2)), rtol=2e-3), c.period
    assert np.all(np.diff(c.amplitude) < 0)


def test_envelope_fit_and_figure(beam_dir, tmp_path):
    run = read_run(beam_dir)
    env = fit_envelope(run.timeseries["time"], run.timeseries["tip_acceleration"])
    assert len(env.amplitude) >= 10  # one peak per half cycle
    assert env.zeta == pytest.approx(ZETA, rel=0.10)
    path = figures.acceleration_envelope([run], ["solid mass"], tmp_path / "env.png")
    assert png_size(path) > (0, 0) and not list(tmp_path.glob("*.tmp"))


def test_read_run_tank_and_snapshots(tank_dir):
    run = read_run(tank_dir)
    n = run.summary["particles"]
    assert n == run.particles > 0
    assert {"tip_acceleration", "wall_tank_force_y", "dissipated_delta"} <= set(run.timeseries)
    times = [t for t, _ in run.snapshots]
    assert len(times) == 6 and times == sorted(times) and times[0] == 0
    assert times[-1] == pytest.approx(run.summary["final_time"])
    for t, path in (run.snapshots[0], run.snapshots[-1]):
        snap = read_snapshot(path)
        assert set(SNAPSHOT_FIELDS) <= set(snap)
        assert snap.dim == 2 and snap.time == pytest.approx(t, abs=1e-12)
        assert snap["position"].shape == (n, 2) and snap["velocity"].shape == (n, 2)
        for f in SNAPSHOT_FIELDS:
            assert len(snap[f]) == n, f
        assert np.array_equal(snap["id"], np.arange(n))  # sorted by id
        assert np.all(snap["density"] > 0)
    # the snapshot's particles: the liquid at 50 % fill of the 0.7 x 0.06 m tank
    pos = read_snapshot(run.snapshots[0][1])["position"]
    assert 0 < pos[:, 0].min() and pos[:, 0].max() < 0.7 and pos[:, 1].max() < 0.031


def test_energy_terms(tank_dir, beam_dir, tmp_path):
    run = read_run(tank_dir)
    e = figures.energy_balance(run)
    scale = np.abs(e["mechanical"]).max()
    assert scale > 0 and np.any(e["dissipation"] < 0) and np.any(e["external"] != 0)
    # the same residual as the C code's: the columns are read and combined right
    assert np.abs(e["residual"] - run.energy["residual_liquid"]).max() < 1e-6 * scale
    path = figures.energy_terms(run, tmp_path / "energy.png")
    assert png_size(path) > (0, 0)
    with pytest.raises(ValueError, match=r"energy\.csv: the run has no liquid"):
        figures.energy_terms(read_run(beam_dir), tmp_path / "x.png")


def test_figures_name_a_missing_column(beam_dir, tmp_path):
    run = read_run(beam_dir)
    del run.timeseries["tip_acceleration"]
    with pytest.raises(ValueError, match=r"timeseries\.csv: no column 'tip_acceleration'"):
        figures.tip_acceleration(run, tmp_path / "a.png")
    with pytest.raises(ValueError, match="no particle snapshots"):
        figures.snapshots(run, tmp_path / "s.png")
    assert not list(tmp_path.iterdir())


# ------------------------------------------------------------------ command line


def test_plot_cli(beam_dir, tank_dir, tmp_path):
    out = tmp_path / "figs"
    proc = plot_cli(beam_dir, tank_dir, "--labels", "solid mass,liquid", "--out", out)
    assert proc.returncode == 0, proc.stderr
    written = [Path(p) for p in proc.stdout.split()]
    names = {p.name for p in written}
    assert names == {"damping_solid_mass.csv", "tip_acceleration_solid_mass.png", "damping_liquid.csv",
                     "tip_acceleration_liquid.png", "energy_terms_liquid.png", "snapshots_liquid.png",
                     "normalized_motion.png", "acceleration_envelope.png", "damping_vs_amplitude.png"}, proc.stdout
    # what the solid mass cannot give, said in one line each
    notes = proc.stderr.strip().splitlines()
    assert len(notes) == 2 and all(n.startswith("note: skipped") for n in notes), proc.stderr
    assert all(p.parent == out and p.exists() for p in written)
    for p in written:
        if p.suffix == ".png":
            w, h = png_size(p)
            assert w > 0 and h > 0, p
    solid = read_csv(out / "damping_solid_mass.csv")
    assert list(solid) == ["time", "amplitude", "period", "delta", "zeta"]
    assert np.allclose(solid["zeta"], ZETA, rtol=0.05)
    liquid = read_csv(out / "damping_liquid.csv")
    assert len(liquid["zeta"]) == 1 and 0 < liquid["zeta"][0] < 0.5
    assert not list(out.glob("*.tmp"))


def test_plot_cli_into_run_directory(beam_dir):
    proc = plot_cli(beam_dir)
    assert proc.returncode == 0, proc.stderr
    assert (beam_dir / "damping.csv").exists() and png_size(beam_dir / "normalized_motion.png") > (0, 0)
    assert str(beam_dir / "tip_acceleration.png") in proc.stdout.split()


def test_plot_cli_help():
    proc = plot_cli("--help")
    assert proc.returncode == 0 and "OUTPUT_DIR" in proc.stdout and "--field" in proc.stdout


# ------------------------------------------------------------------ errors


def test_missing_directory(tmp_path):
    with pytest.raises(FileNotFoundError, match="nowhere: no such directory"):
        read_run(tmp_path / "nowhere")
    proc = plot_cli(tmp_path / "nowhere")
    assert proc.returncode == 1 and proc.stdout == ""
    assert proc.stderr.count("\n") == 1 and "nowhere: no such directory" in proc.stderr


def test_not_an_output_directory(tmp_path):
    (tmp_path / "summary.json").write_text("{}")
    with pytest.raises(FileNotFoundError, match=r"timeseries\.csv: no such file"):
        read_run(tmp_path)
    proc = plot_cli(tmp_path)
    assert proc.returncode == 1 and proc.stderr.count("\n") == 1
    assert str(tmp_path / "timeseries.csv") in proc.stderr and "not a flexslosh output" in proc.stderr


def test_truncated_row(beam_dir, tmp_path):
    text = (beam_dir / "timeseries.csv").read_text()
    lines = text.splitlines()
    torn = "\n".join(lines[:-1]) + "\n" + lines[-1][: len(lines[-1]) // 2]
    (tmp_path / "timeseries.csv").write_text(torn)
    with pytest.raises(ValueError, match=rf"timeseries\.csv: line {len(lines)} has \d+ fields, the header has \d+ \(a partially written last row\)"):
        read_run(tmp_path)
    # a run still writing: the torn last row dropped on request
    run = read_run(tmp_path, allow_partial_last_row=True)
    assert len(run.timeseries["time"]) == len(lines) - 2
    proc = plot_cli(tmp_path)
    assert proc.returncode == 1 and proc.stderr.count("\n") == 1 and "timeseries.csv: line" in proc.stderr
    # a value that is not a number, inside the file
    bad = lines[:5] + [lines[5].replace(",", ",x", 1)] + lines[6:]
    (tmp_path / "timeseries.csv").write_text("\n".join(bad) + "\n")
    with pytest.raises(ValueError, match=r"timeseries\.csv: line 6, column 'time': 'x.*' is not a number"):
        read_run(tmp_path)


def test_bad_snapshot(tank_dir, tmp_path):
    import h5py

    with pytest.raises(FileNotFoundError, match="snapshot_999999.h5: no such file"):
        read_snapshot(tmp_path / "snapshot_999999.h5")
    path = tmp_path / "snapshot_000000.h5"
    with h5py.File(tank_dir / "snapshot_000000.h5", "r") as src, h5py.File(path, "w") as dst:
        for name in SNAPSHOT_FIELDS:
            if name != "pressure":
                dst.create_dataset(f"particles/{name}", data=src[f"particles/{name}"][...])
        dst["particles"].attrs.update(dict(src["particles"].attrs))
    with pytest.raises(ValueError, match=r"snapshot_000000\.h5: /particles lacks the field\(s\) pressure"):
        read_snapshot(path)
    (tmp_path / "junk.h5").write_text("not hdf5")
    with pytest.raises(ValueError, match=r"junk\.h5: not a readable HDF5 file"):
        read_snapshot(tmp_path / "junk.h5")


def test_bad_summary(beam_dir, tmp_path):
    (tmp_path / "timeseries.csv").write_text((beam_dir / "timeseries.csv").read_text())
    (tmp_path / "summary.json").write_text('{"particles": 1')
    with pytest.raises(ValueError, match=r"summary\.json: not valid JSON"):
        read_run(tmp_path)
    (tmp_path / "summary.json").write_text(json.dumps({"particles": 0}))
    assert read_run(tmp_path).summary == {"particles": 0}
