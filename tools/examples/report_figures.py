#!/usr/bin/python3
"""Two of the report's figures, rebuilt from the checkpoints with the slide module: the
final surface profiles of a case's runs (report: profiles.png) and the particles of one
run at its end coloured by σyy (report: snapshots_sigma_yy.png, its last panel).

    PYTHONPATH=tools /usr/bin/python3 tools/examples/report_figures.py cases/column-short/out OUT_DIR

It reads OUT/<run>/mpm_final.h5 of every finished MPM run; the profile is the 99th percentile of the particles' heights in 2 m bins, as
the report's (docs/method.md §6, without the foundation level of a slope case). A
starting point for your own figures: every array of a checkpoint is a numpy array.
"""
import pathlib
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

import slide  # noqa: E402

BIN_WIDTH = 2.0  # m
PERCENTILE = 99.0  # %


def profile(coordinates):
    """(bin centres, heights): the PERCENTILE of the heights of the particles in each bin."""
    x, y = coordinates[:, 0], coordinates[:, 1]
    bins = np.floor(x / BIN_WIDTH).astype(int)
    centres, heights = [], []
    for b in np.unique(bins):
        centres.append((b + 0.5) * BIN_WIDTH)
        heights.append(np.percentile(y[bins == b], PERCENTILE))
    return np.array(centres), np.array(heights)


def main(out, figures):
    runs = sorted(p.parent for p in out.glob("*/mpm_final.h5"))
    if not runs:
        sys.exit(f"report_figures.py: no */mpm_final.h5 in {out}")
    figures.mkdir(parents=True, exist_ok=True)

    fig, ax = plt.subplots(figsize=(9, 3.5))
    for run in runs:
        state = slide.read_checkpoint(run / "mpm_final.h5")
        x, h = profile(state.particles["coordinates"])
        ax.plot(x, h, label=f"{run.name} (t = {state.time:g} s)")
    ax.set_xlabel("x (m)")
    ax.set_ylabel("surface height (m)")
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(figures / "profiles.png", dpi=110)
    plt.close(fig)

    state = slide.read_checkpoint(runs[0] / "mpm_final.h5")
    xy = state.particles["coordinates"]
    sigma_yy = state.particles["stress"][:, 1] / 1e3  # columns xx, yy, zz, xy; kPa
    fig, ax = plt.subplots(figsize=(9, 3.5))
    points = ax.scatter(xy[:, 0], xy[:, 1], c=sigma_yy, s=1, cmap="viridis")
    fig.colorbar(points, ax=ax, label="σyy (kPa)")
    ax.set_aspect("equal")
    ax.set_title(f"{runs[0].name} at t = {state.time:g} s")
    fig.tight_layout()
    fig.savefig(figures / "sigma_yy.png", dpi=110)
    plt.close(fig)
    print(f"report_figures.py: {figures / 'profiles.png'}, {figures / 'sigma_yy.png'}")


if __name__ == "__main__":
    if len(sys.argv) != 3:
        sys.exit(__doc__)
    main(pathlib.Path(sys.argv[1]), pathlib.Path(sys.argv[2]))
