#!/usr/bin/env python3
"""What cases/slope-gmsh's case.toml needs of a slope.msh (Gmsh's ASCII format 4.1):
quadrangles only, each counter-clockwise with positive area; the physical surfaces
"soil" and "foundation" covering exactly the areas of slope.geo's two polygons; the
physical curves "left", "right" and "base" along x = 0, x = 100 m and y = 0 over their
whole lengths.

    check_slope_gmsh_mesh.py MSH_FILE

Prints one line per check and exits 1 if any fails."""
import sys
from collections import defaultdict

# slope.geo's polygons: the soil (0,5) (40,5) (20,15) (0,15); the foundation 100 × 5 m.
AREAS = {"soil": 20 * 10 + 0.5 * 20 * 10, "foundation": 100 * 5}
# The boundary groups: the line each lies on (axis, value) and its length.
CURVES = {"left": ("x", 0.0, 15.0), "right": ("x", 100.0, 5.0), "base": ("y", 0.0, 100.0)}
GMSH_QUADRANGLE, GMSH_LINE = 3, 1


def read_msh41(path):
    lines = open(path).read().split("\n")
    sections, i = {}, 0
    while i < len(lines):
        if lines[i].startswith("$") and not lines[i].startswith("$End"):
            name = lines[i][1:]
            end = lines.index("$End" + name, i)
            sections[name] = lines[i + 1:end]
            i = end
        i += 1
    if sections["MeshFormat"][0].split()[0] != "4.1":
        sys.exit(f"{path}: not Gmsh's format 4.1")
    names = {}
    for row in sections["PhysicalNames"][1:]:
        dim, tag, name = row.split(maxsplit=2)
        names[(int(dim), int(tag))] = name.strip('"')
    # $Entities: each curve's and surface's physical tags.
    entities = sections["Entities"]
    counts = list(map(int, entities[0].split()))
    physical = {}
    row = 1 + counts[0]
    for dim in (1, 2):
        for _ in range(counts[dim]):
            f = entities[row].split()
            tag = int(f[0])
            n_physical = int(f[7])
            physical[(dim, tag)] = [int(t) for t in f[8:8 + n_physical]]
            row += 1
    nodes, body = {}, sections["Nodes"]
    blocks, row = int(body[0].split()[0]), 1
    for _ in range(blocks):
        n = int(body[row].split()[3])
        tags = [int(body[row + 1 + k]) for k in range(n)]
        for k, tag in enumerate(tags):
            nodes[tag] = tuple(map(float, body[row + 1 + n + k].split()[:2]))
        row += 1 + 2 * n
    elements, body = [], sections["Elements"]
    blocks, row = int(body[0].split()[0]), 1
    for _ in range(blocks):
        dim, entity, kind, n = map(int, body[row].split())
        for k in range(n):
            connectivity = list(map(int, body[row + 1 + k].split()[1:]))
            groups = [names[(dim, t)] for t in physical.get((dim, entity), [])]
            elements.append((dim, kind, groups, connectivity))
        row += 1 + n
    return nodes, elements


def main():
    nodes, elements = read_msh41(sys.argv[1])
    failures = []

    def check(ok, text):
        print(("ok     " if ok else "FAILED ") + text)
        if not ok:
            failures.append(text)

    surfaces = [e for e in elements if e[0] == 2]
    kinds = defaultdict(int)
    for e in surfaces:
        kinds[e[1]] += 1
    check(set(kinds) == {GMSH_QUADRANGLE}, f"surface elements: {dict(kinds)} (Gmsh type 3 only)")
    area = defaultdict(float)
    smallest = float("inf")
    for _, _, groups, c in surfaces:
        p = [nodes[t] for t in c]
        a = 0.5 * sum(p[j - 1][0] * p[j][1] - p[j][0] * p[j - 1][1] for j in range(len(p)))
        smallest = min(smallest, a)
        for g in groups:
            area[g] += a
    check(smallest > 0, f"every element counter-clockwise (smallest signed area {smallest:.4g} m²)")
    for name, expected in AREAS.items():
        check(abs(area[name] - expected) <= 1e-9 * expected,
              f"physical surface {name}: {area[name]:.9g} m² (slope.geo: {expected:g} m²)")
    check(set(area) == set(AREAS), f"physical surfaces: {sorted(area)}")
    for name, (axis, value, length) in CURVES.items():
        lines = [e for e in elements if e[0] == 1 and name in e[2]]
        k = 0 if axis == "x" else 1
        on_line = all(abs(nodes[t][k] - value) < 1e-9 for _, _, _, c in lines for t in c)
        total = sum(abs(nodes[c[1]][1 - k] - nodes[c[0]][1 - k]) for _, _, _, c in lines)
        check(on_line and abs(total - length) < 1e-9,
              f"physical curve {name}: {len(lines)} lines on {axis} = {value:g}, "
              f"{total:.9g} m long ({length:g} m)")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
