"""Checkpoints and -fs_restart: a restarted run continues exactly as the uninterrupted one."""
import re

import h5py
import numpy as np
import pytest

from conftest import (TG, assert_no_crash, last_snapshot, petsc_error_message, read_series, read_snapshot,
                      rel_max_diff, run_flexslosh, snapshot_files)

FIELDS = ("position", "velocity", "density", "pressure", "strain_rate", "turbulent_viscosity")


@pytest.fixture(scope="module")
def full_run(tmp_path_factory):
    """TG, 40 steps, checkpoints every 20 steps, on 1 and on 2 ranks (run on demand, once)."""
    cache = {}

    def get(nranks):
        if nranks not in cache:
            out = tmp_path_factory.mktemp(f"full{nranks}")
            run_flexslosh(TG + ["-ts_max_steps", "40", "-fs_checkpoint_interval", "20", "-fs_output_dir", out], nranks=nranks, cwd=out)
            cache[nranks] = out
        return cache[nranks]

    return get


def check_continuation(a_dir, b_dir, tol):
    a, b = last_snapshot(a_dir), last_snapshot(b_dir)
    assert a.attrs["step"] == b.attrs["step"] == 40
    assert a.attrs["time"] == pytest.approx(b.attrs["time"], rel=1e-14, abs=0)
    assert np.array_equal(a["id"], b["id"])
    for f in FIELDS:
        err = rel_max_diff(a[f], b[f])
        assert err <= tol, f"{f}: restarted run differs by {err:.3g} (relative)"
    sa, sb = read_series(a_dir), read_series(b_dir)
    # the restarted run's series starts at the checkpoint's step and then matches row by row
    assert sb["step"][0] == 20 and sb["step"][-1] == 40
    ka = {s: k for k, s in enumerate(sa["step"])}
    rows = [k for k, s in enumerate(sb["step"]) if s > 20]
    assert [sb["step"][k] for k in rows] == list(range(21, 41))
    for name in sa:
        if name == "step":
            continue
        va = np.array([sa[name][ka[sb["step"][k]]] for k in rows])
        vb = sb[name][rows]
        scale = max(np.abs(va).max(), 1e-300)
        # momentum is round-off (1e-17); compare it in absolute terms against the total momentum scale
        if name.startswith("momentum"):
            scale = 1.0
        assert np.abs(va - vb).max() <= tol * scale + 0.0, f"time series column {name} differs"


def test_checkpoint_file(full_run):
    a = full_run(1)
    ck = a / "checkpoint_000020.h5"
    assert ck.exists() and (a / "checkpoint_000040.h5").exists()
    assert not list(a.glob("checkpoint_0000[13]?.h5"))  # only every 20 steps
    with h5py.File(ck, "r") as h5:
        hdr = h5["header"].attrs
        assert hdr["step"] == 20 and hdr["nparticles"] == 2500 and hdr["nranks"] == 1
        assert h5["particles/position"].shape == (2500, 2)
        assert sorted(h5["particles"].keys()) == ["density", "id", "mass", "position", "velocity"]
        t20 = float(hdr["time"])
    series = read_series(a)
    assert t20 == pytest.approx(series["time"][series["step"] == 20][0], rel=1e-9)  # the CSV has 11 digits


def test_restart_same_ranks_is_exact(full_run, tmp_path):
    a = full_run(1)
    b = tmp_path / "B"
    run_flexslosh(TG + ["-fs_restart", a / "checkpoint_000020.h5", "-fs_output_dir", b, "-ts_max_steps", "40"], cwd=tmp_path)
    # observed: bitwise identical (the restart rebuilds exactly the same state)
    check_continuation(a, b, tol=0.0)


def test_restart_two_ranks_is_exact(full_run, tmp_path):
    a = full_run(2)
    b = tmp_path / "B"
    with h5py.File(a / "checkpoint_000020.h5", "r") as h5:
        assert h5["header"].attrs["nranks"] == 2
        assert h5["layout/nlocal"].shape == (2,)
    run_flexslosh(TG + ["-fs_restart", a / "checkpoint_000020.h5", "-fs_output_dir", b, "-ts_max_steps", "40"], nranks=2, cwd=tmp_path)
    check_continuation(a, b, tol=0.0)


def test_restart_on_other_rank_count(full_run, tmp_path):
    # a checkpoint written on 2 ranks, continued on 1: the same run up to round-off
    a = full_run(2)
    b = tmp_path / "B"
    run_flexslosh(TG + ["-fs_restart", a / "checkpoint_000020.h5", "-fs_output_dir", b, "-ts_max_steps", "40"], nranks=1, cwd=tmp_path)
    check_continuation(a, b, tol=1e-12)


def test_restart_missing_file(run, tmp_path):
    missing = tmp_path / "nowhere" / "checkpoint_000020.h5"
    proc = run(TG + ["-fs_restart", missing, "-fs_output_dir", tmp_path / "B", "-ts_max_steps", "40"], check=False)
    assert_no_crash(proc)
    msg = petsc_error_message(proc.stdout)
    assert str(missing) in msg and re.search(r"does not exist|cannot be read", msg), msg


def test_restart_from_a_file_that_is_not_hdf5(run, tmp_path):
    bad = tmp_path / "checkpoint_000020.h5"
    bad.write_text("not an HDF5 file\n")
    proc = run(TG + ["-fs_restart", bad, "-fs_output_dir", tmp_path / "B", "-ts_max_steps", "40"], check=False)
    assert_no_crash(proc)
    msg = petsc_error_message(proc.stdout)
    assert str(bad) in msg and "not an HDF5 file" in msg and "H5Fopen" not in msg, msg


def test_restart_with_other_terms_is_refused(full_run, tmp_path):
    a = full_run(1)
    proc = run_flexslosh(TG + ["-fs_restart", a / "checkpoint_000020.h5", "-fs_output_dir", tmp_path / "B", "-ts_max_steps", "40",
                               "-fs_terms", "continuity,pressure,viscosity"], cwd=tmp_path, check=False)
    assert_no_crash(proc)
    msg = petsc_error_message(proc.stdout)
    assert "checkpoint_000020.h5" in msg and "-fs_terms" in msg, msg


# ---- restarting in the run's own directory, with snapshots at an output interval (dx 0.04: fast)

SMALL = ["-fs_case", "taylor_green", "-fs_dx", "0.04", "-fs_output_interval", "0.01"]


@pytest.fixture(scope="module")
def same_dir(tmp_path_factory):
    """An uninterrupted run (ref) and the same run restarted at step 20 in its own directory (re)."""
    ref = tmp_path_factory.mktemp("ref")
    re_ = tmp_path_factory.mktemp("re")
    for d in (ref, re_):
        run_flexslosh(SMALL + ["-ts_max_steps", "40", "-fs_checkpoint_interval", "20", "-fs_output_dir", d], cwd=d)
    run_flexslosh(SMALL + ["-ts_max_steps", "40", "-fs_restart", re_ / "checkpoint_000020.h5", "-fs_output_dir", re_], cwd=re_)
    return ref, re_


def test_restart_in_place_final_state(same_dir):
    ref, re_ = same_dir
    a = read_snapshot(snapshot_files(ref)[-1])
    index = (re_ / "snapshots.csv").read_text().strip().splitlines()
    b = read_snapshot(re_ / index[-1].split(",")[3])
    assert a.attrs["step"] == b.attrs["step"] == 40
    for f in FIELDS:
        assert rel_max_diff(a[f], b[f]) == 0.0


def test_restart_in_place_time_series_has_no_duplicate_rows(same_dir):
    ref, re_ = same_dir
    sa, sb = read_series(ref), read_series(re_)
    assert list(sb["step"]) == list(range(0, 41))
    for name in sa:
        assert np.array_equal(sa[name], sb[name]), name


def test_restart_in_place_snapshot_schedule(same_dir):
    ref, re_ = same_dir

    def index(d):
        rows = [l.split(",") for l in (d / "snapshots.csv").read_text().strip().splitlines()[1:]]
        return [(int(r[0]), int(r[2])) for r in rows]

    assert index(re_) == index(ref)
