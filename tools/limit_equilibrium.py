#!/usr/bin/python3
"""Factor of safety and yield acceleration of a case's slope (Bishop's simplified method).

    limit_equilibrium.py CASE.toml

An independent check of the statement "the slope stands under gravity" (docs/method.md
§8): circular slip surfaces through the body over a grid of centres and radii, Bishop's
simplified method for each (dry soil, one material, the case's φ and c and ρ),
    F = Σ [c b + W tan φ] / m_α  /  Σ W sin α,   m_α = cos α + sin α tan φ / F,
iterated to convergence; the factor of safety is the smallest F. The pseudo-static yield
acceleration k_y (in g) of each circle is the horizontal inertia k W acting at the slice
centres that brings its F to 1, Σ [c b + W tan φ]/m_α(F = 1) = Σ W sin α + k Σ W d/R
(d the lever arm of the slice centre above the circle's centre); k_y is the smallest.
Both are for the surface of the case's mesh ([mesh] surface of a profile mesh or the
top edges of its blocks), slides towards +x, circles that stay in the body (above the
base y = 0, clear of the wall x = 0).

Uses Debian's python3-numpy only. Prints one line; `slope_stability(case)` returns the
numbers for tools/report.py.
"""
import math
import sys
import tomllib

import numpy as np

G = 9.81


def surface_of(case):
    """The top surface of the body as a polyline, x increasing."""
    mesh = case["mesh"]
    if mesh.get("generator", "profile") == "profile":
        return [tuple(p) for p in mesh["surface"]]
    # blocks: the highest point of the block edges above each x of their corners
    edges = []
    for block in mesh["blocks"]:
        c = block["corners"]
        for k in range(4):
            edges.append((tuple(c[k]), tuple(c[(k + 1) % 4])))
    xs = sorted({p[0] for e in edges for p in e})
    points = []
    for x in xs:
        top = -math.inf
        for (x0, y0), (x1, y1) in edges:
            if min(x0, x1) - 1e-9 <= x <= max(x0, x1) + 1e-9:
                y = y0 if abs(x1 - x0) < 1e-12 else y0 + (y1 - y0) * (x - x0) / (x1 - x0)
                top = max(top, y if abs(x1 - x0) > 1e-12 else max(y0, y1))
        points.append((x, top))
    return points


def slope_stability(case, centres_x=40, centres_y=40, radii=90, slices=400):
    material = case["materials"][0]
    gamma = material["density"] * G
    cohesion = material["cohesion"]
    tan_phi = math.tan(math.radians(material["friction_angle"]))
    surface = surface_of(case)
    sx = np.array([p[0] for p in surface])
    sy = np.array([p[1] for p in surface])
    x_max, height = sx.max(), sy.max()
    best = {"fs": math.inf, "ky": math.inf, "circle": None, "ky_circle": None}
    for xc in np.linspace(0.0, x_max, centres_x):
        for yc in np.linspace(0.5 * height, 4.0 * height, centres_y):
            for radius in np.linspace(0.1 * height, 3.5 * height, radii):
                x = np.linspace(max(xc - radius, 0.0), min(xc + radius, x_max), slices)
                base = yc - np.sqrt(np.maximum(radius**2 - (x - xc) ** 2, 0.0))
                top = np.interp(x, sx, sy)
                inside = base < top
                if inside.sum() < 10 or (base[inside] < 0.0).any() or x[inside].min() <= x[1] - x[0]:
                    continue
                width = x[1] - x[0]
                h = top[inside] - base[inside]
                if h.max() < 0.05 * height:
                    continue
                weight = gamma * h * width
                # α: inclination of the slice base, positive where it falls towards +x
                alpha = np.arcsin(np.clip((xc - x[inside]) / radius, -1.0, 1.0))
                driving = np.sum(weight * np.sin(alpha))
                if driving <= 0.0:
                    continue
                resisting = cohesion * width + weight * tan_phi
                f = 1.0
                for _ in range(100):
                    m_alpha = np.cos(alpha) + np.sin(alpha) * tan_phi / f
                    new = np.sum(resisting / m_alpha) / driving
                    if abs(new - f) < 1e-8:
                        f = new
                        break
                    f = new
                if f < best["fs"]:
                    best["fs"], best["circle"] = f, (xc, yc, radius)
                lever = yc - 0.5 * (base[inside] + top[inside])
                inertia = np.sum(weight * lever) / radius
                m1 = np.cos(alpha) + np.sin(alpha) * tan_phi
                if inertia > 0.0:
                    k = (np.sum(resisting / m1) - driving) / inertia
                    if k < best["ky"]:
                        best["ky"], best["ky_circle"] = k, (xc, yc, radius)
    return best


def main(argv):
    if len(argv) != 2:
        print(__doc__, file=sys.stderr)
        return 2
    with open(argv[1], "rb") as f:
        case = tomllib.load(f)
    r = slope_stability(case)
    xc, yc, radius = r["circle"]
    print(
        f"factor of safety {r['fs']:.3f} (Bishop, circle centre ({xc:.1f}, {yc:.1f}) m, "
        f"radius {radius:.1f} m); pseudo-static yield acceleration k_y = {r['ky']:.3f} g"
    )
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
