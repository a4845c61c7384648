#!/usr/bin/python3
"""Writes the OpenSees files of the elastic column (column.tcl) from the closed form.

A 1 m wide, 2 m high column of 2 × 4 FourNodeQuad elements of 0.5 m, linear elastic
(ElasticIsotropic E = 20 MPa, ν = 0.25, ρ = 2000 kg/m³), rollers on both sides and the
base, loaded by gravity. Its static solution is one-dimensional:
    σyy(y) = −ρ g (H − y),  σxx = σzz = ν/(1 − ν) σyy,  εyy = σyy / M,
    uy(y)  = −(ρ g / M) (H y − y²/2),  M = E (1 − ν) / ((1 + ν)(1 − 2ν)),
and bilinear elements reproduce it exactly at the nodes; their strain is the constant
(u_top − u_bottom)/h, the exact strain at the element's mid-height, at every Gauss point.
So this is what OpenSees (or any correct code) prints for column.tcl, to round-off, and
what fem-solve computes for the same model (case.toml).

The files are in OpenSees's formats: model.json as `print -JSON` writes it (its
"properties" included), the recorder files with the -time column and -precision 16.
Rows: gravity in two load steps (t = 0.5, 1), then `loadConst -time 0.0` and `record`
(t = 0), then two dynamic steps (t = 0.01, 0.02) in which the column stays at rest.

    /usr/bin/python3 make_recorders.py   # rewrites the files next to it
"""
import pathlib

HERE = pathlib.Path(__file__).resolve().parent
RHO, E, NU, G = 2000.0, 20.0e6, 0.25, 9.81
W, H, NX, NY = 1.0, 2.0, 2, 4
h = H / NY
M = E * (1 - NU) / ((1 + NU) * (1 - 2 * NU))
K0 = NU / (1 - NU)


def node_tag(i, j):
    return 1 + i + (NX + 1) * j


def nodes():
    return [(node_tag(i, j), i * W / NX, j * h) for j in range(NY + 1) for i in range(NX + 1)]


def elements():
    out = []
    for j in range(NY):
        for i in range(NX):
            out.append((1 + i + NX * j,
                        [node_tag(i, j), node_tag(i + 1, j), node_tag(i + 1, j + 1), node_tag(i, j + 1)],
                        (j + 0.5) * h))
    return out


def uy(y, load):
    return -load * RHO * G / M * (H * y - y * y / 2)


def number(x):
    return f"{x:.16g}"


def row(t, values):
    return " ".join([number(t)] + [number(v) for v in values]) + "\n"


def write_json():
    node_lines = [f'\t\t\t{{"name": {t}, "ndf": 2, "crd": [{x:g}, {y:g}]}}' for t, x, y in nodes()]
    element_lines = [
        f'\t\t\t{{"name": {tag}, "type": "FourNodeQuad", "nodes": [{", ".join(map(str, conn))}], '
        f'"thickness": 1, "surfacePressure": 0, "masspervolume": 0, "bodyForces": [0, {-RHO * G:g}], '
        f'"material": "1"}}' for tag, conn, _ in elements()]
    text = ("{\n\t\"StructuralAnalysisModel\": {\n"
            "\t\"properties\": {\n"
            "\t\t\"uniaxialMaterials\": [\n\n\t\t],\n"
            "\t\t\"ndMaterials\": [\n"
            f'\t\t\t{{"name": "1", "type": "ElasticIsotropicMaterial", "E": {E:g}, "nu": {NU:g}, "rho": {RHO:g}}}\n'
            "\t\t],\n"
            "\t\t\"sections\": [\n\n\t\t],\n"
            "\t\t\"crdTransformations\": [\n\n\t\t]\n"
            "\t},\n"
            "\t\"geometry\": {\n"
            "\t\t\"nodes\": [\n" + ",\n".join(node_lines) + "\n\t\t],\n"
            "\t\t\"elements\": [\n" + ",\n".join(element_lines) + "\n\t\t]\n"
            "\t}\n}\n}\n")
    (HERE / "model.json").write_text(text)


def state(load):
    """(displacement per node [ux, uy], stress and strain per element per Gauss point)."""
    disp = []
    for _, x, y in nodes():
        disp += [0.0, uy(y, load)]
    stress, strain = [], []
    for _, _, y_mid in elements():
        syy = -load * RHO * G * (H - y_mid)
        for _ in range(4):  # OpenSees's four points: the element's constant
            stress += [K0 * syy, syy, 0.0]
            strain += [0.0, syy / M, 0.0]
    return disp, stress, strain


def write_recorders():
    rows = [(0.5, 0.5), (1.0, 1.0), (0.0, 1.0), (0.01, 1.0), (0.02, 1.0)]  # (time, load factor)
    n = len(nodes())
    files = {name: [] for name in ("disp", "vel", "accel", "stress", "strain")}
    for t, load in rows:
        disp, stress, strain = state(load)
        files["disp"].append(row(t, disp))
        files["vel"].append(row(t, [0.0] * (2 * n)))
        files["accel"].append(row(t, [0.0] * (2 * n)))
        files["stress"].append(row(t, stress))
        files["strain"].append(row(t, strain))
    for name, lines in files.items():
        (HERE / f"{name}.out").write_text("".join(lines))


if __name__ == "__main__":
    write_json()
    write_recorders()
