#!/usr/bin/python3
"""Factor of safety and yield acceleration of a case's slope (Bishop's simplified method).

    limit_equilibrium.py CASE.toml
    limit_equilibrium.py --particles PARTICLES.h5 [--reservoir LEVEL X_MIN] [--x-range X0 X1]

An independent check of the statement "the slope stands under gravity" (docs/method.md
§8): circular slip surfaces through the body over a grid of centres and radii, Bishop's
simplified method for each (dry soil, one material, the case's φ and c and ρ),
    F = Σ [c b + W tan φ] / m_α  /  Σ W sin α,   m_α = cos α + sin α tan φ / F,
iterated to convergence; the factor of safety is the smallest F. The pseudo-static yield
acceleration k_y (in g) of each circle is the horizontal inertia k W acting at the slice
centres that brings its F to 1, Σ [c b + W tan φ]/m_α(F = 1) = Σ W sin α + k Σ W d/R
(d the lever arm of the slice centre above the circle's centre); k_y is the smallest.
On the critical circle the tool also gives Spencer's F (force and moment equilibrium,
the interslice forces at one inclination θ, found with F): on circles it agrees with
Bishop's to a few per mille, a check of both. Then Spencer's F minimised over convex
non-circular surfaces (polylines moved by compass search from the critical circle, the
best circles of other depths and deepened arcs): the lowest the tool finds, lower than
the circles' where the critical surface is not a circle, notably along a weak base
interface (a "friction" or roller base of the FE model's failure stage: its μ, no
cohesion) that circles, kept above the base, cannot follow. Both are for the surface of the case's mesh ([mesh] surface of a profile mesh or the
top edges of its blocks), slides towards +x, circles that stay in the body (above the
base y = 0, clear of the wall x = 0).

With --particles (a transfer's particle file, docs/method.md §10), the slices take their
weight and strength from the particles: W = Σ m_p g of the particles in the slice above
its base, and the base's strength from the particle nearest to it: a liquefied particle
(its residual-strength record) c = S_r, φ = 0; any other c and φ of its material
(`/materials` attributes, the MPM model's) on the effective normal force, its pore
pressure u acting on the base, F = Σ [c b + (W − u b) tan φ]/m_α / Σ W sin α. Where a
reservoir up to LEVEL stands (x ≥ X_MIN), a slice's soil below the level counts with
its buoyant weight and u with its excess over the reservoir's hydrostatic pressure: the
water outside then loads the circle with no net moment (equivalent to the water as a
layer without strength with its thrust at the circle's ends). The surface is the
particles' top.
Circles slide towards +x and stay within X0..X1 (default: the particles' extent).

Uses Debian's python3-numpy (and python3-h5py for --particles) only. Prints one line;
`slope_stability(case)` returns the numbers for tools/report.py.
"""
import math
import sys
import tomllib

import numpy as np

G = 9.81
M_ALPHA_MIN = 0.2  # the usual practical limit of Bishop's m_α


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


def bishop(resisting, alpha, tan_phi, driving, m_alpha_floor=None):
    """F = Σ resisting/m_α / driving, m_α = cos α + sin α tan φ / F, iterated."""
    f = 1.0
    for _ in range(100):
        m_alpha = np.cos(alpha) + np.sin(alpha) * tan_phi / f
        if m_alpha_floor is not None:
            m_alpha = np.maximum(m_alpha, m_alpha_floor)
        new = np.sum(resisting / m_alpha) / driving
        if abs(new - f) < 1e-8:
            return new
        f = new
    return f


def slices_of(sx, sy, gamma, xc, yc, radius, slices=400):
    """The slices of one circle under the surface (sx, sy), one material of unit weight
    gamma: (width b, weights W, base inclinations α (positive where the base falls
    towards +x), levers of the slice centres above the circle's centre), or None for a
    circle that is not a slide of the body: it leaves through the base, the wall x = 0
    or the model's far end (a boundary of the model, not a free face), is too shallow,
    or drives nothing."""
    x_max, height = sx.max(), sy.max()
    x = np.linspace(max(xc - radius, 0.0), min(xc + radius, x_max), slices)
    base = yc - np.sqrt(np.maximum(radius**2 - (x - xc) ** 2, 0.0))
    top = np.interp(x, sx, sy)
    inside = base < top
    width = x[1] - x[0]
    if inside.sum() < 10 or (base[inside] < 0.0).any() \
            or x[inside].min() <= width or x[inside].max() >= x_max - width:
        return None
    h = top[inside] - base[inside]
    if h.max() < 0.05 * height:
        return None
    weight = gamma * h * width
    alpha = np.arcsin(np.clip((xc - x[inside]) / radius, -1.0, 1.0))
    if np.sum(weight * np.sin(alpha)) <= 0.0:
        return None
    lever = yc - 0.5 * (base[inside] + top[inside])
    return width, weight, alpha, lever


def circle(sx, sy, gamma, cohesion, tan_phi, xc, yc, radius, slices=400):
    """Bishop's F and the pseudo-static k (g) of one circle (slices_of; None where it
    gives none). k is None where Bishop's m_α at F = 1 falls below M_ALPHA_MIN."""
    cut = slices_of(sx, sy, gamma, xc, yc, radius, slices)
    return None if cut is None else bishop_of_slices(cut, cohesion, tan_phi, radius)


def bishop_of_slices(cut, cohesion, tan_phi, radius):
    """Bishop's F and k (circle) of a circle's slices (slices_of)."""
    width, weight, alpha, lever = cut
    driving = np.sum(weight * np.sin(alpha))
    resisting = cohesion * width + weight * tan_phi
    f = bishop(resisting, alpha, tan_phi, driving)
    inertia = np.sum(weight * lever) / radius
    m1 = np.cos(alpha) + np.sin(alpha) * tan_phi
    # Bishop's m_α near zero (slices steeper than 90° − φ against the slide at the toe)
    # makes the sum meaningless: such circles give no yield acceleration.
    k = ((np.sum(resisting / m1) - driving) / inertia
         if inertia > 0.0 and m1.min() > M_ALPHA_MIN else None)
    return f, k


def _illinois(function, low, high, tolerance):
    """A root of `function` in [low, high], where it changes sign, by regula falsi with the
    Illinois modification: superlinear where bisection is linear (about 8 evaluations to
    1e-10 on the smooth sums of Spencer's method), and kept within the bracket."""
    f_low, f_high = function(low), function(high)
    if not (np.isfinite(f_low) and np.isfinite(f_high)) or np.sign(f_low) == np.sign(f_high):
        return None
    side = 0
    for _ in range(100):
        x = (low * f_high - high * f_low) / (f_high - f_low)
        f_x = function(x)
        if not np.isfinite(f_x):  # a pole or no root inside: a bisection step instead
            x = 0.5 * (low + high)
            f_x = function(x)
            if not np.isfinite(f_x):
                return None
        if np.sign(f_x) == np.sign(f_high):
            high, f_high = x, f_x
            if side == -1:
                f_low *= 0.5
            side = -1
        else:
            low, f_low = x, f_x
            if side == 1:
                f_high *= 0.5
            side = 1
        if abs(high - low) < tolerance * max(1.0, abs(x)) or f_x == 0.0:
            return x
    return 0.5 * (low + high)


F_GRID = np.geomspace(50.0, 0.01, 120)


def spencer_slices(width, weight, alpha, cohesion, tan_phi, xb, yb, theta_guess=None):
    """Spencer's F of any slip surface cut into slices (widths b, weights W, base
    inclinations α positive where the base falls towards +x, base strengths c and tan φ,
    per slice or one for all, base midpoints (xb, yb) relative to any point): force and
    moment equilibrium with the interslice forces at one inclination θ. Each slice's
    interslice resultant is
        Q = [c l/F + W cos α tan φ/F − W sin α] / [cos(α − θ) (1 + tan(α − θ) tan φ/F)],
    l = b / cos α, acting through its base midpoint (thin slices: W, N and S do); F and θ
    solve Σ Q = 0 (forces) and Σ Q (xb sin θ + yb cos θ) = 0 (moments). On a circle about
    its centre the moment sum is −R Σ Q cos(α − θ), the classical form. Returns (F, θ in
    degrees), or None where no θ in ±60° balances both. `theta_guess` (degrees), a
    nearby surface's θ, is tried first."""
    tan_phi = np.broadcast_to(tan_phi, alpha.shape)
    a = (cohesion * width / np.cos(alpha) + weight * np.cos(alpha) * tan_phi)
    d = weight * np.sin(alpha)

    def q(f, theta):
        f = np.asarray(f, dtype=float)[..., None]
        return (a / f - d) / (np.cos(alpha - theta) + np.sin(alpha - theta) * tan_phi / f)

    # Each sum has poles at small F (cos(α − θ) + sin(α − θ) tan φ / F = 0 on slices with
    # α < θ): its root is the first sign change coming down from a large F.
    def from_above(sum_of):
        values = sum_of(F_GRID)
        change = np.nonzero(np.sign(values[:-1]) != np.sign(values[1:]))[0]
        if len(change) == 0:
            return None
        k = change[0]
        return _illinois(lambda f: sum_of(np.array([f]))[0], F_GRID[k + 1], F_GRID[k], 1e-12)

    def gap(theta):
        lever = xb * np.sin(theta) + yb * np.cos(theta)
        ff = from_above(lambda f: q(f, theta).sum(axis=-1))
        fm = from_above(lambda f: (q(f, theta) * lever).sum(axis=-1))
        return (np.nan, None) if ff is None or fm is None else (ff - fm, fm)

    def crossing(t0, t1):
        g0, g1 = gap(t0)[0], gap(t1)[0]
        if np.isfinite(g0) and np.isfinite(g1) and np.sign(g0) != np.sign(g1) \
                and abs(g0 - g1) < 1.0:  # a crossing, not the jump of a pole
            return _illinois(lambda t: gap(t)[0], t0, t1, 1e-9)
        return None

    if theta_guess is not None:
        guess = math.radians(theta_guess)
        for span in (math.radians(2.0), math.radians(8.0)):
            theta = crossing(guess - span, guess + span)
            if theta is not None:
                return gap(theta)[1], math.degrees(theta)
    # Where several θ balance both, the one nearest 0 (the others put the interslice
    # forces at angles no slide has, with factors of safety far from the slices' own).
    thetas = np.radians(np.linspace(-60.0, 60.0, 49))
    gaps = [gap(t)[0] for t in thetas]
    roots = []
    for (t0, g0), (t1, g1) in zip(zip(thetas, gaps), zip(thetas[1:], gaps[1:])):
        if np.isfinite(g0) and np.isfinite(g1) and np.sign(g0) != np.sign(g1) \
                and abs(g0 - g1) < 1.0:
            theta = _illinois(lambda t: gap(t)[0], t0, t1, 1e-9)
            if theta is not None:
                roots.append(theta)
    if not roots:
        return None
    theta = min(roots, key=abs)
    return gap(theta)[1], math.degrees(theta)


def spencer(sx, sy, gamma, cohesion, tan_phi, xc, yc, radius, slices=400):
    """Spencer's F of one circle (spencer_slices, moments about its centre): (F, θ in
    degrees), None for a circle slices_of rejects or where no θ in ±60° balances both."""
    cut = slices_of(sx, sy, gamma, xc, yc, radius, slices)
    if cut is None:
        return None
    width, weight, alpha, _ = cut
    # The base midpoints relative to the centre.
    xb, yb = -radius * np.sin(alpha), -radius * np.cos(alpha)
    return spencer_slices(width, weight, alpha, cohesion, tan_phi, xb, yb)


def base_interface(case):
    """The strength (c, tan φ) of the model's base y = 0 as the FE model's failure stage
    has it (the strength reduction's): a "friction" base μ without cohesion, a roller
    none; None for a fixed base or a shaken stage's (rock, which a slip surface along it
    shears through the soil above it)."""
    fem = case.get("fem", {})
    base = fem.get("failure", {}).get("boundaries", {}).get("base")
    if "motion" in fem or base not in ("friction", "roller"):
        return None
    return (0.0, fem.get("friction_coefficient", 0.0) if base == "friction" else 0.0)


def polyline_slices(sx, sy, px, py, slices=120):
    """The slices of the slip surface through the vertices (px, py) (x increasing, its ends
    on the ground (sx, sy)), its base clipped at the model's base y = 0: (widths, base
    midpoints (x, y), α, heights, on the model's base?), or None where no slice is under
    the ground."""
    x = np.linspace(px[0], px[-1], slices + 1)
    mid = 0.5 * (x[:-1] + x[1:])
    width = x[1] - x[0]
    raw = np.interp(mid, px, py)
    segment = np.clip(np.searchsorted(px, mid) - 1, 0, len(px) - 2)
    slope = (py[segment + 1] - py[segment]) / (px[segment + 1] - px[segment])
    on_base = raw <= 0.0
    yb = np.where(on_base, 0.0, raw)
    alpha = np.where(on_base, 0.0, np.arctan(-slope))
    h = np.interp(mid, sx, sy) - yb
    inside = h > 0.0
    if inside.sum() < 10:
        return None
    return width, mid[inside], yb[inside], alpha[inside], h[inside], on_base[inside]


def noncircular(case, circles, vertices=9, slices=120):
    """Spencer's F minimised over convex slip surfaces: polylines of `vertices` points,
    their ends on the ground and their inner points at depths below it, moved by compass
    search (compass_search) until the step is 1e-3 of the slope height, from each circle
    of `circles` and, between the first one's ends, its arc deepened 1.5, 2, 3 and 5
    times, down to the model's base at most (surfaces that a weak base interface draws
    to it, which a local search from the circle does not reach). Slices on the base take its interface's strength
    (base_interface). Returns {"fs", "theta", "surface": (px, py)} of the lowest, or
    None when no circle gives a start."""
    material = case["materials"][0]
    gamma = material["density"] * G
    cohesion = material["cohesion"]
    tan_phi = math.tan(math.radians(material["friction_angle"]))
    interface = base_interface(case)
    surface = surface_of(case)
    sx = np.array([p[0] for p in surface])
    sy = np.array([p[1] for p in surface])
    x_max, height = sx.max(), sy.max()
    # The far end is a boundary a surface may not leave through unless the ground meets
    # the base there (a toe at the model's end).
    x_last = x_max if sy[-1] <= 1e-9 else x_max - 0.01 * height
    theta_last = [None]

    def evaluate(params):
        x0, x1, depths = params[0], params[1], params[2:]
        if not (0.01 * height <= x0 < x1 <= x_last) or (depths <= 0.0).any():
            return math.inf, None
        px = np.linspace(x0, x1, vertices)
        py = np.interp(px, sx, sy)
        py[1:-1] -= depths
        slope = np.diff(py) / np.diff(px)
        if (np.diff(slope) < -1e-9).any():  # not convex: no admissible mechanism
            return math.inf, None
        cut = polyline_slices(sx, sy, px, py, slices)
        if cut is None:
            return math.inf, None
        width, xb, yb, alpha, h, on_base = cut
        weight = gamma * h * width
        if np.sum(weight * np.sin(alpha)) <= 0.0:
            return math.inf, None
        c = np.full(len(xb), cohesion)
        t = np.full(len(xb), tan_phi)
        if interface is not None:
            c[on_base], t[on_base] = interface
        result = spencer_slices(width, weight, alpha, c, t, xb - xb.mean(),
                                yb - (yb.max() + height), theta_last[0])
        if result is None:
            return math.inf, None
        theta_last[0] = result[1]
        return result[0], (px, py, result[1])

    def starts(circle, deepened):
        xc, yc, radius = circle
        fine = np.linspace(max(xc - radius, 0.0), min(xc + radius, x_max), 4000)
        ground = np.interp(fine, sx, sy)
        under = yc - np.sqrt(np.maximum(radius**2 - (fine - xc) ** 2, 0.0)) < ground
        if under.sum() < 2:
            return []
        entry, exit_ = fine[under][0], fine[under][-1]
        inner = np.linspace(entry, exit_, vertices)[1:-1]
        top = np.interp(inner, sx, sy)
        arc = top - (yc - np.sqrt(np.maximum(radius**2 - (inner - xc) ** 2, 0.0)))
        # The arc deepened 1.5, 2, 3 and 5 times, down to the base at most.
        return [np.concatenate([[entry, exit_], np.minimum(k * arc, top + 0.01 * height)])
                for k in ((1.0, 1.5, 2.0, 3.0, 5.0) if deepened else (1.0,))]

    best = (math.inf, None)
    for n, circle in enumerate(circles):
        for start in starts(circle, n == 0):
            shapes = {}

            def f_of(params):
                value, shape = evaluate(params)
                shapes[value] = shape
                return value

            value, _ = compass_search(f_of, start, 0.1 * height, 1e-3 * height)
            if value < best[0]:
                best = (value, shapes[value])
    if best[1] is None:
        return None
    px, py, theta = best[1]
    return {"fs": best[0], "theta": theta, "surface": (px, py)}


def compass_search(function, start, step, smallest):
    """The minimum of `function` near `start` by compass search: each parameter up and
    down by `step`, the step halved when no move lowers the value, until it is below
    `smallest`. Returns (value, parameters)."""
    params = np.array(start, dtype=float)
    best = function(params)
    while step > smallest:
        moved = False
        for k in range(len(params)):
            for sign in (1.0, -1.0):
                trial = params.copy()
                trial[k] += sign * step
                value = function(trial)
                if value < best:
                    best, params, moved = value, trial, True
        if not moved:
            step *= 0.5
    return best, params


def slope_stability(case, centres_x=50, centres_y=40, radii=90, slices=400):
    """Bishop's F over circles: a grid of centres from the wall to two slope heights
    beyond the model's end (the centres of toe circles of steep slopes lie beyond the
    toe) and up to six heights, radii up to six heights, then the best circle refined by
    compass search; and the smallest yield acceleration over the grid."""
    material = case["materials"][0]
    gamma = material["density"] * G
    cohesion = material["cohesion"]
    tan_phi = math.tan(math.radians(material["friction_angle"]))
    surface = surface_of(case)
    sx = np.array([p[0] for p in surface])
    sy = np.array([p[1] for p in surface])
    x_max, height = sx.max(), sy.max()
    best = {"fs": math.inf, "ky": math.inf, "circle": None, "ky_circle": None}
    # The best circle of each depth (its deepest point below the ground, in slope
    # heights): starts for the search over non-circular surfaces, which from the deep
    # critical circle alone would miss a shallow slab along the face.
    depths = {}
    for xc in np.linspace(0.0, x_max + 2.0 * height, centres_x):
        for yc in np.linspace(0.5 * height, 6.0 * height, centres_y):
            for radius in np.linspace(0.1 * height, 6.0 * height, radii):
                cut = slices_of(sx, sy, gamma, xc, yc, radius, slices)
                if cut is None:
                    continue
                f, k = bishop_of_slices(cut, cohesion, tan_phi, radius)
                depth = min(int(np.max(cut[1]) / (gamma * cut[0] * height) / 0.1), 5)
                if f < depths.get(depth, (math.inf,))[0]:
                    depths[depth] = (f, (xc, yc, radius))
                if f < best["fs"]:
                    best["fs"], best["circle"] = f, (xc, yc, radius)
                if k is not None and k < best["ky"]:
                    best["ky"], best["ky_circle"] = k, (xc, yc, radius)
    if best["circle"] is not None:
        def bishop_of(p):
            result = circle(sx, sy, gamma, cohesion, tan_phi, p[0], p[1], p[2], slices)
            return math.inf if result is None else result[0]
        fs, refined = compass_search(bishop_of, best["circle"], 0.05 * height, 1e-3 * height)
        best["fs"], best["circle"] = fs, tuple(float(v) for v in refined)
    best["depth_circles"] = [c for _, (f, c) in sorted(depths.items())]
    return best


def particle_stability(path, reservoir=None, x_range=None, centres=30, radii=40, slices=160):
    """Bishop's F over circles through a particle file's body, per-particle strengths."""
    import h5py

    with h5py.File(path, "r") as f:
        q = f["particles"]
        x = q["coordinates"][:]
        mass = q["mass"][:]
        material = q["material_id"][:]
        pore = q["pore_pressure"][:]
        liquefied = q["liquefied"][:] if "liquefied" in q else np.zeros(len(x), int)
        records = q["state/surface_stress"][:] if "state/surface_stress" in q else None
        phi = np.zeros(len(f["materials"]))
        coh = np.zeros(len(f["materials"]))
        for k in range(len(phi)):
            a = f["materials"][str(k)].attrs
            phi[k], coh[k] = a["friction_angle"], a["cohesion"]
    tan_phi = np.tan(np.radians(phi[material]))
    c = coh[material].astype(float)
    if records is not None:
        residual = records[:, 1]
        tan_phi = np.where(liquefied == 1, 0.0, tan_phi)
        c = np.where(liquefied == 1, residual, c)
    # Without a range the particles' extent is the model's: its ends are boundaries (the
    # wall, the far end), not free faces, and a circle may not leave through them.
    closed_ends = x_range is None
    x0, x1 = (x[:, 0].min(), x[:, 0].max()) if x_range is None else x_range
    width_total = x1 - x0
    # The body's top: the highest particle per 1 m column, smoothed over 3 columns.
    edges = np.arange(x0, x1 + 1.0, 1.0)
    column = np.clip(np.digitize(x[:, 0], edges) - 1, 0, len(edges) - 2)
    top = np.full(len(edges) - 1, -np.inf)
    np.maximum.at(top, column, x[:, 1])
    centre_x = 0.5 * (edges[:-1] + edges[1:])
    good = np.isfinite(top)
    surface_x, surface_y = centre_x[good], top[good]
    bottom = x[:, 1].min()
    height = surface_y.max() - bottom
    order = np.argsort(x[:, 0])
    xs = x[order, 0]
    best = {"fs": math.inf, "circle": None}
    gamma_w = 1000.0 * G
    for xc in np.linspace(x0, x1, centres):
        for yc in np.linspace(surface_y.max(), surface_y.max() + 2.0 * height, centres):
            for radius in np.linspace(0.1 * height, 2.5 * height + 0.5 * width_total / 4, radii):
                xa, xb = max(xc - radius, x0), min(xc + radius, x1)
                if xb - xa < 4.0:
                    continue
                b = (xb - xa) / slices
                sx = xa + (np.arange(slices) + 0.5) * b
                base = yc - np.sqrt(np.maximum(radius**2 - (sx - xc) ** 2, 0.0))
                ytop = np.interp(sx, surface_x, surface_y)
                inside = base < ytop
                if inside.sum() < 8 or (base[inside] < bottom + 0.5).any():
                    continue
                if closed_ends and (inside[0] and xa <= x0 + b or inside[-1] and xb >= x1 - b):
                    continue
                alpha = np.arcsin(np.clip((xc - sx) / radius, -1.0, 1.0))
                weight = np.zeros(slices)
                strength_c = np.zeros(slices)
                strength_tan = np.zeros(slices)
                u = np.zeros(slices)
                for i in np.nonzero(inside)[0]:
                    lo, hi = np.searchsorted(xs, sx[i] - 0.5 * b), np.searchsorted(xs, sx[i] + 0.5 * b)
                    members = order[lo:hi]
                    above = members[x[members, 1] > base[i]]
                    # The particles whose centres fall in the slice make its weight.
                    weight[i] = mass[above].sum() * G
                    near = members[np.argmin(np.abs(x[members, 1] - base[i]))] if len(members) else None
                    if near is not None:
                        strength_c[i], strength_tan[i], u[i] = c[near], tan_phi[near], max(pore[near], 0.0)
                    if reservoir is not None and sx[i] >= reservoir[1] and reservoir[0] > base[i]:
                        # Under the reservoir: buoyant weight and the pore pressure in
                        # excess of the reservoir's (the water outside then has no net
                        # effect on the circle).
                        weight[i] -= gamma_w * (min(reservoir[0], ytop[i]) - base[i]) * b
                        u[i] -= gamma_w * (reservoir[0] - base[i])
                driving = np.sum((weight * np.sin(alpha))[inside])
                if driving <= 0.0:
                    continue
                effective = np.maximum(weight - u * b, 0.0)
                weight = np.maximum(weight, 0.0)
                resisting = (strength_c * b + effective * strength_tan)[inside]
                # m_α ≥ 0.2: the usual guard where a steep exit slice would make it vanish.
                f = bishop(resisting, alpha[inside], strength_tan[inside], driving, 0.2)
                if f < best["fs"]:
                    best = {"fs": f, "circle": (xc, yc, radius)}
    return best


def main(argv):
    if len(argv) >= 3 and argv[1] == "--particles":
        path, reservoir, x_range = argv[2], None, None
        rest = argv[3:]
        try:
            while rest:
                if rest[0] == "--reservoir":
                    reservoir, rest = (float(rest[1]), float(rest[2])), rest[3:]
                elif rest[0] == "--x-range":
                    x_range, rest = (float(rest[1]), float(rest[2])), rest[3:]
                else:
                    raise ValueError(f"unknown option {rest[0]}")
            r = particle_stability(path, reservoir, x_range)
        except (OSError, KeyError, ValueError, IndexError) as error:
            print(f"limit_equilibrium.py: {error}", file=sys.stderr)
            return 2
        if r["circle"] is None:
            print("limit_equilibrium.py: no circle passes through the body", file=sys.stderr)
            return 2
        xc, yc, radius = r["circle"]
        print(f"factor of safety {r['fs']:.3f} (Bishop on the particles, circle centre "
              f"({xc:.1f}, {yc:.1f}) m, radius {radius:.1f} m)")
        return 0
    if len(argv) != 2:
        print(__doc__, file=sys.stderr)
        return 2
    with open(argv[1], "rb") as f:
        case = tomllib.load(f)
    r = slope_stability(case)
    xc, yc, radius = r["circle"]
    # Below F = 1 the slope fails under gravity alone: no yield acceleration to state (the
    # smallest k of a failing circle is negative and meaningless as a number).
    ky = (f"pseudo-static yield acceleration k_y = {r['ky']:.3f} g" if r["fs"] >= 1.0 else
          "no yield acceleration: the slope fails under gravity alone")
    material = case["materials"][0]
    surface = surface_of(case)
    sp = spencer(np.array([p[0] for p in surface]), np.array([p[1] for p in surface]),
                 material["density"] * G, material["cohesion"],
                 math.tan(math.radians(material["friction_angle"])), xc, yc, radius)
    spencer_text = ("" if sp is None else
                    f"; Spencer on that circle {sp[0]:.3f} (interslice forces at {sp[1]:.1f}°)")
    print(f"factor of safety {r['fs']:.3f} (Bishop, circle centre ({xc:.1f}, {yc:.1f}) m, "
          f"radius {radius:.1f} m){spencer_text}; {ky}")
    n = noncircular(case, [r["circle"]] + r["depth_circles"])
    if n is not None:
        px, py = n["surface"]
        print(f"non-circular: Spencer {n['fs']:.3f} (interslice forces at {n['theta']:.1f}°) on "
              f"the surface {describe_surface(px, py)}")
    return 0


def describe_surface(px, py):
    """"from (13.6, 13.0) to (30.6, 3.0) m, 9.4 m deep" (and "…, 12.0 m along the base")."""
    x = np.linspace(px[0], px[-1], 400)
    y = np.interp(x, px, py)
    text = (f"from ({px[0]:.1f}, {py[0]:.1f}) to ({px[-1]:.1f}, {py[-1]:.1f}) m, lowest at "
            f"y = {max(y.min(), 0.0):.1f} m")
    along = (x[1] - x[0]) * np.count_nonzero(y <= 0.0)
    return text + (f", {along:.1f} m along the model's base" if along > 0 else "")


if __name__ == "__main__":
    sys.exit(main(sys.argv))
