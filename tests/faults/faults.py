#!/usr/bin/python3
"""Fault tests of fem-solve, fem2mpm and mpm-solve: a full disk and kill -9
(tests/faults/README.md says what is checked and why).

    faults.py reference    BIN SOURCE WORK            the uninterrupted runs (the fixture)
    faults.py disk-full    BIN SOURCE WORK PROGRAM     a tmpfs too small, several sizes
    faults.py kill         BIN SOURCE WORK PROGRAM [--seed S] [--only N]
    faults.py kill-restart BIN SOURCE WORK [--seed S] [--only N]   mpm-solve killed twice

BIN holds the programs, SOURCE is the repository, WORK the folder of the runs (the
reference runs in WORK/reference/). Exit status 0 when every check passes, 1 when one
fails, 77 when the test cannot run here (disk-full without root, kills without strace).
"""
import argparse
import json
import os
import random
import re
import shutil
import sys
import time
from dataclasses import dataclass
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
import outputs  # noqa: E402
import runs  # noqa: E402

SKIP = 77
PROGRAMS = ("fem-solve", "fem2mpm", "mpm-solve")
ENOSPC = "No space left on device"

# Failures of the programs these tests found, that a fix of the programs removes. Each
# is reported on every occurrence; where the circumstances that make it happen are
# recognisable, the test fails when it does not happen any more, so that the entry is
# removed with the fix.
KNOWN_FAILURES = {
    # Empty since the fixes of 2026-12-02 (tests/faults/README.md, "Known failures"):
    # vtk-stderr, hdf5-flush, text-write, report-rename, mpm-start-restart, fem-t0-outputs.
    # The moments that showed them stay among the kills (known_failure_moments) and must
    # now pass like any other.
}
# The checkpoint a run of mpm-solve from a particle file writes at its start.
START_CHECKPOINT = f"mpm_t{runs.TRANSFER_TIME:.3f}.h5"
# fem-solve's geostatic checkpoint, written before the outputs of t = 0 (the others are
# written after the outputs of their time), and those outputs.
GEOSTATIC_CHECKPOINT = "fem_t0.000.h5"
FEM_T0_OUTPUTS = ("fem_history.csv", "vtk/fem_000000.vtu", "fem.pvd",
                  "vtk/fem_gauss_points_000000.vtu", "fem_gauss_points.pvd")


class Findings:
    """The problems of one test: failures, and occurrences of KNOWN_FAILURES."""

    def __init__(self):
        self.failures, self.known = [], []

    def add(self, where, problems, known=None):
        """`problems` of one check at `where`; with `known`, one occurrence of it."""
        if not problems:
            return
        if known in KNOWN_FAILURES:
            self.known.append(known)
            more = f" (and {len(problems) - 1} more)" if len(problems) > 1 else ""
            print(f"  KNOWN FAILURE {known}: {where}: {problems[0]}{more}")
            return
        self.failures += [f"{where}: {p}" for p in problems]
        print(f"  FAIL {where}:")
        for problem in problems:
            print(f"    {problem}")

    def require_known(self, where, known, occurred):
        """`known` was expected here: not seeing it is a failure (the program was fixed?)."""
        if known in KNOWN_FAILURES and not occurred:
            self.add(where, [f"known failure {known} did not occur: if the program was fixed, "
                             "remove it from KNOWN_FAILURES in tests/faults/faults.py"])

    def exit_status(self, seconds):
        for known in sorted(set(self.known)):
            print(f"known failure {known} ({self.known.count(known)}x): {KNOWN_FAILURES[known]}")
        print(f"{len(self.failures)} failure(s), {len(self.known)} known failure(s), "
              f"{seconds:.1f} s")
        return 1 if self.failures else 0


@dataclass
class Context:
    programs: runs.Programs
    schema: outputs.Schema
    work: Path
    # program -> {"seconds": wall time, "counts": syscall counts, "renamed": rename targets}
    reference_runs: dict

    def reference_out(self, program):
        return self.work / "reference" / reference_folder(program) / "out"


def reference_folder(program):
    return {"fem-solve": "fem", "fem2mpm": "transfer", "mpm-solve": "mpm"}[program]


def fresh_folder(folder):
    shutil.rmtree(folder, ignore_errors=True)
    folder.mkdir(parents=True)
    return folder


def context(args):
    work = Path(args.work).resolve()
    case = work / "case.toml"
    programs = runs.Programs(Path(args.bin).resolve(), case, work / "reference")
    schema = outputs.Schema(Path(args.source) / "common" / "io" / "checkpoint-schema.md")
    reference_file = work / "reference" / "runs.json"
    reference_runs = json.loads(reference_file.read_text()) if reference_file.exists() else {}
    return Context(programs, schema, work, reference_runs)


# ---- the reference runs


def reference(args):
    """Runs the three programs uninterrupted, each twice (the second under strace, which
    counts the syscalls a kill may be aimed at): the two must give the same outputs, or
    no comparison with them would mean anything."""
    started, findings = time.monotonic(), Findings()
    ctx = context(args)
    runs.write_small_case(Path(args.source) / "cases" / "column-short" / "case.toml",
                          ctx.programs.case)
    counted = runs.strace_available()
    for program in PROGRAMS:
        folder = fresh_folder(ctx.work / "reference" / reference_folder(program))
        done = runs.run(ctx.programs.fresh(program), folder)
        findings.add(program, [f"status {done.status}: {done.stderr}"] if done.status else [])
        findings.add(program, outputs.complete_file_problems(folder / "out", ctx.schema))
        counts, renamed = {}, []
        if counted:
            again = fresh_folder(ctx.work / "reference" / (reference_folder(program) + "-again"))
            counts, renamed = runs.syscall_counts(ctx.programs.fresh(program), again)
            findings.add(f"{program}, the same run again",
                         outputs.difference_problems(again / "out", folder / "out"))
        ctx.reference_runs[program] = {"seconds": done.seconds, "counts": counts,
                                       "renamed": renamed}
        print(f"{program}: {done.seconds:.2f} s, {len(outputs.final_files(folder / 'out'))} "
              f"files, syscalls {counts or '(no strace: not counted)'}")
    (ctx.work / "reference" / "runs.json").write_text(json.dumps(ctx.reference_runs, indent=1))
    return findings.exit_status(time.monotonic() - started)


# ---- a full disk

# Disk sizes as fractions of what the reference run's outputs occupy: spread so that the
# disk fills inside checkpoints and inside VTK frames (checked: `covered`). mpm-solve's
# checkpoints are a small share of its outputs (the frames are larger): 0.05, 0.235 and
# 0.415 fall inside its first three (the reference's files, in the order written).
DISK_FRACTIONS = {
    "fem-solve": (0.01, 0.04, 0.08, 0.13, 0.2, 0.28, 0.37, 0.47, 0.58, 0.7, 0.82, 0.93),
    "fem2mpm": (0.02, 0.25, 0.5, 0.75, 0.97),
    "mpm-solve": (0.01, 0.05, 0.13, 0.235, 0.28, 0.415, 0.58, 0.7, 0.82, 0.93),
}
NEEDS_FULL_DISK_IN = {"fem-solve": {".h5", ".vtu"}, "fem2mpm": {".h5"},
                      "mpm-solve": {".h5", ".vtu"}}


def disk_use_kib(folder):
    """What the files under `folder` occupy on a tmpfs: whole 4 KiB pages."""
    return sum(-(-(folder / f).stat().st_size // 4096) * 4 for f in outputs.files_of(folder))


def error_line_findings(program, stderr):
    """The stderr of a run that hit the full disk: one line, `PROGRAM: error: …`, naming
    "No space left on device"; returned with the suffix of the file it names."""
    lines = stderr.splitlines()
    line = lines[-1] if lines else ""
    named = re.search(r"(\S+?\.(h5|vtu|pvd|csv|txt|json))\b", line)
    suffix = Path(named.group(1)).suffix if named else ""
    found = []  # (problem, known failure or None)
    if not line.startswith(f"{program}: error: "):
        found.append((f"the last stderr line is not an error line: {line!r}", None))
    if len(lines) != 1:
        found.append((f"stderr has {len(lines)} lines, expected 1: {lines[:2]}",
                      "vtk-stderr" if suffix == ".vtu" else None))
    elif suffix == ".vtu":
        found.append(("a full disk inside a VTK frame gave one stderr line", "fixed:vtk-stderr"))
    # HDF5's flush at the close, and write_text_atomically (HDF5's own detail says "file
    # write failed", without the colon).
    flush, text = "cannot write the file (" in line, ": write failed" in line
    if ENOSPC not in line:
        known = "hdf5-flush" if flush else ("text-write" if text else None)
        found.append((f"the error does not name {ENOSPC!r}: {line}", known))
    elif flush or text:
        found.append((f"the error names {ENOSPC!r}", "fixed:" + ("hdf5-flush" if flush else
                                                                  "text-write")))
    return suffix, found


def report_error_line(findings, where, found):
    for problem, known in found:
        if known and known.startswith("fixed:"):
            findings.require_known(f"{where}: {problem}", known[len("fixed:"):], False)
        else:
            findings.add(where, [problem], known)


def one_full_disk(ctx, program, kib, findings):
    """One run on a tmpfs of `kib` KiB; returns the suffix of the file the error names."""
    folder = fresh_folder(ctx.work / "disk-full" / program / f"{kib}k")
    with runs.SmallDisk(folder / "disk", kib) as disk:
        if not disk.mounted:
            return None
        command = ctx.programs.fresh(program)
        done = runs.run(command, disk.folder)
        where = f"{program} on {kib} KiB ({runs.shell_line(command, disk.folder)})"
        out = disk.folder / "out"
        if not 1 <= done.status <= 127:
            findings.add(where, [f"exit status {done.status}, expected 1-127 (the disk did "
                                 "not fill, or the program crashed)"])
        suffix, found = error_line_findings(program, done.stderr)
        report_error_line(findings, where, found)
        findings.add(where, outputs.complete_file_problems(out, ctx.schema))
        findings.add(where, outputs.reference_problems(out, ctx.reference_out(program)))
        findings.add(where, [f"{t}: a temporary left behind" for t in outputs.temporaries(out)])
        print(f"{program} on {kib:5d} KiB: status {done.status}, "
              f"{len(outputs.final_files(out))} files, full inside a {suffix or '?'} file")
        return suffix


def disk_full(args):
    started, findings = time.monotonic(), Findings()
    ctx = context(args)
    program = args.program
    total = disk_use_kib(ctx.reference_out(program))
    covered = set()
    for fraction in DISK_FRACTIONS[program]:
        kib = max(4, 4 * round(fraction * total / 4))
        suffix = one_full_disk(ctx, program, kib, findings)
        if suffix is None:
            print(f"SKIPPED: could not mount a {kib} KiB tmpfs (it needs root; running as "
                  f"uid {os.geteuid()})")
            return SKIP
        covered.add(suffix)
    missing = NEEDS_FULL_DISK_IN[program] - covered
    findings.add(program, [f"no disk size filled the disk inside a {s} file: change "
                           f"DISK_FRACTIONS" for s in sorted(missing)])
    return findings.exit_status(time.monotonic() - started)


# ---- kill -9


@dataclass
class Moment:
    """When a run gets SIGKILL: on entering the `count`-th `syscall` (strace), or after
    `seconds`. `known`: the known failure this moment is expected to show."""

    syscall: str = ""
    count: int = 0
    seconds: float = 0.0
    known: str = ""
    note: str = ""  # why this moment, when it is not drawn at random

    def describe(self):
        note = f" ({self.note})" if self.note else ""
        if self.syscall:
            return f"SIGKILL on entering {self.syscall} #{self.count}{note}"
        return f"SIGKILL after {self.seconds:.3f} s{note}"

    def command(self, command):
        return runs.strace_kill_prefix(self.syscall, self.count) + command if self.syscall \
            else command

    def run(self, command, folder):
        if self.syscall:
            return runs.run(self.command(command), folder)
        return runs.kill_after(command, folder, self.seconds)


def draw_moments(rng, reference_run, by_syscall, by_time):
    """`by_syscall` moments at a random syscall of the kinds the reference run makes
    (kind, then its number, uniformly), `by_time` at a random fraction of its wall time."""
    counts = {s: n for s, n in reference_run["counts"].items() if n > 0}
    moments = []
    for _ in range(by_syscall):
        syscall = rng.choice(sorted(counts))
        moments.append(Moment(syscall=syscall, count=rng.randint(1, counts[syscall])))
    moments += [Moment(seconds=rng.uniform(0.0, reference_run["seconds"]))
                for _ in range(by_time)]
    return moments


def kill_status_problems(killed):
    """-9: killed; 0: it ended before the kill came; anything else: it failed by itself."""
    if killed.status in (-9, 0):
        return []
    return [f"the run ended with status {killed.status} before its kill: {killed.stderr.strip()}"]


def latest_checkpoint(out, prefix, end_time):
    """The checkpoint of the latest time before the end under `out` (None: none)."""
    times = []
    for path in out.glob(f"{prefix}_t*.h5"):
        t = float(path.name[len(prefix) + 2:-3])
        if t < end_time - 1e-9:
            times.append((t, path))
    return max(times)[1] if times else None


def rerun_problems(program, rerun, left, out):
    """The run after a kill: status 0, nothing on stderr but warnings (printed: a restart
    may warn that the killed run wrote no history yet), no temporary in `out`, and those
    the killed run left (`left`) counted as removed."""
    problems = [] if rerun.status == 0 else [f"status {rerun.status}: {rerun.stderr.strip()}"]
    for line in rerun.stderr.splitlines():
        if line.startswith(f"{program}: warning: "):
            print(f"  note: the continuation warns: {line}")
        elif rerun.status == 0:
            problems.append(f"stderr has a line that is no warning: {line!r}")
    said = re.search(r"removed (\d+) temporary file", rerun.stdout)
    removed = int(said.group(1)) if said else 0
    if removed != len(left):
        problems.append(f"said it removed {removed} temporary file(s); the killed run left "
                        f"{len(left)}: {[str(t) for t in left]}")
    return (problems + [f"{t}: a temporary left behind" for t in outputs.temporaries(out)] +
            [f"{t}: the run after the kill left the output lock" for t in outputs.locks(out)])


def after_kill_problems(ctx, program, out):
    """What a killed (or full-disk) run leaves: complete files, each the reference's."""
    return outputs.complete_file_problems(out, ctx.schema) + \
        outputs.reference_problems(out, ctx.reference_out(program))


def restart_command(ctx, program, out, quiet=False):
    """The restart from the latest checkpoint in `out`, or a fresh run without one: the
    command, what it does in words, the checkpoint (None). Not quiet: its log says how
    many temporaries it removed."""
    prefix, end = ("fem", runs.FEM_END) if program == "fem-solve" else ("mpm", runs.MPM_END)
    checkpoint = latest_checkpoint(out, prefix, end)
    solve = ctx.programs.fem_solve if program == "fem-solve" else ctx.programs.mpm_solve
    restart = checkpoint.relative_to(out.parent) if checkpoint else None
    return solve(restart=restart, quiet=quiet), \
        f"restart from {restart}" if restart else "no checkpoint: a fresh run", checkpoint


def continuation(ctx, program, out):
    """The run after a kill: a restart, or for fem2mpm the same command again."""
    if program == "fem2mpm":
        return ctx.programs.fem2mpm(quiet=False), "the same transfer again", None
    return restart_command(ctx, program, out)


def from_start_checkpoint(program, checkpoints):
    """The known failure of outputs that continue a restart from START_CHECKPOINT."""
    started = program == "mpm-solve" and any(c and c.name == START_CHECKPOINT for c in checkpoints)
    return "mpm-start-restart" if started else None


def known_continuation_failure(program, checkpoint, out):
    """The known failure that makes the outputs of a restart from `checkpoint` differ,
    judged from what the killed run left in `out` (before the restart), or None."""
    if program == "fem-solve" and checkpoint and checkpoint.name == GEOSTATIC_CHECKPOINT:
        present = [(out / name).exists() for name in FEM_T0_OUTPUTS]
        return "fem-t0-outputs" if present[0] and not all(present) else None
    return from_start_checkpoint(program, [checkpoint])


def unpaired_report_findings(out, findings, where):
    """transfer/README.md: a particle file is never left without the report of its run.
    Returns whether one was left without the other."""
    particles, report = (out / "particles.h5").exists(), (out / "particles.transfer.json").exists()
    findings.add(where, ["out/particles.h5 without out/particles.transfer.json"]
                 if particles and not report else [], "report-rename")
    # The report without its particle file is what a kill between the two renames leaves
    # (write_pair_atomically): the missing particle file makes a pipeline run fem2mpm again.
    return particles != report


def kill_trial(ctx, program, moment, folder, findings):
    """Kills a run; checks what it left; continues it (continuation()) and compares the
    outputs with the reference run's. Returns whether the run was killed and how many
    temporaries it left."""
    out = fresh_folder(folder) / "out"
    command = ctx.programs.fresh(program)
    where = f"{program}, {moment.describe()} ({runs.shell_line(moment.command(command), folder)})"
    killed = moment.run(command, folder)
    findings.add(where, kill_status_problems(killed) + after_kill_problems(ctx, program, out))
    if program == "fem2mpm":
        unpaired = unpaired_report_findings(out, findings, where)
        if moment.known == "report-rename":
            findings.require_known(where, moment.known, unpaired)
    left, files = outputs.temporaries(out), len(outputs.final_files(out))
    again, what, checkpoint = continuation(ctx, program, out)
    known = known_continuation_failure(program, checkpoint, out)
    rerun = runs.run(again, folder)
    where_again = f"{where}, then {what} ({runs.shell_line(again, folder)})"
    findings.add(where_again, rerun_problems(program, rerun, left, out))
    differences = outputs.difference_problems(out, ctx.reference_out(program))
    findings.add(where_again, differences, known)
    if moment.known in ("mpm-start-restart", "fem-t0-outputs") and moment.known in KNOWN_FAILURES:
        findings.add(where, [] if known == moment.known else
                     [f"the kill did not leave what {moment.known} needs: it came elsewhere"])
        findings.require_known(where_again, moment.known, bool(differences))
    print(f"  status {killed.status}, {files} files and {len(left)} temporaries left; {what}: "
          f"status {rerun.status}")
    return killed.status == -9, len(left)


KILLS = {"fem-solve": (4, 2), "fem2mpm": (4, 2), "mpm-solve": (4, 2)}  # by syscall, by time


def seeded_rng(args):
    seed = args.seed if args.seed is not None else random.SystemRandom().randrange(2**31)
    args.seed = seed
    print(f"seed {seed} (repeat with --seed {seed})")
    return random.Random(seed)


def reproduce_line(args, number):
    program = f" {args.program}" if args.program else ""
    return (f"  reproduce: {sys.argv[0]} {args.test} {args.bin} {args.source} {args.work}"
            f"{program} --seed {args.seed} --only {number}")


def run_trials(args, trials, findings):
    """Runs trials [(label, folder, function)] (all, or --only N), each printed with its
    number. A trial that fails prints how to repeat it alone and keeps its folder; the
    folder of one that passes is removed."""
    for number, (label, folder, trial) in enumerate(trials, 1):
        if args.only and number != args.only:
            continue
        print(f"{args.test} {number}: {label}")
        failures = len(findings.failures)
        trial()
        if len(findings.failures) > failures:
            print(reproduce_line(args, number))
        else:
            shutil.rmtree(folder)


def known_failure_moments(program, renamed):
    """The moments that show a known failure every time, found among the renames of the
    reference run (`renamed`, in order)."""
    if program == "fem2mpm":
        return [Moment(syscall="rename", count=renamed.index("out/particles.transfer.json") + 1,
                       known="report-rename", note="the report's rename")]
    if program == "mpm-solve":
        return [Moment(syscall="rename", count=renamed.index(f"out/{START_CHECKPOINT}") + 2,
                       known="mpm-start-restart",
                       note=f"the first rename after that of {START_CHECKPOINT}")]
    frame = f"out/{FEM_T0_OUTPUTS[3]}"
    return [Moment(syscall="rename", count=renamed.index(frame) + 1, known="fem-t0-outputs",
                   note=f"the rename of {frame}")]


def kill(args):
    started, findings = time.monotonic(), Findings()
    if not runs.strace_available():
        print("SKIPPED: strace is missing (tools/install-deps.sh installs it)")
        return SKIP
    ctx = context(args)
    program = args.program
    moments = draw_moments(seeded_rng(args), ctx.reference_runs[program], *KILLS[program])
    moments += known_failure_moments(program, ctx.reference_runs[program]["renamed"])
    results = []
    folders = [ctx.work / "kill" / program / str(n) for n in range(1, len(moments) + 1)]
    run_trials(args, [(m.describe(), f, lambda m=m, f=f: results.append(kill_trial(
        ctx, program, m, f, findings))) for m, f in zip(moments, folders)], findings)
    killed, left = sum(r[0] for r in results), sum(r[1] for r in results)
    print(f"{program}: {killed} of {len(results)} runs killed, {left} temporaries left by them")
    if not args.only and left == 0:
        findings.add(program, ["no kill left a temporary: the cleaning was not tested"])
    return findings.exit_status(time.monotonic() - started)


# ---- a kill during the restart (mpm-solve)


def restart_moment(rng, counts, checkpoint):
    """A random syscall of what is left of the run after `checkpoint` (its share of the
    reference's counts: the same files at the same cadence)."""
    start = float(checkpoint.name[len("mpm_t"):-len(".h5")]) if checkpoint \
        else runs.TRANSFER_TIME
    share = (runs.MPM_END - start) / (runs.MPM_END - runs.TRANSFER_TIME)
    syscall = rng.choice(sorted(s for s, n in counts.items() if n > 0))
    return Moment(syscall=syscall, count=rng.randint(1, max(1, int(share * counts[syscall]))))


def killed_restart(ctx, rng, folder, findings):
    """mpm-solve killed at a random syscall, its restart killed at a random syscall of
    its own, a second restart to the end: the outputs must be the reference's. Returns
    how many of the two runs were killed."""
    out = fresh_folder(folder) / "out"
    first = draw_moments(rng, ctx.reference_runs["mpm-solve"], 1, 0)[0]
    command = ctx.programs.mpm_solve()
    where = f"mpm-solve, {first.describe()} ({runs.shell_line(first.command(command), folder)})"
    killed = first.run(command, folder)
    findings.add(where, kill_status_problems(killed) + after_kill_problems(ctx, "mpm-solve", out))
    left_first = outputs.temporaries(out)
    # Quiet, as the reference run whose syscalls were counted (the log's lines are writes).
    restart, what, checkpoint = restart_command(ctx, "mpm-solve", out, quiet=True)
    second = restart_moment(rng, ctx.reference_runs["mpm-solve"]["counts"], checkpoint)
    where += f", then {what} with {second.describe()} " \
        f"({runs.shell_line(second.command(restart), folder)})"
    killed_again = second.run(restart, folder)
    left = outputs.temporaries(out)
    # The restart removes the first run's temporaries before it writes anything, so
    # before any syscall it can be killed at.
    not_removed = [f"{t}: the first run's temporary, not removed by the restart"
                   for t in set(left_first) & set(left)]
    findings.add(where, kill_status_problems(killed_again) + not_removed)
    findings.add(where, after_kill_problems(ctx, "mpm-solve", out),
                 from_start_checkpoint("mpm-solve", [checkpoint]))
    final, final_what, final_checkpoint = restart_command(ctx, "mpm-solve", out)
    rerun = runs.run(final, folder)
    where += f", then {final_what} ({runs.shell_line(final, folder)})"
    findings.add(where, rerun_problems("mpm-solve", rerun, left, out))
    findings.add(where, outputs.difference_problems(out, ctx.reference_out("mpm-solve")),
                 from_start_checkpoint("mpm-solve", [checkpoint, final_checkpoint]))
    print(f"  status {killed.status}, {len(left_first)} temporaries left; {what} with "
          f"{second.describe()}: status {killed_again.status}, {len(left)} temporaries left; "
          f"{final_what}: status {rerun.status}")
    return (killed.status == -9) + (killed_again.status == -9)


def kill_restart(args):
    started, findings = time.monotonic(), Findings()
    if not runs.strace_available():
        print("SKIPPED: strace is missing (tools/install-deps.sh installs it)")
        return SKIP
    ctx = context(args)
    rng = seeded_rng(args)
    # Each trial its own generator, so that --only N draws what the whole test draws.
    seeds = [rng.randrange(2**31) for _ in range(2)]
    results = []
    folders = [ctx.work / "kill-restart" / str(n) for n in range(1, len(seeds) + 1)]
    run_trials(args, [("mpm-solve killed, its restart killed, restarted again", f,
                       lambda s=s, f=f: results.append(killed_restart(
                           ctx, random.Random(s), f, findings)))
                      for s, f in zip(seeds, folders)], findings)
    print(f"mpm-solve: {sum(results)} of {2 * len(results)} runs killed (first runs and "
          "restarts)")
    return findings.exit_status(time.monotonic() - started)


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("test", choices=("reference", "disk-full", "kill", "kill-restart"))
    parser.add_argument("bin")
    parser.add_argument("source")
    parser.add_argument("work")
    parser.add_argument("program", nargs="?", choices=PROGRAMS)
    parser.add_argument("--seed", type=int)
    parser.add_argument("--only", type=int, help="run only this kill (its number)")
    args = parser.parse_args()
    if args.test in ("disk-full", "kill") and not args.program:
        parser.error(f"{args.test} needs a PROGRAM")
    test = {"reference": reference, "disk-full": disk_full, "kill": kill,
            "kill-restart": kill_restart}[args.test]
    sys.exit(test(args))


if __name__ == "__main__":
    main()
