#!/usr/bin/python3
"""The report of a liquefaction flow slide (docs/method.md §10): where the transfer found
liquefied soil, how far the MPM phase carried the body, and what the dam lost.

    liquefied_runout.py PARTICLES.h5 MPM_FINAL.h5 -o OUT_DIR [--crest-x X0 X1]

Writes OUT_DIR/runout.md, OUT_DIR/liquefied.png (the particles at the transfer coloured by
r_u,max, the liquefied ones outlined) and OUT_DIR/deformed.png (initial and final
positions), and prints one line of figures: liquefied area, crest drop, displaced area
(the particles that moved more than 1 m), the horizontal travel towards +x of the
displaced body (its mass-weighted mean and 95th percentile, as the extreme of one particle
is a film's, not the slide's), the largest displacement of the side beyond the crest
(towards −x: whether it held), and the largest displacement of any particle.
Files are written under a temporary name and renamed.
"""
import argparse
import os
import sys

import h5py
import numpy as np


def load(path):
    with h5py.File(path, "r") as f:
        p = f["particles"]
        out = {k: p[k][:] for k in ("coordinates", "displacement", "volume", "material_id",
                                    "mass")}
        for k in ("max_pore_pressure_ratio", "liquefied"):
            out[k] = p[k][:] if k in p else None
        out["time"] = float(f.attrs["time"])
    return out


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("particles")
    parser.add_argument("final")
    parser.add_argument("-o", "--out", required=True)
    parser.add_argument("--crest-x", nargs=2, type=float, default=None,
                        help="x range of the crest (default: the highest 2 %% of the particles)")
    parser.add_argument("--moved", type=float, default=1.0, help="displaced: moved more than this, m")
    args = parser.parse_args()
    try:
        start, end = load(args.particles), load(args.final)
    except (OSError, KeyError) as error:
        sys.exit(f"liquefied_runout.py: {error}")
    os.makedirs(args.out, exist_ok=True)
    x0 = start["coordinates"]
    # The final file's rows are sorted by cell: match them by the stable id order of the start.
    with h5py.File(args.final, "r") as f:
        ids = f["particles/id"][:]
    order = np.argsort(ids)
    x1 = end["coordinates"][order]
    u = x1 - x0
    volume = start["volume"]
    liquefied = start["liquefied"] if start["liquefied"] is not None else np.zeros(len(x0), int)
    ru = start["max_pore_pressure_ratio"]
    if args.crest_x:
        crest = (x0[:, 0] >= args.crest_x[0]) & (x0[:, 0] <= args.crest_x[1])
        crest &= x0[:, 1] >= np.percentile(x0[crest, 1], 90)
    else:
        crest = x0[:, 1] >= np.percentile(x0[:, 1], 98)
    crest_drop = -(x1[crest, 1].max() - x0[crest, 1].max())
    moved = np.linalg.norm(u, axis=1) > args.moved
    mass = start["mass"]
    travel = u[moved, 0]
    beyond = x0[:, 0] < (args.crest_x[0] if args.crest_x else np.median(x0[crest, 0]))
    figures = {
        "t_T": start["time"],
        "t_end": end["time"],
        "liquefied_area": float(volume[liquefied == 1].sum()),
        "liquefied_particles": int((liquefied == 1).sum()),
        "crest_drop": float(crest_drop),
        "displaced_area": float(volume[moved].sum()),
        "mean_travel_x": float(np.average(travel, weights=mass[moved])) if moved.any() else 0.0,
        "p95_travel_x": float(np.percentile(travel, 95)) if moved.any() else 0.0,
        "max_travel_x": float(u[:, 0].max()),
        "far_side_displacement": float(np.linalg.norm(u[beyond], axis=1).max()) if beyond.any() else 0.0,
        "max_displacement": float(np.linalg.norm(u, axis=1).max()),
    }
    line = " ".join(f"{k}={v:.4g}" if isinstance(v, float) else f"{k}={v}" for k, v in figures.items())
    print(line)
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, ax = plt.subplots(figsize=(12, 3.6))
    c = ax.scatter(x0[:, 0], x0[:, 1], c=np.clip(ru, 0, 1.2) if ru is not None else "0.6", s=2,
                   cmap="viridis")
    if ru is not None:
        fig.colorbar(c, ax=ax, label="r_u,max", shrink=0.6)
    ax.scatter(x0[liquefied == 1, 0], x0[liquefied == 1, 1], s=4, facecolors="none",
               edgecolors="red", linewidths=0.5, label="liquefied")
    ax.set_aspect("equal")
    ax.set_xlabel("x (m, upstream +)")
    ax.set_ylabel("elevation (m)")
    ax.set_title(f"transfer at t = {start['time']:.1f} s: largest r_u since the motion's start")
    ax.legend(loc="upper left")
    fig.tight_layout()
    save(fig, f"{args.out}/liquefied.png")
    fig, ax = plt.subplots(figsize=(12, 4.2))
    ax.scatter(x0[:, 0], x0[:, 1], s=1, c="0.8", label=f"t = {start['time']:.1f} s")
    c = ax.scatter(x1[:, 0], x1[:, 1], s=1, c=np.linalg.norm(u, axis=1), cmap="plasma",
                   label=f"t = {end['time']:.1f} s")
    fig.colorbar(c, ax=ax, label="|u| (m)", shrink=0.6)
    ax.scatter(x1[liquefied == 1, 0], x1[liquefied == 1, 1], s=3, facecolors="none",
               edgecolors="tab:green", linewidths=0.3, label="liquefied")
    if moved.any():  # the displaced body and 40 m around it
        lo, hi = min(x0[moved, 0].min(), x1[moved, 0].min()), max(x0[moved, 0].max(), x1[moved, 0].max())
        ax.set_xlim(lo - 40.0, hi + 40.0)
    ax.set_aspect("equal")
    ax.set_xlabel("x (m, upstream +)")
    ax.set_ylabel("elevation (m)")
    ax.set_title(f"crest drop {crest_drop:.2f} m, displaced area {figures['displaced_area']:.0f} m², "
                 f"travel of the displaced body {figures['mean_travel_x']:.1f} m (mean), "
                 f"{figures['p95_travel_x']:.1f} m (95 %)")
    ax.legend(loc="upper left", markerscale=6)
    fig.tight_layout()
    save(fig, f"{args.out}/deformed.png")
    with open(f"{args.out}/runout.md.tmp", "w") as f:
        f.write(f"# Liquefaction and runout: transfer at t = {start['time']:.1f} s\n\n")
        f.write("| quantity | value |\n|---|---|\n")
        f.write(f"| liquefied particles | {figures['liquefied_particles']} "
                f"({figures['liquefied_area']:.1f} m²) |\n")
        f.write(f"| crest drop | {crest_drop:.3f} m |\n")
        f.write(f"| displaced area (moved > {args.moved:g} m) | {figures['displaced_area']:.1f} m² |\n")
        f.write(f"| travel towards +x of the displaced body: mass-weighted mean, 95th percentile "
                f"| {figures['mean_travel_x']:.2f} m, {figures['p95_travel_x']:.2f} m |\n")
        f.write(f"| largest travel towards +x (one particle) | {figures['max_travel_x']:.3f} m |\n")
        f.write(f"| largest displacement of the side beyond the crest (towards −x) "
                f"| {figures['far_side_displacement']:.3f} m |\n")
        f.write(f"| largest displacement | {figures['max_displacement']:.3f} m |\n")
        f.write(f"| MPM end | t = {end['time']:.1f} s |\n\n")
        f.write("![r_u,max at the transfer](liquefied.png)\n\n![initial and final](deformed.png)\n")
    os.replace(f"{args.out}/runout.md.tmp", f"{args.out}/runout.md")


def save(fig, path):
    """Saves a figure under a temporary name, then renames it: a killed run leaves the
    previous picture intact."""
    fig.savefig(path + ".tmp.png", dpi=130)
    os.replace(path + ".tmp.png", path)


if __name__ == "__main__":
    main()
