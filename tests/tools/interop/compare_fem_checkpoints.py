#!/usr/bin/python3
"""Compares two FE checkpoints dataset by dataset: fem-solve's and opensees2fem's.

    compare_fem_checkpoints.py FEM_SOLVE.h5 IMPORTED.h5 [--relative R]

Every dataset and group of the first file must be in the second with the same shape and
type class, and its values within R × (the dataset's largest |value|, or 1 for a dataset
of zeros) of the first's: a float dataset of zeros must be zeros to within R. Integer
datasets must be equal. Attributes are compared the same way, except the root's
`producer` and the free-form /solver group, which name the program that wrote the file.
Prints one line per dataset with its largest difference; exits 1 on any mismatch.
"""
import argparse
import sys

import h5py
import numpy as np

SKIPPED_ATTRIBUTES = {"/": {"producer"}}
SKIPPED_GROUPS = {"/solver"}


def items(f):
    found = {}

    def visit(name, obj):
        found["/" + name] = obj  # returns None: visititems goes on

    f.visititems(visit)
    return found


def values_close(a, b, relative):
    a = np.asarray(a)
    b = np.asarray(b)
    if a.dtype.kind in "SUO" or b.dtype.kind in "SUO":
        return a.tolist() == b.tolist(), 0.0
    if a.shape != b.shape:
        return False, float("inf")
    if a.dtype.kind in "iu" and b.dtype.kind in "iu":
        return bool(np.array_equal(a, b)), float(np.max(np.abs(a - b), initial=0))
    finite = a[np.isfinite(a)] if a.size else a
    scale = float(np.max(np.abs(finite), initial=0.0)) or 1.0
    same_infinities = bool(np.array_equal(np.isinf(a), np.isinf(b)))
    if not same_infinities:
        return False, float("inf")
    masked = np.abs(np.where(np.isinf(a), 0.0, a) - np.where(np.isinf(b), 0.0, b))
    difference = float(np.max(masked, initial=0.0))
    return difference <= relative * scale, difference / scale


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("reference")
    parser.add_argument("imported")
    parser.add_argument("--relative", type=float, default=1e-9)
    args = parser.parse_args()
    failures = 0
    with h5py.File(args.reference, "r") as ref, h5py.File(args.imported, "r") as imp:
        ref_items, imp_items = items(ref), items(imp)
        for name in ["/"] + sorted(ref_items):
            if any(name == g or name.startswith(g + "/") for g in SKIPPED_GROUPS):
                continue
            if name not in imp_items and name != "/":
                print(f"{name}: missing from {args.imported}")
                failures += 1
                continue
            r = ref if name == "/" else ref_items[name]
            i = imp if name == "/" else imp_items[name]
            if isinstance(r, h5py.Dataset):
                if not isinstance(i, h5py.Dataset) or r.shape != i.shape:
                    print(f"{name}: shape {r.shape} against {getattr(i, 'shape', 'a group')}")
                    failures += 1
                    continue
                if r.dtype.kind != i.dtype.kind:
                    print(f"{name}: type {r.dtype} against {i.dtype}")
                    failures += 1
                    continue
                ok, difference = values_close(r[...], i[...], args.relative)
                print(f"{name}: shape {r.shape}, max relative difference {difference:.3g}"
                      + ("" if ok else "  MISMATCH"))
                failures += 0 if ok else 1
            for key, value in r.attrs.items():
                if key in SKIPPED_ATTRIBUTES.get(name, set()):
                    continue
                if key not in i.attrs:
                    print(f"{name}: attribute {key} missing from {args.imported}")
                    failures += 1
                    continue
                ok, difference = values_close(value, i.attrs[key], args.relative)
                if not ok:
                    print(f"{name}: attribute {key} = {value!r} against {i.attrs[key]!r}")
                    failures += 1
        extra = sorted(set(imp_items) - set(ref_items))
        extra = [n for n in extra if not any(n == g or n.startswith(g + "/") for g in SKIPPED_GROUPS)]
        for name in extra:
            print(f"{name}: in {args.imported} only")
            failures += 1
    print(f"{failures} mismatch(es)")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
