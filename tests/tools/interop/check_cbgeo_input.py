#!/usr/bin/python3
"""Checks a CB-Geo MPM input folder (mpm2cbgeo's) against CB-Geo's formats and the
particles it was made from.

    check_cbgeo_input.py PARTICLES.h5 DIR [--domain X0 Y0 X1 Y1 --cell H]
                         [--boundary side=condition ...] [--friction MU] [--end-time T]

The text files are read as CB-Geo's Ascii2D reader reads them (a line holding '#' or '!'
is a comment, blank lines are skipped, the first remaining line is the count); every
count, order, value and unit is compared with the particle file: coordinates per
material in file order, stresses [xx, yy, zz, xy, yz, xz] in Pa in the concatenated
order, volumes M_p/ρ by CB-Geo id (so ρ Σ V = Σ M_p), the grid's nodes and
counter-clockwise cells, the entity sets of the four sides, mpm.json's keys and
settings, and the step-0 particle table CB-Geo resumes from (its fields in its order,
velocities and strains included). Exits 1 with the first failure.
"""
import argparse
import json
import math
import pathlib
import sys

import h5py
import numpy as np


def fail(message):
    print(f"FAIL: {message}")
    sys.exit(1)


def data_lines(path):
    lines = []
    for line in pathlib.Path(path).read_text().splitlines():
        line = line.strip()
        if not line or "#" in line or "!" in line:
            continue
        lines.append(line.split())
    return lines


def check(condition, message):
    if not condition:
        fail(message)


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("particles")
    parser.add_argument("folder")
    parser.add_argument("--domain", type=float, nargs=4, required=True)
    parser.add_argument("--cell", type=float, required=True)
    parser.add_argument("--boundary", action="append", default=[])
    parser.add_argument("--friction", type=float, default=0.0)
    parser.add_argument("--end-time", type=float, required=True)
    args = parser.parse_args()
    folder = pathlib.Path(args.folder)

    with h5py.File(args.particles, "r") as f:
        x = f["particles/coordinates"][...]
        stress = f["particles/stress"][...]
        mass = f["particles/mass"][...]
        material = f["particles/material_id"][...]
        time = float(f.attrs["time"])
        densities = {int(k): float(g.attrs["density"]) for k, g in f["materials"].items()}
        models = {int(k): (g.attrs["mpm_model"] if "mpm_model" in g.attrs else g.attrs["model"]).decode()
                  for k, g in f["materials"].items()}
        angles = {int(k): (float(g.attrs["friction_angle"]), float(g.attrs["cohesion"]))
                  for k, g in f["materials"].items()}
    n = len(mass)
    order = np.concatenate([np.flatnonzero(material == m) for m in sorted(set(material.tolist()))])

    # Mesh: header, nodes on the grid x fastest, cells counter-clockwise from lower left.
    x0, y0, x1, y1 = args.domain
    nx, ny = round((x1 - x0) / args.cell), round((y1 - y0) / args.cell)
    mesh = data_lines(folder / "mesh.txt")
    check([int(v) for v in mesh[0]] == [(nx + 1) * (ny + 1), nx * ny], f"mesh.txt header {mesh[0]}")
    nodes = np.array([[float(v) for v in row] for row in mesh[1:1 + (nx + 1) * (ny + 1)]])
    check(nodes.shape == ((nx + 1) * (ny + 1), 2), f"mesh.txt: {nodes.shape} node rows")
    grid = np.array([[x0 + i * args.cell, y0 + j * args.cell] for j in range(ny + 1) for i in range(nx + 1)])
    check(np.allclose(nodes, grid, atol=1e-12 * max(1.0, abs(x1), abs(y1))), "mesh.txt: nodes off the grid")
    cells = np.array([[int(v) for v in row] for row in mesh[1 + len(nodes):]])
    check(cells.shape == (nx * ny, 4), f"mesh.txt: cells {cells.shape}")
    check(cells.min() >= 0 and cells.max() < len(nodes), "mesh.txt: node id out of range")
    corners = nodes[cells]
    lower_left = corners[:, 0]
    check(np.allclose(corners[:, 1] - lower_left, [args.cell, 0]) and
          np.allclose(corners[:, 2] - lower_left, [args.cell, args.cell]) and
          np.allclose(corners[:, 3] - lower_left, [0, args.cell]), "mesh.txt: cells not ED2Q4 (CCW from lower left)")

    # Particles, per material file; stresses and volumes in the same order.
    config = json.loads((folder / "mpm.json").read_text())
    generators = [p["generator"] for p in config["particles"]]
    check([g["material_id"] for g in generators] == sorted(set(material.tolist())), "generators per material")
    read = []
    for g in generators:
        check(g["type"] == "file" and g["io_type"] == "Ascii2D" and g["particle_type"] == "P2D",
              f"generator {g}")
        rows = data_lines(folder / g["location"])
        count = int(rows[0][0])
        coordinates = np.array([[float(v) for v in row] for row in rows[1:]])
        check(coordinates.shape == (count, 2), f"{g['location']}: {coordinates.shape} rows for {count}")
        read.append(coordinates)
    read = np.concatenate(read)
    check(read.shape == (n, 2) and np.array_equal(read, x[order]), "particle coordinates differ")
    rows = data_lines(folder / "particles-stresses.txt")
    check(int(rows[0][0]) == n, "particles-stresses.txt count")
    s = np.array([[float(v) for v in row] for row in rows[1:]])
    check(s.shape == (n, 6), f"particles-stresses.txt shape {s.shape}")
    check(np.array_equal(s[:, :4], stress[order]) and np.all(s[:, 4:] == 0), "stresses differ")
    rows = data_lines(folder / "particles-volumes.txt")
    ids = np.array([int(r[0]) for r in rows])
    volumes = np.array([float(r[1]) for r in rows])
    check(np.array_equal(ids, np.arange(n)), "particles-volumes.txt: ids are not 0 … n−1")
    rho = np.array([densities[int(m)] for m in material[order]])
    check(np.allclose(volumes * rho, mass[order], rtol=1e-15), "volumes are not M_p/ρ")
    check(abs((volumes * rho).sum() - mass.sum()) <= 1e-12 * mass.sum(), "total mass")

    # Entity sets: the four sides of the grid.
    sets = {s["id"]: s["set"] for s in json.loads((folder / "entity_sets.json").read_text())["node_sets"]}
    check(sorted(sets) == [0, 1, 2, 3], f"node set ids {sorted(sets)}")
    for sid, axis, value in ((0, 0, x0), (1, 0, x1), (2, 1, y0), (3, 1, y1)):
        on_side = np.flatnonzero(np.isclose(nodes[:, axis], value))
        check(sorted(sets[sid]) == on_side.tolist(), f"node set {sid}")

    # mpm.json.
    m = config["mesh"]
    for key, value in (("mesh", "mesh.txt"), ("io_type", "Ascii2D"), ("cell_type", "ED2Q4"),
                       ("node_type", "N2D"), ("entity_sets", "entity_sets.json"),
                       ("particles_stresses", "particles-stresses.txt"),
                       ("particles_volumes", "particles-volumes.txt")):
        check(m.get(key) == value, f"mpm.json mesh.{key} = {m.get(key)!r}")
    constraints = {(c["nset_id"], c["dir"]) for c in m["boundary_conditions"]["velocity_constraints"]}
    expected = set()
    side_ids = {"left": (0, 0), "right": (1, 0), "base": (2, 1), "top": (3, 1)}
    frictions = []
    for item in args.boundary:
        side, condition = item.split("=")
        sid, normal = side_ids[side]
        if condition in ("roller", "friction"):
            expected.add((sid, normal))
        if condition == "fixed":
            expected |= {(sid, 0), (sid, 1)}
        if condition == "friction":
            frictions.append({"nset_id": sid, "dir": normal, "sign_n": -1 if side in ("left", "base") else 1,
                              "friction": args.friction})
    check(constraints == expected, f"velocity constraints {sorted(constraints)}, expected {sorted(expected)}")
    check(m["boundary_conditions"].get("friction_constraints", []) == frictions,
          f"friction constraints {m['boundary_conditions'].get('friction_constraints')}")
    for entry in config["materials"]:
        mid = entry["id"]
        check(entry["density"] == densities[mid], f"material {mid} density")
        if models[mid] == "linear-elastic":
            check(entry["type"] == "LinearElastic2D", f"material {mid} type")
            continue
        check(entry["type"] == "MohrCoulomb2D", f"material {mid} type")
        for key in ("youngs_modulus", "poisson_ratio", "softening", "friction", "dilation", "cohesion",
                    "residual_friction", "residual_dilation", "residual_cohesion", "peak_pdstrain",
                    "residual_pdstrain", "tension_cutoff"):
            check(key in entry, f"material {mid}: {key} missing")
        check((entry["friction"], entry["cohesion"]) == angles[mid], f"material {mid} φ, c (degrees, Pa)")
    a = config["analysis"]
    check(a["type"] == "MPMExplicit2D" and a["mpm_scheme"] in ("usf", "usl"), f"analysis {a}")
    # Resumed from step 0, CB-Geo runs steps 1 … nsteps − 1: (nsteps − 1) dt to the end.
    duration = args.end_time - time
    check(a["dt"] > 0 and abs((a["nsteps"] - 1) * a["dt"] - duration) <= 1e-9 * duration,
          f"dt {a['dt']} × (nsteps {a['nsteps']} − 1) is not the {duration} s to the end")
    check((a["nsteps"] - 1) % config["post_processing"]["output_steps"] == 0,
          "the last step is not an output step: CB-Geo would not write the end state")
    check(config["external_loading_conditions"]["gravity"] == [0.0, -9.81], "gravity")
    check(config["post_processing"]["output_steps"] >= 1, "output_steps")
    # The resume table: CB-Geo's own particle output at step 0, which carries velocities
    # and strains that its ASCII input cannot.
    resume = a["resume"]
    check(resume["resume"] is True and resume["step"] == 0 and resume["uuid"] == a["uuid"], f"resume {resume}")
    digits = len(str(a["nsteps"]))
    table_file = folder / config["post_processing"]["path"] / a["uuid"] / f"particles{0:0{digits}d}.h5"
    with h5py.File(table_file, "r") as f:
        table = f["table"][...]
    fields = (["id", "mass", "volume", "pressure"]
              + [f"{q}_{c}" for q in ("coord", "displacement", "nsize", "velocity") for c in "xyz"]
              + ["stress_xx", "stress_yy", "stress_zz", "tau_xy", "tau_yz", "tau_xz",
                 "strain_xx", "strain_yy", "strain_zz", "gamma_xy", "gamma_yz", "gamma_xz",
                 "epsilon_v", "status", "cell_id", "material_id", "nstate_vars"]
              + [f"svars_{k}" for k in range(20)])
    check(list(table.dtype.names) == fields, f"{table_file}: fields {table.dtype.names}")
    check(np.array_equal(table["id"], np.arange(n)), "table: ids")
    with h5py.File(args.particles, "r") as f:
        velocity = f["particles/velocity"][...][order]
        strain = f["particles/strain"][...][order]
    check(np.array_equal(np.stack([table["coord_x"], table["coord_y"]], 1), x[order]), "table: coordinates")
    check(np.array_equal(np.stack([table["velocity_x"], table["velocity_y"]], 1), velocity), "table: velocities")
    check(np.array_equal(np.stack([table["stress_xx"], table["stress_yy"], table["stress_zz"], table["tau_xy"]], 1),
                         stress[order]), "table: stresses")
    check(np.array_equal(np.stack([table["strain_xx"], table["strain_yy"], table["strain_zz"], table["gamma_xy"]], 1),
                         strain), "table: strains")
    check(np.array_equal(table["mass"], mass[order]) and np.array_equal(table["volume"], volumes), "table: mass, volume")
    check(np.array_equal(table["material_id"], material[order]) and np.all(table["status"] == 1), "table: material, status")
    cell = np.floor((x[order] - [x0, y0]) / args.cell).astype(int)
    cell = np.clip(cell, 0, [nx - 1, ny - 1])
    check(np.array_equal(table["cell_id"], cell[:, 0] + nx * cell[:, 1]), "table: cells")
    print(f"CB-Geo input: {n} particles, {len(nodes)} nodes, {len(cells)} cells, dt {a['dt']:.4g} s × "
          f"{a['nsteps']} steps: every check passed")


if __name__ == "__main__":
    main()
