"""Plots that know the structure (python3 -m flexslosh.plot, flexslosh.figures): a prescribed-motion run gets
its motion's components and the walls' loads against time, a beam run the seed's figures as before.

A 2-D tank rolled and shaken by sines without a ramp (0.1 s, coarse): motion_components gives the roll in
degrees and the translation in mm equal to the sines given (1e-9); the plot command writes motion.png and
wall_loads.png for it and no beam figure (tip acceleration, damping), and with a beam run beside it the
figures of all the runs together are the beam's alone. A 3-D prescribed run's pitch, yaw and axis columns
(a Run built here) are shown in degrees.
"""
from pathlib import Path

import numpy as np
import pytest

from conftest import REPO_ROOT, plot_cli, run_flexslosh

from flexslosh import figures
from flexslosh.output import Run, read_run

ROLL, X = (3.0, 0.7, 20.0), (0.004, 0.5, 0.0)  # A, T, phi (degrees)


@pytest.fixture(scope="module")
def rig_dir(tmp_path_factory):
    out = tmp_path_factory.mktemp("plot") / "rig"
    run_flexslosh(["-fs_case", "tank", "-fs_tank_length", 0.2, "-fs_tank_height", 0.12, "-fs_fill", 0.4, "-fs_dx", 0.01,
                   "-fs_c0", 10, "-fs_structure", "prescribed", "-fs_motion_roll_sines", ",".join(map(str, ROLL)),
                   "-fs_motion_x_sines", ",".join(map(str, X)), "-ts_max_time", 0.1, "-fs_output_interval", 0.05,
                   "-fs_output_dir", out])
    return out


@pytest.fixture(scope="module")
def beam_dir(tmp_path_factory):
    out = tmp_path_factory.mktemp("plot") / "beam"
    run_flexslosh(["-options_file", REPO_ROOT / "cases/beam_free_decay_msd.opts", "-ts_max_time", "0.5",
                   "-fs_output_dir", out])
    return out


def sine(p, t):
    A, T, phi = p
    return A * np.sin(2 * np.pi * t / T + np.radians(phi))


def test_motion_components_are_the_sines(rig_dir):
    run = read_run(rig_dir)
    assert figures.is_prescribed(run)
    t = run.timeseries["time"]
    c = figures.motion_components(run)
    assert list(c["rotation"]) == ["roll (about z)"] and list(c["translation"]) == ["x"]
    assert np.abs(c["rotation"]["roll (about z)"] - sine(ROLL, t)).max() < 1e-9 * ROLL[0]
    assert np.abs(c["translation"]["x"] - 1e3 * sine(X, t)).max() < 1e-9 * 1e3 * X[0]


def test_motion_components_3d_rotations(tmp_path):
    t = np.linspace(0, 1, 11)
    ts = {"time": t, "motion_disp_x": 0 * t, "motion_disp_y": 0.01 * t, "motion_disp_z": 0 * t,
          "motion_angle": 0 * t, "motion_pitch": 0.1 * t, "motion_yaw": -0.2 * t, "motion_axis_angle": 0.3 * t}
    c = figures.motion_components(Run(tmp_path, ts))
    assert set(c["translation"]) == {"y"} and np.allclose(c["translation"]["y"], 10 * t)
    assert set(c["rotation"]) == {"pitch (about x)", "yaw (about y)", "about the axis"}
    assert np.allclose(c["rotation"]["yaw (about y)"], np.degrees(-0.2 * t), rtol=1e-14)
    with pytest.raises(ValueError, match="not a prescribed motion"):
        figures.motion_components(Run(tmp_path, {"time": t, "tip_displacement": t}))


def test_plot_knows_the_structure(rig_dir, beam_dir, tmp_path):
    out = tmp_path / "figs"
    proc = plot_cli(rig_dir, beam_dir, "--labels", "rig,beam", "--out", out)
    assert proc.returncode == 0, proc.stderr
    names = {Path(p).name for p in proc.stdout.split()}
    assert {"motion_rig.png", "wall_loads_rig.png", "energy_terms_rig.png", "snapshots_rig.png"} <= names, names
    assert not {"tip_acceleration_rig.png", "damping_rig.csv", "motion_beam.png", "wall_loads_beam.png"} & names
    assert {"tip_acceleration_beam.png", "damping_beam.csv", "normalized_motion.png", "acceleration_envelope.png",
            "damping_vs_amplitude.png"} <= names, names
    for p in proc.stdout.split():
        assert Path(p).stat().st_size > 0
    # the rig alone: its own figures, and none of the beams' together
    proc = plot_cli(rig_dir, "--out", tmp_path / "rig")
    assert proc.returncode == 0, proc.stderr
    assert {Path(p).name for p in proc.stdout.split()} == {"motion_rig.png", "wall_loads_rig.png",
                                                           "energy_terms_rig.png", "snapshots_rig.png"}
