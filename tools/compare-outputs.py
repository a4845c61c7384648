#!/usr/bin/python3
"""Compares two output trees (e.g. a case's out/ before and after a refactoring):
every HDF5 dataset and attribute bit for bit (the producer attribute aside), every CSV
and VTK file byte for byte, text files without their wall-clock lines; PNGs are skipped.
Usage: /usr/bin/python3 tools/compare-outputs.py BASE NEW
Prints every difference and a count; exit status 1 when there is any."""
import sys, os, h5py, numpy as np, re
base, new = sys.argv[1], sys.argv[2]
diffs = []
def walk(root):
    out = set()
    for d, _, files in os.walk(root):
        for f in files:
            out.add(os.path.relpath(os.path.join(d, f), root))
    return out
def h5items(f):
    items = {}
    def visit(name, obj):
        items[name] = obj
    f.visititems(visit)
    return items
def cmp_attrs(path, a, b):
    ka, kb = set(a.attrs.keys()), set(b.attrs.keys())
    for k in sorted(ka ^ kb):
        diffs.append(f"{path}: attribute {k} only in {'base' if k in ka else 'new'}")
    for k in sorted(ka & kb):
        if k in ("producer",): continue
        va, vb = a.attrs[k], b.attrs[k]
        if isinstance(va, np.ndarray) or isinstance(vb, np.ndarray):
            same = np.array_equal(np.asarray(va), np.asarray(vb))
        else:
            same = va == vb or (isinstance(va, float) and np.isnan(va) and np.isnan(vb))
        if not same:
            diffs.append(f"{path}: attribute {k} {va!r} -> {vb!r}")
def cmp_h5(rel):
    with h5py.File(os.path.join(base, rel), "r") as a, h5py.File(os.path.join(new, rel), "r") as b:
        cmp_attrs(rel + ":/", a, b)
        ia, ib = h5items(a), h5items(b)
        for k in sorted(set(ia) ^ set(ib)):
            diffs.append(f"{rel}:/{k} only in {'base' if k in ia else 'new'}")
        for k in sorted(set(ia) & set(ib)):
            oa, ob = ia[k], ib[k]
            cmp_attrs(f"{rel}:/{k}", oa, ob)
            if isinstance(oa, h5py.Dataset):
                da, db = oa[()], ob[()]
                if isinstance(da, np.ndarray):
                    if da.dtype != db.dtype or da.shape != db.shape or da.tobytes() != db.tobytes():
                        diffs.append(f"{rel}:/{k} differs")
                elif da != db:
                    diffs.append(f"{rel}:/{k} differs")
fa, fb = walk(base), walk(new)
for f in sorted(fa ^ fb):
    diffs.append(f"{f} only in {'base' if f in fa else 'new'}")
wall = re.compile(r"wall|seconds|particle_steps_per_second|elapsed", re.I)
for rel in sorted(fa & fb):
    pa, pb = os.path.join(base, rel), os.path.join(new, rel)
    if rel.endswith(".h5"):
        cmp_h5(rel)
    elif rel.endswith((".txt", ".log", ".md", ".json")):
        la = [l for l in open(pa, errors="replace") if not wall.search(l)]
        lb = [l for l in open(pb, errors="replace") if not wall.search(l)]
        if la != lb:
            diffs.append(f"{rel} differs (text, wall-clock lines ignored)")
    elif rel.endswith(".png"):
        continue
    else:
        if open(pa, "rb").read() != open(pb, "rb").read():
            diffs.append(f"{rel} differs (bytes)")
for d in diffs: print(d)
print(f"{len(fa & fb)} files compared, {len(diffs)} differences")
sys.exit(1 if diffs else 0)
