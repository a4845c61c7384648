#!/usr/bin/python3
"""Reads the sample checkpoints of write_sample_checkpoints with h5py, as a user would.

Only names documented in common/io/checkpoint-schema.md are used: the script reads them from
that page's tables, so the page and the files cannot drift apart. For each kind it
checks that the file holds exactly the documented datasets with their documented shapes,
dtypes and units, the file and group attributes, and a few values whose formulas are in
write_sample_checkpoints.cpp.

Usage: read_checkpoint_with_h5py.py FOLDER SCHEMA_PAGE (common/io/checkpoint-schema.md)
"""
import math
import sys
from pathlib import Path

import h5py
import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "support"))
from checkpoint_schema import documented_schema  # noqa: E402


def text_attrs(obj):
    """The attributes of `obj` as a dict, strings as str. The programs write strings as
    fixed-length UTF-8 (no global heap: see the schema page), which h5py returns as bytes."""
    return {key: value.decode("utf-8") if isinstance(value, bytes) else value
            for key, value in obj.attrs.items()}


FEM_DATASETS, PARTICLE_DATASETS, MATERIAL_ATTRIBUTES = documented_schema(sys.argv[2])

failures = []


def check(condition, message):
    if not condition:
        failures.append(message)


def datasets_of(f):
    names = []
    f.visititems(lambda name, obj: names.append(name) if isinstance(obj, h5py.Dataset) else None)
    return sorted(names)


def check_datasets(f, documented, rows_of):
    label = Path(f.filename).name
    present = set(datasets_of(f))
    # boundary/*/nodes stands for one dataset per node set present in the file
    expanded = {}
    for name, spec in documented.items():
        if name.startswith("boundary/*/"):
            for node_set in f.get("boundary", {}):
                expanded[name.replace("*", node_set)] = spec
        else:
            expanded[name] = spec
    required = {name for name, spec in expanded.items() if not spec[3]}
    check(not present - set(expanded), f"{label}: undocumented datasets {sorted(present - set(expanded))}")
    check(not required - present, f"{label}: missing datasets {sorted(required - present)}")
    for name, (columns, kind, units, _) in expanded.items():
        if name not in f:
            continue
        d = f[name]
        if columns == "4k":
            check(len(d.shape) == 2 and d.shape[0] == rows_of(name) and d.shape[1] % 4 == 0,
                  f"{label}: /{name}: shape {d.shape}, expected ({rows_of(name)}, 4k)")
        else:
            expected = (rows_of(name),) if columns is None else (rows_of(name), columns)
            check(d.shape == expected, f"{label}: /{name}: shape {d.shape}, expected {expected}")
        check(d.dtype.kind == kind and d.dtype.itemsize in (4, 8),
              f"{label}: /{name}: dtype {d.dtype}, expected kind {kind}")
        check(text_attrs(d).get("units") == units,
              f"{label}: /{name}: units {text_attrs(d).get('units')!r}, expected {units!r}")
        if kind == "f":
            check(np.all(np.isfinite(d[...])), f"{label}: /{name}: non-finite values")


def check_header(f, kind, time, step):
    label = Path(f.filename).name
    a = text_attrs(f)
    check(a["schema"] == "fem-mpm-checkpoint", f"{label}: schema {a['schema']!r}")
    check(int(a["schema_version"]) == 2, f"{label}: schema_version {a['schema_version']}")
    check(a["kind"] == kind, f"{label}: kind {a['kind']!r}, expected {kind!r}")
    check(int(a["dimension"]) == 2, f"{label}: dimension {a['dimension']}")
    check(a["case"] == "h5py-sample", f"{label}: case {a['case']!r}")
    check(a["producer"] == "write_sample_checkpoints", f"{label}: producer {a['producer']!r}")
    check(float(a["time"]) == time, f"{label}: time {a['time']}, expected {time}")
    check(int(a["step"]) == step, f"{label}: step {a['step']}, expected {step}")
    check(float(a["pe0"]) == 1.5e6, f"{label}: pe0 {a['pe0']}")


def check_materials(f):
    label = Path(f.filename).name
    materials = f["materials"]
    check(sorted(materials.keys()) == ["0", "1"], f"{label}: /materials {list(materials)}")
    for key in MATERIAL_ATTRIBUTES:
        check(key in text_attrs(materials["0"]), f"{label}: /materials/0: attribute {key} missing")
    soil, rock = text_attrs(materials["0"]), text_attrs(materials["1"])
    check(soil["name"] == "soil" and soil["model"] == "mohr-coulomb", f"{label}: material 0")
    check(soil["friction_angle"] == 30.0 and soil["cohesion"] == 5000.0, f"{label}: soil φ, c")
    check(rock["name"] == "rock" and rock["model"] == "linear-elastic", f"{label}: material 1")
    check(rock["density"] == 2600.0, f"{label}: rock density")


def read_fem(path):
    with h5py.File(path, "r") as f:
        check_header(f, "fem", 2.0, 40)
        check_materials(f)
        n_nodes = f["nodes/reference_coordinates"].shape[0]
        n_elements = f["elements/connectivity"].shape[0]
        n_gp = f["gauss_points/element"].shape[0]
        check((n_nodes, n_elements, n_gp) == (6, 2, 8), f"fem: counts {(n_nodes, n_elements, n_gp)}")
        sets = {"left": 2, "right": 2, "base": 3}

        def rows_of(name):
            group = name.split("/")[0]
            if group == "boundary":
                return sets[name.split("/")[1]]
            return {"nodes": n_nodes, "elements": n_elements, "gauss_points": n_gp}[group]

        check_datasets(f, FEM_DATASETS, rows_of)

        connectivity = f["elements/connectivity"]
        check(text_attrs(connectivity)["type"] == "quad4", "fem: connectivity type")
        check(text_attrs(connectivity)["integration"] == "quad4-2x2", "fem: connectivity integration")
        check(connectivity[...].tolist() == [[0, 1, 4, 3], [1, 2, 5, 4]], "fem: connectivity")
        check(f["elements/material_id"][...].tolist() == [0, 1], "fem: material_id")

        k = np.arange(n_nodes)
        X = f["nodes/reference_coordinates"][...]
        u = f["nodes/displacement"][...]
        check(np.array_equal(X, np.stack([k % 3, k // 3], axis=1).astype(float)), "fem: X")
        check(np.allclose(u, np.stack([0.01 * k, -0.02 * k], axis=1), rtol=0, atol=1e-15), "fem: u")
        check(np.array_equal(f["nodes/coordinates"][...], X + u), "fem: x = X + u")
        check(np.array_equal(f["nodes/pore_pressure"][...], 1000.0 * k), "fem: pore pressure")

        g = np.arange(n_gp)
        stress = f["gauss_points/stress"][...]
        expected = np.stack([-1000.0 * (g + 1), -2000.0 * (g + 1), -1500.0 * (g + 1), 100.0 * g], axis=1)
        check(np.array_equal(stress, expected), "fem: Gauss point stress")
        check(f["gauss_points/element"][...].tolist() == [0] * 4 + [1] * 4, "fem: Gauss elements")
        check(np.isclose(f["gauss_points/weight"][...].sum(), 8.0), "fem: weights sum to 2 × 4")
        xi = f["gauss_points/local_coordinates"][...]
        check(np.allclose(np.abs(xi), 1.0 / math.sqrt(3.0)), "fem: 2×2 Gauss points at ±1/√3")
        check(np.allclose(f["gauss_points/state/plastic_shear_strain"][...], 0.01 * g), "fem: state")

        boundary = f["boundary"]
        check(text_attrs(boundary)["friction_coefficient"] == 0.4, "fem: friction coefficient")
        base = boundary["base"]
        check(text_attrs(base)["condition"] == "friction", "fem: base condition")
        check(text_attrs(base)["normal"].tolist() == [0.0, -1.0], "fem: base normal")
        check(base["nodes"][...].tolist() == [0, 1, 2], "fem: base nodes")
        order = sorted(boundary.keys(), key=lambda name: int(text_attrs(boundary[name])["index"]))
        check(order == ["left", "right", "base"], f"fem: boundary order {order}")
        check(text_attrs(boundary["left"])["condition"] == "roller", "fem: left condition")

        solver = text_attrs(f["solver"])
        check(solver["stage"] == "failure" and int(solver["steps"]) == 40, "fem: solver settings")
        check(float(solver["time_step"]) == 1.0e-3, "fem: solver time_step")


def read_particles(path, kind, time, step):
    with h5py.File(path, "r") as f:
        check_header(f, kind, time, step)
        check_materials(f)
        n_p = f["particles/coordinates"].shape[0]
        check(n_p == 8, f"{kind}: {n_p} particles, expected 8")
        check_datasets(f, PARTICLE_DATASETS, lambda name: n_p)
        p = f["particles"]
        g = np.arange(n_p)
        check(np.array_equal(p["id"][...], 100 + g), f"{kind}: id")
        check(np.all(p["volume"][...] == 0.25), f"{kind}: volume")
        density = np.where(p["material_id"][...] == 0, 2000.0, 2600.0)
        check(np.array_equal(p["mass"][...], density * 0.25), f"{kind}: mass = ρ V")
        check(np.array_equal(p["stress"][:, 1], -2000.0 * (g + 1)), f"{kind}: σyy")
        check(np.array_equal(p["element"][...], g // 4), f"{kind}: source element")

        transfer = text_attrs(f["transfer"])
        check(float(transfer["transfer_time"]) == 2.0, f"{kind}: transfer_time")
        check(transfer["particles_per_element"] == "2x2", f"{kind}: particles_per_element")
        check(transfer["stress_interpolation"] == "rbf", f"{kind}: stress_interpolation")
        check(transfer["rbf_polynomial"] == "linear", f"{kind}: rbf_polynomial")
        check(float(transfer["rbf_shape"]) == 0.5, f"{kind}: rbf_shape")
        check(int(transfer["rbf_neighbours"]) == 0, f"{kind}: rbf_neighbours")
        return {name: f[name][...] for name in ("particles/coordinates", "particles/velocity",
                                                 "particles/affine_velocity_gradient")
                if name in f} | {
            "solver": text_attrs(f["solver"])}


def main():
    folder = Path(sys.argv[1])
    check(len(FEM_DATASETS) >= 20 and len(PARTICLE_DATASETS) >= 15 and len(MATERIAL_ATTRIBUTES) >= 9,
          f"schema page parsed to {len(FEM_DATASETS)} fem datasets, {len(PARTICLE_DATASETS)} "
          f"particle datasets, {len(MATERIAL_ATTRIBUTES)} material attributes: tables not found")
    read_fem(folder / "fem.h5")
    particles = read_particles(folder / "particles.h5", "particles", 2.0, 0)
    mpm = read_particles(folder / "mpm.h5", "mpm", 3.0, 500)
    moved = mpm["particles/coordinates"] - particles["particles/coordinates"]
    check(np.allclose(moved, [0.1, 0.0], rtol=0, atol=1e-12), "mpm: particles moved 0.1 m in x")
    check(np.array_equal(mpm["particles/velocity"], np.tile([0.1, 0.0], (8, 1))), "mpm: velocity")
    # optional: an APIC run's affine velocity [Cxx, Cxy, Cyx, Cyy]; the particle file has none
    check("particles/affine_velocity_gradient" not in particles,
          "particles: affine_velocity_gradient present")
    check(np.allclose(mpm.get("particles/affine_velocity_gradient", np.zeros((8, 4))),
                      np.tile([0.0, -0.2, 0.2, 0.0], (8, 1)), rtol=0, atol=1e-15),
          "mpm: affine_velocity_gradient")
    check(mpm["solver"].get("shape_function") == "gimp", "mpm: solver shape_function")
    check(float(mpm["solver"].get("grid_spacing")) == 0.5, "mpm: solver grid_spacing")
    for message in failures:
        print(f"FAIL {message}")
    print(f"read_checkpoint_with_h5py: {len(failures)} failures")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
