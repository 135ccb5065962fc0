#!/usr/bin/env python3
"""Mutation check: break a line of the physics (or of the output's safeguards) on purpose, rebuild, run the tests that should notice, restore.

Each mutation in MUTATIONS replaces one exact piece of a source line (it must occur exactly once) with a
plausible mistake, rebuilds the build directory, runs its candidate tests (ctest names, pytest node ids:
all part of `make test`) and records which of them fail. A mutation that no test catches is reported as
SURVIVED and makes the script exit with 1. The candidate tests are first run on the unmutated
sources: they must pass (exit 2 otherwise). The source file is restored afterwards, whatever happens, and
the build is brought back to the unmutated sources at the end.

    scripts/mutation-check.py [--build build] [--only name,name] [--list]

It takes a few minutes a mutation on 2 cores (docs/testing.md has the last results). Not part of make test:
run it after changing the tests of the physics, or the physics itself.
"""
from __future__ import annotations

import argparse
import os
import re
import subprocess
import sys
import time
from dataclasses import dataclass, field
from pathlib import Path

REPO = Path(__file__).resolve().parents[1]


@dataclass
class Mutation:
    name: str
    what: str
    path: str
    old: str
    new: str
    ctest: list[str] = field(default_factory=list)  # ctest test names (exact)
    pytest: list[str] = field(default_factory=list)  # pytest node ids or files under tests/python


MUTATIONS = [
    Mutation("pressure_sign", "the pressure term's pair sum p_i + p_j becomes p_i - p_j",
             "src/terms/impls/pressure.c", "f = (pi + p[j]) * nb->Vj[k]", "f = (pi - p[j]) * nb->Vj[k]",
             ctest=["terms_match_inline", "test_terms"],
             pytest=["test_taylor_green.py::test_taylor_green_decay_rate_converges",
                     "test_walls.py::test_hydrostatic_tank_stays_quiet"]),
    Mutation("kernel_gradient", "the Wendland kernel's gradient factor -5 a_d/h^2 becomes -4 a_d/h^2",
             "src/particles/kernel.c", "k->fnorm    = -5.0 *", "k->fnorm    = -4.0 *",
             ctest=["test_terms", "test_neighbours"],
             pytest=["test_taylor_green.py::test_taylor_green_decay_rate_converges",
                     "test_standing_wave.py::test_standing_wave_period_and_viscous_decay",
                     "test_walls.py::test_hydrostatic_tank_stays_quiet"]),
    Mutation("delta_coefficient", "the delta term's density difference loses its factor 2",
             "src/terms/impls/delta.c", "Dij = 2.0 * ((rj[2 * dim] - rhoi)", "Dij = 1.0 * ((rj[2 * dim] - rhoi)",
             ctest=["terms_match_inline"],
             pytest=["test_standing_wave.py::test_standing_wave_period_and_viscous_decay",
                     "test_walls.py::test_hydrostatic_tank_stays_quiet"]),
    Mutation("wall_pressure_hydrostatic", "the wall pressure's hydrostatic carry rho g.(x_k - x_i) changes sign",
             "src/boundary/impls/polygon/polygon.c", "num[k] += (P->pressure[i] + rho * (g[0]",
             "num[k] += (P->pressure[i] - rho * (g[0]",
             ctest=["test_walls"],
             pytest=["test_walls.py::test_hydrostatic_tank_stays_quiet",
                     "test_coupling.py::test_liquid_at_rest_does_not_drive_the_beam"]),
    Mutation("gamma_angle", "gamma's angle term of a segment adds the near end's angle instead of subtracting it",
             "src/boundary/impls/polygon/shepard.c",
             "ang     = PetscAtan2Real(b, d) - PetscAtan2Real(a, d);",
             "ang     = PetscAtan2Real(b, d) + PetscAtan2Real(a, d);",
             ctest=["test_boundary", "test_walls"],
             pytest=["test_walls.py::test_hydrostatic_tank_stays_quiet"]),
    Mutation("coupling_reaction", "the vertical load the structure receives takes the reaction with the wrong sign",
             "src/coupling/coupling.c", "F[1] = -c->reaction[1];", "F[1] = c->reaction[1];",
             pytest=["test_coupling.py::test_liquid_adds_its_mass_to_the_vertical_oscillation",
                     "test_coupling.py::test_reaction_loads_balance_the_liquids_momentum",
                     "test_energy.py::test_coupled_free_decay_dt"]),
    Mutation("structure_damping", "the mass-spring-damper's damping force is halved",
             "src/structure/impls/msd.c", "- p->c * y[1] - p->K * y[0]", "- 0.5 * p->c * y[1] - p->K * y[0]",
             pytest=["test_structure.py::test_log_decrement_gives_back_xi_and_period",
                     "test_coupling.py::test_empty_tank_is_the_solid_mass"]),
    Mutation("frame_inertia", "the tank frame's vertical inertial acceleration has the wrong sign",
             "src/coupling/coupling.c", "gy = c->gravity[1] - mo->acc[1]", "gy = c->gravity[1] + mo->acc[1]",
             ctest=["test_frame"],
             pytest=["test_coupling.py::test_liquid_adds_its_mass_to_the_vertical_oscillation",
                     "test_energy.py::test_coupled_free_decay_dt",
                     "test_motion.py::test_shaken_tank_follows_linear_theory"]),
    Mutation("energy_term_work", "the energy budget books half the pressure term's power",
             "src/terms/impls/pressure.c", "return -V[i] * (P->invgamma", "return -0.5 * V[i] * (P->invgamma",
             ctest=["terms_match_inline"],
             pytest=["test_energy.py::test_taylor_green", "test_energy.py::test_dam_break_dt"]),
    Mutation("restart_time", "a restart resumes one step later than the checkpoint's time",
             "src/solver/solver.c", "TSSetTime(s->ts, s->state.restart_hdr.time)",
             "TSSetTime(s->ts, s->state.restart_hdr.time + s->state.restart_hdr.dt)",
             pytest=["test_restart.py::test_restart_same_ranks_is_exact",
                     "test_coupling.py::test_coupled_restart_is_exact"]),
    Mutation("viscosity_factor", "the viscous term's K = 2(dim + 2) becomes 2(dim + 1)",
             "src/terms/impls/viscosity.c", "ctx->K = 2.0 * (dim + 2);", "ctx->K = 2.0 * (dim + 1);",
             pytest=["test_taylor_green.py", "test_standing_wave.py::test_standing_wave_period_and_viscous_decay"]),
    Mutation("wall_continuity_sign", "the wall part of the continuity equation changes sign",
             "src/terms/impls/wall.c", "rate->drho += ri[2 * D] * sum;", "rate->drho -= ri[2 * D] * sum;",
             ctest=["terms_match_inline", "test_terms"],
             pytest=["test_walls.py::test_hydrostatic_tank_stays_quiet",
                     "test_standing_wave.py::test_standing_wave_period_and_viscous_decay"]),
    Mutation("coriolis", "the rotating tank frame's Coriolis acceleration has the wrong sign",
             "src/coupling/coupling.c", "ax = a[0] + 2 * ff.omega * uy", "ax = a[0] - 2 * ff.omega * uy",
             ctest=["test_frame"],
             pytest=["test_motion.py", "test_energy.py::test_coupled_free_decay_dt"]),
    Mutation("modal_damping", "the modal structure's damping 2 xi omega loses its factor 2",
             "src/structure/impls/modal.c", "- 2 * p->xi[i] * w * y[n + i]", "- p->xi[i] * w * y[n + i]",
             pytest=["test_structure.py::test_log_decrement_gives_back_xi_and_period"]),
    Mutation("solid_angle", "the 3-D solid angle's denominator takes the length of C for that of B in one product",
             "src/boundary/impls/trimesh/mesh.c", "Dot(A, C) * lb", "Dot(A, C) * lc",
             ctest=["test_trimesh", "test_mesh", "test_boundary"],
             pytest=["test_walls_3d.py"]),
    Mutation("les_length", "the LES length L = 2h of the turbulent viscosity becomes h",
             "src/terms/impls/viscosity.c", "const PetscReal L = 2.0 * P->h, nucoef",
             "const PetscReal L = 1.0 * P->h, nucoef",
             ctest=["terms_match_inline"],
             pytest=["test_taylor_green.py", "test_standing_wave.py"]),
    Mutation("delta_les_coefficient", "delta-LES's delta_i = (C L)^2 S/(c0 h) (S the strain rate's norm) loses a factor L",
             "src/terms/impls/delta.c", "coef = ctx->C * ctx->C * L * L / (P->c0 * P->h)",
             "coef = ctx->C * ctx->C * L / (P->c0 * P->h)",
             ctest=["terms_match_inline"],
             pytest=["test_time_step.py", "test_standing_wave.py"]),
    # the output's safeguards (issue 34): one run per directory, no stale results, no writes through links,
    # every rank able to write, options files read whole
    Mutation("output_lock", "the output directory's lock is never refused (two runs write into one directory)",
             "src/io/fsutil.c", "flock(f, LOCK_EX | LOCK_NB) != 0", "flock(f, LOCK_EX | LOCK_NB) != 0 && 0",
             pytest=["test_crash.py::test_one_run_per_directory_and_no_stale_results"]),
    Mutation("output_clear", "a new run keeps what an earlier run left in its directory",
             "src/solver/monitor.c", "if (!s->opt.restart[0]) PetscCall(FSOutputDirClear(",
             "if (0) PetscCall(FSOutputDirClear(",
             pytest=["test_crash.py::test_one_run_per_directory_and_no_stale_results"]),
    Mutation("monitor_rows_unreduced", "the monitors' rows are made from this rank's sums, not their reduction",
             "src/monitor/interface/monitor.c", "PetscCall(FSSolverReduceSumMax(s, b.nsum, b.sum, b.nmax, b.max));",
             "if (0) PetscCall(FSSolverReduceSumMax(s, b.nsum, b.sum, b.nmax, b.max));",
             ctest=["test_monitor_mpi2"]),
    Mutation("step_rows_unreduced", "a step's rows are made from this rank's sums, not those the step's reduction gave",
             "src/solver/stepping.c", "PetscCall(PetscArraycpy(rows->sum, sum + 2, rows->nsum));",
             "if (0) PetscCall(PetscArraycpy(rows->sum, sum + 2, rows->nsum));",
             ctest=["test_monitor_mpi2"], pytest=["test_mpi.py::test_coupled_step_collectives_with_a_row_every_step"]),
    Mutation("stage_powers_unreduced", "a coupled stage's energy rates are made from this rank's powers, not their sums",
             "src/coupling/coupling.c", "for (PetscInt k = 0; k < nextra; k++) extra[k] = all[nr + k];",
             "for (PetscInt k = 0; k < nextra && 0; k++) extra[k] = all[nr + k];",
             pytest=["test_mpi.py::test_coupled_step_collectives_with_a_row_every_step"]),
    Mutation("output_entry_kept", "an output file is created without first removing what is under its name",
             "src/io/fsutil.c", "if (lstat(path, &sb) == 0) {", "if (lstat(path, &sb) == 0 && 0) {",
             pytest=["test_crash.py::test_links_and_files_planted_in_the_output_directory_are_not_written_through"]),
    Mutation("output_probe", "only rank 0 checks that the output directory is writable",
             "src/io/fsutil.c", "err     = FSProbeDirectory(path, rank);", "err     = rank ? 0 : FSProbeDirectory(path, rank);",
             pytest=["test_rank_errors.py::test_an_output_dir_one_rank_cannot_write_ends_every_rank"]),
    Mutation("options_file_pipe", "an options file that is a pipe is left to PETSc",
             "app/flexslosh.c", "!S_ISREG(sb.st_mode) && !S_ISDIR(sb.st_mode)", "0 && !S_ISDIR(sb.st_mode)",
             pytest=["test_bad_input.py::test_options_file_from_a_pipe_is_refused"]),
    # the checkpoints' checks (issue 34): a restart reads nothing it has not checked
    Mutation("checkpoint_checksum_ignored", "a checkpoint's stored checksum is taken as matching whatever was read",
             "src/io/checkpoint.c", "PetscCall(PetscStrcmp(stored, computed, &same));", "same = PETSC_TRUE;",
             pytest=["test_restart.py::test_restart_refuses_a_bad_checkpoint", "test_fuzz_files.py"]),
    Mutation("checkpoint_checksum_index", "the checksum's term forgets the value's place (two values swapped, or the "
             "ranks' shares in another order, would not change it)",
             "src/io/checkpoint.c", "FSMix64(bits ^ FSMix64(i))", "FSMix64(bits)",
             pytest=["test_restart.py::test_checkpoint_checksums"]),
    Mutation("checkpoint_time_nan", "a checkpoint's time is checked only for its sign (NaN and Inf pass)",
             "src/io/checkpoint.c", "PetscCheck(!PetscIsInfOrNanReal(h->time) && h->time >= 0,",
             "PetscCheck(!(h->time < 0),",
             pytest=["test_restart.py::test_restart_refuses_a_bad_checkpoint"]),
    Mutation("checkpoint_nlocal_sign", "a writer's count in /layout/nlocal may be negative (the sum still checked)",
             "src/io/checkpoint.c", "PetscCheck(counts[r] >= 0 && counts[r] <= N", "PetscCheck(counts[r] <= N",
             pytest=["test_restart.py::test_restart_refuses_a_bad_checkpoint"]),
    Mutation("restart_ids_once", "the ids' check looks each id up without marking it (duplicates pass)",
             "src/solver/output.c", "if (PetscBTLookupSet(seen, rbuf[k] - first))", "if (PetscBTLookup(seen, rbuf[k] - first))",
             pytest=["test_restart.py::test_restart_refuses_a_bad_checkpoint", "test_fuzz_files.py"]),
]


def run(cmd: list[str], cwd: Path, env: dict, timeout: float) -> subprocess.CompletedProcess:
    try:
        return subprocess.run(cmd, cwd=cwd, env=env, capture_output=True, text=True, timeout=timeout)
    except subprocess.TimeoutExpired as e:
        return subprocess.CompletedProcess(cmd, 124, e.stdout or "", f"timed out after {timeout} s")


def build(build_dir: Path, env: dict) -> None:
    r = run(["cmake", "--build", str(build_dir), "-j", os.environ.get("JOBS", "2")], REPO, env, 1800)
    if r.returncode:
        sys.exit(f"build failed:\n{r.stdout[-3000:]}\n{r.stderr[-3000:]}")


def failing_tests(m: Mutation, build_dir: Path, env: dict, timeout: float) -> tuple[list[str], float]:
    """The candidate tests of m that fail on the mutated build, and the seconds they took."""
    t0, failed = time.time(), []
    if m.ctest:
        regex = "^(" + "|".join(re.escape(n) for n in m.ctest) + ")$"
        r = run(["ctest", "-R", regex], build_dir, env, timeout)
        failed += [f"ctest {n}" for n in re.findall(r"^\s*\d+ - (\S+) \(", r.stdout, re.M)]
        if r.returncode == 124:
            failed.append("ctest (timed out)")
    if m.pytest:
        ids = [f"tests/python/{p}" for p in m.pytest]
        r = run([sys.executable, "-m", "pytest", "-q", "-rf", "-p", "no:cacheprovider", *ids], REPO, env, timeout)
        failed += [f"pytest {t}" for t in re.findall(r"^FAILED tests/python/(\S+)", r.stdout, re.M)]
        if r.returncode == 124:
            failed.append("pytest (timed out)")
        elif r.returncode not in (0, 1):
            failed.append(f"pytest (exit {r.returncode})")
    return failed, time.time() - t0


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--build", default="build", help="the CMake build directory (configured already)")
    ap.add_argument("--only", default="", help="comma-separated mutation names")
    ap.add_argument("--list", action="store_true", help="list the mutations and stop")
    ap.add_argument("--timeout", type=float, default=900, help="seconds for each mutation's ctest and pytest runs")
    a = ap.parse_args()
    todo = [m for m in MUTATIONS if not a.only or m.name in a.only.split(",")]
    if a.list or not todo:
        for m in MUTATIONS:
            print(f"{m.name:28s} {m.path}: {m.what}")
        return 0 if a.list else 2
    build_dir = (REPO / a.build).resolve()
    env = dict(os.environ, FLEXSLOSH_BUILD=str(build_dir), PYTHONPATH=str(REPO / "python"),
               OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1", OMPI_MCA_rmaps_base_oversubscribe="1")
    # the candidate tests must pass on the unmutated sources, or a failure would not be the mutation's
    build(build_dir, env)
    union = Mutation("baseline", "", "", "", "", sorted({t for m in todo for t in m.ctest}),
                     sorted({t for m in todo for t in m.pytest}))
    failed, secs = failing_tests(union, build_dir, env, a.timeout)
    print(f"baseline (unmutated): {len(union.ctest)} ctest, {len(union.pytest)} pytest selections; {secs:.0f} s")
    if failed:
        print("  failing already: " + ", ".join(failed))
        return 2
    survived = []
    try:
        for m in todo:
            src = REPO / m.path
            text = src.read_text()
            if text.count(m.old) != 1:
                sys.exit(f"{m.name}: '{m.old}' occurs {text.count(m.old)} times in {m.path}; expected once")
            try:
                src.write_text(text.replace(m.old, m.new))
                build(build_dir, env)
                failed, secs = failing_tests(m, build_dir, env, a.timeout)
            finally:
                src.write_text(text)
            print(f"{m.name}: {m.what} ({m.path}); {secs:.0f} s", flush=True)
            print("  " + ("caught by: " + ", ".join(failed) if failed else "SURVIVED: no test failed"), flush=True)
            if not failed:
                survived.append(m.name)
    finally:
        build(build_dir, env)
    print(f"{len(todo) - len(survived)} of {len(todo)} mutations caught" +
          (f"; survived: {', '.join(survived)}" if survived else ""))
    return 1 if survived else 0


if __name__ == "__main__":
    sys.exit(main())
