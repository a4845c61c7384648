#!/usr/bin/python3
"""Figures of a case's runs (PNG, in OUT/report/).

    /usr/bin/python3 tools/plots.py cases/column-short/case.toml cases/column-short/out

Uses Debian's python3-matplotlib, python3-numpy and python3-h5py only. Reads what the
pipeline wrote: fem/fem_history.csv, tt*/mpm_history.csv, the recorders' CSVs, sweep.csv,
profiles.csv, the particle checkpoints and, for the σyy figure of the main transfer, its
FE checkpoint's Gauss points and tt<main>/after-0.5s/ (datasets as documented in
common/io/checkpoint-schema.md).
Every figure is optional: one whose inputs are missing is skipped. The last file
written is OUT/report/figures.txt, the names of the PNGs made (one a line): the Make
pipeline's target for this step.
"""
import math
import pathlib
import sys
import tomllib

import h5py
import matplotlib

matplotlib.use("Agg")
import matplotlib.colors  # noqa: E402
import matplotlib.pyplot as plt  # noqa: E402
import matplotlib.transforms  # noqa: E402
import matplotlib.tri  # noqa: E402
import numpy as np  # noqa: E402

import slide  # noqa: E402  (tools/slide: the readers of what the programs write)

G = 9.81
ZONE_JACOBIAN_AVG = 0.97  # docs/method.md §3: recommended transfer zone
ZONE_EPS_Q_AVG = 0.20


def read_csv(path):
    return slide.read_rows(path)


def column(rows, name):
    return np.array([float(r[name]) if r[name] not in ("", "nan") else np.nan for r in rows])


def run_label(run):
    return run if not run.startswith("tt") else f"t_T = {run[2:]} s"


# Curves of runs that end up on top of each other (tt0 and pure MPM, early transfers)
# stay apart: the reference tt0 is a wide pale band drawn underneath, every other run a
# thin line with its own dash pattern and sparse markers staggered along the curve.
TRANSFER_DASHES = ["--", "-.", ":", (0, (6, 2)), (0, (3, 1, 1, 1, 1, 1)), (0, (1, 1))]
TRANSFER_MARKERS = ["o", "s", "^", "v", "D", "P", "X", "*"]
# Dark, distinct colours for the transfers (red and blue are the pure runs').
TRANSFER_COLOURS = ["tab:purple", "tab:green", "tab:orange", "tab:brown", "tab:olive",
                    "tab:cyan", "tab:pink", "tab:gray", "black"]
PURE_STYLES = {
    "pure-mpm": dict(color="tab:red", ls="--", marker="x"),
    "pure-fem": dict(color="tab:blue", ls="-.", marker="+"),
}


def run_styles(runs, points):
    """Plot keyword arguments per run name, for curves of about `points` samples."""
    transfers = [r for r in runs if r.startswith("tt")]
    colours = [TRANSFER_COLOURS[k % len(TRANSFER_COLOURS)] for k in range(len(transfers))]
    step = max(points // 10, 1)
    styles = {}
    for i, run in enumerate(runs):
        if run == "tt0":
            styles[run] = dict(color=colours[transfers.index(run)], ls="-", lw=5, alpha=0.35, zorder=2,
                               solid_capstyle="butt")
            continue
        if run in PURE_STYLES:
            style = dict(PURE_STYLES[run], lw=1.3, zorder=4)
        else:
            k = transfers.index(run)
            style = dict(color=colours[k], ls=TRANSFER_DASHES[k % len(TRANSFER_DASHES)],
                         marker=TRANSFER_MARKERS[k % len(TRANSFER_MARKERS)], lw=1.3, zorder=3)
        style.update(markersize=4, markevery=((i * step) // max(len(runs), 1) % step, step),
                     markerfacecolor="none")
        styles[run] = style
    return styles


def transfer_runs(out):
    runs = []
    for d in out.glob("tt*"):
        try:
            runs.append((float(d.name[2:]), d))
        except ValueError:
            continue
    return [d for _, d in sorted(runs)]


SAVED = []


def save(fig, path):
    fig.savefig(path, dpi=110, bbox_inches="tight")
    plt.close(fig)
    SAVED.append(path.name)
    print(f"plots: {path}")


def initial_outline(case, out):
    """The top of the initial body where the case gives no surface polyline (a blocks
    mesh): in every 1 m wide strip the highest FE node of the t = 0 checkpoint, then
    down to the base at the last one."""
    path = out / "fem" / "fem_t0.000.h5"
    if not path.exists():
        return [], []
    with h5py.File(path, "r") as f:
        nodes = f["nodes/reference_coordinates"][:]
    strip = np.floor(nodes[:, 0] / 1.0 + 1e-9)
    xs, ys = [], []
    for s in np.unique(strip):
        top = nodes[strip == s]
        x, y = top[np.argmax(top[:, 1])]
        xs.append(x)
        ys.append(y)
    return xs + [xs[-1]], ys + [0.0]


def plot_profiles(case, out, figures):
    path = out / "profiles.csv"
    if not path.exists():
        return
    rows = read_csv(path)
    runs = list(dict.fromkeys(r["run"] for r in rows))
    fig, ax = plt.subplots(figsize=(10, 4.5))
    surface = case.get("mesh", {}).get("surface")
    if surface:  # the body's initial outline: its surface polyline, down to the base
        xs = [p[0] for p in surface] + [surface[-1][0]]
        ys = [p[1] for p in surface] + [0.0]
    else:
        xs, ys = initial_outline(case, out)
    if xs:
        ax.plot(xs, ys, color="0.4", ls=":", lw=1, label="initial body", zorder=1)
    points = max(sum(1 for r in rows if r["run"] == run) for run in runs)
    styles = run_styles(runs, points)
    for run in runs:
        sel = [r for r in rows if r["run"] == run]
        x = [float(r["x_centre"]) for r in sel]
        y = [float(r["height"]) for r in sel]
        ax.plot(x, y, label=run_label(run), **styles[run])
    ax.set_xlabel("x (m)")
    ax.set_ylabel("surface height y (m)")
    ax.set_title(f"{case['case']['name']}: final surface profiles "
                 f"(99th percentile per {case['metrics'].get('bin_width', 2.0):g} m bin)")
    ax.set_xlim(left=0)
    ax.set_ylim(bottom=0)
    ax.set_aspect("equal", adjustable="box")
    ax.grid(True, lw=0.3, alpha=0.5)
    # Below the x label (32 points under the axes): inside, on a flat runout, it hides
    # a curve wherever it goes.
    below = matplotlib.transforms.offset_copy(ax.transAxes, fig=fig, y=-32, units="points")
    ax.legend(fontsize=7, ncol=min(len(runs) + 1, 6), loc="upper center", bbox_to_anchor=(0.5, 0),
              bbox_transform=below, frameon=False)
    save(fig, figures / "profiles.png")


def plot_histories(case, out, figures):
    tau_c = math.sqrt(case["metrics"]["initial_height"] / G)
    runs = transfer_runs(out) + [out / "pure-mpm"]
    histories = [(d.name, d / "mpm_history.csv") for d in runs if (d / "mpm_history.csv").exists()]
    if not histories:
        return
    fig, (ax1, ax2) = plt.subplots(1, 2, figsize=(11, 4))
    samples = {name: read_csv(path) for name, path in histories}
    styles = run_styles(list(samples), max(len(rows) for rows in samples.values()))
    for name, rows in samples.items():
        t = column(rows, "time") / tau_c
        ax1.plot(t, column(rows, "runout_normalised"), label=run_label(name), **styles[name])
        ax2.plot(t, column(rows, "ke_over_pe0"), label=run_label(name), **styles[name])
    fem = out / "fem" / "fem_history.csv"
    if fem.exists():
        rows = read_csv(fem)
        ax2.plot(column(rows, "time") / tau_c, column(rows, "ke_over_pe0"), color="k",
                 ls=(0, (2, 1)), lw=1, label="FE phase", zorder=5)
    ax1.set_xlabel("t / τc")
    ax1.set_ylabel("R_N = (x_toe − L0)/L0")
    ax2.set_xlabel("t / τc")
    ax2.set_ylabel("KE / PE0")
    for ax in (ax1, ax2):
        ax.grid(True, lw=0.3, alpha=0.5)
        ax.legend(fontsize=7)
    fig.suptitle(f"{case['case']['name']}: runout and kinetic energy (τc = {tau_c:.2f} s)")
    save(fig, figures / "runout_and_energy.png")


def point_motion(path):
    """The first point of a recorder's CSV: (time, |u|, |v|), for an FE node (n<k>_ux …,
    absolute) or an MPM particle (p<k>_ux …); None for an element recorder."""
    recorder = slide.read_recorder(path)
    for owner, values in recorder.items():
        if owner[:1] in ("n", "p") and owner[1:].isdigit() and "ux" in values:
            return (recorder["time"], np.hypot(values["ux"], values["uy"]),
                    np.hypot(values["vx"], values["vy"]))
    return None


def plot_recorders(case, out, figures):
    """Per [[mpm.recorders]] table: the displacement and speed of its first point through
    the FE phase (the node nearest it, when [[fem.recorders]] has a table of that name)
    and every MPM run (the particle that started nearest it)."""
    runs = transfer_runs(out) + [out / "pure-mpm"]
    for spec in case.get("mpm", {}).get("recorders", []):
        name = spec["name"]
        curves = [(d.name, point_motion(d / "recorders" / f"{name}.csv")) for d in runs
                  if (d / "recorders" / f"{name}.csv").exists()]
        curves = [(run, c) for run, c in curves if c is not None]
        if not curves:
            continue
        fig, (ax1, ax2) = plt.subplots(1, 2, figsize=(11, 4))
        styles = run_styles([run for run, _ in curves], max(len(c[0]) for _, c in curves))
        for run, (t, u, v) in curves:
            ax1.plot(t, u, label=run_label(run), **styles[run])
            ax2.plot(t, v, label=run_label(run), **styles[run])
        fem = out / "fem" / "recorders" / f"{name}.csv"
        motion = point_motion(fem) if fem.exists() else None
        if motion is not None:
            for ax, values in ((ax1, motion[1]), (ax2, motion[2])):
                ax.plot(motion[0], values, color="k", ls=(0, (2, 1)), lw=1, label="FE phase",
                        zorder=5)
        x, y = spec["points"][0]
        ax1.set_ylabel("|u| since t = 0 (m)")
        ax2.set_ylabel("speed (m/s)")
        for ax in (ax1, ax2):
            ax.set_xlabel("t (s)")
            ax.grid(True, lw=0.3, alpha=0.5)
            ax.legend(fontsize=7)
        fig.suptitle(f"{case['case']['name']}: recorder \"{name}\", the material that started "
                     f"nearest ({x:g}, {y:g}) m")
        save(fig, figures / f"recorder_{name}.png")


def zone_mask(rows):
    j_avg = column(rows, "jacobian_ratio_avg")
    e_avg = column(rows, "eps_q_avg")
    # No element above 3 % deviatoric strain yet: nothing has distorted, inside the zone.
    inside = np.where(np.isnan(j_avg), True, j_avg >= ZONE_JACOBIAN_AVG)
    return inside & np.where(np.isnan(e_avg), True, e_avg <= ZONE_EPS_Q_AVG)


def plot_fem_quality(case, out, figures):
    path = out / "fem" / "fem_history.csv"
    if not path.exists():
        return
    rows = read_csv(path)
    t = column(rows, "time")
    inside = zone_mask(rows)
    # Area and shape (area_ratio, scaled_jacobian_*): a middle panel, when the history has
    # them (fem-solve wrote histories without them before).
    shape = all(name in rows[0] for name in ("area_ratio", "scaled_jacobian_min",
                                             "scaled_jacobian_avg")) if rows else False
    fig, axes = plt.subplots(1, 3 if shape else 2, figsize=(16 if shape else 11, 4))
    fig.subplots_adjust(wspace=0.28)
    ax1, ax2 = axes[0], axes[-1]
    for ax in axes:
        ax.fill_between(t, 0, 1, where=inside, transform=ax.get_xaxis_transform(),
                        color="tab:green", alpha=0.15, label="recommended transfer zone")
    ax1.plot(t, column(rows, "jacobian_ratio_min"), "k-", label="(|J_t|/|J_0|)_min")
    ax1.plot(t, column(rows, "jacobian_ratio_avg"), "b--", label="(|J_t|/|J_0|)_avg, εq > 3 %")
    ax1.axhline(ZONE_JACOBIAN_AVG, color="b", lw=0.5, ls=":")
    ax1.axhline(0.0, color="r", lw=0.5)
    ax1.set_xlabel("t (s)")
    ax1.set_ylabel("|J_t| / |J_0|")
    ax1.legend(fontsize=7)
    if shape:
        ax = axes[1]
        ax.plot(t, column(rows, "area_ratio"), color="tab:purple", ls="-",
                label="area ratio ΣV_t / ΣV_0")
        ax.plot(t, column(rows, "scaled_jacobian_min"), "k-",
                label="scaled Jacobian, min over all elements")
        ax.plot(t, column(rows, "scaled_jacobian_avg"), "b--",
                label="scaled Jacobian, avg over εq > 3 %")
        ax.axhline(0.0, color="r", lw=0.5)
        ax.set_xlabel("t (s)")
        ax.set_ylabel("area ratio, scaled Jacobian")
        ax.set_title("scaled Jacobian: 1 square, 0 flat corner, < 0 inverted", fontsize=8)
        ax.legend(fontsize=7)
    ax2.plot(t, 100 * column(rows, "eps_q_avg"), "b--", label="εq,avg (εq > 3 %)")
    ax2.plot(t, 100 * column(rows, "eps_q_max"), "k-", label="εq,max")
    ax2.axhline(100 * ZONE_EPS_Q_AVG, color="b", lw=0.5, ls=":")
    ax2.set_yscale("symlog", linthresh=10)
    ax2.set_ylim(bottom=0)
    ax2.set_xlabel("t (s)")
    ax2.set_ylabel("deviatoric strain εq (%)")
    ax2.legend(fontsize=7)
    fig.suptitle(f"{case['case']['name']}: FE mesh quality")
    save(fig, figures / "fem_mesh_quality.png")


def plot_rmse_vs_quality(case, out, figures):
    path = out / "sweep.csv"
    if not path.exists():
        return
    rows = [r for r in read_csv(path) if r["run"].startswith("tt") and r["rmse"] != ""]
    for r in rows:
        # No element has εq > 3 % yet (t_T = 0): the undistorted mesh, (1, 0 %).
        if r["jacobian_ratio_avg"] == "":
            r["jacobian_ratio_avg"], r["eps_q_avg"] = "1", "0"
    rows.sort(key=lambda r: float(r["tt"]))
    if len(rows) < 2:
        return
    fig, (ax1, ax2) = plt.subplots(1, 2, figsize=(10, 4))
    j = column(rows, "jacobian_ratio_avg")
    e = 100 * column(rows, "eps_q_avg")
    rmse = column(rows, "rmse")
    for ax, x, label, limit in ((ax1, j, "(|J_t|/|J_0|)_avg at transfer", ZONE_JACOBIAN_AVG),
                                (ax2, e, "εq,avg at transfer (%)", 100 * ZONE_EPS_Q_AVG)):
        ax.plot(x, rmse, "o-")
        for xi, yi, r in zip(x, rmse, rows):
            ax.annotate(f"{float(r['tt']):g} s", (xi, yi), fontsize=7, xytext=(3, 3),
                        textcoords="offset points")
        ax.axvline(limit, color="g", ls=":", label="zone limit")
        ax.set_xlabel(label)
        ax.set_ylabel("profile RMSE vs t_T = 0")
        ax.legend(fontsize=7)
    fig.suptitle(f"{case['case']['name']}: runout profile error against FE mesh quality")
    save(fig, figures / "rmse_vs_mesh_quality.png")


def read_snapshot(path):
    """Coordinates, {field: values} and time of a particle checkpoint; the field "spacing"
    is each particle's own (m: the square root of its area)."""
    with h5py.File(path, "r") as f:
        x = f["particles/coordinates"][:]
        fields = {"sigma_yy": f["particles/stress"][:, 1] / 1e3,
                  "eps_q": 100 * f["particles/eps_q"][:],
                  "displacement": np.linalg.norm(f["particles/displacement"][:], axis=1),
                  "spacing": np.sqrt(f["particles/volume"][:])}
        return x, fields, float(f.attrs["time"])


def nice_ceil(value):
    """`value` rounded up to a multiple of a fifth of its order of magnitude (157 → 160,
    4.08 → 4.2)."""
    step = 0.2 * 10 ** math.floor(math.log10(value))
    return math.ceil(value / step - 1e-9) * step


def plot_snapshots(case, out, figures):
    main = out / f"tt{case['transfer'].get('main_time', 0):g}"
    run = main if main.exists() else out / "pure-mpm"
    files = [(float(p.stem[5:]), p) for p in run.glob("mpm_t*.h5")]
    if (run / "particles.h5").exists():
        files.append((float(run.name[2:]) - 1e-9, run / "particles.h5"))  # first of its time
    files.sort(key=lambda item: item[0])
    # One file per time: the transfer's particles.h5 and mpm_t<t_T>.h5 hold the same state.
    files = [p for i, (t, p) in enumerate(files) if i == 0 or t - files[i - 1][0] > 1e-6]
    if not files:
        return
    pick = [files[i] for i in sorted({0, len(files) // 3, 2 * len(files) // 3, len(files) - 1})]
    height = case["metrics"]["initial_height"]
    rho = case["materials"][0]["density"]
    spacing = case["mpm"]["cell_size"] / case["mpm"].get("particles_per_cell", [4, 4])[0]
    states = [read_snapshot(path) for path in pick]
    # εq on a log scale from 0.1 %: a linear scale that stops at 100 % saturates the whole
    # slid mass and hides the shear band, whose strain is orders above the body's.
    eps_top = max(100.0, nice_ceil(max(fields["eps_q"].max() for _, fields, _ in states)))
    u_top = nice_ceil(max(max(fields["displacement"].max() for _, fields, _ in states), 1e-3))
    for field, label, cmap, norm in (
        ("sigma_yy", "σyy (kPa)", "viridis",
         matplotlib.colors.Normalize(-rho * G * height / 1e3, 0)),
        ("eps_q", "εq (%), log scale", "magma_r", matplotlib.colors.LogNorm(0.1, eps_top)),
        ("displacement", "|u| since t = 0 (m)", "viridis", matplotlib.colors.Normalize(0, u_top)),
    ):
        snapshots = [(x, np.maximum(fields[field], 0.1) if field == "eps_q" else fields[field],
                      time) for x, fields, time in states]
        # One x and y range for every panel, from the wall to the farthest particle, so
        # that the panels line up and show the spreading at the same scale.
        x_max = nice_ceil(1.02 * max(x[:, 0].max() for x, _, _ in snapshots))
        y_max = nice_ceil(1.02 * max(x[:, 1].max() for x, _, _ in snapshots))
        ratio = y_max / x_max
        # Panels stacked for a wide body (a runout), side by side for a tall one.
        stacked = ratio < 0.5
        width = 7.6 if stacked else 8.4 / len(pick)  # inches of one panel
        rows, cols = (len(pick), 1) if stacked else (1, len(pick))
        fig, axes = plt.subplots(rows, cols, squeeze=False, sharex=True, sharey=True,
                                 figsize=(10 if stacked else 10.5,
                                          (width * ratio + 0.45) * rows + 0.8))
        axes = axes.ravel()
        # Discs about 1.5 particle spacings wide: they overlap, so the body looks solid
        # (squares one spacing wide leave pixel gaps once rasterised).
        marker_points = 1.5 * spacing * width * 72 / x_max
        for ax, (x, values, time) in zip(axes, snapshots):
            sc = ax.scatter(x[:, 0], x[:, 1], c=values, s=max(marker_points ** 2, 0.2),
                            marker="o", linewidths=0, cmap=cmap, norm=norm, rasterized=True)
            ax.set_xlim(0, x_max)
            ax.set_ylim(0, y_max)
            ax.set_aspect("equal")
            ax.set_title(f"t = {time:.2f} s", fontsize=8)
        for ax in axes[-cols:]:
            ax.set_xlabel("x (m)")
        for ax in axes[::cols]:
            ax.set_ylabel("y (m)")
        fig.colorbar(sc, ax=list(axes), label=label, shrink=0.8)
        fig.suptitle(f"{case['case']['name']}, {run.name}: particles coloured by {label}")
        save(fig, figures / f"snapshots_{field}.png")


def densities(f, material):
    """ρ of every particle, from the /materials attributes (one read per material)."""
    ids = np.unique(material)
    rho = {m: f[f"materials/{m}"].attrs["density"] for m in ids}
    return np.array([rho[m] for m in ids])[np.searchsorted(ids, material)]


def plot_geostatic_transfer_error(case, out, figures):
    # Only a body with a flat top has the closed form σyy = −ρg(H − y) (both columns and
    # the geostatic column; not the slopes).
    surface = case["mesh"].get("surface")
    if not surface or len({p[1] for p in surface}) != 1:
        return
    path = out / "tt0" / "particles.h5"
    if not path.exists():
        return
    with h5py.File(path, "r") as f:
        x = f["particles/coordinates"][:]
        syy = f["particles/stress"][:, 1]
        rho = densities(f, f["particles/material_id"][:])
    height = surface[0][1]
    exact = -rho * G * (height - x[:, 1])
    error = 100 * (syy - exact) / (rho * G * height)
    fig, ax = plt.subplots(figsize=(5, 5))
    limit = max(np.abs(error).max(), 1e-6)
    # Discs about 1.5 particle spacings wide on the ~3.8 in wide axes.
    extent = max(np.ptp(x[:, 0]), np.ptp(x[:, 1]), 1e-9)
    spacing = case["mpm"]["cell_size"] / case["mpm"].get("particles_per_cell", [4, 4])[0]
    if case["transfer"].get("particles_per_element"):
        spacing = case["mesh"].get("element_size", spacing) / case["transfer"][
            "particles_per_element"][0]
    size = max((1.5 * spacing * 3.8 * 72 / extent) ** 2, 0.5)
    sc = ax.scatter(x[:, 0], x[:, 1], c=error, s=size, linewidths=0, cmap="coolwarm",
                    vmin=-limit, vmax=limit, rasterized=True)
    fig.colorbar(sc, label="(σyy − (−ρg(H−y))) / ρgH (%)")
    ax.set_aspect("equal")
    ax.set_xlabel("x (m)")
    ax.set_ylabel("y (m)")
    ax.set_title(f"σyy transfer error at t = 0\nmax |e| = {np.abs(error).max():.3g} % of ρgH",
                 fontsize=10)
    save(fig, figures / "geostatic_transfer_error.png")


def read_gauss_points(path):
    """Current coordinates, σyy (kPa), time and each point's spacing (m: the square root of
    the area it stands for, its element's over the element's Gauss points; the points are
    stored element by element) of an FE checkpoint."""
    with h5py.File(path, "r") as f:
        x = f["gauss_points/coordinates"][:]
        volume = f["elements/volume"][:]
        per_element = max(len(x) // max(len(volume), 1), 1)
        spacing = np.sqrt(np.repeat(volume / per_element, per_element))
        return x, f["gauss_points/stress"][:, 1] / 1e3, float(f.attrs["time"]), spacing


def main_transfer_states(case, out):
    """The σyy states of the main transfer (transfer.main_time), as (what, time, x, σyy in
    kPa, each point's spacing in m): the FE Gauss points at t_T, the particles made from them, the
    particles 0.5 s later and at the end. Missing files are left out."""
    tt = case["transfer"].get("main_time", 0)
    run = out / f"tt{tt:g}"
    fem = out / "fem" / f"fem_t{tt:.3f}.h5"
    states = []
    if fem.exists():
        x, syy, time, spacing = read_gauss_points(fem)
        states.append(("FE Gauss points at the transfer", time, x, syy, spacing))
    # 0.5 s after t_T: the short run the pipeline makes for this figure
    # (tt<T>/after-0.5s/, cases/pipeline.mk), else the main run's checkpoint nearest to it.
    after = run / "after-0.5s" / "mpm_final.h5"
    if not after.exists():
        checkpoints = [(abs(float(p.stem[5:]) - tt - 0.5), p) for p in run.glob("mpm_t*.h5")
                       if float(p.stem[5:]) > tt + 1e-6]
        after = min(checkpoints)[1] if checkpoints else None
    for what, path in (("particles at the transfer", run / "particles.h5"),
                       ("MPM", after), ("MPM, end of the run", run / "mpm_final.h5")):
        if path is None or not path.exists():
            continue
        x, fields, time = read_snapshot(path)
        if what == "MPM":
            what = f"MPM, t_T + {time - tt:.2f} s"
        states.append((what, time, x, fields["sigma_yy"], fields["spacing"]))
    return states


def plot_stress_at_transfer(case, out, figures):
    """σyy of the main transfer: the FE state at t_T beside the particles made from it,
    0.5 s later and at the end, on one colour scale (docs/method.md §6, stress quality at
    rest)."""
    states = main_transfer_states(case, out)
    if len(states) < 2:
        return
    tt = case["transfer"].get("main_time", 0)
    height = case["metrics"]["initial_height"]
    rho = max(m["density"] for m in case["materials"])
    # One scale for every panel: from the weight of the initial column, −ρ g H0 at its
    # base, to a little tension; values beyond it take the end colours (extend="both").
    vmin, vmax = -nice_ceil(rho * G * height / 1e3), nice_ceil(0.05 * rho * G * height / 1e3)
    x_max = nice_ceil(1.02 * max(s[2][:, 0].max() for s in states))
    y_max = nice_ceil(1.05 * max(s[2][:, 1].max() for s in states))
    ratio = y_max / x_max
    # Wide (a runout): one panel a row; tall: side by side.
    stacked = ratio < 0.5
    width = 8.6 if stacked else 9.0 / len(states)  # inches of one panel
    rows, cols = (len(states), 1) if stacked else (1, len(states))
    fig, axes = plt.subplots(rows, cols, squeeze=False, sharex=True, sharey=True,
                             layout="constrained",
                             figsize=(10.5 if stacked else 11,
                                      (width * ratio + 0.5) * rows + (0.7 if stacked else 1.2)))
    axes = axes.ravel()
    # The stress quality of the end state's deposit (sweep.csv), on its panel.
    rows_by_run = {r["run"]: r for r in read_csv(out / "sweep.csv")} \
        if (out / "sweep.csv").exists() else {}
    quality = rows_by_run.get(f"tt{tt:g}", {})
    quality = [f"{name} {float(quality[key]):#.3g}" for name, key in (
        ("p50", "stress_quality_p50"), ("p90", "stress_quality_p90"),
        ("p99", "stress_quality_p99"), ("max", "stress_quality_max"))
               ] if quality.get("stress_quality_p50") else []
    for ax, (what, time, x, syy, spacing) in zip(axes, states):
        # The points' values, interpolated linearly over a Delaunay triangulation of them
        # with the triangles longer than 2.5 of their corners' largest spacing left out
        # (across the gaps and concave parts of the outline; per point, so that a mesh of
        # square elements over flat ones keeps both): a solid body at any scale, where
        # markers of a pixel or two leave pale lines between the rows once rasterised.
        # Every point's own value shows at its position, so the particle-to-particle
        # noise stays visible.
        mesh = matplotlib.tri.Triangulation(x[:, 0], x[:, 1])
        corners = x[mesh.triangles]
        longest = np.max(np.linalg.norm(corners - np.roll(corners, 1, axis=1), axis=2), axis=1)
        mesh.set_mask(longest > 2.5 * spacing[mesh.triangles].max(axis=1))
        sc = ax.tripcolor(mesh, syy, shading="gouraud", cmap="viridis", vmin=vmin, vmax=vmax,
                          rasterized=True)
        ax.set_xlim(0, x_max)
        ax.set_ylim(0, y_max)
        ax.set_aspect("equal")
        title = f"{what}, t = {time:.2f} s" if stacked else f"{what}\nt = {time:.2f} s"
        ax.set_title(title, fontsize=9 if stacked else 8, loc="left")
        ax.grid(True, lw=0.3, alpha=0.4)
    last = axes[len(states) - 1]
    if quality and states[-1][0].startswith("MPM, end"):
        what = "e = |σyy − σyy,lith| / ρgH0 at rest"
        if stacked:  # in the empty top right corner of a runout
            last.text(0.99, 0.95, f"{what}: " + ", ".join(quality), transform=last.transAxes,
                      ha="right", va="top", fontsize=8,
                      bbox=dict(boxstyle="round", fc="white", ec="0.7", alpha=0.9))
        else:  # under the narrow panel
            last.set_xlabel(f"x (m)\n{what}:\n" + ", ".join(quality[:2]) + ",\n"
                            + ", ".join(quality[2:]), fontsize=8)
    for ax in axes[-cols:]:
        if not ax.get_xlabel():
            ax.set_xlabel("x (m)")
    for ax in axes[::cols]:
        ax.set_ylabel("y (m)")
    fig.colorbar(sc, ax=list(axes), extend="both", shrink=0.9, pad=0.01,
                 label="σyy (kPa), compression negative")
    fig.suptitle(f"{case['case']['name']}: σyy of the main transfer (t_T = {tt:g} s), "
                 "FE Gauss points and material points")
    save(fig, figures / "stress_at_transfer.png")


def main():
    if len(sys.argv) != 3:
        sys.exit("usage: plots.py CASE.toml OUT_DIR")
    with open(sys.argv[1], "rb") as f:
        case = tomllib.load(f)
    out = pathlib.Path(sys.argv[2])
    figures = out / "report"
    figures.mkdir(parents=True, exist_ok=True)
    for plot in (plot_profiles, plot_histories, plot_recorders, plot_fem_quality,
                 plot_rmse_vs_quality, plot_snapshots, plot_geostatic_transfer_error,
                 plot_stress_at_transfer):
        plot(case, out, figures)
    listing = figures / "figures.txt"
    tmp = listing.with_suffix(".txt.tmp")
    tmp.write_text("".join(f"{name}\n" for name in SAVED))
    tmp.replace(listing)


if __name__ == "__main__":
    main()
