#!/usr/bin/python3
"""Compares two mpm checkpoints of the same run made on different rank counts.

The rows of a checkpoint are in the order the ranks hold them (docs/parallel.md), so the
particles are matched by id. Checks:
  - the same layout: every group, dataset (shape, dtype, chunks, filters) and attribute
    name of one file is in the other, string attributes equal (the producer aside; the
    ranks' slabs and the rows each held, /solver slab_cuts and slab_rows, are written on
    several ranks only and are the rank count's own: equal when both files have as many);
  - the same particles: the ids, and per id the mass, material and source element bit
    for bit (carried, never recomputed);
  - every floating-point particle field within TOL of the field's largest magnitude;
  - total momentum and kinetic energy within TOL relative (mass: exactly the same values,
    so the sum differs by its summation order only, 1e-15);
  - the solver attributes: integers equal, reals within TOL relative.
Prints the largest differences; exit status 1 on any failure.

Usage: compare_by_id.py A.h5 B.h5 [TOL]   (default TOL 1e-10)
"""
import sys

import h5py
import numpy as np

a_path, b_path = sys.argv[1], sys.argv[2]
tol = float(sys.argv[3]) if len(sys.argv) > 3 else 1e-10
failures = []


def layout(f):
    items = {}

    def visit(name, obj):
        if isinstance(obj, h5py.Dataset):
            items[name] = ("dataset", obj.shape, obj.dtype.str, obj.chunks, obj.compression,
                           obj.shuffle, obj.fletcher32)
        else:
            items[name] = ("group",)
    f.visititems(visit)
    return items


def text(v):
    return v.decode() if isinstance(v, bytes) else v


with h5py.File(a_path, "r") as a, h5py.File(b_path, "r") as b:
    la, lb = layout(a), layout(b)
    for name in sorted(set(la) | set(lb)):
        if la.get(name) != lb.get(name):
            failures.append(f"layout of /{name}: {la.get(name)} vs {lb.get(name)}")
    for name in ["/"] + sorted(set(la) & set(lb)):
        own = {"slab_cuts", "slab_rows"} if name == "solver" else set()
        aa, ba = a[name].attrs, b[name].attrs
        if set(aa) - own != set(ba) - own:
            failures.append(f"{name}: attributes {sorted(set(aa) ^ set(ba))} in one file only")
        for k in (set(aa) & set(ba)) - own:
            va, vb = text(aa[k]), text(ba[k])
            if isinstance(va, str) and k != "producer" and va != vb:
                failures.append(f"{name}: attribute {k} {va!r} vs {vb!r}")

    pa, pb = a["particles"], b["particles"]
    ia, ib = np.argsort(pa["id"][:]), np.argsort(pb["id"][:])
    if not np.array_equal(pa["id"][:][ia], pb["id"][:][ib]):
        failures.append("the files hold different particle ids")
    else:
        for k in ("mass", "material_id", "element"):
            if not np.array_equal(pa[k][:][ia], pb[k][:][ib]):
                failures.append(f"particles/{k} differs for the same ids")
        worst = []

        def fields(g, prefix=""):
            for k, v in g.items():
                if isinstance(v, h5py.Group):
                    yield from fields(v, prefix + k + "/")
                elif v.dtype.kind == "f" and v.shape and v.shape[0] == len(ia):
                    yield prefix + k
        for k in fields(pa):
            x, y = pa[k][:][ia], pb[k][:][ib]
            scale = max(np.abs(x).max(), np.abs(y).max(), 1e-300)
            rel = np.abs(x - y).max() / scale
            worst.append((rel, k))
            if not rel <= tol:
                failures.append(f"particles/{k}: max difference {rel:.3g} of its largest value")
        worst.sort(reverse=True)
        print("largest field differences (of the field's largest value): " +
              ", ".join(f"{k} {r:.2g}" for r, k in worst[:4]))

        m = pa["mass"][:][ia]
        va, vb = pa["velocity"][:][ia], pb["velocity"][:][ib]
        mass_a, mass_b = m.sum(), pb["mass"][:][ib][::-1].sum()
        p_a, p_b = (m[:, None] * va).sum(0), (m[:, None] * vb).sum(0)
        ke_a, ke_b = 0.5 * (m * (va**2).sum(1)).sum(), 0.5 * (m * (vb**2).sum(1)).sum()
        p_scale = (m * np.linalg.norm(va, axis=1)).sum()
        d_mass = abs(mass_a - mass_b) / mass_a
        d_p = np.abs(p_a - p_b).max() / p_scale
        d_ke = abs(ke_a - ke_b) / ke_a if ke_a > 0 else abs(ke_b)
        print(f"total mass {mass_a:.10g} kg/m (relative difference {d_mass:.2g}), momentum "
              f"{p_a[0]:.10g}, {p_a[1]:.10g} kg m/s (difference {d_p:.2g} of Σ m|v|), kinetic "
              f"energy {ke_a:.10g} J/m (relative difference {d_ke:.2g})")
        if not d_mass <= 1e-15:
            failures.append(f"total mass differs by {d_mass:.3g}")
        if not d_p <= tol:
            failures.append(f"total momentum differs by {d_p:.3g} of Σ m|v|")
        if not d_ke <= tol:
            failures.append(f"kinetic energy differs by {d_ke:.3g}")

    sa, sb = a["solver"].attrs, b["solver"].attrs
    for k in sorted(set(sa) & set(sb)):
        va, vb = np.asarray(text(sa[k])), np.asarray(text(sb[k]))
        if k in ("slab_cuts", "slab_rows"):
            if len(str(va).split()) == len(str(vb).split()) and str(va) != str(vb):
                failures.append(f"solver attribute {k}: {va} vs {vb}")
            continue  # else written on other rank counts
        if va.dtype.kind == "f":
            if not np.allclose(va, vb, rtol=tol, atol=0):
                failures.append(f"solver attribute {k}: {va} vs {vb}")
        elif not np.array_equal(va, vb):
            failures.append(f"solver attribute {k}: {va} vs {vb}")

for f in failures:
    print("FAIL:", f)
print(f"{a_path} vs {b_path}: {'different' if failures else 'the same within ' + str(tol)}")
sys.exit(1 if failures else 0)
