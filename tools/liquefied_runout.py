#!/usr/bin/python3
"""The report of a liquefaction flow slide (docs/method.md §10): where the transfer found
liquefied soil, how far the MPM phase carried the body, and what the dam lost.

    liquefied_runout.py PARTICLES.h5 MPM_FINAL.h5 -o OUT_DIR [--crest-x X0 X1]

Writes OUT_DIR/runout.md, OUT_DIR/liquefied.png (the particles at the transfer coloured by
r_u,max, the liquefied ones outlined) and OUT_DIR/deformed.png (initial and final
positions), and prints one line of figures: liquefied area, crest drop, displaced area
(the particles that moved more than 1 m), the largest horizontal travel towards +x.
"""
import argparse
import sys

import h5py
import numpy as np


def load(path):
    with h5py.File(path, "r") as f:
        p = f["particles"]
        out = {k: p[k][:] for k in ("coordinates", "displacement", "volume", "material_id")}
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
    import os
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
    figures = {
        "t_T": start["time"],
        "t_end": end["time"],
        "liquefied_area": float(volume[liquefied == 1].sum()),
        "liquefied_particles": int((liquefied == 1).sum()),
        "crest_drop": float(crest_drop),
        "displaced_area": float(volume[moved].sum()),
        "max_travel_x": float(u[:, 0].max()),
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
        fig.colorbar(c, ax=ax, label="r_u,max")
    ax.scatter(x0[liquefied == 1, 0], x0[liquefied == 1, 1], s=4, facecolors="none",
               edgecolors="red", linewidths=0.5, label="liquefied")
    ax.set_aspect("equal")
    ax.set_xlabel("x (m, upstream +)")
    ax.set_ylabel("elevation (m)")
    ax.set_title(f"transfer at t = {start['time']:.1f} s: largest r_u since the motion's start")
    ax.legend(loc="upper left")
    fig.tight_layout()
    fig.savefig(f"{args.out}/liquefied.png", dpi=130)
    fig, ax = plt.subplots(figsize=(12, 3.6))
    ax.scatter(x0[:, 0], x0[:, 1], s=1, c="0.75", label=f"t = {start['time']:.1f} s")
    ax.scatter(x1[:, 0], x1[:, 1], s=1, c=np.where(liquefied == 1, "tab:red", "tab:blue"),
               label=f"t = {end['time']:.1f} s (red: liquefied)")
    ax.set_aspect("equal")
    ax.set_xlabel("x (m, upstream +)")
    ax.set_ylabel("elevation (m)")
    ax.set_title(f"crest drop {crest_drop:.2f} m, displaced area {figures['displaced_area']:.0f} m², "
                 f"largest travel {figures['max_travel_x']:.2f} m")
    ax.legend(loc="upper left", markerscale=6)
    fig.tight_layout()
    fig.savefig(f"{args.out}/deformed.png", dpi=130)
    with open(f"{args.out}/runout.md", "w") as f:
        f.write(f"# Liquefaction and runout: transfer at t = {start['time']:.1f} s\n\n")
        f.write("| quantity | value |\n|---|---|\n")
        f.write(f"| liquefied particles | {figures['liquefied_particles']} "
                f"({figures['liquefied_area']:.1f} m²) |\n")
        f.write(f"| crest drop | {crest_drop:.3f} m |\n")
        f.write(f"| displaced area (moved > {args.moved:g} m) | {figures['displaced_area']:.1f} m² |\n")
        f.write(f"| largest horizontal travel towards +x | {figures['max_travel_x']:.3f} m |\n")
        f.write(f"| largest displacement | {figures['max_displacement']:.3f} m |\n")
        f.write(f"| MPM end | t = {end['time']:.1f} s |\n\n")
        f.write("![r_u,max at the transfer](liquefied.png)\n\n![initial and final](deformed.png)\n")


if __name__ == "__main__":
    main()
