#!/usr/bin/python3
"""The pore-water report of a saturated FE run (docs/method.md §10), from what fem-solve
writes.

    pore_water.py CASE.toml FEM_OUT REPORT_DIR [--snapshots t1,t2,...]
        REPORT_DIR/report.md with its figures: the history of the largest r_u and of the
        area with r_u >= 0.7, the recorders' p, Δp and r_u, and snapshots of Δp and r_u
        over the mesh at the checkpoint times asked (default: before the shaking, at its
        middle, at its end and at the end of the run)

Δp_e = p_e − the element's mean of the nodal p_static, r_u = Δp_e/σ′v0 (0 where
σ′v0 < 1 kPa), as fem-solve computes them (fem/pore_fluid.hpp). Uses Debian's
python3-numpy, python3-matplotlib and python3-h5py only.
"""
import pathlib
import sys
import tomllib

import h5py
import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

import slide  # noqa: E402  (tools/slide: the readers of what the programs write)
from matplotlib.collections import PolyCollection  # noqa: E402

MIN_RATIO_STRESS = 1e3  # Pa, fem/pore_fluid.hpp
HIGH_RATIO = 0.7


def read_table(path):
    """A CSV with a header line, as a dict of numpy columns (tools/slide)."""
    return slide.read_table(path)


def write_figure(figure, path):
    """Saves through a temporary file, so a killed run leaves no half figure."""
    temporary = path.with_name(path.name + ".tmp.png")
    figure.savefig(temporary, dpi=110)
    plt.close(figure)
    temporary.replace(path)


def element_fields(path):
    """Coordinates (current), connectivity, Δp_e and r_u per element of a checkpoint."""
    with h5py.File(path, "r") as f:
        if "pore_pressure" not in f["elements"]:
            raise SystemExit(f"{path}: no /elements/pore_pressure: not a saturated run")
        x = f["nodes/coordinates"][...]
        cells = f["elements/connectivity"][...]
        p = f["elements/pore_pressure"][...]
        static = f["nodes/static_pore_pressure"][...]
        stress0 = f["gauss_points/initial_vertical_effective_stress"][...]
        gauss_element = f["gauss_points/element"][...]
        time = float(f.attrs["time"])
    excess = p - static[cells].mean(axis=1)
    # r_u per Gauss point (0 where σ′v0 < 1 kPa), then the element's mean, as fem-solve.
    point_excess = excess[gauss_element]
    point_ratio = np.where(stress0 >= MIN_RATIO_STRESS,
                           point_excess / np.maximum(stress0, MIN_RATIO_STRESS), 0.0)
    per_element = np.bincount(gauss_element, minlength=len(cells))
    ratio = np.bincount(gauss_element, weights=point_ratio, minlength=len(cells)) / per_element
    # A dry element's p is 0 (fem/pore_fluid.hpp); a saturated one's is not, below the table.
    saturated = p != 0.0
    return time, x, cells, excess, ratio, saturated


def snapshot_figure(snapshots, path):
    """Δp and r_u over the mesh, one row per checkpoint."""
    figure, axes = plt.subplots(len(snapshots), 2, figsize=(13, 2.6 * len(snapshots)),
                                squeeze=False)
    wet = [s for s in snapshots if s[5].any()]
    excess_limit = max((np.abs(s[3][s[5]]).max() for s in wet), default=0.0) or 1.0
    ratio_limit = max([1.0] + [s[4][s[5]].max() for s in wet])
    for row, (time, x, cells, excess, ratio, saturated) in enumerate(snapshots):
        polygons = x[cells]
        for column, (values, label, limits, colours) in enumerate(
                [(excess / 1e3, "Δp (kPa)", (-excess_limit / 1e3, excess_limit / 1e3), "RdBu_r"),
                 (ratio, "r_u", (0.0, ratio_limit), "viridis")]):
            ax = axes[row][column]
            shown = np.where(saturated, values, np.nan)
            collection = PolyCollection(polygons, array=shown, cmap=colours, edgecolor="none")
            collection.set_clim(*limits)
            ax.add_collection(collection)
            ax.autoscale_view()
            ax.set_aspect("equal")
            ax.set_title(f"t = {time:g} s: {label} (dry elements blank)", fontsize=9)
            figure.colorbar(collection, ax=ax, shrink=0.8)
    figure.tight_layout()
    write_figure(figure, path)


def history_figure(history, shaking, path):
    figure, axes = plt.subplots(2, 1, figsize=(8, 5), sharex=True)
    t = history["time"]
    axes[0].plot(t, history["pore_pressure_ratio_max"])
    axes[0].axhline(HIGH_RATIO, color="grey", linestyle=":", label=f"r_u = {HIGH_RATIO}")
    axes[0].set_ylabel("largest r_u")
    axes[0].legend(loc="upper left")
    axes[1].plot(t, history["high_pore_pressure_area"])
    axes[1].set_ylabel(f"area with r_u ≥ {HIGH_RATIO} (m²)")
    axes[1].set_xlabel("t (s)")
    for ax in axes:
        if shaking:
            ax.axvspan(*shaking, color="orange", alpha=0.15, label="shaking")
        ax.grid(alpha=0.3)
    figure.tight_layout()
    write_figure(figure, path)


def place(label, checkpoint):
    """'n610 (55, 5)': a recorder's node or element with its reference position."""
    with h5py.File(checkpoint, "r") as f:
        x = f["nodes/reference_coordinates"][...]
        cells = f["elements/connectivity"][...]
    index = int(label[1:])
    point = x[index] if label[0] == "n" else x[cells[index]].mean(axis=0)
    return f"{label} ({point[0]:.3g}, {point[1]:.3g}) m"


def recorder_figure(tables, shaking, path, checkpoint):
    """Δp at the recorders' nodes, r_u at their elements (every recorder file)."""
    figure, axes = plt.subplots(2, 1, figsize=(8, 5), sharex=True)
    for table in tables:
        for name in table:
            if name.endswith("_dp"):
                axes[0].plot(table["time"], table[name] / 1e3, label=place(name[:-3], checkpoint))
            elif name.endswith("_ru"):
                axes[1].plot(table["time"], table[name], label=place(name[:-3], checkpoint))
    axes[0].set_ylabel("Δp (kPa)")
    axes[1].set_ylabel("r_u")
    axes[1].set_xlabel("t (s)")
    for ax in axes:
        if shaking:
            ax.axvspan(*shaking, color="orange", alpha=0.15)
        ax.legend(loc="upper left", fontsize=8)
        ax.grid(alpha=0.3)
    figure.tight_layout()
    write_figure(figure, path)


def main(argv):
    if len(argv) not in (4, 6) or (len(argv) == 6 and argv[4] != "--snapshots"):
        raise SystemExit(__doc__)
    case_path, fem_out, report = (pathlib.Path(a) for a in argv[1:4])
    with open(case_path, "rb") as f:
        case = tomllib.load(f)
    motion = case.get("fem", {}).get("motion", {})
    horizontal = motion.get("horizontal", {})
    shaking = None
    if "start_time" in motion and "duration" in horizontal:
        shaking = (motion["start_time"], motion["start_time"] + horizontal["duration"])
    end = case["fem"]["end_time"]
    if len(argv) == 6:
        times = [float(t) for t in argv[5].split(",")]
    elif shaking:
        times = [shaking[0], 0.5 * (shaking[0] + shaking[1]), shaking[1], end]
    else:
        times = [0.0, end]
    report.mkdir(parents=True, exist_ok=True)
    history = read_table(fem_out / "fem_history.csv")
    if "pore_pressure_ratio_max" not in history:
        raise SystemExit(f"{fem_out}/fem_history.csv: no pore_pressure_ratio_max: not a saturated run")
    snapshots = []
    for t in times:
        path = fem_out / f"fem_t{t:.3f}.h5"
        if not path.exists():
            raise SystemExit(f"{path}: no checkpoint at t = {t:g} s (checkpoint_every sets them)")
        snapshots.append(element_fields(path))
    snapshot_figure(snapshots, report / "pore_water_snapshots.png")
    history_figure(history, shaking, report / "pore_water_history.png")
    lines = [f"# Pore water: {case['case']['name']}", "",
             case["case"].get("description", ""), "",
             "Δp = p − p_static (the state before shaking), r_u = Δp/σ′v0 (docs/method.md §10).",
             "", "| quantity | value |", "|---|---|"]
    peak = int(np.argmax(history["pore_pressure_ratio_max"]))
    lines.append(f"| largest r_u | {history['pore_pressure_ratio_max'][peak]:.3f} at "
                 f"t = {history['time'][peak]:.2f} s |")
    lines.append(f"| largest area with r_u ≥ {HIGH_RATIO} | "
                 f"{history['high_pore_pressure_area'].max():.2f} m² |")
    for time, _, _, excess, ratio, saturated in snapshots:
        if not saturated.any():
            lines.append(f"| t = {time:g} s | no saturated element |")
            continue
        lines.append(f"| t = {time:g} s: Δp range, mean r_u of the saturated elements | "
                     f"{excess[saturated].min() / 1e3:.2f} … {excess[saturated].max() / 1e3:.2f}"
                     f" kPa, {ratio[saturated].mean():.4f} |")
    recorders = fem_out / "recorders"
    tables = []
    for path in sorted(recorders.glob("*.csv")) if recorders.exists() else []:
        table = read_table(path)
        if len(table.get("time", ())) and any(n.endswith(("_dp", "_ru")) for n in table):
            tables.append(table)
    lines += ["", "![largest r_u and the area above 0.7](pore_water_history.png)", ""]
    if tables:
        first = fem_out / f"fem_t{times[0]:.3f}.h5"
        recorder_figure(tables, shaking, report / "pore_water_recorders.png", first)
        for table in tables:
            for name in table:
                if name.endswith("_dp"):
                    lines.append(f"- recorder node {place(name[:-3], first)}: Δp from "
                                 f"{table[name].min() / 1e3:.2f} to {table[name].max() / 1e3:.2f} kPa")
                elif name.endswith("_ru"):
                    lines.append(f"- recorder element {place(name[:-3], first)}: r_u up to "
                                 f"{table[name].max():.4f}")
        lines += ["", "![recorders](pore_water_recorders.png)", ""]
    lines += ["![snapshots of Δp and r_u](pore_water_snapshots.png)", ""]
    temporary = report / "report.md.tmp"
    temporary.write_text("\n".join(lines) + "\n")
    temporary.replace(report / "report.md")
    print(f"pore_water: wrote {report / 'report.md'}")


if __name__ == "__main__":
    main(sys.argv)
