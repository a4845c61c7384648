#!/usr/bin/python3
"""Writes an FE checkpoint's model and state in OpenSees's formats, as OpenSees would
print and record the same model: a manual check of opensees2fem on a real model
(tools/interop/README.md, "Checking the import on a case").

    write_opensees_files.py FEM_CHECKPOINT.h5 OUT_DIR [--precision 6] [--start-time 0]

OUT_DIR/model.json is the `print -JSON` form (SSPquad elements for quad4-1gp,
FourNodeQuad for quad4-2x2, Tri31 for tri3; node and element tags from 1 in the
checkpoint's order; material tag = material id + 1); the recorder files hold two rows
with the -time column: the reference state (t = -1: zero displacement and strain) and
the checkpoint's state at its time, written with the given number of significant digits
(OpenSees's default is 6). Stress is written as a multi-yield material answers a
"stress" request (σxx σyy σzz σxy and a stress ratio, here 0) when a material runs that
model in FE, else as σxx σyy σxy.
"""
import argparse
import pathlib

import h5py
import numpy as np

CLASS = {"quad4-1gp": "SSPquad", "quad4-2x2": "FourNodeQuad", "tri3": "Tri31"}


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("checkpoint")
    parser.add_argument("out")
    parser.add_argument("--precision", type=int, default=6)
    args = parser.parse_args()
    out = pathlib.Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    number = lambda x: f"{x:.{args.precision}g}"
    with h5py.File(args.checkpoint, "r") as f:
        time = float(f.attrs["time"])
        X = f["nodes/reference_coordinates"][...]
        u = f["nodes/displacement"][...]
        v = f["nodes/velocity"][...]
        a = f["nodes/acceleration"][...]
        conn = f["elements/connectivity"][...]
        integration = f["elements/connectivity"].attrs["integration"].decode()
        material = f["elements/material_id"][...]
        gauss_element = f["gauss_points/element"][...]
        stress = f["gauss_points/stress"][...]
        strain = f["gauss_points/strain"][...]
        multi_yield = any(g.attrs["model"].decode() == "pressure-independent-multi-yield"
                          for g in f["materials"].values())
    element_class = CLASS[integration]
    nodes = [f'\t\t\t{{"name": {i + 1}, "ndf": 2, "crd": [{x:g}, {y:g}]}}' for i, (x, y) in enumerate(X)]
    elements = [f'\t\t\t{{"name": {e + 1}, "type": "{element_class}", "nodes": [{", ".join(str(n + 1) for n in c)}], '
                f'"thickness": 1, "bodyForces": [0, 0], "material": "{m + 1}"}}' for e, (c, m) in enumerate(zip(conn, material))]
    (out / "model.json").write_text(
        "{\n\t\"StructuralAnalysisModel\": {\n\t\"properties\": {\n\t\t\"ndMaterials\": [\n"
        + ("PressureIndependMultiYield - loadStage: 1\n" if multi_yield else "")
        + "\t\t]\n\t},\n\t\"geometry\": {\n\t\t\"nodes\": [\n" + ",\n".join(nodes) + "\n\t\t],\n"
        "\t\t\"elements\": [\n" + ",\n".join(elements) + "\n\t\t]\n\t}\n}\n}\n")

    def rows(name, reference, state):
        text = " ".join([number(-1.0)] + [number(x) for x in reference]) + "\n"
        text += " ".join([number(time)] + [number(x) for x in state]) + "\n"
        (out / name).write_text(text)

    zeros = np.zeros(u.size)
    rows("disp.out", zeros, u.ravel())
    rows("vel.out", zeros, v.ravel())
    rows("accel.out", zeros, a.ravel())
    order = np.argsort(gauss_element, kind="stable")
    if multi_yield:
        s = np.column_stack([stress[order], np.zeros(len(order))])
    else:
        s = stress[order][:, [0, 1, 3]]
    rows("stress.out", np.zeros(s.size), s.ravel())
    rows("strain.out", np.zeros(len(order) * 3), strain[order][:, [0, 1, 3]].ravel())
    print(f"{out}: {len(X)} nodes, {len(conn)} {element_class} elements, t = {time} s, "
          f"{args.precision} significant digits")


if __name__ == "__main__":
    main()
