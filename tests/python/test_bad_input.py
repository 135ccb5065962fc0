"""Bad input gives a clean error that names the option and the value; blow-ups are detected."""
import os
import re
import resource
import subprocess
import time

import h5py
import numpy as np
import pytest

from conftest import MPI_ENV, REPO_ROOT, TG, assert_no_crash, flexslosh_bin, petsc_error_message

# (arguments, regular expressions the PETSc error message must match)
BAD = {
    "dx_zero": (["-fs_dx", "0"], [r"-fs_dx 0\b", "positive"]),
    "dx_negative": (["-fs_dx", "-1"], [r"-fs_dx -1\b", "positive"]),
    "h_over_dx_zero": (["-fs_h_over_dx", "0"], [r"-fs_h_over_dx 0\b", "range"]),
    "c0_zero": (["-fs_c0", "0"], [r"-fs_c0 0\b", "positive"]),
    "rho0_negative": (["-fs_rho0", "-5"], [r"-fs_rho0 -5\b", "positive"]),
    "dim_4": (["-fs_dim", "4"], [r"-fs_dim 4\b", "2 or 3"]),
    "unknown_term": (["-fs_terms", "continuity,nosuchterm"], ["-fs_terms", r'"nosuchterm"', "continuity"]),
    "unknown_case": (["-fs_case", "nosuchcase"], ["-fs_case", r'"nosuchcase"']),
    "missing_options_file": (["-options_file", "/nonexistent.opts"], [r"options file /nonexistent\.opts"]),
    "gravity_3_values_in_2d": (["-fs_gravity", "0,-9.81,0"], ["-fs_gravity", r"has 3 values", r"expected 2"]),
    "gravity_1_value_in_2d": (["-fs_gravity", "-9.81"], ["-fs_gravity", r"has 1 values", r"expected 2"]),
    "gravity_2_values_in_3d": (["-fs_dim", "3", "-fs_gravity", "0,-9.81"], ["-fs_gravity", r"has 2 values", r"expected 3"]),
    "cfl_too_large": (["-fs_cfl", "3"], [r"-fs_cfl 3\b", "range"]),
    "delta_max_negative": (["-fs_delta_max", "-1"], [r"-fs_delta_max -1\b", "non-negative"]),
    "delta_max_below_min": (["-fs_delta_min", "0.2", "-fs_delta_max", "0.1"], [r"-fs_delta_max 0.1\b", r"below -fs_delta_min 0.2\b"]),
    "gravity_nan": (["-fs_gravity", "0,nan"], ["-fs_gravity", "component 1", "finite"]),
    # snapshots 1e-20 s apart in a run to 1 s: the next snapshot's time was counted up to, forever (issue 34)
    "output_interval_tiny": (["-fs_output_interval", "1e-20"],
                             [r"-fs_output_interval 1e-20\b", r"at least 1e-12 of the final time -ts_max_time 1\b"]),
    # PETSc's own integer options are checked as flexslosh's: 2^32 + 1 steps ran one step (PETSc kept the low 32 bits)
    "max_steps_beyond_int": (["-ts_max_steps", "4294967297"], [r"-ts_max_steps 4294967297 is out of range: expected at least 0"]),
    "max_steps_not_integer": (["-ts_max_steps", "2.5"], [r"-ts_max_steps 2\.5 is not an integer"]),
}

# the same for the wall cases' options (a coarse tank)
BAD_WALLS = {
    "restitution": (["-fs_walls_bounce_restitution", "5"], [r"-fs_walls_bounce_restitution 5\b", r"\[0, 1\]"]),
    "bounce_distance": (["-fs_walls_bounce_distance", "-1"], [r"-fs_walls_bounce_distance -1\b", r"\[0, 0.5\)"]),
    "load_point": (["-fs_walls_load_point", "1,2,3,4"], ["-fs_walls_load_point", "2 or 3 values", "got 4"]),
    "compartments": (["-fs_tank_shape", "baffled", "-fs_tank_compartments", "0"], [r"-fs_tank_compartments 0\b", "at least 1"]),
}


@pytest.mark.parametrize("name", list(BAD_WALLS))
def test_bad_wall_option(run, tmp_path, name):
    args, patterns = BAD_WALLS[name]
    proc = run(["-fs_case", "tank", "-fs_dx", "0.006", "-ts_max_steps", "2", "-fs_output_dir", tmp_path / "out"] + args,
               check=False)
    assert_no_crash(proc)
    msg = petsc_error_message(proc.stdout)
    for pat in patterns:
        assert re.search(pat, msg), f"{pat!r} not in the error message:\n{msg}"


def test_tiny_c0_names_c0(run, tmp_path):
    """A -fs_c0 too small for the liquid's hydrostatic pressure is named as such, with the c0 needed, before the
    structure is set up (it was blamed on -fs_beam_payload_mass: the liquid's masses follow its density, here 3 to
    270,000 times rho0), and in the uncoupled tank not reported as a blow-up with the advice to reduce -fs_cfl."""
    for extra in (["-options_file", REPO_ROOT / "cases" / "coupled_rectangular.opts"], ["-fs_case", "tank"]):
        proc = run(extra + ["-fs_dx", "0.01", "-fs_c0", "0.3", "-ts_max_steps", "1", "-fs_output_dir", tmp_path / "out"],
                   check=False, timeout=60)
        assert_no_crash(proc)
        msg = petsc_error_message(proc.stdout)
        assert re.search(r"The particles of case tank \(its initial state\) have a density variation \|rho/rho0 - 1\| "
                         r"of [0-9.]+, above -fs_max_density_variation 0\.3", msg), msg
        assert re.search(r"-fs_c0 0\.3 is too small .* raise -fs_c0 to at least 0\.\d+", msg), msg
        assert "payload" not in msg and "blew up" not in msg and "-fs_cfl" not in msg, msg


@pytest.mark.parametrize("name", list(BAD))
def test_bad_option(run, tmp_path, name):
    args, patterns = BAD[name]
    proc = run(TG + ["-fs_dx", "0.05", "-ts_max_steps", "2", "-fs_output_dir", tmp_path / "out"] + args, check=False,
               timeout=60)  # each ends within a second: a bad option never hangs
    assert_no_crash(proc)
    msg = petsc_error_message(proc.stdout)
    assert msg, f"no PETSc error message in:\n{proc.stdout[-3000:]}"
    for pat in patterns:
        assert re.search(pat, msg), f"{pat!r} not in the error message:\n{msg}"
    assert not (tmp_path / "out" / "summary.json").exists()


@pytest.mark.parametrize("nested", [False, True])
def test_options_file_from_a_pipe_is_refused(tmp_path, nested):
    """-options_file <(cat case.opts): PETSc reads an options file twice and found the pipe empty the second time, so
    the run went on as the default case (taylor_green) with exit 0; directly or through another file, it is refused by
    name (docs/running.md, "Running")."""
    r, w = os.pipe()
    os.write(w, (REPO_ROOT / "cases" / "coupled_rectangular.opts").read_bytes())
    os.close(w)
    pipe = f"/dev/fd/{r}"
    given = pipe
    if nested:
        (tmp_path / "outer.opts").write_text(f"-options_file {pipe}\n")
        given = tmp_path / "outer.opts"
    try:
        proc = subprocess.run([str(flexslosh_bin()), "-options_file", str(given), "-ts_max_steps", "2", "-fs_progress", "0",
                               "-fs_output_dir", str(tmp_path / "out")], cwd=tmp_path, pass_fds=(r,), stdout=subprocess.PIPE,
                              stderr=subprocess.STDOUT, text=True, timeout=60)
    finally:
        os.close(r)
    assert_no_crash(proc)
    assert proc.returncode != 0, proc.stdout[-2000:]
    msg = petsc_error_message(proc.stdout)
    assert f"-options_file {pipe} is a pipe, not a regular file" in msg, proc.stdout[-2000:]
    assert (f"(in -options_file {given})" in msg) == nested, msg
    assert not (tmp_path / "out").exists()


def test_unwritable_output_dir(run, tmp_path):
    afile = tmp_path / "afile"
    afile.write_text("not a directory\n")
    outdir = afile / "sub"
    proc = run(TG + ["-fs_dx", "0.05", "-ts_max_steps", "2", "-fs_output_dir", outdir], check=False)
    assert_no_crash(proc)
    msg = petsc_error_message(proc.stdout)
    assert str(outdir) in msg and "-fs_output_dir" in msg, msg
    assert "Not a directory" in msg


@pytest.mark.parametrize("nranks", [1, 2])
def test_blow_up_is_detected(run, tmp_path, nranks):
    # CFL 2 on a coarse Taylor-Green vortex, with the diffusive limits lifted: the density blows up within a few steps
    proc = run(TG + ["-fs_dx", "0.05", "-fs_cfl", "2", "-fs_cfl_viscous", "5", "-fs_delta_cfl", "5", "-ts_max_steps", "200", "-fs_output_dir", tmp_path / "out"],
               nranks=nranks, check=False)
    assert_no_crash(proc)
    msg = petsc_error_message(proc.stdout)
    m = re.search(r"density blow-up at step (\d+), time ([-+0-9.eE]+): particle (\d+) at \(", msg)
    assert m, f"no diagnostic line naming step, time and particle:\n{msg}"
    step, time, particle = int(m.group(1)), float(m.group(2)), int(m.group(3))
    assert 1 <= step < 20 and time > 0
    assert 0 <= particle < 400
    err = re.search(r"The run blew up: density variation ([0-9.eE+-]+) above -fs_max_density_variation 0\.3 at step (\d+), time", msg)
    assert err, msg
    assert float(err.group(1)) > 0.3 and int(err.group(2)) == step
    # the run stopped there: the time series ends before the blow-up step
    ts = (tmp_path / "out" / "timeseries.csv").read_text().strip().splitlines()
    assert int(ts[-1].split(",")[0]) == step - 1


# ---- the global DOFs of the state (the structure's DOFs, the dissipated energies, the energy block) and the
# structure's energy are checked too (issue 34): the dry msd beam (shortest period 0.166 s) at -ts_dt 0.5, three
# times its period, blows up; it ran to the end before, 919 of its 1001 rows NaN or Inf

BEAM = ["-options_file", REPO_ROOT / "cases" / "beam_free_decay_msd.opts", "-ts_dt", "0.5", "-ts_max_time", "500",
        "-fs_output_interval", "0", "-fs_checkpoint_interval", "10"]
NONFINITE = {
    # the damping power c v^2 overflows first: the energy block's integral of it
    "damping_work": ([], r"the energy block's work_struct_damping is -Inf at step 42, time 21\b"),
    # undamped, a row every 1000 steps: the structure's DOF itself
    "structure_dof": (["-fs_beam_damping", "0", "-fs_series_interval", "1000"],
                      r"the structure msd's DOF 0 \(of 2\) is NaN at step 83, time 41\.5\b"),
    # undamped, a row every step: the structure's energy, checked before energy.csv's row is written
    "structure_energy": (["-fs_beam_damping", "0"],
                         r"the structure's energy is not finite: structure msd's kinetic energy is \+Inf at step 42, "
                         r"time 21\b"),
}


@pytest.mark.parametrize("name", list(NONFINITE))
def test_structure_blow_up_is_detected(run, tmp_path, name):
    args, pattern = NONFINITE[name]
    out = tmp_path / "out"
    proc = run(BEAM + args + ["-fs_output_dir", out], check=False, timeout=60)
    assert_no_crash(proc)
    msg = petsc_error_message(proc.stdout)
    assert re.search(r"The run blew up: " + pattern, msg), msg
    assert re.search(r"Likely cause: the time step 0\.5 \(-ts_dt\) is 3\.02 times the structure's shortest period "
                     r"0\.1656\d* s.*reduce -ts_dt", msg), msg
    step = int(re.search(r"at step (\d+)", pattern).group(1))
    interval = 1000 if "-fs_series_interval" in args else 1
    # nothing of that step written: every row finite up to the one before it, the checkpoints before it whole
    for csv in ("timeseries.csv", "energy.csv"):
        rows = np.loadtxt(out / csv, delimiter=",", skiprows=1, ndmin=2)
        assert np.isfinite(rows).all(), csv
        assert rows[-1, 0] == (step - 1) // interval * interval, csv
    last = sorted(out.glob("checkpoint_*.h5"))[-1]
    assert last.name == f"checkpoint_{(step - 1) // 10 * 10:06d}.h5"
    with h5py.File(last, "r") as h5:
        assert np.isfinite(h5["header/global"][...]).all()
    assert not list(out.glob("*.tmp")) and not (out / "summary.json").exists()


def test_blow_up_threshold_option(run, tmp_path):
    # the stable default run trips a tiny -fs_max_density_variation at once (TG starts at 0.5 %): the case's initial
    # state, said so with the c0 that would do (it was "The run blew up ... at step 0 ...; reduce -fs_cfl")
    proc = run(TG + ["-fs_dx", "0.05", "-ts_max_steps", "5", "-fs_max_density_variation", "1e-3", "-fs_output_dir", tmp_path / "out"],
               check=False)
    assert_no_crash(proc)
    msg = petsc_error_message(proc.stdout)
    assert re.search(r"The particles of case taylor_green \(its initial state\) have a density variation \|rho/rho0 - 1\| "
                     r"of 0\.0047\d*, above -fs_max_density_variation 0\.001\b", msg), msg
    assert re.search(r"raise -fs_c0 to at least 21\.8, or -fs_max_density_variation", msg), msg
    assert "blew up" not in msg and "-fs_cfl" not in msg, msg


# ---- a -fs_dx that makes more particles than an index counts or the memory holds: a clean error before any
# allocation (not a 32-bit overflow corrupting the heap, not minutes of allocating), under a 4 GB address-space limit
# (ulimit -v) that the memory check honours, so that the verdict does not depend on the machine's memory

TOO_FINE = {
    # 4100 x 1024 x 1024 points: past 2^31 (the lattice's buffer size overflowed: "malloc(): corrupted top size")
    "index": (["-fs_case", "tank", "-fs_dim", "3", "-fs_tank_length", "4.1", "-fs_tank_height", "2.048", "-fs_fill", "0.5",
               "-fs_tank_width", "1.024", "-fs_dx", "0.001", "-ts_max_steps", "1"],
              [r"-fs_dx 0\.001\b", r"4\.3e\+09 particles", r"more than an index can count", r"coarser -fs_dx"]),
    # 2333 x 100 x 167 points (the liquid's 0.00105 m^3 / dx^3: 3.89e7 particles), 72 GB at 2 kB a particle in 3-D
    # (it allocated for 43 s, then failed in DMSwarm)
    "memory": (["-options_file", "cases/coupled_rectangular_3d.opts", "-fs_dx", "0.0003"],
               [r"-fs_dx 0\.0003\b", r"3\.89e\+07 particles", r"72\.4 GB", r"2000 bytes a particle in 3-D",
                r"coarser -fs_dx or more ranks"]),
}


def _limit_memory():
    resource.setrlimit(resource.RLIMIT_AS, (4000000 * 1024, 4000000 * 1024))


@pytest.mark.parametrize("name", list(TOO_FINE))
def test_too_fine_dx_is_a_clean_error(tmp_path, name):
    args, patterns = TOO_FINE[name]
    start = time.monotonic()
    proc = subprocess.run([str(flexslosh_bin()), "-fs_progress", "0", "-fs_output_dir", str(tmp_path / "out")] + args,
                          cwd=REPO_ROOT, env=dict(os.environ, **MPI_ENV), stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                          text=True, timeout=120, preexec_fn=_limit_memory)
    elapsed = time.monotonic() - start
    assert_no_crash(proc)
    assert "corrupted" not in proc.stdout and "Out of memory" not in proc.stdout, proc.stdout[-3000:]
    msg = petsc_error_message(proc.stdout)
    for pat in patterns:
        assert re.search(pat, msg), f"{pat!r} not in the error message:\n{msg}"
    assert elapsed < 10, f"the error took {elapsed:.1f} s: the check must come before the allocations"
