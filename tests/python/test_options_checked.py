"""Every numeric -fs_ option that -help lists refuses NaN, Inf and values outside its range where it is
read, with an error naming the option and the value; or this file says why it accepts them (ACCEPT).

Each option gets NaN, -1, 0 and 1e300 (integers: -1, 0, 2^40 and a word) on top of the cheapest set-up
that reads it (BASE: a coarse case, stopped before the first step). An option that -help lists and that
neither refuses a value nor is in ACCEPT for it fails the test, so new options must be classified here.
The name options get a wrong name (NAMES)."""
import os
import re
import subprocess
from concurrent.futures import ThreadPoolExecutor

import pytest

from conftest import MPI_ENV, flexslosh_bin, petsc_error_message

REAL_VALUES = ["nan", "-1", "0", "1e300"]
INT_VALUES = ["-1", "0", str(2**40), "x"]
# how the message shows each value
SHOWN = {"nan": r"\bnan\b", "-1": r"-1\b", "0": r"\b0\b", "1e300": r"1e\+?300\b", str(2**40): str(2**40), "x": r"\bx\b"}

TANK = ["-fs_case", "tank", "-fs_dx", "0.01", "-fs_tank_length", "0.1"]
TANK3 = ["-fs_case", "tank", "-fs_dim", "3", "-fs_tank_length", "0.1", "-fs_tank_width", "0.04", "-fs_dx", "0.01"]
# the cheapest set-up that reads each option, by prefix (the first that matches); the tank otherwise
BASE = [
    ("-fs_tg_depth", ["-fs_case", "taylor_green", "-fs_dim", "3", "-fs_dx", "0.1"]),
    ("-fs_tg_", ["-fs_case", "taylor_green", "-fs_dx", "0.0625"]),
    ("-fs_shear_", ["-fs_case", "shear", "-fs_dx", "0.0625"]),
    ("-fs_drop_", ["-fs_case", "drop", "-fs_dx", "0.2"]),
    ("-fs_surface_tension_", ["-fs_case", "drop", "-fs_dx", "0.2"]),
    ("-fs_channel_width", ["-fs_case", "channel", "-fs_dim", "3", "-fs_dx", "0.125", "-fs_channel_length", "2",
                           "-fs_channel_width", "2"]),
    ("-fs_channel_", ["-fs_case", "channel", "-fs_dx", "0.125", "-fs_channel_length", "2"]),
    ("-fs_sw_width", ["-fs_case", "standing_wave", "-fs_dim", "3", "-fs_dx", "0.25"]),
    ("-fs_sw_mode_z", ["-fs_case", "standing_wave", "-fs_dim", "3", "-fs_dx", "0.25"]),
    ("-fs_sw_", ["-fs_case", "standing_wave", "-fs_dx", "0.125"]),
    ("-fs_dam_tank_width", ["-fs_case", "dam_break", "-fs_dim", "3", "-fs_dx", "0.3"]),
    ("-fs_dam_", ["-fs_case", "dam_break", "-fs_dx", "0.25"]),
    ("-fs_beam_", TANK + ["-fs_structure", "modal"]),
    ("-fs_modal_", TANK + ["-fs_structure", "modal"]),
    ("-fs_msd_", TANK + ["-fs_structure", "msd"]),
    ("-fs_shifting_", ["-fs_case", "taylor_green", "-fs_dx", "0.0625", "-fs_terms", "continuity,pressure,shifting"]),
    ("-fs_tensile_control_", ["-fs_case", "taylor_green", "-fs_dx", "0.0625", "-fs_terms", "continuity,pressure,tensile_control"]),
    ("-fs_walls_element_size", TANK3),
    ("-fs_tank_width", TANK3),
    ("-fs_tank_baffle_", TANK + ["-fs_tank_shape", "baffled", "-fs_tank_compartments", "2", "-fs_tank_compartment_length", "0.05"]),
    ("-fs_tank_compartment", TANK + ["-fs_tank_shape", "baffled", "-fs_tank_compartments", "2", "-fs_tank_compartment_length", "0.05"]),
    ("-fs_motion_z_", TANK3 + ["-fs_structure", "prescribed"]),
    ("-fs_motion_pitch_", TANK3 + ["-fs_structure", "prescribed"]),
    ("-fs_motion_yaw_", TANK3 + ["-fs_structure", "prescribed"]),
    ("-fs_motion_axis_direction", TANK3 + ["-fs_structure", "prescribed"]),
    ("-fs_motion_axis_", TANK3 + ["-fs_structure", "prescribed", "-fs_motion_axis_direction", "0,0,1"]),
    ("-fs_motion_", TANK + ["-fs_structure", "prescribed"]),
    ("-fs_tank_reference", TANK + ["-fs_structure", "msd"]),
    ("", TANK),
]

FINITE = "any finite value"
# option -> {value: why it is accepted}; every other value must be refused
ACCEPT = {
    "-fs_background_pressure": {v: "a constant of either sign added to the equation of state" for v in ("-1", "0", "1e300")},
    "-fs_beam_force": {v: "a point force of either sign (0: none)" for v in ("-1", "0", "1e300")},
    "-fs_beam_preload": {v: "an initial deflection of either sign (0: the beam at rest)" for v in ("-1", "0")},
    "-fs_surface_tension_sigma": {"0": "no surface tension (the drop tests' reference)"},
    "-fs_nu": {"0": "an inviscid liquid", "1e300": "only bounds the time step"},
    "-fs_relax_time": {"0": "no relaxation", "1e300": "relax the whole run"},
    "-fs_fill_packing_thin": {"0": "the relaxed packing's lattice never thinned"},
    "-fs_rest_check_time": {"0": "no at-rest check", "1e300": "check the whole run"},
    "-fs_rest_check_speed": {"1e300": "a liquid at rest never warned of"},
    "-fs_output_interval": {"0": "the first and last snapshots only", "1e300": "the same"},
    "-fs_progress_interval": {"0": "a line every step", "1e300": "no line"},
    "-fs_checkpoint_interval": {"0": "no checkpoints"},
    "-fs_cfl_viscous": {"1e300": "a limit that never binds: the acoustic CFL still does"},
    "-fs_cfl_force": {"1e300": "a limit that never binds: the acoustic CFL still does"},
    "-fs_max_density_variation": {"1e300": "no blow-up detection"},
    "-fs_beam_tank_mass": {"0": "no tank mass"},
    "-fs_beam_ballast_mass": {"0": "no ballast"},
    "-fs_beam_payload_mass": {"0": "-fs_beam_ballast_mass as given"},
    "-fs_beam_tank_inertia": {"0": "no rotary inertia"},
    "-fs_beam_damping": {"0": "undamped"},
    "-fs_modal_damping": {"0": "undamped modes"},
    "-fs_msd_mass": {"0": "the sum of the named parts", "1e300": "the structure stands still"},
    "-fs_msd_stiffness": {"0": "3 EI/a^3 from the beam", "1e300": "a rigid support"},
    "-fs_msd_liquid_mass": {"0": "no reduced model (the default): the liquid is the particles'"},
    "-fs_msd_liquid_lag": {"0": "the reduced model looks up the current amplitude (the default)"},
    "-fs_delta_c": {"0": "no density diffusion", "1e300": "only bounds the time step"},
    "-fs_delta_constant": {"0": "the delta-LES delta", "1e300": "only bounds the time step"},
    "-fs_delta_min": {"0": "no floor", "1e300": "only bounds the time step"},
    "-fs_delta_max": {"0": "no cap", "1e300": "a cap that never binds"},
    "-fs_delta_cfl": {"0": "0.1875 with RK4, else -fs_cfl_viscous's coefficient", "1e300": "a limit that never binds (unstable in slams: docs)"},
    "-fs_les_c": {"0": "no turbulent viscosity", "1e300": "only bounds the time step"},
    "-fs_viscosity_K": {"1e300": "only bounds the time step"},
    "-fs_shifting_c": {"0": "no shifting", "1e300": "the shifting velocity is capped by -fs_shifting_max"},
    "-fs_walls_repulsion": {"0": "no repulsion (the default)"},
    "-fs_shifting_umin": {"0": "no smallest reference speed", "1e300": "capped by -fs_shifting_max"},
    "-fs_shifting_max": {"1e300": "no cap on the shifting velocity"},
    "-fs_tensile_control_surface": {"0": "the control everywhere in tension, the free surface included"},
    "-fs_tensile_control_epsilon": {"0": "no repulsion: the artificial pressure off"},
    "-fs_halo_skin": {"1e300": "every rank sees every particle: slow, not wrong"},
    "-fs_rebalance_threshold": {"0": "the cuts of the start stay", "1e300": "never exceeded: the cuts of the start stay"},
    "-fs_walls_bounce_distance": {"0": "no bounce"},
    "-fs_walls_bounce_restitution": {"0": "a bounce stops the normal velocity"},
    "-fs_tank_baffle_gap": {"0": "baffles standing on the floor"},
    "-fs_sw_mode_z": {"0": "no wave across the width"},
    "-fs_sw_reynolds": {"1e300": "an inviscid wave"},
    "-fs_c0": {"1e300": "only shrinks the time step"},
    "-fs_tg_Re": {"1e300": "an inviscid vortex"},
    "-fs_shear_Re": {"1e300": "an inviscid shear flow"},
    "-fs_shear_U": {"1e300": "a fast shear flow: c0 and nu follow it, the time step shrinks"},
    "-fs_channel_shear": {"-1": "a shear of either sign", "0": "the liquid at rest (the Poiseuille start-up)",
                          "1e300": "a fast shear: c0 follows it, the time step shrinks"},
    "-fs_rho0": {"1e300": "only scales the masses and pressures"},
    "-fs_motion_ramp": {"0": "no smooth start", "1e300": "a start so slow the motion never grows"},
    **{f"-fs_motion_{c}_poly": {v: "an offset of either sign (the liquid feels accelerations only)" for v in ("-1", "0", "1e300")}
       for c in ("x", "y", "z", "roll", "pitch", "yaw", "axis")},
}

# option -> {value: (what the error says, why)}: refused further on, with a PETSc error that names no
# option (a length of 1e300 leaves no particle or breaks the walls, a huge mass breaks the modes, ...)
HUGE_LENGTH = (r"no particle|intersects itself|nan|inf", "a length of 1e300 breaks the geometry, refused where it is built")
DOWNSTREAM = {
    **{o: {"1e300": HUGE_LENGTH} for o in (
        "-fs_tank_length", "-fs_tank_height", "-fs_tank_width", "-fs_tank_compartment_length", "-fs_tank_baffle_thickness",
        "-fs_tank_baffle_gap", "-fs_tank_baffle_height", "-fs_dam_width", "-fs_dam_height", "-fs_dam_tank_length",
        "-fs_dam_tank_height", "-fs_dam_tank_width", "-fs_sw_length", "-fs_sw_depth", "-fs_sw_width", "-fs_tg_L",
        "-fs_shear_L", "-fs_beam_length", "-fs_beam_I", "-fs_beam_mass_per_length")},
    **{o: {"1e300": (r"nan|inf|deflation|converge", "1e300 overflows the modes, which SLEPc refuses")} for o in (
        "-fs_beam_E", "-fs_beam_tank_mass", "-fs_beam_ballast_mass", "-fs_beam_payload_mass", "-fs_beam_tank_inertia")},
    "-fs_tg_U": {"1e300": (r"nan", "1e300 overflows the c0 derived from it")},
    **{o: {"1e300": HUGE_LENGTH} for o in ("-fs_channel_length", "-fs_channel_height")},
    "-fs_channel_width": {"1e300": (r"not finite", "the extruded walls' box is refused where the mesh is built")},
    "-fs_msd_beam_mass_fraction": {"0": (r"moving mass 0", "accepted, but the base has no other moving mass")},
    "-fs_beam_preload": {"1e300": (r"structure's energy is not finite",
                                   "accepted, but its elastic energy overflows: the state's check stops the run at step 0")},
}

# name options: a wrong name and what the error must say; None: why a wrong value is not tested here
NAMES = {
    "-fs_case": (["nosuch"], None),
    "-fs_structure": (["nosuch"], None),
    "-fs_terms": (["continuity,nosuch"], None),
    "-fs_tank_shape": (["nosuch"], None),
    "-fs_boundary": (["nosuch"], None),
    "-fs_walls_visibility": (["nosuch"], None),
    "-fs_neighbour_rebuild": (["nosuch"], None),
    "-fs_neighbour_candidates": (["nosuch"], None),
    "-fs_pair_cache": (["nosuch"], None),
    "-fs_balance": (["nosuch"], None),
    "-fs_fill_packing": (["nosuch"], None),
    "-fs_tensile_control_type": (["-fs_terms", "continuity,pressure,tensile_control", "-fs_tensile_control_type", "nosuch"], "nosuch"),
    "-fs_fill_packing_cache": None,  # a folder, made where a packing is written: test_packing.py
    "-fs_coupling_loads": (["-fs_structure", "msd", "-fs_coupling_loads", "nosuch"], "nosuch"),
    "-fs_walls_noslip": (["nosuch"], None),
    "-fs_walls_moment_walls": (["-fs_walls_moment_walls", "nosuch", "-fs_walls_moment_points", "0,0"], "nosuch"),
    "-fs_tank_file": (["-fs_tank_shape", "file", "-fs_tank_file", "/nonexistent.walls"], "/nonexistent.walls"),
    "-fs_tank_stl_scale": (["nosuch"], None),
    "-fs_tank_stl": (TANK3[4:] + ["-fs_dim", "3", "-fs_tank_shape", "stl", "-fs_tank_stl", "/nonexistent.stl"], "/nonexistent.stl"),
    "-fs_msd_liquid_table": (["-fs_case", "beam", "-fs_options_check", "0", "-fs_structure", "msd", "-fs_msd_liquid_mass", "2",
                              "-fs_msd_liquid_table", "/nonexistent.table"], "/nonexistent.table"),
    "-fs_probes": (["/nonexistent.probes"], "/nonexistent.probes"),
    "-fs_restart": (["/nonexistent.h5"], "/nonexistent.h5"),
    "-fs_output_dir": None,  # an unwritable directory: test_bad_input.py's test_unwritable_output_dir
    "-fs_output_name": None,  # names the default directory only (not with -fs_output_dir): test_output_default.py
    "-fs_restart_allow_changes": None,  # names items of a checkpoint's record: test_restart.py
    "-fs_view": None,  # a viewer, read by the executable after the set-up (PetscObjectViewFromOptions)
    **{f"-fs_motion_{c}_file": (TANK3[2:4] * (c == "z") + ["-fs_structure", "prescribed", f"-fs_motion_{c}_file", "/nonexistent.motion"],
                                "/nonexistent.motion") for c in ("x", "y", "z", "roll")},
    **{f"-fs_motion_{c}_file": (TANK3[2:4] + ["-fs_structure", "prescribed", "-fs_motion_axis_direction", "0,0,1",
                                              f"-fs_motion_{c}_file", "/nonexistent.motion"], "/nonexistent.motion")
       for c in ("pitch", "yaw", "axis")},
    "-fs_motion_file": (TANK3[2:4] + ["-fs_structure", "prescribed", "-fs_motion_file", "/nonexistent.motion"],
                        "/nonexistent.motion"),
}


def run(args, tmp):
    env = dict(os.environ, **MPI_ENV)
    cmd = [str(flexslosh_bin()), "-fs_progress", "0", "-fs_output", "0", "-ts_max_steps", "0",
           "-fs_output_dir", str(tmp)] + args
    try:
        p = subprocess.run(cmd, env=env, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True, timeout=60)
    except subprocess.TimeoutExpired:
        return None, " ".join(cmd)
    return p, " ".join(cmd)


@pytest.fixture(scope="module")
def help_options(tmp_path_factory):
    """option -> kind ("real", "int", "reals", "name", "bool") for every -fs_ option -help lists."""
    p, cmd = run(["-help"], tmp_path_factory.mktemp("help"))
    assert p is not None and p.returncode == 0, cmd
    kinds = {}
    for m in re.finditer(r"^\s*(-fs_\w+)(:?) <([^>]*)>", p.stdout, re.M):
        opt, colon, shown = m.groups()
        if colon:
            kinds[opt] = "bool"
        elif re.fullmatch(r"now -?\d+ : formerly -?\d+", shown):
            kinds[opt] = "int"
        elif re.fullmatch(r"[-+0-9.eE]+ : [-+0-9.eE]+", shown):
            kinds[opt] = "real"
        elif re.fullmatch(r"[-+0-9.eE]+(,[-+0-9.eE]+)*", shown):
            kinds[opt] = "reals"
        else:
            kinds[opt] = "name"
    assert len(kinds) > 80, f"parsed only {len(kinds)} options from -help"
    return kinds


def base_of(opt):
    return next(args for prefix, args in BASE if opt.startswith(prefix))


def test_tables_name_listed_options(help_options):
    stale = sorted((set(ACCEPT) | set(DOWNSTREAM) | set(NAMES)) - set(help_options))
    assert not stale, f"in the tables but not listed by -help: {stale}"
    names = sorted(o for o, k in help_options.items() if k == "name" and o not in NAMES)
    assert not names, f"name options without an entry in NAMES: {names}"


def test_bases_run(tmp_path):
    for args in {tuple(a) for _, a in BASE}:
        p, cmd = run(list(args), tmp_path)
        assert p is not None and p.returncode == 0, f"{cmd}\n{petsc_error_message(p.stdout) if p else 'timeout'}"


def check(opt, kind, value, p, cmd):
    """'' when the outcome is right, else what is wrong."""
    if p is None:
        return f"{cmd}: no answer within 60 s"
    out = p.stdout
    if any(bad in out for bad in ("Segmentation", "signal", "SEGV", "core dumped")) or p.returncode < 0:
        return f"{cmd}: crashed (exit {p.returncode})\n{out[-1500:]}"
    msg = petsc_error_message(out)
    later = DOWNSTREAM.get(opt, {}).get(value)
    if later is not None:
        ok = p.returncode > 0 and msg.strip()
        return "" if ok else f"{cmd}: documented as refused further on ({later[1]}) but:\n{msg or out[-1500:]}"
    why = ACCEPT.get(opt, {}).get(value)
    if why is not None:
        return "" if p.returncode == 0 else f"{cmd}: documented as accepted ({why}) but failed:\n{petsc_error_message(out)}"
    if p.returncode == 0:
        return f"{cmd}: accepted, but neither refused nor in ACCEPT"
    msg = petsc_error_message(out)
    # a list given one value may be refused for its length, without showing the value
    if opt not in msg or (kind != "reals" and not re.search(SHOWN[value], msg.replace(opt, ""))):
        return f"{cmd}: the error does not name {opt} and {value}:\n{msg}"
    return ""


def test_numeric_options_refuse_bad_values(help_options, tmp_path):
    jobs = []
    for opt, kind in sorted(help_options.items()):
        values = {"real": REAL_VALUES, "reals": REAL_VALUES, "int": INT_VALUES}.get(kind)
        for v in values or []:
            jobs.append((opt, kind, v, base_of(opt) + [opt, v]))
    assert len(jobs) > 300
    # each run stops before its first step and mostly waits on MPI_Init: 4 at a time fill 2 cores
    with ThreadPoolExecutor(4) as pool:
        results = list(pool.map(lambda j: j[:3] + run(j[3], tmp_path / f"{j[0]}{j[2]}"), jobs))
    wrong = [w for w in (check(*r) for r in results) if w]
    assert not wrong, f"{len(wrong)} of {len(jobs)} runs wrong:\n\n" + "\n\n".join(wrong)


@pytest.mark.parametrize("opt", sorted(o for o, v in NAMES.items() if v))
def test_wrong_names_are_refused(opt, tmp_path):
    args, shown = NAMES[opt]
    if len(args) == 1:
        args, shown = [opt] + args, args[0].split(",")[-1]
    p, cmd = run(TANK + args, tmp_path)
    assert p is not None and p.returncode > 0, cmd
    msg = petsc_error_message(p.stdout)
    # a file's error names the file, not the option
    assert (opt in msg or shown.startswith("/")) and shown in msg, f"{cmd}:\n{msg}"
