#!/usr/bin/python3
"""The liquefaction summary of a level or sloping deposit (docs/method.md §10).

    liquefaction_report.py CASE.toml FEM_OUT REPORT_DIR [--elements water] [--surface surface]
                           [--threshold 0.95]

Reads fem-solve's element recorder (its r_u and γxy columns, one element per depth, the
positions as the case file lists them) and node recorder at the surface, and writes
REPORT_DIR/liquefaction.md with its plots: r_u against time at every depth, the profiles
of the largest r_u and of γxy, the time each depth first reached the threshold, and the
surface's settlement and lateral displacement. Uses Debian's python3-matplotlib.
"""
import argparse
import math
import os
import sys
import tomllib

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

import slide  # noqa: E402  (tools/slide: the readers of what the programs write)


def fail(message):
    sys.exit(f"liquefaction_report.py: {message}")


def read_rows(path):
    if not os.path.exists(path):
        fail(f"{path}: no such file (did fem-solve run with the recorders of the case?)")
    rows = slide.read_rows(path)
    if not rows:
        fail(f"{path}: no rows")
    return rows


def recorder(case, name):
    for r in case.get("fem", {}).get("recorders", []):
        if r.get("name") == name:
            return r
    fail(f"the case has no recorder named {name!r}")


def save(fig, path):
    tmp = os.path.join(os.path.dirname(path), "." + os.path.basename(path) + ".tmp.png")
    fig.savefig(tmp, dpi=110)
    os.replace(tmp, path)
    plt.close(fig)


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("case")
    parser.add_argument("fem_out")
    parser.add_argument("report_dir")
    parser.add_argument("--elements", default="water", help="the element recorder (one element per depth)")
    parser.add_argument("--surface", default="surface", help="the node recorder at the surface")
    parser.add_argument("--threshold", type=float, default=0.95, help="r_u that counts as liquefied")
    args = parser.parse_args()
    with open(args.case, "rb") as f:
        case = tomllib.load(f)
    top = max(y for _, y in case["mesh"]["surface"]) if "surface" in case.get("mesh", {}) else None
    points = recorder(case, args.elements).get("elements", [])
    rows = read_rows(os.path.join(args.fem_out, "recorders", args.elements + ".csv"))
    ru_keys = [k for k in rows[0] if k.endswith("_ru")]
    g_keys = [k for k in rows[0] if k.endswith("_gxy")]
    if len(ru_keys) != len(points):
        fail(f"{args.elements}.csv has {len(ru_keys)} elements, the case lists {len(points)}")
    times = [float(r["time"]) for r in rows]
    shaking = case["fem"].get("motion", {})
    start = float(shaking.get("start_time", 0.0))
    duration = float(shaking.get("horizontal", {}).get("duration", 0.0))
    depths = [(top - y) if top is not None else -y for _, y in points]

    # Per depth: the largest r_u, when it first reached the threshold, the final r_u and
    # the shear strain at the end of the shaking and at the end.
    table = []
    end_of_shaking = min(range(len(times)), key=lambda i: abs(times[i] - (start + duration)))
    for depth, ru, g in zip(depths, ru_keys, g_keys):
        values = [float(r[ru]) for r in rows]
        first = next((t for t, v in zip(times, values) if v >= args.threshold), math.nan)
        g0 = float(rows[0][g])
        table.append({"depth": depth, "ru_max": max(values), "first": first, "ru_end": values[-1],
                      "gamma_shaking": float(rows[end_of_shaking][g]) - g0,
                      "gamma_end": float(rows[-1][g]) - g0})

    surface = read_rows(os.path.join(args.fem_out, "recorders", args.surface + ".csv"))
    ux_key = next(k for k in surface[0] if k.endswith("_ux_rel"))
    uy_key = next(k for k in surface[0] if k.endswith("_uy_rel"))
    s_times = [float(r["time"]) for r in surface]
    ux = [float(r[ux_key]) for r in surface]
    uy = [float(r[uy_key]) for r in surface]
    at_start = min(range(len(s_times)), key=lambda i: abs(s_times[i] - start))
    at_end_of_shaking = min(range(len(s_times)), key=lambda i: abs(s_times[i] - (start + duration)))
    settlement = [-(v - uy[at_start]) for v in uy]
    lateral = [v - ux[at_start] for v in ux]

    os.makedirs(args.report_dir, exist_ok=True)
    fig, ax = plt.subplots(figsize=(9, 5))
    for depth, ru in zip(depths, ru_keys):
        ax.plot(times, [float(r[ru]) for r in rows], lw=0.8, label=f"{depth:.2f} m")
    ax.axhline(args.threshold, color="k", lw=0.6, ls="--")
    ax.axvspan(start, start + duration, color="0.9", zorder=0)
    ax.set(xlabel="t (s)", ylabel="r_u", title="excess pore pressure ratio by depth (shaking shaded)")
    ax.legend(fontsize=7, ncol=2)
    ax.grid(alpha=0.3)
    save(fig, os.path.join(args.report_dir, "liquefaction_ru.png"))

    fig, axes = plt.subplots(1, 3, figsize=(12, 5))
    axes[0].plot([t["ru_max"] for t in table], depths, "o-")
    axes[0].axvline(args.threshold, color="k", lw=0.6, ls="--")
    axes[0].set(xlabel="largest r_u", ylabel="depth (m)", title="largest r_u")
    axes[1].plot([100 * t["gamma_shaking"] for t in table], depths, "o-", label="end of shaking")
    axes[1].plot([100 * t["gamma_end"] for t in table], depths, "s--", label="end")
    axes[1].set(xlabel="γxy (%)", title="shear strain since t = 0")
    axes[1].legend(fontsize=8)
    axes[2].plot(s_times, [1000 * v for v in settlement], label="settlement")
    axes[2].plot(s_times, [1000 * v for v in lateral], label="lateral")
    axes[2].set(xlabel="t (s)", ylabel="mm", title="surface displacement since the shaking began")
    axes[2].legend(fontsize=8)
    for ax in axes[:2]:
        ax.invert_yaxis()
    for ax in axes:
        ax.grid(alpha=0.3)
    fig.tight_layout()
    save(fig, os.path.join(args.report_dir, "liquefaction_profiles.png"))

    liquefied = [t for t in table if t["ru_max"] >= args.threshold]
    lines = [
        f"# Liquefaction: {case['case']['name']}",
        "",
        f"Shaking from t = {start:g} s for {duration:g} s. r_u ≥ {args.threshold:g} counts as liquefied.",
        "",
        "| depth (m) | largest r_u | first r_u ≥ threshold (s after the shaking began) | r_u at the end | γxy end of shaking (%) | γxy at the end (%) |",
        "|---|---|---|---|---|---|",
    ]
    for t in table:
        first = "never" if math.isnan(t["first"]) else f"{t['first'] - start:.2f}"
        lines.append(f"| {t['depth']:.2f} | {t['ru_max']:.3f} | {first} | {t['ru_end']:.3f} | "
                     f"{100 * t['gamma_shaking']:.3f} | {100 * t['gamma_end']:.3f} |")
    depth_range = (f"{min(t['depth'] for t in liquefied):.2f} to {max(t['depth'] for t in liquefied):.2f} m"
                   if liquefied else "none")
    lines += [
        "",
        f"- depths that reached r_u ≥ {args.threshold:g}: {depth_range} ({len(liquefied)} of {len(table)} recorded)",
        f"- surface settlement since the shaking began: {1000 * settlement[-1]:.1f} mm at t = {s_times[-1]:g} s "
        f"({1000 * settlement[at_end_of_shaking]:.1f} mm at the end of the shaking)",
        f"- surface lateral displacement: {1000 * lateral[-1]:.1f} mm at the end, largest {1000 * max(map(abs, lateral)):.1f} mm",
        "",
        "![r_u by depth](liquefaction_ru.png)",
        "",
        "![profiles and surface displacement](liquefaction_profiles.png)",
        "",
    ]
    path = os.path.join(args.report_dir, "liquefaction.md")
    with open(path + ".tmp", "w") as f:
        f.write("\n".join(lines))
    os.replace(path + ".tmp", path)
    print(f"liquefaction_report: wrote {path}")


if __name__ == "__main__":
    main()
