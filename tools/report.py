#!/usr/bin/python3
"""Writes OUT/report/report.md for a case: tables, figures and a short reading.

    /usr/bin/python3 tools/report.py cases/column-short/case.toml cases/column-short/out

Run tools/plots.py first (make report does both). Inputs: fem/fem_history.csv,
sweep.md and sweep.csv (slide-metrics sweep; its stress_quality_* columns give the
table of the stress quality at rest), the figures in OUT/report/.
"""
import datetime
import math
import pathlib
import sys
import tomllib

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

import slide  # noqa: E402  (tools/slide: the readers of what the programs write)

G = 9.81
ZONE_JACOBIAN_AVG = 0.97
ZONE_EPS_Q_AVG = 0.20


def number(text):
    try:
        return float(text)
    except (TypeError, ValueError):
        return math.nan


def read_csv(path):
    return slide.read_rows(path, missing_ok=True)


def inside_zone(row):
    j_avg, e_avg = number(row["jacobian_ratio_avg"]), number(row["eps_q_avg"])
    # No element above 3 % deviatoric strain: nothing has distorted yet.
    return (math.isnan(j_avg) or j_avg >= ZONE_JACOBIAN_AVG) and (
        math.isnan(e_avg) or e_avg <= ZONE_EPS_Q_AVG)


def signed_percent(value):
    """+4.6%, and +0.0% rather than -0.0% for a value that rounds to zero."""
    text = f"{value:+.1%}"
    return "+0.0%" if text == "-0.0%" else text


def time_text(t):
    """A history time as make's TT wants it: 1.3, not 1.30 or 1.3000000000000003."""
    return f"{round(t, 6):g}"


def make_command(case_file, out, goals):
    """The make command line, from the repository's top, that makes `goals` for this case
    and output folder."""
    case_dir = case_file.resolve().parent
    where = case_dir.relative_to(case_dir.parents[1])  # cases/<name>
    default_out = out.resolve() == (case_dir / "out").resolve()
    return f"make -C {where} {goals}" + ("" if default_out else f" OUT={out}")


def fem_summary(history, tau_c, case_file, out):
    if not history:
        return None, None, []
    last_inside = None
    for row in history:
        if inside_zone(row):
            last_inside = number(row["time"])
        else:
            break
    negative = next((number(r["time"]) for r in history
                     if number(r["jacobian_ratio_min"]) <= 0.0), None)
    # An element is inverted when det J ≤ 0 at one of its corners (the definition fem2mpm
    # refuses by): scaled_jacobian_min < 0. Histories without that column: as before.
    shape = "scaled_jacobian_min" in history[0]
    inverted = next((number(r["time"]) for r in history
                     if number(r["scaled_jacobian_min"]) < 0.0), None) if shape else negative
    entangled = min((t for t in (negative, inverted) if t is not None), default=None)
    lines = []
    # The FE phase never left the zone: its last output is no recommendation, only its end.
    never_left = last_inside is not None and last_inside >= number(history[-1]["time"]) - 1e-9
    if never_left:
        lines.append(f"- **The FE phase never left the recommended transfer zone** "
                     f"((|J_t|/|J_0|)_avg ≥ {ZONE_JACOBIAN_AVG} and εq,avg ≤ "
                     f"{ZONE_EPS_Q_AVG:.0%}) up to its end at t = {last_inside:.2f} s: every "
                     "FE output is a clean transfer, and the mesh sets no latest transfer time "
                     "(run the FE phase longer to see when it leaves the zone).")
        peak = max(history, key=lambda r: number(r["ke_over_pe0"]))
        top, end = number(peak["ke_over_pe0"]), number(history[-1]["ke_over_pe0"])
        if top > 0 and end < 0.01 * top:
            # The slide stopped inside the zone: a transfer after the stop hands MPM a
            # body at rest (docs/new-case.md §5).
            lines.append(f"  The FE slide stopped inside the zone: KE/PE0 fell from its peak "
                         f"{top:.3g} at t = {number(peak['time']):.2f} s to {end:.3g} at the "
                         "end, so the FE phase carried the whole failure (the pure FE run). "
                         "For MPM to carry the moving mass, transfer while it moves, at or "
                         f"before t ≈ {number(peak['time']):.1f} s; a transfer after the stop "
                         "hands MPM a body at rest.")
    elif last_inside is not None:
        lines.append(f"- Last output time inside the recommended transfer zone "
                     f"((|J_t|/|J_0|)_avg ≥ {ZONE_JACOBIAN_AVG} and εq,avg ≤ "
                     f"{ZONE_EPS_Q_AVG:.0%}): **t = {last_inside:.2f} s** "
                     f"(t/τc = {last_inside / tau_c:.2f}).")
        if last_inside > 0:
            tt = time_text(last_inside)
            ran = (out / f"tt{tt}" / "mpm_final.h5").exists()
            lines.append(f"  The FE phase keeps its state there (fem/fem_t{last_inside:.3f}.h5); "
                         + (f"the run transferred then is row tt{tt} below." if ran else
                            f"to run MPM from it: `{make_command(case_file, out, f'mpm TT={tt}')}`"
                            f", then `{make_command(case_file, out, 'report')}`."))
    if shape and inverted is not None:
        lines.append(f"- First element inverted (det J < 0 at a corner or zero area, scaled "
                     f"Jacobian < 0; "
                     f"fem2mpm refuses it without --allow-inverted) at t = {inverted:.2f} s "
                     f"(t/τc = {inverted / tau_c:.2f}).")
    if negative is not None:
        lines.append(f"- (|J_t|/|J_0|)_min first ≤ 0 (an element inverted at its centre) at "
                     f"t = {negative:.2f} s (t/τc = {negative / tau_c:.2f}).")
    if entangled is None:
        lines.append("- No element inverted during the FE phase.")
    if shape:
        def at(row):
            avg = number(row["scaled_jacobian_avg"])
            return (f"area ratio ΣV_t/ΣV_0 = {number(row['area_ratio']):.3f}, scaled Jacobian "
                    f"min {number(row['scaled_jacobian_min']):.3f}"
                    + ("" if math.isnan(avg) else f", avg over εq > 3 % {avg:.3f}")
                    + f" at t = {number(row['time']):.2f} s")
        picked = [r for r in history if last_inside is not None
                  and abs(number(r["time"]) - last_inside) < 1e-6][:1]
        if not picked or picked[0] is not history[-1]:
            picked.append(history[-1])
        lines.append("- Mesh area and shape (1 for the undeformed mesh): "
                     + "; ".join(at(r) for r in picked) + ".")
    peak = max(history, key=lambda r: number(r["ke_over_pe0"]))
    lines.append(f"- Peak KE/PE0 in the FE phase: {number(peak['ke_over_pe0']):.4f} at "
                 f"t = {number(peak['time']):.2f} s.")
    return (None if never_left else last_inside), entangled, lines


def geostatic_error(case, path):
    """Max and RMS of (σyy − (−ρg(H − y)))/ρgH over the particles of `path`, in %."""
    import h5py
    import numpy as np
    with h5py.File(path, "r") as f:
        y = f["particles/coordinates"][:, 1]
        syy = f["particles/stress"][:, 1]
        material = f["particles/material_id"][:]
        ids = np.unique(material)  # one attribute read per material, not per particle
        rho = np.array([f[f"materials/{m}"].attrs["density"] for m in ids])[
            np.searchsorted(ids, material)]
    height = case["metrics"]["initial_height"]
    error = 100 * (syy + rho * G * (height - y)) / (rho * G * height)
    return np.abs(error).max(), np.sqrt(np.mean(error ** 2))


def geostatic_reading(case, out):
    parts = []
    for path, when in ((out / "tt0" / "particles.h5", "right after the transfer"),
                       (out / "tt0" / "mpm_final.h5",
                        f"after MPM to {case['mpm']['end_time']:g} s"),
                       (out / "pure-mpm" / "mpm_final.h5", "in pure MPM at the same time")):
        if path.exists():
            worst, rms = geostatic_error(case, path)
            parts.append(f"{when} σyy differs from −ρg(H − y) by at most {worst:.2f} % of ρgH "
                         f"(RMS {rms:.2f} %)")
    if not parts:
        return ""
    return ("The geostatic column checks the transfer of a known stress field: "
            + "; ".join(parts) + ". The transfer's largest errors sit at the top and side rows of "
            "particles, where the interpolation extrapolates beyond the outermost Gauss "
            "points; the column neither moves nor spreads (R_N ≈ 0).")


def reading(case, sweep, last_inside, tau_c):
    runs = {r["run"]: r for r in sweep}
    if "tt0" not in runs:
        return ("No t_T = 0 reference run was made, so the runs are not compared; run "
                "`make sweep` for the full comparison.")
    ref = runs["tt0"]
    text = [f"The t_T = 0 transfer (the geostatic state handed straight to MPM) runs out "
            f"R_N = {number(ref['runout_normalised']):.3f} with a crest height "
            f"H_c = {number(ref['crest_height']):.1f} m."]
    if ref.get("x_front_95", "") != "":
        text.append(
            f"R_N is measured at the extreme toe (x_toe = {number(ref['x_toe']):.1f} m); the "
            f"front of 95 % of the mass is at x_95 = {number(ref['x_front_95']):.1f} m, with a "
            f"sheet of {number(ref['sheet_length']):.1f} m beyond it holding "
            f"{number(ref['sheet_mass_share']):.1%} of the mass at a mean thickness of "
            f"{number(ref['sheet_thickness']):.2f} m (docs/method.md §6). The comparisons "
            "below are of R_N, the extreme toe.")
    transfers = [r for r in sweep if r["run"].startswith("tt") and r["run"] != "tt0"]
    if any(r["runout_normalised_error"] == "" for r in transfers) or not transfers:
        # slide-metrics leaves the relative error out when the reference runout is under
        # one profile bin: compare the runs in metres.
        if transfers:
            text.append(
                f"The reference runout R = {number(ref['runout']):.2f} m is under one profile "
                f"bin ({case['metrics']['bin_width']:g} m), too short for a relative "
                "error: the runs' runouts are " + ", ".join(
                    f"{r['run']} {number(r['runout']):.2f} m" for r in transfers) + ".")
        transfers = []
    if last_inside is not None and transfers:
        within = [r for r in transfers if number(r["tt"]) <= last_inside + 1e-9]
        beyond = [r for r in transfers if number(r["tt"]) > last_inside + 1e-9]
        if within:
            worst = max(within, key=lambda r: abs(number(r["runout_normalised_error"])))
            text.append(
                f"Transfers inside the recommended zone (t_T ≤ {last_inside:.2f} s) stay within "
                f"{abs(number(worst['runout_normalised_error'])):.1%} of it in R_N "
                f"(largest profile RMSE {max(number(r['rmse']) for r in within):.3f}).")
        if beyond:
            worst = max(beyond, key=lambda r: abs(number(r["runout_normalised_error"])))
            rough = max(beyond, key=lambda r: number(r["rmse"]))
            text.append(
                f"Later transfers inherit more FE mesh distortion: the largest profile RMSE "
                f"is {number(rough['rmse']):.3f} (t_T = {number(rough['tt']):g} s), the "
                f"largest R_N error {signed_percent(number(worst['runout_normalised_error']))} "
                f"(t_T = {number(worst['tt']):g} s).")
        text.append(
            f"**Recommended transfer time for this case: t_T ≈ {time_text(last_inside)} s "
            f"(t_T/τc = {last_inside / tau_c:.2f})**, the last FE output inside the zone: "
            "late enough for the FE phase to capture the onset of failure, early enough that "
            "the mesh distortion does not bias the runout.")
    for name, label in (("pure-mpm", "Pure MPM"), ("pure-fem", "Pure FE (small strain)")):
        if name in runs and runs[name]["runout_normalised_error"] != "":
            text.append(f"{label} differs from it by "
                        f"{signed_percent(number(runs[name]['runout_normalised_error']))} in R_N.")
    return " ".join(text)


def stress_quality_lines(case, sweep, report_dir):
    """The stress quality at rest of every run (sweep.csv) and the σyy figure of the main
    transfer (plots.py), docs/method.md §6."""
    columns = ("stress_quality_p50", "stress_quality_p90", "stress_quality_p99",
               "stress_quality_max")
    rows = [r for r in sweep if all(c in r for c in columns)]
    figure = (report_dir / "stress_at_transfer.png").exists()
    if not rows and not figure:
        return []
    lines = ["## Stress at the transfer and at rest", ""]
    if rows:
        lines += [
            "Stress quality at rest (docs/method.md §6): over the particles of a run's final state "
            "that are at rest (speed < 1 cm/s) and that the surface profile measures, "
            "e = |σyy − σyy,lith| / (ρ g H0), σyy,lith = −ρ g (h_b − y) under the profile "
            "height h_b of the particle's bin; 0 for a deposit that carries just its own "
            "weight. Empty: no particle at rest."
            + (" pure-fem is the FE end state on particles (element by element), with its FE "
               "velocities." if any(r["run"] == "pure-fem" for r in rows) else ""), "",
            "| run | t_T (s) | e p50 | e p90 | e p99 | e max |", "|---|---|---|---|---|---|"]
        for r in rows:
            cells = ["" if r[c] == "" else f"{number(r[c]):#.3g}" for c in columns]
            lines.append(f"| {r['run']} | {r['tt']} | " + " | ".join(cells) + " |")
        lines.append("")
    if figure:
        tt = case["transfer"].get("main_time", 0)
        lines += [f"σyy of the main transfer (t_T = {tt:g} s): the FE Gauss points at t_T, the "
                  "particles made from them, the particles 0.5 s later and at the end of the "
                  "run, on one colour scale (kPa, compression negative).", "",
                  "![σyy at the transfer, 0.5 s later and at rest](stress_at_transfer.png)", ""]
    return lines


_STABILITY = {}


def slope_stability_of(case):
    """limit_equilibrium.slope_stability of the report's case, searched once (a few
    seconds) for the sections that use it (Shaking, Factor of safety)."""
    import limit_equilibrium
    if id(case) not in _STABILITY:
        _STABILITY[id(case)] = limit_equilibrium.slope_stability(case)
    return _STABILITY[id(case)]


def seismic_lines(case, out, report_dir, sweep):
    """The shaking of a case with [fem.motion] (docs/method.md §8): the motion, the check
    that the slope stands before it, the time histories, KE/PE0 of both phases."""
    spec = case["fem"].get("motion")
    if spec is None or not (out / "fem" / "motion.csv").exists():
        return []
    import seismic

    motion = seismic.read_table(out / "fem" / "motion.csv")
    seismic.plot_motion(out / "fem" / "motion.csv", report_dir / "motion.png")
    start = spec.get("start_time", 0.0)
    end = motion["time"][-1]
    peak_a = np.max(np.abs(motion["ax"]))
    peak_v = np.max(np.abs(motion["vx"]))
    peak_u = np.max(np.abs(motion["ux"]))
    stability = slope_stability_of(case)
    history = read_csv(out / "fem" / "fem_history.csv")
    before = [r for r in history if number(r["time"]) <= start + 1e-9]
    lines = ["## Shaking", ""]
    lines.append(
        f"- Base: {spec.get('base', 'rigid')}"
        + (f" (ρ_r = {spec['rock_density']:g} kg/m³, V_s,r = {spec['rock_shear_wave_speed']:g} m/s, "
           f"{spec.get('input', 'incident')} motion)" if spec.get("base") == "compliant" else "")
        + f"; sides {spec.get('lateral', 'boundaries')}.")
    lines.append(
        f"- Motion from t = {start:g} to {end:.2f} s: peak |a| = {peak_a:.3f} m/s² "
        f"({peak_a / G:.3f} g), |v| = {peak_v:.3f} m/s, |u| = {peak_u:.3f} m after baseline "
        "correction (figure below).")
    lines.append(
        f"- Before the shaking the slope stands: factor of safety {stability['fs']:.2f} "
        f"(Bishop's simplified method, tools/limit_equilibrium.py; circle centre "
        f"({stability['circle'][0]:.1f}, {stability['circle'][1]:.1f}) m, radius "
        f"{stability['circle'][2]:.1f} m), pseudo-static yield acceleration "
        f"k_y = {stability['ky']:.3f} g, so the peak base acceleration is "
        f"{peak_a / G / stability['ky']:.1f} k_y.")
    if before:
        ke = max(number(r["ke_over_pe0"]) for r in before)
        last = before[-1]
        lines.append(
            f"- Pre-shaking check (FE, t = 0 → {start:g} s on the seismic boundaries): KE/PE0 at "
            f"most {ke:.2e}, {ke_trend(before)}; {int(number(last['n_elements_yielding']))} "
            f"elements yielding at t = {start:g} s.")
    recorders = []
    for name in ("crest", "toe"):
        path = out / "fem" / "recorders" / f"{name}.csv"
        if path.exists():
            table = seismic.read_table(path)
            ux = table[seismic.node_columns(table, "ux_rel")[0]]
            uy = table[seismic.node_columns(table, "uy_rel")[0]]
            t = table["time"]
            at = lambda q, time: float(np.interp(time, t, q))  # noqa: E731
            recorders.append((name, t, ux, uy))
            lines.append(
                f"- The {name} relative to the base: u = ({at(ux, start):+.3f}, {at(uy, start):+.3f}) m "
                f"when the shaking starts, ({at(ux, end):+.3f}, {at(uy, end):+.3f}) m when it ends, "
                f"({ux[-1]:+.3f}, {uy[-1]:+.3f}) m at t = {t[-1]:g} s.")
    lines += ["", "![base motion](motion.png)", ""]
    if recorders:
        fig, axes = plt.subplots(2, 1, figsize=(8, 6), sharex=True)
        axes[0].plot(motion["time"], motion["ax"] / G, "k-", lw=0.8)
        axes[0].set_ylabel("base a_x (g)")
        for name, t, ux, uy in recorders:
            axes[1].plot(t, ux, label=f"{name}: u_x")
            axes[1].plot(t, uy, "--", label=f"{name}: u_y")
        axes[1].set_ylabel("displacement relative to the base (m)")
        axes[1].set_xlabel("t (s)")
        axes[1].legend(ncol=2)
        for ax in axes:
            ax.axvspan(start, end, color="0.9", zorder=0)
            ax.grid(alpha=0.3)
        axes[0].set_title("FE phase: the recorders (grey: the shaking)")
        fig.tight_layout()
        seismic.write_figure(fig, report_dir / "recorders.png")
        lines += ["![recorders](recorders.png)", ""]
    # KE/PE0 of the FE phase and of every MPM run against time.
    fig, ax = plt.subplots(figsize=(8, 4.5))
    ax.semilogy([number(r["time"]) for r in history], [max(number(r["ke_over_pe0"]), 1e-9) for r in history],
                "k-", lw=2, label="FE")
    for run in sorted(out.glob("tt*/mpm_history.csv"), key=lambda p: float(p.parent.name[2:])):
        rows = read_csv(run)
        ax.semilogy([number(r["time"]) for r in rows], [max(number(r["ke_over_pe0"]), 1e-9) for r in rows],
                    lw=0.9, label=f"MPM from t_T = {run.parent.name[2:]} s")
    ax.axvspan(start, end, color="0.9", zorder=0)
    ax.set_xlabel("t (s)")
    ax.set_ylabel("KE / PE0")
    ax.set_title("Kinetic energy of the FE phase and of the MPM runs (grey: the shaking)")
    ax.legend(fontsize=7, ncol=2)
    ax.grid(alpha=0.3, which="both")
    fig.tight_layout()
    seismic.write_figure(fig, report_dir / "seismic_energy.png")
    lines += ["![KE/PE0](seismic_energy.png)", ""]
    return lines


def ke_trend(rows):
    """Whether KE/PE0 of the pre-shaking rows falls (settling) or grows (a runaway)."""
    ke = [number(r["ke_over_pe0"]) for r in rows]
    if len(ke) < 4:
        return "too few rows to judge"
    half = len(ke) // 2
    first, second = max(ke[:half]), max(ke[half:])
    return (f"falling from {first:.2e} to {second:.2e} (settling, no runaway)" if second <= first
            else f"**growing** from {first:.2e} to {second:.2e}")


def seismic_reading(case, sweep):
    """How the runout depends on when, relative to the shaking, the body was handed over."""
    spec = case["fem"]["motion"]
    start = spec.get("start_time", 0.0)
    runs = sorted((r for r in sweep if r["run"].startswith("tt")), key=lambda r: number(r["tt"]))
    if len(runs) < 2:
        return ""
    comp = case["fem"]["motion"].get("horizontal", {})
    duration = comp.get("duration", 2 * comp.get("peak_time", 0.0))
    motion_end = start + duration
    def phase(t):
        return "before" if t <= start + 1e-9 else ("during" if t < motion_end - 1e-9 else "after")
    groups = {}
    for r in runs:
        groups.setdefault(phase(number(r["tt"])), []).append(r)
    text = [f"The shaking runs from t = {start:g} to {motion_end:g} s."]
    for name in ("before", "during", "after"):
        if name not in groups:
            continue
        rs = groups[name]
        values = [number(r["runout"]) for r in rs]
        text.append(
            f"Transfers {name} it (t_T = {', '.join(format(number(r['tt']), 'g') for r in rs)} s) run out "
            f"R = {min(values):.2f} to {max(values):.2f} m.")
    return " ".join(text)


def grid_edge_lines(case, out, sweep):
    """The runs whose toe (the measured particles' front, docs/method.md §6: a foundation
    layer across the grid does not count) ends within a cell of the grid's far edge (+x,
    the runout direction), or whose particles left the grid. Their runout is the grid's,
    not the slide's (mpm-solve warns of the same at the end of the run)."""
    import h5py
    rows = []
    for row in sweep:
        path = out / row["run"] / "mpm_final.h5"
        if not path.exists():
            continue
        with h5py.File(path, "r") as f:
            solver = f["solver"].attrs
            cell = float(solver["cell_size"])
            edge = float(solver["domain_min_x"]) + cell * int(solver["cells_x"])
            frozen = int(solver.get("frozen_particles", 0))
        toe = number(row.get("x_toe", ""))
        if math.isnan(toe):
            toe = number(row["runout"]) + case["metrics"]["initial_length"]
        if frozen or edge - toe < cell:
            rows.append(f"| {row['run']} | {edge:g} | {toe:.2f} | {frozen} |")
    if not rows:
        return ["## Grid", "", "Every run's toe ends more than a cell from the grid's far edge "
                "(+x) and no particle left the grid: the runout figures are the slide's.", ""]
    return ["## Grid: runs bounded by the grid's far edge", "",
            "**These runs end against the grid's far edge (+x): their runout is the grid's, "
            "not the slide's; extend `[mpm] domain`.**", "",
            "| run | far edge x (m) | toe x (m) | particles that left the grid |",
            "|---|---|---|---|"] + rows + [""]


REST_SPEED = 0.01  # m/s: a run is at rest from the output after which no particle is faster


def slide_measures(case, run_dir):
    """The slope engineer's measures of one MPM run (docs/method.md §6, "Slide measures"),
    from its final state and history: displaced area, failure depth, travel angle, peak
    speed, rest time. None when the run has no final state."""
    final = run_dir / "mpm_final.h5"
    if not final.exists():
        return None
    state = slide.read_checkpoint(final)
    p = state.particles
    x, u = p["coordinates"], p["displacement"]
    origin = x - u                      # where each particle was at t = 0
    moved = np.linalg.norm(u, axis=1)
    threshold = 0.01 * case["metrics"]["initial_height"]
    displaced = moved > threshold
    m = {"run": run_dir.name, "threshold": threshold, "end": state.time,
         "area": float(p["volume"][displaced].sum()), "max_u": float(moved.max())}
    if displaced.any():
        # The ground surface at t = 0: the highest original particle of each profile bin.
        width = case["metrics"]["bin_width"]
        bins = np.floor(origin[:, 0] / width).astype(int)
        top = {b: origin[bins == b, 1].max() for b in np.unique(bins)}
        depth = np.array([top[b] for b in bins[displaced]]) - origin[displaced, 1]
        m["depth"] = float(depth.max())
        source = origin[displaced]
        crown = source[np.argmax(source[:, 1])]
        tip = x[displaced][np.argmax(x[displaced, 0])]
        drop, reach = crown[1] - tip[1], tip[0] - crown[0]
        m["travel_angle"] = math.degrees(math.atan2(drop, reach)) if reach > 0 else math.nan
    history = run_dir / "mpm_history.csv"
    if history.exists():
        h = slide.read_table(history)
        if "max_speed" in h and len(h["max_speed"]):
            k = int(np.argmax(h["max_speed"]))
            m["peak_speed"], m["peak_time"] = float(h["max_speed"][k]), float(h["time"][k])
            moving = np.nonzero(h["max_speed"] >= REST_SPEED)[0]
            m["rest_time"] = (float(h["time"][0]) if len(moving) == 0 else
                              float(h["time"][moving[-1] + 1]) if moving[-1] + 1 < len(h["time"])
                              else None)
    return m


def slide_measure_lines(case, out, sweep):
    """The table of slide measures of every MPM run of the sweep."""
    rows = []
    for row in sweep:
        if row["run"] == "pure-fem":
            continue
        m = slide_measures(case, out / row["run"])
        if m is None:
            continue

        def fmt(key, spec):
            value = m.get(key)
            return "–" if value is None or (isinstance(value, float) and math.isnan(value)) \
                else format(value, spec)
        rest = ("still moving" if "rest_time" in m and m["rest_time"] is None else
                fmt("rest_time", ".1f") + (" s" if m.get("rest_time") is not None else ""))
        rows.append(f"| {m['run']} | {m['end']:.2f} s | {rest} | {fmt('area', '.0f')} | "
                    f"{fmt('depth', '.1f')} | {fmt('travel_angle', '.1f')} | "
                    f"{fmt('peak_speed', '.2f')} | {fmt('peak_time', '.1f')} | "
                    f"{fmt('max_u', '.2f')} |")
    if not rows:
        return []
    threshold = 0.01 * case["metrics"]["initial_height"]
    return ["## Slide measures", "",
            f"Per MPM run, from its final state and history (docs/method.md §6): the "
            f"displaced area (particles that moved more than {threshold:.2g} m, 1 % of H0, "
            "since t = 0, their volume at the end), the deepest point of the failure surface "
            "below the original ground (the deepest displaced particle's start under the "
            "ground surface above it), the travel angle (Fahrböschung) from the highest "
            "displaced point at t = 0 to the farthest displaced particle at the end, the "
            f"peak particle speed and when, the time from which no particle moves faster than "
            f"{REST_SPEED:g} m/s, and the largest displacement.", "",
            "| run | ran to | at rest from | displaced area (m²) | failure depth (m) | "
            "travel angle (°) | peak speed (m/s) | at t (s) | largest \\|u\\| (m) |",
            "|---|---|---|---|---|---|---|---|---|"] + rows + [""]


def read_strength_reduction(path):
    """fem-solve --strength-reduction's table: ({key: value}, [trial rows])."""
    trials = []
    for line in path.read_text().splitlines():
        if line.startswith("#") or not line.strip() or " = " in line:
            continue
        factor, stable, ratio, displacement, folder = [c.strip() for c in line.split(",")]
        trials.append({"factor": float(factor), "stable": stable == "yes",
                       "ratio": float(ratio), "displacement": float(displacement),
                       "folder": folder})
    return slide.read_summary(path), trials


def mechanism_figure(trial_dir, report_dir, factor):
    """The failing trial's displacement magnitude on its reference mesh: the mechanism."""
    from matplotlib.collections import PolyCollection
    states = sorted(trial_dir.glob("fem_t*.h5"), key=lambda p: float(p.stem[5:]))
    if not states:
        return None
    last = slide.read_checkpoint(states[-1])
    x = last.nodes["reference_coordinates"]
    u = np.linalg.norm(last.nodes["displacement"], axis=1)
    cells = last.elements["connectivity"]
    fig, ax = plt.subplots(figsize=(9, 3.6))
    polygons = PolyCollection(x[cells], array=u[cells].mean(axis=1), cmap="viridis",
                              edgecolors="none")
    ax.add_collection(polygons)
    ax.autoscale_view()
    ax.set_aspect("equal")
    ax.set_xlabel("x (m)")
    ax.set_ylabel("y (m)")
    ax.set_title(f"Strength reduction: the failing trial F = {factor:.3f}, |u| at its end")
    fig.colorbar(polygons, ax=ax, label="|u| (m)")
    fig.tight_layout()
    name = "fos_mechanism.png"
    path = report_dir / name
    tmp = path.with_name(".fos_mechanism.tmp.png")
    fig.savefig(tmp, dpi=110)
    plt.close(fig)
    tmp.replace(path)
    return name


def fos_lines(case, out, report_dir):
    """The factor of safety by strength reduction (make fos) beside Bishop's."""
    path = out / "fos" / "strength_reduction.txt"
    if not path.exists():
        return []
    import limit_equilibrium
    values, trials = read_strength_reduction(path)
    srm = float(values["factor_of_safety"])
    failing = float(values["failing_factor"])
    # Bishop over the case's surface for one material on a profile or blocks mesh; on the
    # t = 0 transfer's particles otherwise (a Gmsh mesh, several materials).
    particles = out / "tt0" / "particles.h5"
    simple = (case["mesh"].get("generator", "profile") in ("profile", "blocks")
              and len(case["materials"]) == 1)
    noncircular = None
    if simple:
        stability = slope_stability_of(case)
        bishop = stability["fs"]
        noncircular = limit_equilibrium.noncircular(
            case, [stability["circle"]] + stability["depth_circles"])
    elif particles.exists():
        bishop = limit_equilibrium.particle_stability(particles)["fs"]
    else:
        bishop = math.nan
    lines = ["## Factor of safety", "",
             "| method | F |", "|---|---|",
             f"| strength reduction (FE, Mohr–Coulomb, `make fos`) | {srm:.3f} "
             f"(fails at {failing:.3f}) |",
             "| Bishop's simplified method (circles, tools/limit_equilibrium.py"
             + ("" if simple else ", on the t = 0 particles") + ") | "
             + ("not computed (no out/tt0/particles.h5)" if math.isnan(bishop) else
                f"{bishop:.3f}") + " |"]
    if noncircular is not None:
        lowest = min(bishop, noncircular["fs"])
        lines.append("| Spencer's method over convex non-circular surfaces (the lowest found; "
                     + limit_equilibrium.describe_surface(*noncircular["surface"]) + ") | "
                     f"{noncircular['fs']:.3f} |")
    else:
        lowest = bishop
    comparison = ("" if math.isnan(lowest) else
                  f"The strength reduction's F is {signed_percent(srm / lowest - 1.0)} from the "
                  "lowest limit-equilibrium F (docs/method.md §3 gives the reasons they "
                  "differ). ")
    # At the factor found the reduced friction angle can be large for a weak slope, and
    # the flow rule's dilation (ψ ≤ φ_F) far below it: a non-associated soil fails at a
    # lower F than the rigid-plastic mechanisms of limit equilibrium (docs/method.md §3).
    soil = case["materials"][0]
    phi_f = math.degrees(math.atan(math.tan(math.radians(soil.get("friction_angle", 0.0))) / srm))
    if phi_f - min(soil.get("dilation_angle", 0.0), phi_f) > 20.0:
        comparison += (f"At F = {srm:.3f} the reduced friction angle is φ_F = "
                       f"{phi_f:.1f}° with ψ = {soil.get('dilation_angle', 0.0):g}°: "
                       "non-associated flow that far from φ_F fails below limit equilibrium. ")
    lines += ["", comparison + f"Criterion: {values.get('criterion', '')}; {len(trials)} trials "
              f"of {float(values['trial_duration']):.3g} s (out/fos/strength_reduction.txt). "
              + ("The slope fails under gravity alone (F < 1)." if srm < 1.0 else
                 "The slope stands under gravity (F ≥ 1): a runout needs a trigger."), ""]
    failing_trial = [t for t in trials if not t["stable"] and t["factor"] == failing]
    if failing_trial:
        figure = mechanism_figure(out / "fos" / failing_trial[0]["folder"], report_dir, failing)
        if figure:
            lines += [f"![the mechanism at F = {failing:.3f}]({figure})", ""]
    return lines


PAPER_MEASURES = {"crest_height": ("crest height H_c", "m"),
                  "runout_normalised": ("normalised runout R_N", "")}


def paper_lines(case, case_file, sweep):
    """The paper's published figures (paper.toml beside the case file, if there is one)
    beside this project's, and what makes them differ: for the crest, the cell
    volumetric smoothing the paper's MPM code does not have (mpm/README.md, "Against the
    paper's crest")."""
    path = case_file.parent / "paper.toml"
    if not path.exists():
        return []
    with open(path, "rb") as f:
        paper = tomllib.load(f)
    runs = {r["run"]: r for r in sweep}
    lines = ["## Against the paper", "",
             "| run | measure | paper | this run | difference |", "|---|---|---|---|---|"]
    for run, figures in paper.items():
        for key, published in figures.items():
            label, unit = PAPER_MEASURES[key]
            ours = number(runs[run][key]) if run in runs and runs[run].get(key) else math.nan
            mine = "not run" if math.isnan(ours) else f"{ours:.2f} {unit}".strip()
            difference = "" if math.isnan(ours) else signed_percent(ours / published - 1.0)
            lines.append(f"| {run} | {label} | {published:g} {unit} | {mine} | {difference} |")
    plastic = case["mpm"].get("volumetric_smoothing", "cell") != "none"
    lines += ["", "The paper's MPM code has no volumetric anti-locking for Mohr–Coulomb. "
              + ("This case smooths the volumetric stress and strain rate over each cell "
                 "(`[mpm] volumetric_smoothing = \"cell\"`, the default for plastic "
                 "materials), which keeps the isochoric flow from locking: the crest settles "
                 "lower than the paper's, and refining the grid moves the unsmoothed crest "
                 "toward the smoothed one (mpm/README.md, \"Against the paper's crest\", has "
                 "the table). To reproduce the paper's code, run with "
                 "`volumetric_smoothing = \"none\"`." if plastic else
                 "This case runs without it (`volumetric_smoothing = \"none\"`), as the "
                 "paper's code does; its flow locks on the cells, which holds the crest "
                 "higher than the converged one (mpm/README.md, \"Against the paper's "
                 "crest\")."), ""]
    return lines


def input_echo_lines(case, case_file, out):
    """What the runs were made from: the program version (the producer of the FE phase's
    first checkpoint), the case file, and its materials and settings as a table."""
    lines = ["## Inputs", ""]
    first = out / "fem" / "fem_t0.000.h5"
    if first.exists():
        state = slide.read_checkpoint(first)
        lines.append(f"- Made by {state.attrs.get('producer', 'an unknown program')} "
                     f"(out/fem/fem_t0.000.h5), from `{case_file}`.")
    fem, mpm, mesh = case["fem"], case["mpm"], case["mesh"]
    damping = fem.get("damping", {})
    lines += [
        f"- Mesh: {mesh.get('generator', 'profile')}"
        + (f" ({mesh['file']})" if "file" in mesh else "")
        + f", {mesh.get('element', 'quad4-1gp')}"
        + (f", element size {mesh['element_size']:g} m" if "element_size" in mesh else "")
        + f"; FE: {fem.get('kinematics', 'small-strain')}, to {fem.get('end_time', 0):g} s, "
        f"Courant {fem.get('courant', 0.5):g}, base μ {fem.get('friction_coefficient', 0):g}, "
        f"Rayleigh β_K {damping.get('rayleigh_stiffness', 0):g} s, α_M "
        f"{damping.get('rayleigh_mass', 0):g} 1/s, local α {damping.get('local', 0):g}"
        + ("; base motion" if "motion" in fem else "") + ".",
        f"- Transfer: {case['transfer'].get('particles_per_element', [4, 4])} particles per "
        f"element, stresses by {case['transfer'].get('stress_interpolation', 'rbf')}, main "
        f"t_T = {case['transfer'].get('main_time', 0):g} s.",
        f"- MPM: domain {mpm['domain'][0]} to {mpm['domain'][1]} m, {mpm['cell_size']:g} m cells, "
        f"{mpm.get('shape_function', 'gimp')}, {mpm.get('update_scheme', 'musl').upper()}, "
        f"{mpm.get('velocity_transfer', 'flip-pic')}, to {mpm['end_time']:g} s, base μ "
        f"{mpm.get('friction_coefficient', 0):g}, local α {mpm.get('local_damping', 0):g}, "
        "boundaries " + ", ".join(f"{side} {kind}" for side, kind in
                                  mpm.get("boundaries", {}).items()) + ".", "",
        "| material | FE model | MPM model | ρ (kg/m³) | E (MPa) | ν | φ (°) | c (kPa) | ψ (°) |",
        "|---|---|---|---|---|---|---|---|---|"]
    for m in case["materials"]:
        fe_model = m.get("fem_model", m.get("model", "mohr-coulomb"))
        e = m.get("youngs_modulus")
        lines.append(
            f"| {m['name']} | {fe_model} | {m.get('mpm_model', fe_model)} | "
            f"{m.get('density', 0):g} | {'–' if e is None else format(e / 1e6, 'g')} | "
            f"{m.get('poisson_ratio', '–')} | {m.get('friction_angle', '–')} | "
            f"{m.get('cohesion', 0) / 1e3:g} | {m.get('dilation_angle', 0)} |")
    return lines + [""]


def main():
    if len(sys.argv) != 3:
        sys.exit("usage: report.py CASE.toml OUT_DIR")
    case_file = pathlib.Path(sys.argv[1])
    with open(case_file, "rb") as f:
        case = tomllib.load(f)
    out = pathlib.Path(sys.argv[2])
    report_dir = out / "report"
    report_dir.mkdir(parents=True, exist_ok=True)
    metrics = case["metrics"]
    tau_c = math.sqrt(metrics["initial_height"] / G)
    history = read_csv(out / "fem" / "fem_history.csv")
    sweep = read_csv(out / "sweep.csv")
    last_inside, _, fem_lines = fem_summary(history, tau_c, case_file, out)

    md = [f"# {case['case']['name']}: {case['case'].get('description', '')}", "",
          f"Generated {datetime.datetime.now():%Y-%m-%d %H:%M} by `make report` from "
          f"`{out}`. Definitions: docs/method.md §6 (profile, toe, R_N, H_c, RMSE against the "
          "t_T = 0 run) and §3 (mesh quality).", "",
          "## Case", "",
          f"- L0 = {metrics['initial_length']:g} m, H0 = {metrics['initial_height']:g} m, "
          f"τc = sqrt(H0/g) = {tau_c:.2f} s.",
          f"- FE phase to {case['fem'].get('end_time', 0):g} s "
          f"({case['mesh'].get('element', 'quad4-1gp')}, "
          f"{case['fem'].get('kinematics', 'small-strain')}); MPM to "
          f"{case['mpm']['end_time']:g} s on {case['mpm']['cell_size']:g} m cells "
          f"({case['mpm'].get('shape_function', 'gimp')}, "
          f"{case['mpm'].get('update_scheme', 'musl').upper()}).", ""]
    md += input_echo_lines(case, case_file, out)
    if fem_lines:
        md += ["## FE phase: mesh quality and when to transfer", ""] + fem_lines + [""]
        if (report_dir / "fem_mesh_quality.png").exists():
            md += ["![FE mesh quality](fem_mesh_quality.png)", ""]
    if (out / "sweep.md").exists():
        md += ["## Runs", "", (out / "sweep.md").read_text(), ""]
    for figure, caption in (("profiles.png", "Final surface profiles"),
                            ("runout_and_energy.png", "Runout and kinetic energy"),
                            ("rmse_vs_mesh_quality.png", "Profile error against FE mesh quality"),
                            ("snapshots_sigma_yy.png", "Particles coloured by σyy"),
                            ("snapshots_eps_q.png", "Particles coloured by εq (log scale)"),
                            ("snapshots_displacement.png", "Particles coloured by |u| since t = 0"),
                            ("geostatic_transfer_error.png", "Transfer error of σyy")):
        if (report_dir / figure).exists():
            md += [f"![{caption}]({figure})", ""]
    for spec in case["mpm"].get("recorders", []):
        if (report_dir / f"recorder_{spec['name']}.png").exists():
            md += [f"![Recorder {spec['name']}: displacement and speed](recorder_{spec['name']}.png)",
                   ""]
    md += slide_measure_lines(case, out, sweep)
    md += grid_edge_lines(case, out, sweep)
    md += paper_lines(case, case_file, sweep)
    md += fos_lines(case, out, report_dir)
    md += seismic_lines(case, out, report_dir, sweep)
    md += stress_quality_lines(case, sweep, report_dir)
    if sweep:
        text = reading(case, sweep, last_inside, tau_c)
        if "motion" in case["fem"]:
            text += " " + seismic_reading(case, sweep)
        if case["fem"].get("end_time", 0) == 0:
            text = geostatic_reading(case, out)
        md += ["## Reading", "", text, ""]
    path = report_dir / "report.md"
    tmp = path.with_suffix(".md.tmp")
    tmp.write_text("\n".join(md))
    tmp.replace(path)
    print(f"report: {path}")


if __name__ == "__main__":
    main()
