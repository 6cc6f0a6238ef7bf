#!/usr/bin/env python3
"""Compare two radnet HDF5 results, dataset by dataset, bit for bit.

    compare_h5.py REFERENCE.h5 CANDIDATE.h5 [--allow-missing] [--quiet]

Every dataset of either file must exist in the other with the same shape, dtype and
bytes (NaN compares equal to NaN at the same place). Attributes are compared too,
except those that describe the run rather than its result: /meta created_utc and
version, and every attribute of /report and its groups that is a timing or a speed
(time_*_s, case_*_time_*_s, *_seconds, rays_per_second, mpi_ranks). Exit 0 when identical, 1 when anything differs (each difference
is printed), 2 on bad usage.

Used by bench/compare_outputs.sh (before/after a refactor: every example and analytic
case bit-identical) and by ctest (a run with 1 and with 2 threads gives the same file).
"""
import sys

import h5py
import numpy as np

VOLATILE_ATTRIBUTES = {("/meta", "created_utc"), ("/meta", "version")}


def volatile(obj_name, attr_name):
    if (obj_name, attr_name) in VOLATILE_ATTRIBUTES:
        return True
    timing = ("time_" in attr_name and attr_name.endswith("_s")) or attr_name.endswith("_seconds")
    if obj_name.startswith("/report") and (timing or attr_name in ("rays_per_second", "mpi_ranks")):
        return True
    return False


def collect(h5):
    """{path: object} of every group and dataset, the root included."""
    objects = {"/": h5}
    h5.visititems(lambda name, obj: objects.__setitem__("/" + name, obj))
    return objects


def same_values(a, b):
    a = np.asarray(a)
    b = np.asarray(b)
    if a.shape != b.shape or a.dtype != b.dtype:
        return False
    if a.dtype.kind == "f":
        # Bytes, so that -0.0 and 0.0 differ; NaN equals NaN at the same place.
        same_bytes = a.tobytes() == b.tobytes()
        return same_bytes or bool(np.all(np.isnan(a) & np.isnan(b)))
    return np.array_equal(a, b)


def describe(value):
    text = repr(np.asarray(value).ravel()[:4])
    return text if len(text) < 120 else text[:117] + "..."


def compare(ref_path, cand_path, allow_missing=False):
    differences = []
    with h5py.File(ref_path, "r") as ref, h5py.File(cand_path, "r") as cand:
        ref_objects, cand_objects = collect(ref), collect(cand)
        for path in sorted(set(ref_objects) | set(cand_objects)):
            if path not in cand_objects or path not in ref_objects:
                if not allow_missing:
                    side = "candidate" if path not in cand_objects else "reference"
                    differences.append(f"{path}: missing in the {side}")
                continue
            r, c = ref_objects[path], cand_objects[path]
            if isinstance(r, h5py.Dataset) != isinstance(c, h5py.Dataset):
                differences.append(f"{path}: a dataset in one file, a group in the other")
                continue
            if isinstance(r, h5py.Dataset):
                rv, cv = r[()], c[()]
                if r.dtype.kind == "O" or h5py.check_string_dtype(r.dtype):
                    equal = np.array_equal(np.asarray(rv, dtype=object), np.asarray(cv, dtype=object))
                else:
                    equal = same_values(rv, cv)
                if not equal:
                    if np.shape(rv) != np.shape(cv):
                        differences.append(f"{path}: shape {np.shape(rv)} != {np.shape(cv)}")
                    elif r.dtype.kind == "f" and np.shape(rv) == np.shape(cv):
                        delta = np.nanmax(np.abs(np.asarray(rv) - np.asarray(cv))) if np.size(rv) else 0.0
                        differences.append(f"{path}: values differ (max |Δ| = {delta:.3e})")
                    else:
                        differences.append(f"{path}: values differ: {describe(rv)} != {describe(cv)}")
            for name in sorted(set(r.attrs) | set(c.attrs)):
                if volatile(path, name):
                    continue
                if name not in r.attrs or name not in c.attrs:
                    if not allow_missing:
                        side = "candidate" if name not in c.attrs else "reference"
                        differences.append(f"{path} attribute {name}: missing in the {side}")
                    continue
                ra, ca = r.attrs[name], c.attrs[name]
                if isinstance(ra, (str, bytes)) or isinstance(ca, (str, bytes)):
                    equal = ra == ca
                else:
                    equal = same_values(ra, ca)
                if not equal:
                    differences.append(f"{path} attribute {name}: {describe(ra)} != {describe(ca)}")
    return differences


def main(argv):
    args = [a for a in argv[1:] if not a.startswith("--")]
    flags = {a for a in argv[1:] if a.startswith("--")}
    if len(args) != 2 or flags - {"--allow-missing", "--quiet"}:
        print(__doc__.strip().splitlines()[2].strip(), file=sys.stderr)
        return 2
    differences = compare(args[0], args[1], "--allow-missing" in flags)
    for d in differences:
        print(f"{args[1]}: {d}")
    if not differences and "--quiet" not in flags:
        print(f"{args[1]}: identical to {args[0]}")
    return 1 if differences else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
