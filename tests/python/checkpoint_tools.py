"""The checksums of a checkpoint (format version 3, src/io/checkpoint.c), computed again from their description,
for the tests that change a checkpoint's values on purpose and sign it again (so that what is tested is the
check of the values, not the checksum), or make it an older checkpoint without checksums.

A dataset's checksum is "sum64:" and 16 hex digits: the sum modulo 2^64, over the dataset's values taken in
order (particle-major), of mix(bits(v_i) ^ mix(i)), mix being splitmix64's finalizer and bits(v) the float64's
64 bits. The header's is the same sum over its items k = 0, 1, ...: version, step, nglobal, nparticles, nranks,
nfields, /particles.nparticles (as 64-bit integers), the bits of time and dt, FNV-1a of format and of setup."""
import h5py
import numpy as np

MASK = (1 << 64) - 1
DATASETS = ("particles/position", "particles/velocity", "particles/density", "particles/mass", "particles/id",
            "particles/build_position", "layout/nlocal", "layout/domain", "header/global")


def _mix(z):
    """splitmix64's finalizer on numpy uint64 arrays (wrapping arithmetic)"""
    z = z + np.uint64(0x9E3779B97F4A7C15)
    z = (z ^ (z >> np.uint64(30))) * np.uint64(0xBF58476D1CE4E5B9)
    z = (z ^ (z >> np.uint64(27))) * np.uint64(0x94D049BB133111EB)
    return z ^ (z >> np.uint64(31))


def _sum(items):
    items = np.asarray(items, dtype=np.uint64)
    with np.errstate(over="ignore"):
        terms = _mix(items ^ _mix(np.arange(items.size, dtype=np.uint64)))
        return f"sum64:{int(np.sum(terms, dtype=np.uint64)):016x}"


def checksum(values):
    """the checksum of a dataset's values"""
    return _sum(np.ascontiguousarray(np.asarray(values, dtype="<f8")).ravel().view(np.uint64))


def _fnv(data):
    h = 0xCBF29CE484222325
    for c in data:
        h = ((h ^ c) * 0x100000001B3) & MASK
    return h


def _text(v):
    return v if isinstance(v, bytes) else str(v).encode()


def header_checksum(h5):
    """the checksum of an open checkpoint's header"""
    a = h5["header"].attrs
    ints = [int(a[k]) & MASK for k in ("version", "step", "nglobal", "nparticles", "nranks", "nfields")]
    ints.append(int(h5["particles"].attrs["nparticles"]) & MASK)
    bits = [int(np.array([float(a[k])], dtype="<f8").view(np.uint64)[0]) for k in ("time", "dt")]
    strings = [_fnv(_text(a["format"])), _fnv(_text(a["setup"]) if "setup" in a else b"")]
    return _sum(ints + bits + strings)


def resign(h5):
    """signs an open checkpoint (h5py, writable) again: every checksum computed from what it now holds"""
    for name in DATASETS:
        if name in h5 and "checksum" in h5[name].attrs:
            h5[name].attrs["checksum"] = np.bytes_(checksum(h5[name][...]))
    if "checksum" in h5["header"].attrs:
        h5["header"].attrs["checksum"] = np.bytes_(header_checksum(h5))


def strip_checksums(h5):
    """removes every checksum, as in a checkpoint written before format version 3"""
    for name in DATASETS:
        if name in h5 and "checksum" in h5[name].attrs:
            del h5[name].attrs["checksum"]
    if "checksum" in h5["header"].attrs:
        del h5["header"].attrs["checksum"]


def edit(path, change, sign=True):
    """applies change(h5) to the checkpoint at path, then signs it again (sign) or leaves its checksums"""
    with h5py.File(path, "r+") as h5:
        change(h5)
        if sign:
            resign(h5)
