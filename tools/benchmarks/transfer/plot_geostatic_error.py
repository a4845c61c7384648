#!/usr/bin/python3
"""Draws the geostatic-4x4 transfer error field (Debian's python3-matplotlib).

    bench_transfer geostatic err.csv && plot_geostatic_error.py err.csv transfer/geostatic-error.png

Each particle of the 4 m column (16 x 16 elements of 4 x 4 Gauss-Legendre particles) is a
square coloured by its signed sigma_yy error over rho g H, blue negative, red positive,
saturating at +-2 %. The dashed square is one element (0.25 m) inside the boundary: the
issue's "interior" particles; the title gives the largest error inside it and everywhere.
"""
import csv
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

SCALE = 0.02    # error over rho g H at full colour
SIDE = 4.0      # m, column width and height
ELEMENT = 0.25  # m


def main():
    rows = list(csv.DictReader(open(sys.argv[1])))
    x = [float(r["x"]) for r in rows]
    y = [float(r["y"]) for r in rows]
    e = [float(r["error_over_rho_g_h"]) for r in rows]
    inside = [abs(v) for xi, yi, v in zip(x, y, e)
              if ELEMENT < xi < SIDE - ELEMENT and ELEMENT < yi < SIDE - ELEMENT]
    worst, worst_inside = max(abs(v) for v in e), max(inside)

    fig, ax = plt.subplots(figsize=(6.4, 5.4))
    cloud = ax.scatter(x, y, c=[100 * v for v in e], cmap="RdBu_r", vmin=-100 * SCALE,
                       vmax=100 * SCALE, marker="s", s=14, linewidths=0)
    ax.add_patch(plt.Rectangle((ELEMENT, ELEMENT), SIDE - 2 * ELEMENT, SIDE - 2 * ELEMENT,
                               fill=False, linestyle="--", linewidth=0.8, color="0.3"))
    ax.set_xlim(0, SIDE)
    ax.set_ylim(0, SIDE)
    ax.set_aspect("equal")
    ax.set_xlabel("x (m)")
    ax.set_ylabel("y (m)")
    ax.set_title("geostatic-4x4, plain multiquadric: σyy error / ρgH\n"
                 f"max {100 * worst_inside:.2f} % inside the dashed line, "
                 f"{100 * worst:.2f} % everywhere", fontsize=10)
    bar = fig.colorbar(cloud, ax=ax)
    bar.set_label("(σyy − σyy,exact) / ρgH  (%)")
    fig.tight_layout()
    fig.savefig(sys.argv[2], dpi=110)
    print(f"wrote {sys.argv[2]}: max |error| {worst:.4f} of rho g H "
          f"({worst_inside:.4f} one element inside), colour scale ±{SCALE}")


if __name__ == "__main__":
    main()
