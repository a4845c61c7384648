#!/usr/bin/python3
"""Plots of slide-element's outputs (tools/slide_element.cpp).

    element_plot.py test.csv [more.csv ...] -o test.png
        a simple-shear test: stress path (tau against sigma'_v), stress-strain loops, and
        for cyclic tests r_u and gamma against cycles
    element_plot.py --crr DIR [DIR ...] -o crr.png
        CRR curves (CSR against cycles to 3 % strain) of calibrations, one per folder,
        with the calibration point marked

Uses Debian's python3-matplotlib (/usr/bin/python3).
"""
import argparse
import math
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

import slide  # noqa: E402  (tools/slide: the readers of what the programs write)


def read_csv(path):
    table = slide.read_table(path)
    if not table or not len(next(iter(table.values()))):
        sys.exit(f"element_plot.py: {path}: no rows")
    return table


def read_summary(path):
    return slide.read_summary(path)


def save(fig, out):
    tmp = os.path.join(os.path.dirname(os.path.abspath(out)), "." + os.path.basename(out) + ".tmp.png")
    fig.savefig(tmp, dpi=120)
    os.replace(tmp, out)


def plot_tests(paths, out):
    tests = [(p, read_csv(p)) for p in paths]
    cyclic = any(max(t["cycles"]) > 0 for _, t in tests)
    fig, axes = plt.subplots(2, 2 if cyclic else 1, figsize=(11 if cyclic else 6, 8), squeeze=False)
    for path, t in tests:
        label = os.path.basename(path)
        kpa = 1e-3
        axes[0][0].plot([v * kpa for v in t["vertical_stress_Pa"]], [v * kpa for v in t["shear_stress_Pa"]],
                        lw=0.8, label=label)
        axes[1][0].plot([100 * g for g in t["shear_strain"]], [v * kpa for v in t["shear_stress_Pa"]],
                        lw=0.8, label=label)
        if cyclic:
            axes[0][1].plot(t["cycles"], t["pore_pressure_ratio"], lw=0.8, label=label)
            axes[1][1].plot(t["cycles"], [100 * g for g in t["shear_strain"]], lw=0.8, label=label)
    axes[0][0].set(xlabel="σ′v (kPa)", ylabel="τ (kPa)", title="stress path")
    axes[1][0].set(xlabel="γ (%)", ylabel="τ (kPa)", title="stress–strain")
    if cyclic:
        axes[0][1].set(xlabel="cycles", ylabel="r_u = 1 − σ′v/σ′v0", title="excess pore pressure")
        axes[1][1].set(xlabel="cycles", ylabel="γ (%)", title="shear strain")
    for row in axes:
        for ax in row:
            ax.grid(alpha=0.3)
    axes[0][0].legend(fontsize=8)
    fig.tight_layout()
    save(fig, out)


def plot_crr(folders, out):
    fig, ax = plt.subplots(figsize=(7, 5))
    for folder in folders:
        curve = read_csv(os.path.join(folder, "crr_curve.csv"))
        summary = read_summary(os.path.join(folder, "calibration.txt"))
        points = [(n, s) for n, s in zip(curve["cycles_to_3pct"], curve["csr"]) if not math.isnan(n)]
        label = f"D_R = {summary['relative_density']:g}, h_po = {summary['contraction_rate']:.3g}"
        line, = ax.plot([p[0] for p in points], [p[1] for p in points], "o-", ms=3, label=label)
        ax.plot([summary["target_cycles"]], [summary["target_crr"]], "*", ms=12, color=line.get_color())
    ax.set(xscale="log", xlabel="uniform cycles to 3 % single-amplitude shear strain",
           ylabel="CSR = τ/σ′v0", title="cyclic resistance (σ′v0 = 1 atm, K0 = 0.5); ★ target")
    ax.grid(alpha=0.3, which="both")
    ax.legend(fontsize=8)
    fig.tight_layout()
    save(fig, out)


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("inputs", nargs="+", help="CSV files, or calibration folders with --crr")
    parser.add_argument("--crr", action="store_true", help="the inputs are calibration folders")
    parser.add_argument("-o", "--out", required=True, help="the PNG file to write")
    args = parser.parse_args()
    for path in args.inputs:
        if not os.path.exists(path):
            sys.exit(f"element_plot.py: {path}: no such file or folder")
    (plot_crr if args.crr else plot_tests)(args.inputs, args.out)


if __name__ == "__main__":
    main()
