"""The same run on 1, 2 and 3 ranks gives the same particles (up to round-off)."""
import numpy as np
import pytest

from conftest import TG, last_snapshot, read_series, read_summary, rel_max_diff, run_flexslosh

TG_ARGS = TG + ["-ts_max_steps", "50"]
SHEAR_ARGS = ["-fs_case", "shear", "-fs_dim", "3", "-fs_dx", "0.0625", "-ts_max_steps", "10", "-fs_output_interval", "0"]
TOL = 1e-10


def _runner(tmp_path_factory, name, args):
    cache = {}

    def get(nranks):
        if nranks not in cache:
            out = tmp_path_factory.mktemp(f"{name}{nranks}")
            run_flexslosh(args + ["-fs_output_dir", out], nranks=nranks, cwd=out)
            cache[nranks] = out
        return cache[nranks]

    return get


@pytest.fixture(scope="module")
def tg(tmp_path_factory):
    return _runner(tmp_path_factory, "tg", TG_ARGS)


@pytest.fixture(scope="module")
def shear(tmp_path_factory):
    return _runner(tmp_path_factory, "shear", SHEAR_ARGS)


def compare_runs(ref, other, nranks, nparticles, dim, steps):
    a, b = last_snapshot(ref), last_snapshot(other)
    s = read_summary(other)
    assert s["ranks"] == nranks and s["particles"] == nparticles and s["steps"] == steps
    # the particles really were spread over all the ranks
    assert sorted(np.unique(b["rank"]).astype(int)) == list(range(nranks))
    assert a.attrs["step"] == b.attrs["step"] == steps
    assert a.attrs["time"] == pytest.approx(b.attrs["time"], rel=1e-13)
    assert a["id"].shape == b["id"].shape == (nparticles,)
    assert np.array_equal(a["id"], b["id"])
    assert np.array_equal(a["id"], np.arange(nparticles))
    for field in ("position", "velocity", "density", "strain_rate", "turbulent_viscosity"):
        assert a[field].shape == b[field].shape
        assert rel_max_diff(a[field], b[field]) < TOL, f"{field}: {nranks} ranks differ from 1 rank by {rel_max_diff(a[field], b[field]):.3g}"
    assert a["position"].shape == (nparticles, dim)
    sa, sb = read_series(ref), read_series(other)
    assert np.array_equal(sa["step"], sb["step"])
    assert np.allclose(sa["time"], sb["time"], rtol=1e-13, atol=0)
    assert rel_max_diff(sa["kinetic_energy"], sb["kinetic_energy"]) < TOL
    assert rel_max_diff(sa["max_density_variation"], sb["max_density_variation"]) < 1e-8


@pytest.mark.parametrize("nranks", [2, 3])
def test_taylor_green_ranks_agree(tg, nranks):
    compare_runs(tg(1), tg(nranks), nranks, 2500, 2, 50)


def test_taylor_green_moved(tg):
    # guard against comparing frozen states: the vortex turned and decayed in 50 steps
    a = read_series(tg(1))
    assert a["kinetic_energy"][-1] < 0.99 * a["kinetic_energy"][0]
    snap0 = last_snapshot(tg(1))
    from conftest import read_snapshot, snapshot_files
    first = read_snapshot(snapshot_files(tg(1))[0])
    assert np.abs(snap0["position"] - first["position"]).max() > 0.05


def test_shear_3d_ranks_agree(shear):
    compare_runs(shear(1), shear(2), 2, 16 ** 3, 3, 10)
    b = last_snapshot(shear(2))
    # the flow stays a shear flow u = (U sin(2 pi y), 0, 0)
    assert np.abs(b["velocity"][:, 1:]).max() < 1e-3
    assert np.abs(b["velocity"][:, 0]).max() > 0.9


def test_three_ranks_do_not_hang(tmp_path):
    # regression: src/solver.c read -fs_case_view into an uninitialized PetscBool, so a rank could list
    # the cases (a collective viewer call) alone and deadlock the run at random
    for k in range(4):
        out = tmp_path / f"o{k}"
        run_flexslosh(["-fs_case", "taylor_green", "-fs_dx", "0.05", "-ts_max_steps", "2", "-fs_output_dir", out], nranks=3,
                      cwd=tmp_path, timeout=60)
        assert read_summary(out)["ranks"] == 3


def test_parallel_statistics(tg):
    """summary.json's "parallel" (src/solver/parallelstats.c) is consistent: the owned particles add up to the
    total, 2 ranks have ghosts from each other and send to each other, the halo's own counts of what it sent are
    within PETSc's counts of all messages, and 1 rank sends nothing to another and takes part in no collective."""
    one, two = read_summary(tg(1))["parallel"], read_summary(tg(2))["parallel"]
    assert one["collectives_per_step"] == [0] and one["send_ranks"] == [0] and one["halo_messages_per_step"] == [0]
    assert one["ghosts"][0] > 0  # the periodic images
    assert two["grid"] == [1, 2] and two["steps"] == 50
    assert sum(two["owned"]) == sum(two["owned_first"]) == 2500
    assert all(g > 0 for g in two["ghosts"]) and two["send_ranks"] == [1, 1]
    assert all(p > 0 for p in two["pairs_with_ghosts"])
    assert 1 <= two["imbalance_owned_end"] <= 1.1 and 1 <= two["imbalance_owned"] <= 1.1
    for r in range(2):
        own = two["halo_messages_per_step"][r] + two["halo_build_messages_per_step"][r] + two["migration_messages_per_step"][r]
        assert 0 < own <= two["messages_per_step"][r]
        assert 0 < two["halo_bytes_per_step"][r] <= 1.02 * two["bytes_per_step"][r]
        # at least the time step's, the checks' and the rebuild decision's reductions in each step
        assert two["collectives_per_step"][r] >= 3


def test_memory_counts_the_shared_libraries_once(tg):
    """summary.json's "memory": each rank's peak resident memory holds its copy of the libraries' pages, which the
    ranks of a node share; "peak_resident_shared_once" counts them once. On 1 rank it is the peak; on 2 ranks of one
    machine it is the peak less one rank's shared clean pages (with Debian's PETSc about 37 MiB a rank, measured:
    95.2 -> 57.1 MiB for 2 ranks of a small dam break, 46.6 on 1 rank)."""
    one, two = read_summary(tg(1))["memory"], read_summary(tg(2))["memory"]
    assert one["peak_resident_shared_once"] == one["peak_resident"]
    assert two["shared_clean"] > 2 * 10 * 2**20  # each rank maps the libraries (PETSc's alone are over 10 MiB)
    saved = two["peak_resident"] - two["peak_resident_shared_once"]
    assert 0.4 * two["shared_clean"] <= saved <= 0.5 * two["shared_clean"] + 1  # one rank's share, the larger kept
    assert two["peak_resident_shared_once"] < 1.5 * one["peak_resident"]


def test_coupled_step_collectives(tmp_path):
    """The coupled tank's step on 2 ranks takes part in 1 collective a stage (the reaction's MPI_Allreduce, whose
    sums every rank's copy of the structure integrates, with the energy rates' sums riding on it; the walls' pressure
    sums go between the ranks that share an element), 4 a step with RK4, and 1 of the step's own (state check,
    bounces, rebuild decision, the next time step and the last rows' write status in one), the time series' rows
    thinned out. Measured 5.1 over 20 steps (the end's write-status check and the set-up's; 9.25 while the energy
    rates took an MPI_Reduce a stage, 22.65 while rank 0 held the structure and broadcast it twice a stage, and the
    step's reductions were three, 34.65 before that): a collective added to the stage or the step fails this."""
    from conftest import REPO_ROOT
    run_flexslosh(["-options_file", "cases/coupled_rectangular.opts", "-fs_dx", "0.01", "-ts_max_steps", "20",
                   "-fs_output_interval", "0", "-fs_series_interval", "1000", "-fs_output_dir", tmp_path], nranks=2,
                  cwd=REPO_ROOT)
    summary = read_summary(tmp_path)
    par = summary["parallel"]
    assert all(5 <= c <= 5.2 for c in par["collectives_per_step"]), par["collectives_per_step"]
    assert summary["wall_pressure_reductions"] == 0 and summary["wall_pressure_exchanged_values"] > 0


def test_coupled_step_collectives_with_a_row_every_step(tmp_path):
    """With a row of timeseries.csv and energy.csv every step the coupled tank on 2 ranks takes 5 collectives a
    step (docs/performance.md, "What a rank owns, sends and waits for"): the 5 above, the row's sums (its sums, the
    walls' loads, the energies' sums and the largest speed) riding on the step's own reduction (FSMonitorRowsBegin(),
    taken before the lists are rebuilt; the two files' write status rides on the next step's). Measured 5.1 (8 ranks
    too); 6.1 with the row's own reduction, 10.2 with the energy rates' MPI_Reduce a stage as well, 14.15 with the
    row's five collectives, 33.1 before the structure ran on every rank and the step's and the row's reductions were
    merged. The time series and the energy budget are the same as on 1 rank."""
    from conftest import REPO_ROOT
    out = {}
    for n in (1, 2):
        out[n] = tmp_path / f"r{n}"
        run_flexslosh(["-options_file", "cases/coupled_rectangular.opts", "-fs_dx", "0.01", "-ts_max_steps", "20",
                       "-fs_output_interval", "0", "-fs_output_dir", out[n]], nranks=n, cwd=REPO_ROOT)
    par = read_summary(out[2])["parallel"]
    assert par["steps"] == 20
    assert all(5 <= c <= 5.2 for c in par["collectives_per_step"]), par["collectives_per_step"]
    one, two = (np.genfromtxt(out[n] / "timeseries.csv", delimiter=",", names=True) for n in (1, 2))
    assert len(one) == len(two) == 21
    for col in ("tip_displacement", "tip_acceleration", "load_force_y"):
        assert np.allclose(two[col], one[col], rtol=1e-9, atol=1e-12 * np.abs(one[col]).max()), col
    # the energy budget too: the powers' sums ride on the stage's reduction, the row's sums on the step's
    one, two = (np.genfromtxt(out[n] / "energy.csv", delimiter=",", names=True) for n in (1, 2))
    for col in ("E_kin", "E_liquid_abs", "work_delta", "work_wall", "work_ext", "work_struct_damping", "E_total"):
        assert np.allclose(two[col], one[col], rtol=1e-9, atol=1e-12 * np.abs(one[col]).max()), col


def test_the_step_reduction_under_every_allreduce_algorithm(tmp_path):
    """The step's one reduction packs sums and maxima into one buffer with an operation of its own
    (FSSolverReduceSumMax). MPI may cut a reduced vector into pieces (Open MPI's ring and reduce-scatter allreduce
    do, and its tuned choice takes the latter on 32 ranks for the 2-D dam break's 41 values): the buffer is one element
    of a contiguous type so that it cannot. The coupled tank on 4 ranks with each of Open MPI's allreduce algorithms
    forced (0: its own choice, 3: recursive doubling, 4: ring, 6: reduce-scatter and allgather) makes the same time
    series and energy budget (the time steps bit for bit). When the operation took a plain vector, the ring's run had other time steps from the
    first step on (the pieces' first value read as the number of sums) and the reduce-scatter's crashed."""
    from conftest import REPO_ROOT
    out = {}
    for alg in (0, 3, 4, 6):
        out[alg] = tmp_path / f"alg{alg}"
        run_flexslosh(["-options_file", "cases/coupled_rectangular.opts", "-fs_dx", "0.01", "-ts_max_steps", "10",
                       "-fs_output_interval", "0", "-fs_output_dir", out[alg]], nranks=4, cwd=REPO_ROOT,
                      env={"OMPI_MCA_coll_tuned_use_dynamic_rules": 1, "OMPI_MCA_coll_tuned_allreduce_algorithm": alg})
    for name in ("timeseries.csv", "energy.csv"):
        ref = np.genfromtxt(out[0] / name, delimiter=",", names=True)
        assert len(ref) == 11
        for alg in (3, 4, 6):
            other = np.genfromtxt(out[alg] / name, delimiter=",", names=True)
            for col in ref.dtype.names:  # the sums to round-off (in SI units: about 1e-15 on the near-zero ones)
                assert np.allclose(other[col], ref[col], rtol=1e-12, atol=1e-12 * max(np.abs(ref[col]).max(), 1.0)), \
                    (alg, name, col)
            if name == "timeseries.csv":  # the maxima that set the time step: the same whatever the order
                assert np.array_equal(other["dt"], ref["dt"]), alg


@pytest.mark.parametrize("nranks", [1, 2])
def test_rows_see_the_state_after_the_bounces(tmp_path, nranks):
    """A row of timeseries.csv is the state the step ends with: its sums are taken after the walls' bounces
    (FSBoundaryBounce) moved the particles, and the same on every rank count. The dam break at dx = 0.05 with
    inelastic bounces (restitution 0, within 0.45 dx of a wall: about 150 bounces in 40 steps) and a checkpoint
    every step: each row's kinetic energy, momentum and largest speed equal the checkpoint's particles' (to the
    CSV's ten digits: measured 3.4e-11). With the rows' sums taken before the bounces the kinetic energy is off by
    2.3e-5 and the vertical momentum by 6.1e-4 of its largest value."""
    import h5py
    out = tmp_path / "o"
    run_flexslosh(["-fs_case", "dam_break", "-fs_dx", "0.05", "-ts_max_steps", "40", "-fs_checkpoint_interval", "1",
                   "-fs_walls_bounce_distance", "0.45", "-fs_walls_bounce_restitution", "0",
                   "-fs_output_dir", out], nranks=nranks, cwd=tmp_path)
    assert read_summary(out)["wall_bounces"] > 100
    series = read_series(out)
    rows = {int(s): k for k, s in enumerate(series["step"])}
    cols = ("kinetic_energy", "momentum_x", "momentum_y", "max_velocity")
    scale = {c: np.abs(series[c]).max() for c in cols}
    checked, ranks = 0, set()
    for path in sorted(out.glob("checkpoint_*.h5")):
        with h5py.File(path, "r") as f:
            step = int(f["header"].attrs["step"])
            v, m = f["particles/velocity"][...], f["particles/mass"][...]
        mom = (m[:, None] * v).sum(axis=0)
        mine = {"kinetic_energy": 0.5 * (m * (v * v).sum(axis=1)).sum(), "momentum_x": mom[0], "momentum_y": mom[1],
                "max_velocity": np.sqrt((v * v).sum(axis=1)).max()}
        for c in cols:
            assert abs(series[c][rows[step]] - mine[c]) <= 1e-9 * scale[c], (step, c, series[c][rows[step]], mine[c])
        checked += 1
    assert checked == 40
    # the particles were on every rank
    assert sorted(np.unique(last_snapshot(out)["rank"]).astype(int)) == list(range(nranks))


def test_the_split_density_diffusion_ranks_agree(tmp_path_factory):
    # -fs_delta_split's stages (src/solver/split.c) exchange the ghosts' densities between stages: the seed's tank
    # through its first slam (0.1 s, 840 particles) on 2 ranks as on 1
    from conftest import REPO_ROOT
    run = _runner(tmp_path_factory, "split", ["-options_file", REPO_ROOT / "cases" / "coupled_rectangular.opts",
                                              "-fs_delta_split", "-ts_max_time", "0.1", "-fs_output_interval", "0.1"])
    steps = read_summary(run(1))["steps"]
    compare_runs(run(1), run(2), 2, 840, 2, steps)
    assert read_summary(run(2))["split_stages"]["total"] >= 2 * steps
    sa, sb = read_series(run(1)), read_series(run(2))
    assert rel_max_diff(sa["tip_displacement"], sb["tip_displacement"]) < TOL
