"""Bad files, fuzzed: the wall file (-fs_tank_file), STL files (-fs_tank_stl, ASCII and binary), options
files (-options_file), the probe file (-fs_probes), a prescribed motion's time series
(-fs_motion_<c>_file) and a checkpoint (-fs_restart: bits flipped anywhere in the HDF5 file or in a dataset's
values, bytes overwritten, the file cut; the values the issue found accepted, signed again so that their own
checks answer), each mutated a few hundred times in all from a small valid seed with a fixed
random seed (truncated, random bytes inserted or overwritten, numbers replaced by huge, tiny, NaN, Inf,
negative or empty values, lines dropped, repeated or swapped, the closing keywords removed, names
duplicated, an empty file, a directory in place of the file, a binary STL of the wrong size, ...).

Every case runs the binary on a tiny set-up for one step and must end in one of two ways:

- a valid run: exit status 0 and a complete output directory (summary.json parses, timeseries.csv and
  energy.csv have a header and whole rows, the snapshots open as HDF5, particles.xdmf is XML, no
  file left under a .tmp name);
- a clear error: an exit status in 1..127, PETSc's error message (or flexslosh's "[0] flexslosh:" line)
  naming the file as given on the command line; for an options file the file or one of the words it
  holds (an option, or the value PETSc's own -ts_* options could not read); for a motion file also the
  solver's diagnostic of the step (a valid file may shake the tank faster than the liquid can follow);
  and an output directory that is not partial: no summary.json, no .tmp file, every file in it whole
  as above.

Never a signal (a negative status, or 128 + N), a crash marker in the output, or a run that does not
end within the time limit. The seeds must run; the inputs of the bugs this fuzzing found are fixed
cases with the message they must give. About 350 cases, 65-85 s on two busy cores.
"""
import concurrent.futures
import json
import os
import random
import re
import struct
import subprocess
import time
import xml.etree.ElementTree as ET

from checkpoint_tools import edit
from conftest import MPI_ENV, flexslosh_bin, petsc_error_message

SEED = 20260611
TIMEOUT = int(os.environ.get("FUZZ_TIMEOUT", 60))  # seconds a case may take (a hang); each takes about 0.4 s alone
WORKERS = 4  # a short run mostly waits on MPI_Init and the file system: 4 at a time fill 2 cores
DIR = object()  # a directory in place of the file

# ------------------------------------------------------------------ the seeds

WALLS = b"""# a 0.1 m x 0.06 m tank with a post
wall tank          # the container, counter-clockwise
0 0 floor
0.1 0
0.1 0.06
0 0.06
end
wall post          # an obstacle, clockwise
0.045 0.005
0.045 0.015
0.055 0.015
0.055 0.005
end
"""

OPTIONS = b"""# a tiny tank at rest
-fs_case tank
-fs_tank_shape rectangular
-fs_tank_length 0.1
-fs_tank_height 0.06
-fs_fill 0.5
-fs_dx 0.01
-fs_relax_time 0.01
-fs_delta_min 0.1
-ts_max_time 0.1
"""

PROBES = b"""# probes of the tiny tank
probe bottom 0.05 0.005
probe wall 0.0 0.01 diameter 0.01
gauge middle 0.05 0.0 0.05 0.06
"""

MOTION = b"""# time (s), x (m)
0 0
0.01, 0.0001
0.02 0.0003
0.05\t0.0002
1 0
"""


def box_facets(lo, hi):
    """The 12 triangles of the box lo..hi with outward normals."""
    (x0, y0, z0), (x1, y1, z1) = lo, hi
    v = [(x0, y0, z0), (x1, y0, z0), (x1, y1, z0), (x0, y1, z0), (x0, y0, z1), (x1, y0, z1), (x1, y1, z1), (x0, y1, z1)]
    tris = []
    for a, b, c, d in [(0, 3, 2, 1), (4, 5, 6, 7), (0, 1, 5, 4), (2, 3, 7, 6), (0, 4, 7, 3), (1, 2, 6, 5)]:
        tris += [(v[a], v[b], v[c]), (v[a], v[c], v[d])]
    return tris


TANK3 = box_facets((0, 0, 0), (0.04, 0.04, 0.02))
POST3 = box_facets((0.015, 0.005, 0.005), (0.025, 0.035, 0.015))


def ascii_stl(solids):
    out = []
    for name, tris in solids:
        out.append(f"solid {name}")
        for t in tris:
            out += ["  facet normal 0 0 0", "    outer loop"] + [f"      vertex {p[0]} {p[1]} {p[2]}" for p in t]
            out += ["    endloop", "  endfacet"]
        out.append(f"endsolid {name}")
    return ("\n".join(out) + "\n").encode()


def binary_stl(tris, count=None):
    data = bytearray(b"binary box".ljust(80, b" "))
    data += struct.pack("<I", len(tris) if count is None else count)
    for t in tris:
        data += struct.pack("<3f", 0, 0, 0)
        for p in t:
            data += struct.pack("<3f", *p)
        data += b"\0\0"
    return bytes(data)


STL_ASCII = ascii_stl([("tank", TANK3), ("post", POST3)])
STL_BINARY = binary_stl(TANK3)

# ------------------------------------------------------------------ mutations

NUMBER = re.compile(rb"(?<![\w.])-?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?(?![\w.])")
BAD_NUMBERS = [b"1e300", b"-1e300", b"1e400", b"-1e400", b"nan", b"-nan", b"inf", b"-inf", b"Infinity", b"-1", b"0",
               b"-0", b"", b"1e-300", b"4e-320", b"1e9", b"1e6", b"-1e6", b"4294967297", b"99999999999999999999999",
               b"0x1p4", b"1.2.3", b"1e", b"--1", b"1,5", b"0.1x", b"1e-9"]


def lines_of(data):
    return data.splitlines(keepends=True)


def m_truncate(data, rng):
    return data[:rng.randrange(len(data))], "truncated"


def m_insert(data, rng):
    k, at = rng.randint(1, 8), rng.randrange(len(data) + 1)
    return data[:at] + rng.randbytes(k) + data[at:], f"{k} random bytes inserted at {at}"


def m_overwrite(data, rng):
    k = rng.randint(1, 8)
    at = rng.randrange(max(1, len(data) - k))
    return data[:at] + rng.randbytes(k) + data[at + k:], f"{k} bytes overwritten at {at}"


def m_flip(data, rng):
    b = bytearray(data)
    for _ in range(rng.randint(1, 4)):
        i = rng.randrange(len(b))
        b[i] ^= 1 << rng.randrange(8)
    return bytes(b), "bits flipped"


def m_number(data, rng):
    nums = list(NUMBER.finditer(data))
    m = rng.choice(nums)
    new = rng.choice(BAD_NUMBERS)
    return data[:m.start()] + new + data[m.end():], f"number {m.group()!r} -> {new!r}"


def m_del_line(data, rng):
    ls = lines_of(data)
    i = rng.randrange(len(ls))
    return b"".join(ls[:i] + ls[i + 1:]), f"line {i + 1} deleted"


def m_dup_line(data, rng):
    ls = lines_of(data)
    i = rng.randrange(len(ls))
    return b"".join(ls[:i + 1] + ls[i:]), f"line {i + 1} repeated"


def m_swap_lines(data, rng):
    ls = lines_of(data)
    i, j = rng.randrange(len(ls)), rng.randrange(len(ls))
    ls[i], ls[j] = ls[j], ls[i]
    return b"".join(ls), f"lines {i + 1} and {j + 1} swapped"


def m_long_line(data, rng):
    ls = lines_of(data)
    i = rng.randrange(len(ls) + 1)
    long = bytes(rng.choice(b"abcxyz0123456789.-e ") for _ in range(rng.choice([100, 1100, 5000]))) + b"\n"
    return b"".join(ls[:i] + [long] + ls[i:]), f"a line of {len(long) - 1} characters inserted at line {i + 1}"


def m_nul(data, rng):
    at = rng.randrange(len(data))
    return data[:at] + b"\0" + data[at:], f"a NUL byte at {at}"


def m_crlf(data, rng):
    return data.replace(b"\n", b"\r\n"), "CRLF line ends"


def m_drop_keyword(*keywords):
    def mutate(data, rng):
        ls = lines_of(data)
        idx = [i for i, line in enumerate(ls) if line.split()[:1] and line.split()[0] in keywords]
        i = rng.choice(idx)
        return b"".join(ls[:i] + ls[i + 1:]), f"line {i + 1} ({ls[i].strip()!r}) deleted"
    return mutate


def m_rename(pattern, names):
    """a name (group 1 of pattern) replaced by another name or a bad one"""
    def mutate(data, rng):
        ms = list(re.finditer(pattern, data, re.M))
        m = rng.choice(ms)
        new = rng.choice(names)
        return data[:m.start(1)] + new + data[m.end(1):], f"name {m.group(1)!r} -> {new!r}"
    return mutate


BAD_NAMES = [b"tank", b"post", b"floor", b"a,b", b'q"uote', b"x" * 70, b"\x01ctl", b"caf\xc3\xa9", b"\xff\xfe",
             b"1st", b"-dash", b"a" * 63]

GENERIC = [m_truncate, m_insert, m_overwrite, m_flip, m_number, m_number, m_number, m_del_line, m_dup_line,
           m_swap_lines, m_long_line, m_nul]


def binary_mutations():
    tris = TANK3

    def count(data, rng):
        c = rng.choice([0, 1, 11, 13, 24, 2**31, 2**32 - 1])
        return binary_stl(tris, c), f"triangle count {c} in the header (12 triangles)"

    def coord(data, rng):
        b = bytearray(data)
        t, k = rng.randrange(12), rng.randrange(9)
        v = rng.choice([float("nan"), float("inf"), -float("inf"), 3e38, -3e38, 1e-40, 0.0, 1e6])
        struct.pack_into("<f", b, 84 + 50 * t + 12 + 4 * k, v)
        return bytes(b), f"triangle {t} coordinate {k} -> {v}"

    def extra(data, rng):
        k = rng.choice([1, 49, 50, 51, 100])
        return data + rng.randbytes(k), f"{k} bytes appended"

    def solid_header(data, rng):
        return b"solid tank".ljust(80, b" ") + data[80:], "binary file whose header starts with 'solid'"

    def drop_tri(data, rng):
        t = rng.randrange(12)
        d = data[:84 + 50 * t] + data[84 + 50 * (t + 1):]
        return d[:80] + struct.pack("<I", 11) + d[84:], f"triangle {t} removed (count 11)"

    return [count, coord, coord, extra, solid_header, drop_tri, m_truncate, m_overwrite, m_flip]


# ------------------------------------------------------------------ the cases

BASE2 = ["-fs_case", "tank", "-fs_dx", "0.01", "-fs_output_interval", "0"]
BASE3 = ["-fs_case", "tank", "-fs_dim", "3", "-fs_dx", "0.01", "-fs_output_interval", "0"]


class Case:
    def __init__(self, kind, what, files, args, options_from=None, expect=None):
        self.kind, self.what, self.files, self.args = kind, what, files, args
        self.options_from = options_from  # the options file whose option names may be named in the error
        self.expect = expect  # "ok": must run; a regular expression: the error message must match it


def make_cases():
    rng = random.Random(SEED)
    cases = []

    def fuzz(kind, seed, mutators, n, fname, args, options_from=None):
        for _ in range(n):
            mut = rng.choice(mutators)
            data, what = mut(seed, rng)
            cases.append(Case(kind, what, {fname: data}, args, options_from))
        cases.append(Case(kind, "the seed", {fname: seed}, args, options_from, expect="ok"))
        cases.append(Case(kind, "empty file", {fname: b""}, args, options_from))
        cases.append(Case(kind, "a directory", {fname: DIR}, args, options_from,
                          expect=None if kind == "options" else "a directory|not a regular file"))

    # 2-D walls
    walls_args = BASE2 + ["-fs_tank_shape", "file", "-fs_tank_file", "tank.walls", "-ts_max_steps", "1"]
    fuzz("walls", WALLS,
         GENERIC + [m_drop_keyword(b"end"), m_drop_keyword(b"end"), m_drop_keyword(b"wall"),
                    m_rename(rb"^wall (\S+)", BAD_NAMES), m_rename(rb"^wall (\S+)", BAD_NAMES),
                    m_rename(rb"^0 0 (\S+)", BAD_NAMES), m_crlf],
         90, "tank.walls", walls_args)
    # 3-D walls from STL files
    stl_args = BASE3 + ["-fs_tank_shape", "stl", "-fs_tank_stl", "tank.stl", "-ts_max_steps", "1"]
    fuzz("stl", STL_ASCII,
         GENERIC + [m_drop_keyword(b"endsolid", b"endfacet", b"endloop", b"outer", b"vertex", b"facet"),
                    m_rename(rb"^solid (\S+)", BAD_NAMES), m_rename(rb"^solid (\S+)", BAD_NAMES),
                    m_rename(rb"^solid (\S+)", [b"", b"tank  post"]), m_crlf],
         45, "tank.stl", stl_args)
    fuzz("stl", STL_BINARY, binary_mutations(), 30, "tank.stl", stl_args)
    # options files (the length of the run on the command line, which wins over the file)
    opt_args = ["-options_file", "tiny.opts", "-ts_max_steps", "1", "-fs_output_interval", "0"]
    fuzz("options", OPTIONS,
         GENERIC + [m_rename(rb"^(-\S+)", [b"-fs_dx", b"-fs_case", b"-options_file", b"-fs_tank_file", b"-", b"--",
                                             b"-fs_probes", b"-fs_restart", b"-fs_tank_stl"])],
         50, "tiny.opts", opt_args, options_from="tiny.opts")
    for what, files in [
            ("an options file that includes itself", {"tiny.opts": OPTIONS + b"-options_file tiny.opts\n"}),
            ("two options files that include each other",
             {"tiny.opts": OPTIONS + b"-options_file other.opts\n",
              "other.opts": b"-fs_fill 0.4\n-options_file tiny.opts\n"}),
            ("an options file that includes a directory", {"tiny.opts": OPTIONS + b"-options_file sub\n", "sub": DIR}),
            ("an options file that includes a missing file", {"tiny.opts": OPTIONS + b"-options_file missing.opts\n"}),
            ("an options file that includes another twice",
             {"tiny.opts": OPTIONS + b"-options_file other.opts\n-options_file other.opts\n",
              "other.opts": b"-fs_fill 0.4\n"}),
    ]:
        cases.append(Case("options", what, files, opt_args, options_from="tiny.opts"))
    # the inputs of the bugs the fuzzing found (fixed), with what the message must say
    for what, data, expect in [
            ("a vertex at 1e6 m", WALLS.replace(b"\n0.1 0\n", b"\n1e6 0\n"), r"tank\.walls:2-7.*3e\+08 particles"),
            ("a vertex at 1e9 m", WALLS.replace(b"\n0.1 0\n", b"\n1e9 0\n"), r"more than an index can count"),
            ("a wall name with a comma", WALLS.replace(b"wall post", b"wall a,b"), r"tank\.walls:8: bad wall name"),
            ("a wall name with a quote", WALLS.replace(b"wall post", b'wall q"t'), r"tank\.walls:8: bad wall name"),
            ("an edge name of bytes", WALLS.replace(b"0 0 floor", b"0 0 \xff\xfe"), r"tank\.walls:3: bad wall name"),
            ("a number glued to a word", WALLS.replace(b"0.1 0.06", b"0.1 0.06x"), r"tank\.walls:5: cannot parse"),
            ("a NaN y coordinate", WALLS.replace(b"0.1 0.06", b"0.1 nan"), r"tank\.walls:5: y = \"nan\""),
            ("a NUL byte", WALLS.replace(b"0.1 0.06", b"0.1\0 0.06"), r"tank\.walls:5: a NUL byte"),
            ("only comments", b"# nothing\n", r"tank\.walls: no wall in the file")]:
        cases.append(Case("walls", what, {"tank.walls": data}, walls_args, expect=expect))
    cases.append(Case("stl", "a solid name with a comma", {"tank.stl": STL_ASCII.replace(b"solid post", b"solid a,b")},
                      stl_args, expect=r"tank\.stl:\d+: bad wall name"))
    cases.append(Case("options", "a UTF-8 byte-order mark", {"tiny.opts": b"\xef\xbb\xbf" + OPTIONS}, opt_args, "tiny.opts",
                      expect=r'options file "tiny\.opts" starts with the bytes EF BB BF, a UTF-8 byte-order mark'))
    cases.append(Case("options", "stray bytes in an option's name and value (an option nothing reads: refused)",
                      {"tiny.opts": OPTIONS + b"-fs_d\xb5x caf\xc3\xa9\xff\n"}, opt_args, "tiny.opts",
                      expect=r"-fs_d.x is not an option of flexslosh: did you mean -fs_dx"))
    # probes
    probe_args = BASE2 + ["-fs_tank_length", "0.1", "-fs_probes", "tank.probes", "-ts_max_steps", "1"]
    fuzz("probes", PROBES,
         GENERIC + [m_rename(rb"^\w+ (\S+)", BAD_NAMES), m_drop_keyword(b"probe", b"gauge")],
         30, "tank.probes", probe_args)
    # a prescribed motion's time series
    motion_args = BASE2 + ["-fs_tank_length", "0.1", "-fs_structure", "prescribed", "-fs_motion_x_file", "x.motion",
                           "-ts_max_steps", "2"]
    fuzz("motion", MOTION, GENERIC, 30, "x.motion", motion_args)
    for what, data, expect in [
            ("a gauge to y = 1e300", PROBES.replace(b"0.05 0.0 0.05 0.06", b"0.05 0.0 0.05 1e300"),
             r"tank\.probes:4: gauge \"middle\" reaches outside the domain"),
            ("a probe name of control bytes", PROBES.replace(b"probe bottom", b"probe b\x01x"),
             r"tank\.probes:2: bad name"),
            ("a NUL byte", PROBES.replace(b"probe wall", b"probe\0 wall"), r"tank\.probes:3: a NUL byte")]:
        cases.append(Case("probes", what, {"tank.probes": data}, probe_args, expect=expect))
    # a byte-order mark, named with its bytes (the word after it was shown with the mark invisible in it)
    bom = rb"the file starts with the bytes EF BB BF, a UTF-8 byte-order mark"
    for kind, fname, data, args, expect in [
            ("walls", "tank.walls", WALLS, walls_args, rb"tank\.walls:1: " + bom),
            ("stl", "tank.stl", STL_ASCII, stl_args, rb"tank\.stl:1: " + bom),
            ("probes", "tank.probes", PROBES, probe_args, rb"tank\.probes:1: " + bom),
            ("motion", "x.motion", MOTION, motion_args, rb"x\.motion, line 1: " + bom)]:
        cases.append(Case(kind, "a UTF-8 byte-order mark", {fname: b"\xef\xbb\xbf" + data}, args, expect=expect.decode()))
    for what, data, expect in [
            ("a NUL byte", MOTION.replace(b"0.02 0.0003", b"0.02\0 0.0003"), r"x\.motion, line 4: a NUL byte"),
            ("values that overflow the spline", b"0 0\n1e-300 1e300\n1 0\n", r"x\.motion: the points")]:
        cases.append(Case("motion", what, {"x.motion": data}, motion_args, expect=expect))
    return cases


# ------------------------------------------------------------------ checkpoints

CKPT_RUN = ["-fs_case", "taylor_green", "-fs_dx", "0.05", "-fs_output_interval", "0"]
CKPT_ARGS = CKPT_RUN + ["-fs_restart", "ck.h5", "-ts_max_steps", "3"]


def checkpoint_seed(root):
    """The seed checkpoint (Taylor-Green at dx 0.05, 400 particles, step 2) and where each dataset's values lie."""
    import h5py

    out = root / "checkpoint_seed"
    subprocess.run([str(flexslosh_bin()), "-fs_progress", "0"] + CKPT_RUN + ["-ts_max_steps", "2",
                   "-fs_checkpoint_interval", "2", "-fs_output_dir", str(out)], check=True, cwd=root,
                   env=dict(os.environ, **MPI_ENV), stdout=subprocess.DEVNULL, timeout=120)
    path = out / "checkpoint_000002.h5"
    places = {}
    with h5py.File(path, "r") as h5:
        def visit(name, obj):
            if isinstance(obj, h5py.Dataset):
                info = obj.id.get_chunk_info(0)  # PETSc writes one chunk per dataset
                places[name] = (info.byte_offset, info.size)
        h5.visititems(visit)
    return path.read_bytes(), places


def checkpoint_cases(rng, root):
    seed, places = checkpoint_seed(root)
    names = sorted(places)

    def flip_value(data, rng):  # a bit of a stored value: the dataset's checksum must catch it
        name = rng.choice(names)
        at, size = places[name]
        b = bytearray(data)
        i = at + rng.randrange(size)
        b[i] ^= 1 << rng.randrange(8)
        return bytes(b), f"a bit of /{name}'s values flipped at byte {i}"

    cases = []
    for _ in range(14):  # anywhere in the file: a valid run (a bit no one reads) or an error naming the file
        mut = rng.choice([m_flip, m_flip, m_flip, m_overwrite, m_truncate, m_insert])
        data, what = mut(seed, rng)
        cases.append(Case("checkpoint", what, {"ck.h5": data}, CKPT_ARGS))
    for _ in range(8):
        data, what = flip_value(seed, rng)
        cases.append(Case("checkpoint", what, {"ck.h5": data}, CKPT_ARGS, expect=r"ck\.h5\": /\S+ does not match its checksum"))
    cases.append(Case("checkpoint", "the seed", {"ck.h5": seed}, CKPT_ARGS, expect="ok"))
    cases.append(Case("checkpoint", "a directory", {"ck.h5": DIR}, CKPT_ARGS, expect=r"ck\.h5\" does not exist or cannot be read"))

    # the values issue 34 found accepted, signed again: each refused by its own check, naming the file and the item
    def signed(change):
        tmp = root / "checkpoint_edit.h5"
        tmp.write_bytes(seed)
        edit(tmp, change)
        return tmp.read_bytes()

    def attr(name, value):
        return lambda h5: h5["header"].attrs.__setitem__(name, value)

    def value(dset, i, v):
        def change(h5):
            a = h5[dset][...]
            a[i] = v
            h5[dset][...] = a
        return change

    for what, change, expect in [
            ("time NaN (ran on forever)", attr("time", float("nan")), r"/header\.time is nan"),
            ("time 5e306 (ended at once)", attr("time", 5e306), r"/header\.time 5e\+306 and /header\.dt"),
            ("time a string", attr("time", "0.1"), r"/header\.time is a string, expected a number"),
            ("a negative step", attr("step", -3), r"/header\.step is -3"),
            ("a negative mass", value("particles/mass", 3, -1.0), r"/particles/mass\[3\] is -1"),
            ("a duplicate id", value("particles/id", 3, 4.0), r"/particles/id holds the id 4 more than once"),
            ("a huge id", value("particles/id", 3, 1e20), r"/particles/id\[3\] is 1e\+20"),
            ("a negative count", value("layout/nlocal", 0, -5.0), r"/layout/nlocal\[0\] is -5")]:
        cases.append(Case("checkpoint", what, {"ck.h5": signed(change)}, CKPT_ARGS, expect=r"ck\.h5\".*" + expect))
    return cases


# ------------------------------------------------------------------ running and judging


def csv_problem(path):
    text = path.read_bytes()
    if not text:
        return f"{path.name} is empty"
    if not text.endswith(b"\n"):
        return f"{path.name} ends in a torn row"
    rows = text.decode(errors="replace").splitlines()
    n = len(rows[0].split(","))
    for k, row in enumerate(rows[1:], 2):
        if len(row.split(",")) != n:
            return f"{path.name} row {k} has {len(row.split(','))} fields, the header {n}"
    return None


def output_problems(out, ok):
    """what is wrong with the output directory out of a run that succeeded (ok) or failed"""
    import h5py

    problems = []
    if not out.exists():
        return ["no output directory"] if ok else []
    names = sorted(p.name for p in out.iterdir())
    if ok:
        for need in ("summary.json", "timeseries.csv", "energy.csv", "snapshot_000000.h5", "particles.xdmf"):
            if need not in names:
                problems.append(f"{need} missing")
    elif "summary.json" in names:
        problems.append("summary.json written by a run that failed")
    for name in names:
        path = out / name
        try:
            if name.endswith(".tmp"):
                problems.append(f"{name} left behind")
            elif name.endswith(".csv"):
                p = csv_problem(path)
                if p:
                    problems.append(p)
            elif name.endswith(".json"):
                json.loads(path.read_text())
            elif name.endswith(".xdmf"):
                ET.parse(path)
            elif name.endswith(".h5"):
                with h5py.File(path, "r") as h5:
                    list(h5.keys())
        except Exception as e:  # noqa: BLE001 (any failure to read is a damaged file)
            problems.append(f"{name} does not read: {e}")
    return problems


# (PETSc's error class "Floating point exception" is the solver's blow-up check, an error return: a real
# SIGFPE shows in the status)
CRASH = ("Segmentation", "SEGV", "signal", "core dumped", "Traceback", "Bus error")


# a valid motion file may move the tank too fast for the liquid: the solver's diagnostics of the step (or, for
# values that overflow the energy at the start, of the state the run starts from)
RUN_ERROR = re.compile(r"The run blew up|since the neighbour lists were built|left the tank|"
                       r"The state the run starts from, the set-up of case \w+, is not finite")


def run_case(k, case, root):
    work = root / f"{k:03d}_{case.kind}"
    work.mkdir()
    for name, data in case.files.items():
        if data is DIR:
            (work / name).mkdir()
        else:
            (work / name).write_bytes(data)
    out = work / "out"
    cmd = [str(flexslosh_bin()), "-fs_progress", "0", "-fs_options_left", "0"] + case.args + ["-fs_output_dir", "out"]
    env = dict(os.environ, **MPI_ENV)
    t0 = time.time()
    try:
        proc = subprocess.run(cmd, cwd=work, env=env, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, timeout=TIMEOUT)
    except subprocess.TimeoutExpired:
        return [f"no end within {TIMEOUT} s (a hang)"], None, time.time() - t0
    text = proc.stdout.decode(errors="replace")
    problems = []
    if proc.returncode < 0 or proc.returncode >= 128:
        problems.append(f"ended by a signal (status {proc.returncode})")
    for mark in CRASH:
        if mark in text:
            problems.append(f"crash marker {mark!r} in the output")
    if case.expect == "ok" and proc.returncode != 0:
        problems.append(f"a valid input ended with status {proc.returncode}")
    if case.expect not in (None, "ok") and (proc.returncode == 0
                                            or not re.search(case.expect, petsc_error_message(text))):
        problems.append(f"the error message does not match {case.expect!r}")
    if proc.returncode == 0:
        problems += output_problems(out, True)
    elif 0 < proc.returncode < 128:
        msg = petsc_error_message(text)
        if not msg.strip():
            problems.append("an error status without PETSc's error message")
        else:
            named = list(case.files)
            if case.options_from and case.files[case.options_from] is not DIR:
                # an options file: its options, or the value PETSc could not read (its own -ts_* options)
                named += [t.decode(errors="replace") for t in case.files[case.options_from].split() if len(t) > 1]
            if not any(n in msg for n in named) and not (case.kind == "motion" and RUN_ERROR.search(msg)):
                problems.append(f"the error message names none of {named[:6]}")
        problems += output_problems(out, False)
    return problems, text, time.time() - t0


def test_bad_files_fuzzed(tmp_path):
    cases = make_cases() + checkpoint_cases(random.Random(SEED + 1), tmp_path)
    t0 = time.time()
    with concurrent.futures.ThreadPoolExecutor(WORKERS) as pool:
        results = list(pool.map(lambda kc: run_case(kc[0], kc[1], tmp_path), enumerate(cases)))
    elapsed = time.time() - t0
    failures, counts = [], {}
    for k, (case, (problems, text, secs)) in enumerate(zip(cases, results)):
        counts.setdefault(case.kind, [0, 0, 0])[0] += 1
        errored = text is not None and ("flexslosh: error:" in text or "Error Message" in text)
        counts[case.kind][2] += text is not None and not errored and not problems
        if problems:
            counts[case.kind][1] += 1
            failures.append(f"case {k} ({case.kind}: {case.what}, {secs:.1f} s): {'; '.join(problems)}\n"
                            + (petsc_error_message(text)[-600:] if text else "") + "\n" + (text or "")[-400:])
    summary = ", ".join(f"{kind} {n} ({ran} ran, {bad} bad)" for kind, (n, bad, ran) in counts.items())
    print(f"{len(cases)} cases in {elapsed:.0f} s: {summary}")
    assert not failures, f"{len(failures)} of {len(cases)} cases failed ({summary}):\n\n" + "\n\n".join(failures[:40])
