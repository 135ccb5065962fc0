"""Checkpoints and -fs_restart: a restarted run continues exactly as the uninterrupted one."""
import re

import h5py
import numpy as np
import pytest

from checkpoint_tools import checksum, edit, header_checksum, strip_checksums
from conftest import (REPO_ROOT, TG, assert_no_crash, last_snapshot, petsc_error_message, read_series, read_snapshot,
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
        assert sorted(h5["particles"].keys()) == ["build_position", "density", "id", "mass", "position", "velocity"]
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


# ---- a restart continues the same run: the checkpoint's set-up record against this run's

def restart_of(full_run, tmp_path, extra, nranks=1, check=False, timeout=120):
    a = full_run(1)
    return run_flexslosh(TG + ["-fs_restart", a / "checkpoint_000020.h5", "-fs_output_dir", tmp_path / "B",
                               "-ts_max_steps", "40"] + extra, nranks=nranks, cwd=tmp_path, check=check, timeout=timeout)


def test_restart_as_another_case_is_refused(full_run, tmp_path):
    proc = restart_of(full_run, tmp_path, ["-fs_case", "standing_wave"])
    assert_no_crash(proc)
    msg = petsc_error_message(proc.stdout)
    assert "checkpoint_000020.h5" in msg and "-fs_case: taylor_green -> standing_wave" in msg, msg
    assert "-fs_restart_allow_changes" in msg, msg


def test_restart_with_another_spacing_names_both_values(full_run, tmp_path):
    proc = restart_of(full_run, tmp_path, ["-fs_dx", "0.04"])
    assert_no_crash(proc)
    msg = petsc_error_message(proc.stdout)
    assert "-fs_dx: 0.02 -> 0.04" in msg, msg
    # one error lists every difference: here only the spacing
    assert "1 item(s) differ" in msg, msg


def test_restart_allows_the_changes_named(full_run, tmp_path):
    proc = restart_of(full_run, tmp_path, ["-fs_nu", "0.02"])
    assert_no_crash(proc)
    assert "-fs_nu: 0.01 -> 0.02" in petsc_error_message(proc.stdout)
    restart_of(full_run, tmp_path, ["-fs_nu", "0.02", "-fs_restart_allow_changes", "fs_nu"], check=True)


def test_restart_may_change_the_final_time_and_output(full_run, tmp_path):
    # -ts_max_time, -ts_max_steps and the output options never define the run
    proc = restart_of(full_run, tmp_path, ["-ts_max_time", "0.5", "-ts_max_steps", "25", "-fs_output_interval", "0.001",
                                           "-fs_checkpoint_interval", "5"], check=True)
    assert read_series(tmp_path / "B")["step"][-1] == 25, proc.stdout[-2000:]


def test_restart_with_changed_walls_is_refused(tmp_path):
    walls = tmp_path / "tank.walls"
    box = "wall tank\n0 0\n0.4 0\n0.4 0.2\n0 0.2\nend\n"
    walls.write_text(box)
    base = ["-fs_case", "tank", "-fs_tank_shape", "file", "-fs_tank_file", walls, "-fs_dx", "0.02",
            "-fs_output_interval", "0", "-ts_max_steps", "4"]
    run_flexslosh(base + ["-fs_checkpoint_interval", "2", "-fs_output_dir", tmp_path / "A"], cwd=tmp_path)
    walls.write_text(box.replace("0.4 0.2", "0.4 0.21"))  # the same file, one vertex moved
    proc = run_flexslosh(base + ["-fs_restart", tmp_path / "A" / "checkpoint_000002.h5", "-fs_output_dir", tmp_path / "B"],
                         cwd=tmp_path, check=False)
    assert_no_crash(proc)
    msg = petsc_error_message(proc.stdout)
    assert "walls_geometry" in msg and "1 item(s) differ" in msg, msg


def damaged_copy(full_run, tmp_path, how):
    src = full_run(1) / "checkpoint_000020.h5"
    dst = tmp_path / "checkpoint_000020.h5"
    dst.write_bytes(src.read_bytes())
    how(dst)
    return dst


@pytest.mark.parametrize("nranks", [1, 2])
def test_restart_from_a_truncated_checkpoint(full_run, tmp_path, nranks):
    def cut(p):
        with open(p, "r+b") as fp:
            fp.truncate(p.stat().st_size // 2)

    bad = damaged_copy(full_run, tmp_path, cut)
    proc = run_flexslosh(TG + ["-fs_restart", bad, "-fs_output_dir", tmp_path / "B", "-ts_max_steps", "40"],
                         nranks=nranks, cwd=tmp_path, check=False, timeout=60)
    assert_no_crash(proc)
    msg = petsc_error_message(proc.stdout)
    assert str(bad) in msg and "truncated" in msg, msg


@pytest.mark.parametrize("item,expect", [("particles/velocity", "velocity"), ("layout/nlocal", "/layout/nlocal"),
                                         ("header.setup", "/header.setup")])
def test_restart_from_a_checkpoint_missing_an_item(full_run, tmp_path, item, expect):
    def delete(p):
        with h5py.File(p, "r+") as h5:
            if "." in item:
                group, attr = item.split(".")
                del h5[group].attrs[attr]
            else:
                del h5[item]

    bad = damaged_copy(full_run, tmp_path, delete)
    # 1 rank wrote it: on 1 rank the layout is read, on 2 the particles are split evenly
    for nranks in (1, 2) if item != "layout/nlocal" else (1,):
        proc = run_flexslosh(TG + ["-fs_restart", bad, "-fs_output_dir", tmp_path / "B", "-ts_max_steps", "40"],
                             nranks=nranks, cwd=tmp_path, check=False, timeout=60)
        assert_no_crash(proc)
        msg = petsc_error_message(proc.stdout)
        assert str(bad) in msg and expect in msg and ("missing" in msg or "has no field" in msg), msg


# ---- a coupled run restarted on another number of ranks

COUPLED = ["-options_file", REPO_ROOT / "cases" / "coupled_rectangular.opts", "-fs_output_interval", "0",
           "-ts_max_steps", "60", "-fs_checkpoint_interval", "30"]


def test_coupled_restart_on_three_ranks_agrees(tmp_path):
    """The coupled rectangular tank (msd beam), 60 steps on 2 ranks, against the same run restarted at
    step 30 on 3 ranks. Observed: the particles of the final checkpoints agree to 3e-14 (relative to each
    field's largest value), the global DOFs (beam, dissipated energies) to 3e-15; the time series'
    columns agree to the 11 digits printed, but for the round-off columns (the x loads and momentum of
    the symmetric tank, 1e-12 N against loads of 1e3 N), which agree to 1e-15 of their family's scale.
    The rest is the sums' order over 3 ranks instead of 2."""
    a, b = tmp_path / "A", tmp_path / "B"
    run_flexslosh(COUPLED + ["-fs_output_dir", a], nranks=2, cwd=tmp_path)
    run_flexslosh(COUPLED + ["-fs_output_dir", b, "-fs_restart", a / "checkpoint_000030.h5"], nranks=3, cwd=tmp_path)
    with h5py.File(a / "checkpoint_000060.h5", "r") as ha, h5py.File(b / "checkpoint_000060.h5", "r") as hb:
        assert ha["header"].attrs["nranks"] == 2 and hb["header"].attrs["nranks"] == 3
        assert ha["header"].attrs["time"] == pytest.approx(hb["header"].attrs["time"], rel=1e-14)
        oa, ob = np.argsort(ha["particles/id"][...]), np.argsort(hb["particles/id"][...])
        for f in ("position", "velocity", "density"):
            assert rel_max_diff(ha["particles/" + f][...][oa], hb["particles/" + f][...][ob]) <= 1e-12, f
        assert rel_max_diff(ha["header/global"][...], hb["header/global"][...]) <= 1e-12
    sa, sb = read_series(a), read_series(b)
    assert list(sb["step"]) == list(range(30, 61))
    rows = sb["step"] > 30
    ka = [list(sa["step"]).index(s) for s in sb["step"][rows]]

    def family(name):  # the columns a round-off column is measured against
        return [n for n in sa if n.split("_")[0] == name.split("_")[0]] if name.split("_")[0] in ("momentum", "wall", "load") else [name]

    for name in sa:
        va, vb = sa[name][ka], sb[name][rows]
        scale = max(max(np.abs(sa[n]).max() for n in family(name)), 1e-300)
        assert np.abs(va - vb).max() <= 1e-12 * scale, f"time series column {name}: {np.abs(va - vb).max() / scale:.3g}"


def test_restart_from_a_version_1_checkpoint(full_run, tmp_path):
    """A checkpoint written before the set-up record (format version 1) is refused, saying so, unless
    -fs_restart_allow_changes all: then it restarts unchecked, with a warning."""
    def old(p):
        with h5py.File(p, "r+") as h5:
            del h5["header"].attrs["setup"]
            h5["header"].attrs["version"] = np.int64(1)
            strip_checksums(h5)  # none before version 3

    ck = damaged_copy(full_run, tmp_path, old)
    args = TG + ["-fs_restart", ck, "-fs_output_dir", tmp_path / "B", "-ts_max_steps", "22"]
    proc = run_flexslosh(args, cwd=tmp_path, check=False)
    assert_no_crash(proc)
    msg = petsc_error_message(proc.stdout)
    assert str(ck) in msg and "format version 1" in msg and "-fs_restart_allow_changes all" in msg, msg
    proc = run_flexslosh(args + ["-fs_restart_allow_changes", "all"], cwd=tmp_path)
    assert "has no record of its run's set-up: not checked" in proc.stdout


# ---- every value a restart reads is checked before it is used, and a refused restart leaves the output as it was
# (issue 34): the checkpoint's type, range and consistency checks, its checksums

TINY = ["-fs_case", "taylor_green", "-fs_dx", "0.05", "-fs_output_interval", "0", "-fs_checkpoint_interval", "2"]


@pytest.fixture(scope="module")
def tiny_run(tmp_path_factory):
    """TG at dx 0.05 (400 particles), 4 steps, checkpoints at steps 2 and 4, on 1 or 2 ranks (run on demand, once)."""
    cache = {}

    def get(nranks):
        if nranks not in cache:
            out = tmp_path_factory.mktemp(f"tiny{nranks}")
            run_flexslosh(TINY + ["-ts_max_steps", "4", "-fs_output_dir", out], nranks=nranks, cwd=out)
            cache[nranks] = out
        return cache[nranks]

    return get


def set_attr(obj, name, value):
    def change(h5):
        h5[obj].attrs[name] = value
    return change


def set_value(dset, index, value):
    def change(h5):
        a = h5[dset][...]
        a[index] = value if value is not None else a[index + 1]  # None: the next one's value (a duplicate)
        h5[dset][...] = a
    return change


def next_float(dset, index):
    def change(h5):
        a = h5[dset][...]
        a[index] = np.nextafter(a[index], np.inf)  # the last bit of the mantissa flipped
        h5[dset][...] = a
    return change


def drop_attr(obj, name):
    def change(h5):
        del h5[obj].attrs[name]
    return change


# name -> (the change, whether the checkpoint is signed again, ranks that write and read it, what the error says).
# Before these checks (observed): a NaN time ran on (5,000 steps and 125 NaN checkpoints in 30 s), a time of 5e306
# or Inf ended at once with exit 0, a negative mass was reported as a blow-up with the advice to reduce -fs_cfl,
# duplicate, NaN or huge ids were accepted, a negative /layout/nlocal and a string time were HDF5 errors that named
# no file, a negative step a TS error that named none, and a flipped bit went unnoticed.
BAD_CHECKPOINTS = {
    "time_nan": (set_attr("header", "time", np.nan), True, 1,
                 r"attribute /header\.time is nan: expected a finite number >= 0"),
    "time_inf": (set_attr("header", "time", np.inf), True, 1, r"attribute /header\.time is inf: expected a finite"),
    "time_huge": (set_attr("header", "time", 5e306), True, 1,
                  r"/header\.time 5e\+306 and /header\.dt [-0-9.e]+: the time step is below the time's resolution"),
    "time_string": (set_attr("header", "time", "0.1"), True, 1,
                    r"attribute /header\.time is a string, expected a number"),
    "step_negative": (set_attr("header", "step", np.int32(-3)), True, 1,
                      r"attribute /header\.step is -3: expected an integer in \[0, 2147483647\]"),
    "mass_negative": (set_value("particles/mass", 3, -1.0), True, 1, r"/particles/mass\[3\] is -1: expected a positive"),
    "mass_zero": (set_value("particles/mass", 7, 0.0), True, 1, r"/particles/mass\[7\] is 0: expected a positive"),
    "id_duplicate": (set_value("particles/id", 3, None), True, 1,
                     r"/particles/id holds the id \d+ more than once: expected each of 0 to 399 once"),
    "id_huge": (set_value("particles/id", 3, 1e20), True, 1, r"/particles/id\[3\] is 1e\+20: expected an integer in \[0, 399\]"),
    "id_nan": (set_value("particles/id", 5, np.nan), True, 1, r"/particles/id\[5\] is nan: expected an integer"),
    "id_duplicate_across_ranks": (set_value("particles/id", 350, 2.0), True, 2, r"/particles/id holds the id 2 more than once"),
    "nlocal_negative": (set_value("layout/nlocal", slice(None), [-5, 405]), True, 2,
                        r"/layout/nlocal\[0\] is -5: expected an integer in \[0, 400\]"),
    "density_far": (set_value("particles/density", 3, 100.0), True, 1,
                    r"The particles of checkpoint \"[^\"]+\" \(-fs_restart\) have a density variation \|rho/rho0 - 1\| "
                    r"of 99\.?, above -fs_max_density_variation 0\.3: particle \d+ at"),
    "velocity_bit": (next_float("particles/velocity", (300, 1)), False, 2,
                     r"/particles/velocity does not match its checksum \(sum64:[0-9a-f]{16} stored in "
                     r"/particles/velocity\.checksum, sum64:[0-9a-f]{16} computed"),
    "header_bit": (set_attr("header", "step", np.int32(3)), False, 1,
                   r"the header \(the attributes of /header\) does not match its checksum"),
    "checksum_missing": (drop_attr("particles/mass", "checksum"), False, 1,
                         r"/particles/mass has no checksum \(attribute /particles/mass\.checksum\), which format version 3"),
}


@pytest.mark.parametrize("name", list(BAD_CHECKPOINTS))
def test_restart_refuses_a_bad_checkpoint(tiny_run, tmp_path, name):
    """Restarted in the run's own directory from a changed checkpoint: an error that names the file and what is
    wrong, not a blow-up, and timeseries.csv, energy.csv and the rest of the directory as they were."""
    change, sign, nranks, pattern = BAD_CHECKPOINTS[name]
    run_dir = tmp_path / "run"
    run_dir.mkdir()
    for f in tiny_run(nranks).iterdir():
        (run_dir / f.name).write_bytes(f.read_bytes())
    ck = run_dir / "checkpoint_000002.h5"
    edit(ck, change, sign=sign)
    before = {f.name: f.read_bytes() for f in run_dir.iterdir()}
    proc = run_flexslosh(TINY + ["-ts_max_steps", "6", "-fs_restart", ck, "-fs_output_dir", run_dir], nranks=nranks,
                         cwd=tmp_path, check=False, timeout=60)
    assert_no_crash(proc)
    msg = petsc_error_message(proc.stdout)
    assert proc.returncode != 0 and str(ck) in msg and re.search(pattern, msg), msg
    assert "blew up" not in msg and "-fs_cfl" not in msg, msg
    after = {f.name: f.read_bytes() for f in run_dir.iterdir()}
    assert sorted(after) == sorted(before)
    for f in before:
        assert after[f] == before[f], f"{f} changed by a restart that was refused"


def test_checkpoint_checksums(tiny_run):
    """The checksums of a checkpoint written on 2 ranks are those of their description (checkpoint_tools.py): a sum
    over the values and their places, the same whichever ranks wrote or read them (the 2-rank checkpoints restart on
    1 and 3 ranks above, each rank verifying its share)."""
    with h5py.File(tiny_run(2) / "checkpoint_000002.h5", "r") as h5:
        assert h5["header"].attrs["version"] == 3
        assert h5["header"].attrs["checksum"].decode() == header_checksum(h5)
        for name in ("particles/position", "particles/id", "layout/nlocal", "layout/domain", "header/global"):
            assert h5[name].attrs["checksum"].decode() == checksum(h5[name][...]), name


def test_restart_from_a_checkpoint_without_checksums(tiny_run, tmp_path):
    """A checkpoint of format version 2 (before the checksums) still restarts, with a warning, exactly."""
    src = tiny_run(1)
    ck = tmp_path / "checkpoint_000002.h5"
    ck.write_bytes((src / "checkpoint_000002.h5").read_bytes())

    def old(h5):
        strip_checksums(h5)
        h5["header"].attrs["version"] = np.int32(2)

    edit(ck, old, sign=False)
    proc = run_flexslosh(TINY + ["-ts_max_steps", "4", "-fs_restart", ck, "-fs_output_dir", tmp_path / "B"], cwd=tmp_path)
    assert f"Warning: checkpoint {ck} (format version 2) has no checksums" in proc.stdout
    with h5py.File(src / "checkpoint_000004.h5", "r") as a, h5py.File(tmp_path / "B" / "checkpoint_000004.h5", "r") as b:
        for f in ("position", "velocity", "density"):
            assert np.array_equal(a["particles/" + f][...], b["particles/" + f][...]), f
