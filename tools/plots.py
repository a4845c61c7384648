#!/usr/bin/python3
"""Figures of a case's runs (PNG, in OUT/report/).

    /usr/bin/python3 tools/plots.py cases/column-short/case.toml cases/column-short/out

Uses Debian's python3-matplotlib, python3-numpy and python3-h5py only. Reads what the
pipeline wrote: fem/fem_history.csv, tt*/mpm_history.csv, sweep.csv, profiles.csv and
the particle checkpoints (datasets as documented in common/checkpoint-schema.md).
Every figure is optional: one whose inputs are missing is skipped. The last file
written is OUT/report/figures.txt, the names of the PNGs made (one a line): the Make
pipeline's target for this step.
"""
import csv
import math
import pathlib
import sys
import tomllib

import h5py
import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

G = 9.81
ZONE_JACOBIAN_AVG = 0.97  # METHOD.md §3: recommended transfer zone
ZONE_EPS_Q_AVG = 0.20


def read_csv(path):
    with open(path, newline="") as f:
        rows = list(csv.DictReader(f))
    return rows


def column(rows, name):
    return np.array([float(r[name]) if r[name] not in ("", "nan") else np.nan for r in rows])


def run_label(run):
    return run if not run.startswith("tt") else f"t_T = {run[2:]} s"


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


def plot_profiles(case, out, figures):
    path = out / "profiles.csv"
    if not path.exists():
        return
    rows = read_csv(path)
    runs = list(dict.fromkeys(r["run"] for r in rows))
    fig, ax = plt.subplots(figsize=(10, 4))
    surface = case.get("mesh", {}).get("surface")
    if surface:  # the body's initial outline: its surface polyline, down to the base
        xs = [p[0] for p in surface] + [surface[-1][0]]
        ys = [p[1] for p in surface] + [0.0]
    else:
        length, height = case["metrics"]["initial_length"], case["metrics"]["initial_height"]
        xs, ys = [0, length, length], [height, height, 0]
    ax.plot(xs, ys, "k:", lw=1, label="initial body")
    cmap = plt.get_cmap("viridis", max(len(runs), 2))
    for i, run in enumerate(runs):
        sel = [r for r in rows if r["run"] == run]
        x = [float(r["x_centre"]) for r in sel]
        y = [float(r["height"]) for r in sel]
        style = {"pure-mpm": "r--", "pure-fem": "b-."}.get(run)
        if style:
            ax.plot(x, y, style, lw=1.5, label=run)
        else:
            ax.plot(x, y, color=cmap(i), lw=1.2, label=run_label(run))
    ax.set_xlabel("x (m)")
    ax.set_ylabel("surface height (m), 99th percentile per 2 m bin")
    ax.set_title(f"{case['case']['name']}: final surface profiles")
    ax.set_ylim(bottom=0)
    ax.set_aspect("equal", adjustable="datalim")
    ax.legend(fontsize=7, ncol=2)
    save(fig, figures / "profiles.png")


def plot_histories(case, out, figures):
    tau_c = math.sqrt(case["metrics"]["initial_height"] / G)
    runs = transfer_runs(out) + [out / "pure-mpm"]
    histories = [(d.name, d / "mpm_history.csv") for d in runs if (d / "mpm_history.csv").exists()]
    if not histories:
        return
    fig, (ax1, ax2) = plt.subplots(1, 2, figsize=(11, 4))
    cmap = plt.get_cmap("viridis", max(len(histories), 2))
    for i, (name, path) in enumerate(histories):
        rows = read_csv(path)
        t = column(rows, "time") / tau_c
        color = "r" if name == "pure-mpm" else cmap(i)
        ax1.plot(t, column(rows, "runout_normalised"), color=color, lw=1, label=run_label(name))
        ax2.plot(t, column(rows, "ke_over_pe0"), color=color, lw=1, label=run_label(name))
    fem = out / "fem" / "fem_history.csv"
    if fem.exists():
        rows = read_csv(fem)
        ax2.plot(column(rows, "time") / tau_c, column(rows, "ke_over_pe0"), "k--", lw=1,
                 label="FE phase")
    ax1.set_xlabel("t / τc")
    ax1.set_ylabel("R_N = (x_toe − L0)/L0")
    ax2.set_xlabel("t / τc")
    ax2.set_ylabel("KE / PE0")
    ax1.legend(fontsize=7)
    ax2.legend(fontsize=7)
    fig.suptitle(f"{case['case']['name']}: runout and kinetic energy (τc = {tau_c:.2f} s)")
    save(fig, figures / "runout_and_energy.png")


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
    fig, (ax1, ax2) = plt.subplots(1, 2, figsize=(11, 4))
    for ax in (ax1, ax2):
        ax.fill_between(t, 0, 1, where=inside, transform=ax.get_xaxis_transform(),
                        color="tab:green", alpha=0.15, label="recommended transfer zone")
    ax1.plot(t, column(rows, "jacobian_ratio_min"), "k-", label="(|J_t|/|J_0|)_min")
    ax1.plot(t, column(rows, "jacobian_ratio_avg"), "b--", label="(|J_t|/|J_0|)_avg, εq > 3 %")
    ax1.axhline(ZONE_JACOBIAN_AVG, color="b", lw=0.5, ls=":")
    ax1.axhline(0.0, color="r", lw=0.5)
    ax1.set_xlabel("t (s)")
    ax1.set_ylabel("|J_t| / |J_0|")
    ax1.legend(fontsize=7)
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


def particle_snapshot(ax, path, field, label, cmap, vmin=None, vmax=None):
    with h5py.File(path, "r") as f:
        x = f["particles/coordinates"][:]
        if field == "sigma_yy":
            values = f["particles/stress"][:, 1] / 1e3
        else:
            values = 100 * f["particles/eps_q"][:]
        time = f.attrs["time"]
    sc = ax.scatter(x[:, 0], x[:, 1], c=values, s=0.3, cmap=cmap, vmin=vmin, vmax=vmax,
                    rasterized=True)
    ax.set_aspect("equal")
    ax.set_title(f"t = {time:.2f} s", fontsize=8)
    return sc


def plot_snapshots(case, out, figures):
    main = out / f"tt{case['transfer'].get('main_time', 0):g}"
    run = main if main.exists() else out / "pure-mpm"
    files = sorted(run.glob("mpm_t*.h5"), key=lambda p: float(p.stem[5:]))
    if (run / "particles.h5").exists():
        files.insert(0, run / "particles.h5")
    if not files:
        return
    pick = [files[i] for i in sorted({0, len(files) // 3, 2 * len(files) // 3, len(files) - 1})]
    height = case["metrics"]["initial_height"]
    rho = case["materials"][0]["density"]
    for field, label, cmap, limits in (
        ("sigma_yy", "σyy (kPa)", "viridis", (-rho * G * height / 1e3, 0)),
        ("eps_q", "εq (%)", "magma_r", (0, 100)),
    ):
        fig, axes = plt.subplots(len(pick), 1, figsize=(10, 2.2 * len(pick)), sharex=True)
        for ax, path in zip(np.atleast_1d(axes), pick):
            sc = particle_snapshot(ax, path, field, label, cmap, *limits)
        fig.colorbar(sc, ax=axes, label=label, shrink=0.8)
        fig.suptitle(f"{case['case']['name']}, {run.name}: particles coloured by {label}")
        save(fig, figures / f"snapshots_{field}.png")


def plot_geostatic_transfer_error(case, out, figures):
    path = out / "tt0" / "particles.h5"
    if not path.exists():
        return
    with h5py.File(path, "r") as f:
        x = f["particles/coordinates"][:]
        syy = f["particles/stress"][:, 1]
        material = f["particles/material_id"][:]
        rho = np.array([f[f"materials/{m}"].attrs["density"] for m in material])
    height = case["metrics"]["initial_height"]
    exact = -rho * G * (height - x[:, 1])
    error = 100 * (syy - exact) / (rho * G * height)
    fig, ax = plt.subplots(figsize=(5, 5))
    limit = max(np.abs(error).max(), 1e-6)
    sc = ax.scatter(x[:, 0], x[:, 1], c=error, s=8, cmap="coolwarm", vmin=-limit, vmax=limit)
    fig.colorbar(sc, label="(σyy − (−ρg(H−y))) / ρgH (%)")
    ax.set_aspect("equal")
    ax.set_title(f"σyy transfer error at t = 0\nmax |e| = {np.abs(error).max():.3g} % of ρgH",
                 fontsize=10)
    save(fig, figures / "geostatic_transfer_error.png")


def main():
    if len(sys.argv) != 3:
        sys.exit("usage: plots.py CASE.toml OUT_DIR")
    with open(sys.argv[1], "rb") as f:
        case = tomllib.load(f)
    out = pathlib.Path(sys.argv[2])
    figures = out / "report"
    figures.mkdir(parents=True, exist_ok=True)
    for plot in (plot_profiles, plot_histories, plot_fem_quality, plot_rmse_vs_quality,
                 plot_snapshots, plot_geostatic_transfer_error):
        plot(case, out, figures)
    listing = figures / "figures.txt"
    tmp = listing.with_suffix(".txt.tmp")
    tmp.write_text("".join(f"{name}\n" for name in SAVED))
    tmp.replace(listing)


if __name__ == "__main__":
    main()
