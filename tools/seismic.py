#!/usr/bin/python3
"""Seismic checks and figures (docs/method.md §8), from what fem-solve and mpm-solve write.

    seismic.py motion MOTION.csv PNG
        the processed base motion (acceleration, velocity, displacement) of a run
    seismic.py column CASE_DIR RIGID_OUT COMPLIANT_OUT REPORT_DIR [SATURATED_OUT]
        verifications 1 and 2 on cases/column-seismic: the rigid-base transfer function
        against |1/cos(ωH/V_s*)| and the compliant base's Ricker pulse (and, with
        SATURATED_OUT, the same pulse through the saturated column of
        compliant-saturated.toml); report.md and figures in REPORT_DIR; exit status 1 when
        a check fails
    seismic.py sliding-block CASE.toml FEM_OUT MPM_OUT REPORT_DIR [--check fe]
        verification 3: the block's permanent slip in FE and MPM against the Newmark
        sliding-block integral of the same base motion; exit status 1 when a check fails
        (with --check fe only the FE phase's is checked, MPM's is printed)

Uses Debian's python3-numpy, python3-matplotlib and python3-h5py only. The recorder
columns are those of fem/recorders.hpp; motion.csv those of common/physics/ground_motion.hpp.
"""
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

# The tolerances of docs/method.md §8.
RESONANCE_TOLERANCE = 0.01  # f1 against V_s/4H
DOUBLING_TOLERANCE = 0.03  # surface peak against twice the incident one
REFLECTED_ENERGY_LIMIT = 0.05  # share of the incident energy the base sends back
NEWMARK_TOLERANCE = 0.05  # permanent slip against the Newmark integral


def read_table(path):
    """A CSV with a header line, as a dict of numpy columns (tools/slide)."""
    return slide.read_table(path)


def node_columns(table, quantity):
    """The columns n<k>_<quantity> of a node recorder (absolute), in recorder order."""
    return [n for n in table if n.startswith("n") and n.endswith("_" + quantity)]


def spectrum(time, values, frequencies):
    """The Fourier transform ∫ x(t) e^{−iωt} dt of samples at (possibly uneven) times."""
    weights = np.gradient(time)
    return np.exp(-2j * np.pi * np.outer(frequencies, time)) @ (values * weights)


def write_figure(fig, path):
    """Saves atomically (temporary name, then rename), so a figure is never half written."""
    path = pathlib.Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    tmp = path.with_name("." + path.name + ".tmp.png")
    fig.savefig(tmp, dpi=120)
    plt.close(fig)
    tmp.replace(path)


def write_text(path, text):
    path = pathlib.Path(path)
    tmp = path.with_name("." + path.name + ".tmp")
    tmp.write_text(text)
    tmp.replace(path)


# --------------------------------------------------------------------------- motion


def plot_motion(motion_csv, png):
    m = read_table(motion_csv)
    fig, axes = plt.subplots(3, 1, figsize=(8, 7), sharex=True)
    for ax, (q, label, unit) in zip(
        axes, [("a", "acceleration", "m/s²"), ("v", "velocity", "m/s"), ("u", "displacement", "m")]
    ):
        ax.plot(m["time"], m[q + "x"], label="horizontal")
        if np.any(m[q + "y"] != 0.0):
            ax.plot(m["time"], m[q + "y"], label="vertical")
        ax.set_ylabel(f"{label} ({unit})")
        ax.grid(alpha=0.3)
    axes[0].legend()
    axes[0].set_title("Base motion after resampling and baseline correction")
    axes[-1].set_xlabel("t (s)")
    fig.tight_layout()
    write_figure(fig, png)


# --------------------------------------------------------------------------- column


def column_properties(case_path):
    with open(case_path, "rb") as f:
        case = tomllib.load(f)
    m = case["materials"][0]
    shear = m["youngs_modulus"] / (2 * (1 + m["poisson_ratio"]))
    height = max(p[1] for p in case["mesh"]["surface"])
    return {
        "vs": math.sqrt(shear / m["density"]),
        "height": height,
        "beta": case["fem"].get("damping", {}).get("rayleigh_stiffness", 0.0),
        "case": case,
    }


def closed_form_transfer(f, vs, height, beta):
    """|1/cos(ωH/V_s*)| of a Kelvin–Voigt shear column, V_s* = V_s sqrt(1 + iωβ)."""
    w = 2 * np.pi * f
    return np.abs(1.0 / np.cos(w * height / (vs * np.sqrt(1 + 1j * w * beta))))


def rigid_column(case_dir, out, report):
    p = column_properties(pathlib.Path(case_dir) / "case.toml")
    rec = read_table(pathlib.Path(out) / "recorders" / "surface.csv")
    t = rec["time"]
    surface = node_columns(rec, "ux")[0]
    f = np.linspace(0.25, 20.0, 7901)  # 2.5 mHz steps
    ratio = np.abs(spectrum(t, rec[surface], f) / spectrum(t, rec["base_ux"], f))
    closed = closed_form_transfer(f, p["vs"], p["height"], p["beta"])
    f1 = p["vs"] / (4 * p["height"])
    near = (f > 0.5 * f1) & (f < 1.5 * f1)
    f1_measured = f[near][np.argmax(ratio[near])]
    f1_closed = f[near][np.argmax(closed[near])]
    band = (f >= 0.5) & (f <= 15.0)
    error = np.max(np.abs(ratio[band] / closed[band] - 1))

    fig, ax = plt.subplots(figsize=(8, 4.5))
    ax.semilogy(f, closed, "k-", lw=2.5, alpha=0.35, label="closed form |1/cos(ωH/V_s*)|")
    ax.semilogy(f, ratio, "C0-", lw=1, label="fem-solve: |U_surface / U_base|")
    for k in range(1, 6):
        ax.axvline((2 * k - 1) * f1, color="0.7", lw=0.6, ls=":")
    ax.set_xlabel("f (Hz)")
    ax.set_ylabel("amplification")
    ax.set_title(
        f"Shear column on a rigid base: f1 = {f1_measured:.4f} Hz (V_s/4H = {f1:.4f} Hz), "
        f"ξ(f1) = {math.pi * f1 * p['beta']:.3f}"
    )
    ax.legend()
    ax.grid(alpha=0.3, which="both")
    fig.tight_layout()
    write_figure(fig, pathlib.Path(report) / "transfer_function.png")

    fig, ax = plt.subplots(figsize=(8, 4))
    a_surface = rec[node_columns(rec, "ax")[0]]
    ax.plot(t, rec["base_ax"], label="base (input)")
    ax.plot(t, a_surface, label="surface")
    ax.set_xlim(0, min(t[-1], 6.0))
    ax.set_xlabel("t (s)")
    ax.set_ylabel("a_x (m/s²)")
    ax.set_title("Rigid base: absolute horizontal acceleration")
    ax.legend()
    ax.grid(alpha=0.3)
    fig.tight_layout()
    write_figure(fig, pathlib.Path(report) / "rigid_time_history.png")
    return {
        "f1": f1,
        "f1_measured": f1_measured,
        "f1_closed": f1_closed,
        "f1_error": f1_measured / f1 - 1,
        "transfer_error": error,
        "ok": abs(f1_measured / f1 - 1) <= RESONANCE_TOLERANCE,
    }


def compliant_column(case_dir, out, report, case_name="compliant.toml", figure="compliant"):
    p = column_properties(pathlib.Path(case_dir) / case_name)
    rec = read_table(pathlib.Path(out) / "recorders" / "surface.csv")
    motion = read_table(pathlib.Path(out) / "motion.csv")
    spec = p["case"]["fem"]["motion"]
    if spec.get("input", "incident") != "incident":
        raise SystemExit(f"{case_name}: the check expects input = \"incident\"")
    t = rec["time"]
    v = rec[node_columns(rec, "vx")[0]]
    travel = p["height"] / p["vs"]
    # The first passage: until the pulse's return could arrive, 2H/V_s after it.
    peak_time = t[np.argmax(np.abs(v))]
    first = t < peak_time + travel
    second = t >= peak_time + travel
    incident_peak = np.max(np.abs(motion["vx"]))
    surface_peak = np.max(np.abs(v[first]))
    doubling_error = surface_peak / (2 * incident_peak) - 1
    # Energy: the surface sees each upgoing wave doubled, so the energy of the wave the
    # base reflected relative to the incident one is the ratio of ∫v² of the passages.
    energy_first = np.trapz(v[first] ** 2, t[first])
    energy_second = np.trapz(v[second] ** 2, t[second])
    reflected = energy_second / energy_first

    fig, ax = plt.subplots(figsize=(8, 4))
    ax.plot(motion["time"], 2 * motion["vx"], "k-", lw=2.5, alpha=0.35, label="2 v_in(t)")
    ax.plot(t - travel, v, "C1-", lw=1, label=f"surface v_x(t + H/V_s)")
    ax.set_xlabel("t (s)")
    ax.set_ylabel("v_x (m/s)")
    ax.set_title(
        f"Compliant base: surface peak / 2 v_in = {1 + doubling_error:.4f}, "
        f"reflected energy {reflected:.2e}"
    )
    ax.legend()
    ax.grid(alpha=0.3)
    fig.tight_layout()
    write_figure(fig, pathlib.Path(report) / f"{figure}_time_history.png")
    return {
        "incident_peak": incident_peak,
        "surface_peak": surface_peak,
        "doubling_error": doubling_error,
        "reflected": reflected,
        "ok": abs(doubling_error) <= DOUBLING_TOLERANCE and reflected < REFLECTED_ENERGY_LIMIT,
    }


def column(case_dir, rigid_out, compliant_out, report, saturated_out=None):
    report = pathlib.Path(report)
    report.mkdir(parents=True, exist_ok=True)
    r = rigid_column(case_dir, rigid_out, report)
    c = compliant_column(case_dir, compliant_out, report)
    s = None
    if saturated_out:
        s = compliant_column(case_dir, saturated_out, report, "compliant-saturated.toml",
                             "saturated")
    plot_motion(pathlib.Path(rigid_out) / "motion.csv", report / "rigid_motion.png")
    plot_motion(pathlib.Path(compliant_out) / "motion.csv", report / "compliant_motion.png")
    verdict = lambda ok: "pass" if ok else "**FAIL**"  # noqa: E731
    text = f"""# column-seismic: verification of the shaken column

Made by `tools/seismic.py column` from the runs of `case.toml` (rigid base) and
`compliant.toml` (compliant base); docs/method.md §8, verifications 1 and 2.

| check | measured | expected | error | tolerance | |
|---|---|---|---|---|---|
| rigid base: first resonance f1 | {r['f1_measured']:.4f} Hz | V_s/4H = {r['f1']:.4f} Hz | {100 * r['f1_error']:+.3f} % | 1 % | {verdict(r['ok'])} |
| rigid base: peak of the closed form | {r['f1_measured']:.4f} Hz | {r['f1_closed']:.4f} Hz | {100 * (r['f1_measured'] / r['f1_closed'] - 1):+.3f} % | | |
| rigid base: transfer function, 0.5–15 Hz | | \\|1/cos(ωH/V_s*)\\| | max {100 * r['transfer_error']:.2f} % | | |
| compliant base: surface peak velocity | {c['surface_peak']:.5f} m/s | 2 v_in = {2 * c['incident_peak']:.5f} m/s | {100 * c['doubling_error']:+.3f} % | 3 % | {verdict(abs(c['doubling_error']) <= DOUBLING_TOLERANCE)} |
| compliant base: reflected energy | {c['reflected']:.2e} of the incident | 0 | | < 5 % | {verdict(c['reflected'] < REFLECTED_ENERGY_LIMIT)} |
{saturated_rows(s, verdict)}
The closed form's peak lies below V_s/4H because the damping (Kelvin–Voigt, ξ = πfβ_K)
lowers the resonance slightly; the 1 % check is against V_s/4H as docs/method.md states it.

![transfer function](transfer_function.png)

![rigid base, time history](rigid_time_history.png)

![compliant base, time history](compliant_time_history.png)
{"![saturated column, time history](saturated_time_history.png)" if s else ""}

![rigid base motion](rigid_motion.png)

![compliant base motion](compliant_motion.png)
"""
    write_text(report / "report.md", text)
    print(
        f"rigid: f1 = {r['f1_measured']:.4f} Hz ({100 * r['f1_error']:+.3f} % of V_s/4H), "
        f"transfer function within {100 * r['transfer_error']:.2f} % over 0.5–15 Hz; "
        f"compliant: surface peak {100 * c['doubling_error']:+.3f} % of 2 v_in, "
        f"reflected energy {c['reflected']:.2e}"
        + (f"; saturated: surface peak {100 * s['doubling_error']:+.3f} % of 2 v_in, "
           f"reflected energy {s['reflected']:.2e}" if s else "")
    )
    return 0 if r["ok"] and c["ok"] and (s is None or s["ok"]) else 1


def saturated_rows(s, verdict):
    """The saturated column's two rows of the report's table (none without it)."""
    if s is None:
        return ""
    return (
        f"| saturated column (u–p): surface peak velocity | {s['surface_peak']:.5f} m/s | "
        f"2 v_in = {2 * s['incident_peak']:.5f} m/s | {100 * s['doubling_error']:+.3f} % | 3 % | "
        f"{verdict(abs(s['doubling_error']) <= DOUBLING_TOLERANCE)} |\n"
        f"| saturated column (u–p): reflected energy | {s['reflected']:.2e} of the incident | 0 "
        f"| | < 5 % | {verdict(s['reflected'] < REFLECTED_ENERGY_LIMIT)} |\n"
    )


# --------------------------------------------------------------------------- sliding block


def newmark_slip(time, ground_acceleration, mu, theta=0.0):
    """The permanent slip of a rigid block on a plane inclined by θ (falling towards +x)
    with Coulomb friction μ, the plane shaken along itself with a_g(t) (Newmark's
    sliding-block integral, in the plane's frame: gravity g sin θ along it, g cos θ
    into it). The block sticks while the friction it needs, |a_g − g sin θ|, is at most
    μ g cos θ; sliding, its acceleration is g sin θ − μ g cos θ sign(v_rel) until the
    relative velocity returns to zero. Returns u_rel(t) on the given times."""
    along, normal = G * math.sin(theta), G * math.cos(theta)
    limit = mu * normal
    v_rel = 0.0
    u_rel = 0.0
    out = np.zeros_like(time)
    for k in range(1, len(time)):
        dt = time[k] - time[k - 1]
        ag = 0.5 * (ground_acceleration[k] + ground_acceleration[k - 1])
        if v_rel == 0.0:
            needed = ag - along  # the friction force per unit mass that sticking takes
            if abs(needed) > limit:
                # slides the way gravity and the base's inertia push it
                v_rel = (along - ag + math.copysign(limit, needed)) * dt
        else:
            new = v_rel + (along - math.copysign(limit, v_rel) - ag) * dt
            v_rel = 0.0 if new * v_rel < 0.0 else new
        u_rel += v_rel * dt
        out[k] = u_rel
    return out


def block_slip(checkpoint):
    """The time and the mass-weighted mean x displacement of the particles of an mpm
    checkpoint, relative to the base's displacement then (the grid motion's: a rigid
    base in these tests)."""
    import h5py

    with h5py.File(checkpoint, "r") as h5:
        time = float(h5.attrs["time"])
        u = h5["/particles/displacement"][:, 0]
        m = h5["/particles/mass"][:]
        base = 0.0
        if "motion" in h5:
            g = h5["motion"]
            samples = h5["/motion/displacement"][:, 0]
            t = g.attrs["start_time"] + g.attrs["step"] * np.arange(len(samples))
            base = float(np.interp(time, t, samples, left=0.0, right=samples[-1]))
    return time, float(np.sum(m * u) / np.sum(m)) - base


def sliding_block(case_path, fem_out, mpm_out, report, check="both"):
    with open(case_path, "rb") as f:
        case = tomllib.load(f)
    mu = case["fem"]["friction_coefficient"]
    theta = math.radians(case["case"].get("gravity_angle", 0.0))
    motion = read_table(pathlib.Path(fem_out) / "motion.csv")
    # Fine samples of the same motion (linear between its samples), from the start of
    # the failure stage (t = 0: a block on an incline may creep before the shaking).
    t = np.linspace(0.0, motion["time"][-1], 200001)
    a = np.interp(t, motion["time"], motion["ax"], left=0.0, right=0.0)
    slip = newmark_slip(t, a, mu, theta)
    expected = slip[-1]
    rec = read_table(pathlib.Path(fem_out) / "recorders" / "block.csv")
    fem_slip = rec[node_columns(rec, "ux_rel")[0]]
    fem_final = fem_slip[-1]
    mpm_times, mpm_slips = [], []
    for path in sorted(pathlib.Path(mpm_out).glob("mpm_t*.h5")) + [
        pathlib.Path(mpm_out) / "mpm_final.h5"
    ]:
        time, value = block_slip(path)
        mpm_times.append(time)
        mpm_slips.append(value)
    order = np.argsort(mpm_times)
    mpm_times, mpm_slips = np.array(mpm_times)[order], np.array(mpm_slips)[order]
    mpm_final = mpm_slips[-1]
    fem_error = fem_final / expected - 1
    mpm_error = mpm_final / expected - 1
    fig, ax = plt.subplots(figsize=(8, 4))
    ax.plot(t, slip, "k-", lw=2.5, alpha=0.35, label=f"Newmark integral: {expected:.4f} m")
    ax.plot(rec["time"], fem_slip, "C0-", lw=1, label=f"fem-solve: {fem_final:.4f} m")
    ax.plot(mpm_times, mpm_slips, "C1o--", label=f"mpm-solve checkpoints: {mpm_final:.4f} m")
    ax.set_xlabel("t (s)")
    ax.set_ylabel("slip relative to the base (m)")
    ax.set_title(
        f"Sliding block, μ = {mu}, incline {math.degrees(theta):g}°: FE {100 * fem_error:+.2f} %, "
        f"MPM {100 * mpm_error:+.2f} %"
    )
    ax.legend()
    ax.grid(alpha=0.3)
    fig.tight_layout()
    write_figure(fig, pathlib.Path(report) / "sliding_block.png")
    print(
        f"sliding block: Newmark {expected:.5f} m, fem-solve {fem_final:.5f} m "
        f"({100 * fem_error:+.2f} %), mpm-solve {mpm_final:.5f} m ({100 * mpm_error:+.2f} %)"
    )
    ok = abs(fem_error) <= NEWMARK_TOLERANCE
    if check == "both":
        ok = ok and abs(mpm_error) <= NEWMARK_TOLERANCE
    return 0 if ok else 1


def main(argv):
    if len(argv) >= 2 and argv[1] == "motion" and len(argv) == 4:
        plot_motion(argv[2], argv[3])
        return 0
    if len(argv) >= 2 and argv[1] == "column" and len(argv) in (6, 7):
        return column(*argv[2:])
    if len(argv) >= 2 and argv[1] == "sliding-block" and len(argv) == 6:
        return sliding_block(*argv[2:])
    if len(argv) == 8 and argv[1] == "sliding-block" and argv[6] == "--check" and argv[7] == "fe":
        return sliding_block(*argv[2:6], check="fe")
    print(__doc__, file=sys.stderr)
    return 2


if __name__ == "__main__":
    sys.exit(main(sys.argv))
