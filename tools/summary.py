#!/usr/bin/python3
"""The cross-case summary of the transfer-time sweeps (docs/method.md §3, §6).

    /usr/bin/python3 tools/summary.py OUT_DIR CASE_DIR[:CASE_OUT] ...

For every case folder given (its case.toml, and its outputs in CASE_OUT, default
CASE_DIR/out) that has a sweep.csv, writes to OUT_DIR:
  - rmse_vs_mesh_quality.png: the profile RMSE of every transfer of every case against
    the FE mesh quality at its transfer time, (|J_t|/|J_0|)_avg and εq,avg, one marker
    per case, with the recommended transfer zone shaded;
  - report.md: that figure and each case's sweep table (its sweep.md).
`make -C cases summary` (and the end of `make -C cases validate`) runs it on the five
cases. Debian's python3-matplotlib only.
"""
import csv
import pathlib
import sys
import tomllib

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

ZONE_JACOBIAN_AVG = 0.97  # docs/method.md §3: recommended transfer zone
ZONE_EPS_Q_AVG = 0.20
MARKERS = "osD^vP*X"


def read_sweep(path):
    with open(path, newline="") as f:
        rows = [r for r in csv.DictReader(f) if r["run"].startswith("tt") and r["rmse"] != ""]
    for r in rows:
        # No element has εq > 3 % yet (t_T = 0): the undistorted mesh, (1, 0 %).
        if r["jacobian_ratio_avg"] in ("", "nan"):
            r["jacobian_ratio_avg"], r["eps_q_avg"] = "1", "0"
    return sorted(rows, key=lambda r: float(r["tt"]))


def main():
    if len(sys.argv) < 3:
        sys.exit("usage: summary.py OUT_DIR CASE_DIR[:CASE_OUT] ...")
    out = pathlib.Path(sys.argv[1])
    out.mkdir(parents=True, exist_ok=True)
    cases = []
    for arg in sys.argv[2:]:
        case_dir, _, case_out = arg.partition(":")
        case_dir = pathlib.Path(case_dir)
        case_out = pathlib.Path(case_out) if case_out else case_dir / "out"
        sweep = case_out / "sweep.csv"
        if not sweep.exists():
            print(f"summary.py: {case_dir.name}: no {sweep}, skipped", file=sys.stderr)
            continue
        with open(case_dir / "case.toml", "rb") as f:
            name = tomllib.load(f)["case"]["name"]
        cases.append((name, case_out, read_sweep(sweep)))
    if not cases:
        sys.exit("summary.py: no case with a sweep.csv (run `make sweep` first)")

    fig, (ax1, ax2) = plt.subplots(1, 2, figsize=(11, 4.5), sharey=True)
    ax1.axvspan(ZONE_JACOBIAN_AVG, 1.02, color="g", alpha=0.08, lw=0)
    ax2.axvspan(0.0, 100 * ZONE_EPS_Q_AVG, color="g", alpha=0.08, lw=0)
    for k, (name, _, rows) in enumerate(cases):
        if not rows:
            continue
        j = [float(r["jacobian_ratio_avg"]) for r in rows]
        e = [100 * float(r["eps_q_avg"]) for r in rows]
        rmse = [float(r["rmse"]) for r in rows]
        style = dict(marker=MARKERS[k % len(MARKERS)], ls="-", lw=0.8, label=name)
        ax1.plot(j, rmse, **style)
        ax2.plot(e, rmse, **style)
        for ax, x in ((ax1, j), (ax2, e)):
            for xi, yi, r in zip(x, rmse, rows):
                ax.annotate(f"{float(r['tt']):g} s", (xi, yi), fontsize=6, xytext=(3, 2),
                            textcoords="offset points")
    ax1.axvline(ZONE_JACOBIAN_AVG, color="g", ls=":", label="zone: (|J_t|/|J_0|)_avg ≥ 0.97")
    ax2.axvline(100 * ZONE_EPS_Q_AVG, color="g", ls=":", label="zone: εq,avg ≤ 20 %")
    ax1.set_xlabel("(|J_t|/|J_0|)_avg at the transfer (elements with εq > 3 %)")
    ax2.set_xlabel("εq,avg at the transfer (%)")
    ax1.set_ylabel("profile RMSE against t_T = 0")
    ax1.invert_xaxis()  # distortion grows to the right in both panels
    for ax in (ax1, ax2):
        ax.grid(alpha=0.3)
        ax.legend(fontsize=7)
    fig.suptitle("Runout profile error of every transfer against the FE mesh quality "
                 "(shaded: the recommended transfer zone)", fontsize=10)
    figure = out / "rmse_vs_mesh_quality.png"
    tmp = figure.with_name(figure.stem + ".tmp.png")
    fig.savefig(tmp, dpi=110, bbox_inches="tight")
    plt.close(fig)
    tmp.replace(figure)

    md = ["# Transfer-time sweeps of every case", "",
          "Profile RMSE (docs/method.md §6, against each case's t_T = 0 transfer) against the FE",
          "mesh quality at the transfer time; the shaded bands are the recommended zone",
          "((|J_t|/|J_0|)_avg ≥ 0.97, εq,avg ≤ 20 %, both over the elements with εq > 3 %).",
          "", "![RMSE against mesh quality](rmse_vs_mesh_quality.png)", ""]
    for name, case_out, _ in cases:
        md += [f"## {name}", ""]
        table = case_out / "sweep.md"
        md += [table.read_text().strip() if table.exists() else "(no sweep.md)", ""]
        report = case_out / "report" / "report.md"
        if report.exists():
            md += [f"Full report: `{report}`.", ""]
    tmp = out / "report.md.tmp"
    tmp.write_text("\n".join(md) + "\n")
    tmp.replace(out / "report.md")
    print(f"summary.py: wrote {out / 'report.md'} and {figure}")


if __name__ == "__main__":
    main()
