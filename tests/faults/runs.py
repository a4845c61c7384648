"""Running the three programs for the fault tests: the small case, the command lines,
the two ways of killing a run with SIGKILL, and a small tmpfs (tests/faults/README.md).

Every program runs with its own run folder as working directory and writes into
`out/` there (`out/particles.h5` for fem2mpm), its inputs given by absolute paths, so
that the paths the programs record (the transfer report's) are the same in every run.
"""
import os
import re
import signal
import subprocess
import time
from dataclasses import dataclass
from pathlib import Path

# A coarse, short column-short (cases/column-short/case.toml): 2.5 m elements (320) and
# cells, FE to 1.5 s with a checkpoint every 0.25 s and an output every 0.05 s, the
# transfer at 1 s with 2 × 2 points per element (1280 particles), MPM from 1 s to 1.5 s
# with a checkpoint every 0.1 s and an output (and a VTK frame) every 0.025 s. rbf-local
# warns of nothing on this mesh (the global RBF's limiter warns), so that a program's
# stderr holds its error line only.
CASE_CHANGES = {
    "mesh": {"element_size": "2.5"},
    "fem": {"end_time": "1.5", "checkpoint_every": "0.25", "output_every": "0.05"},
    "transfer": {"particles_per_element": "[2, 2]", "stress_interpolation": '"rbf-local"',
                 "main_time": "1.0", "sweep_times": "[0.0, 1.0]"},
    "mpm": {"domain": "[[0.0, 0.0], [100.0, 45.0]]", "cell_size": "2.5", "end_time": "1.5",
            "checkpoint_every": "0.1", "output_every": "0.025"},
}
FEM_END, TRANSFER_TIME, MPM_END = 1.5, 1.0, 1.5
# The syscalls a kill may be aimed at: the writes of every file and the renames that give
# a finished file its name (HDF5 writes with pwrite64; VTK, CSV and text with write and
# writev).
KILL_SYSCALLS = ("write", "writev", "pwrite64", "rename")


def write_small_case(source_case, target):
    """Writes the variant of `source_case` with CASE_CHANGES; every key must be found
    once in its table, so that a change of the original cannot go unnoticed."""
    table, found, lines = None, set(), []
    for line in Path(source_case).read_text().splitlines():
        header = re.match(r"^\[+([^\]]+)\]+", line)
        if header:
            table = header.group(1)
        key = re.match(r"^(\w+)\s*=", line)
        if key and key.group(1) in CASE_CHANGES.get(table, {}):
            if (table, key.group(1)) in found:
                raise RuntimeError(f"{source_case}: {table}.{key.group(1)} given twice")
            found.add((table, key.group(1)))
            line = f"{key.group(1)} = {CASE_CHANGES[table][key.group(1)]}"
        lines.append(line)
    missing = {(t, k) for t, keys in CASE_CHANGES.items() for k in keys} - found
    if missing:
        raise RuntimeError(f"{source_case}: no {sorted(missing)} to change")
    Path(target).parent.mkdir(parents=True, exist_ok=True)
    Path(target).write_text("\n".join(lines) + "\n")


@dataclass
class Programs:
    """The command lines of the three programs on the small case."""

    bin: Path
    case: Path
    reference: Path  # the reference runs' root: fem/, transfer/, mpm/

    def fem_solve(self, restart=None, quiet=True):
        # --no-disk-check: the run starts whatever its estimate, so that the disk fills
        # during it (the point of the disk-full tests; the estimate's refusal is tested in
        # tests/run and tests/mpi).
        line = [str(self.bin / "fem-solve"), str(self.case), "-o", "out", "--no-disk-check"]
        return line + (["--restart", str(restart)] if restart else []) + (["-q"] if quiet else [])

    def fem2mpm(self, quiet=True):
        checkpoint = self.reference / "fem" / "out" / f"fem_t{TRANSFER_TIME:.3f}.h5"
        return [str(self.bin / "fem2mpm"), str(checkpoint), "-o", "out/particles.h5", "--case",
                str(self.case)] + (["-q"] if quiet else [])

    def mpm_solve(self, restart=None, quiet=True):
        start = ["--restart", str(restart)] if restart else [
            "--particles", str(self.reference / "transfer" / "out" / "particles.h5")]
        return [str(self.bin / "mpm-solve"), str(self.case), "-o", "out", "--threads", "1",
                "--no-disk-check"] + \
            start + (["-q"] if quiet else [])

    def fresh(self, program):
        return {"fem-solve": self.fem_solve, "fem2mpm": self.fem2mpm,
                "mpm-solve": self.mpm_solve}[program]()


@dataclass
class Run:
    status: int  # the exit status, or -N when signal N ended the program
    stdout: str
    stderr: str
    seconds: float


# Instrumented builds (tools/sanitize.sh) run the programs 10-25 times slower: ctest
# passes the build's factor on the time limits below.
TIMEOUT_FACTOR = float(os.environ.get("SLIDE_TEST_TIMEOUT_FACTOR", "1"))


def run(command, folder, timeout=120):
    """Runs `command` in `folder` to its end, stdout and stderr captured."""
    Path(folder).mkdir(parents=True, exist_ok=True)
    started = time.monotonic()
    done = subprocess.run(command, cwd=folder, capture_output=True, text=True,
                          timeout=timeout * TIMEOUT_FACTOR)
    return Run(done.returncode, done.stdout, done.stderr, time.monotonic() - started)


def shell_line(command, folder):
    """The command as one line a user can paste to reproduce it."""
    return f"cd {folder} && " + " ".join(command)


# ---- killing


def strace_prefix():
    """strace, and in a sanitizer build (tools/sanitize.sh) the leak check off for the
    traced program: LeakSanitizer stops the program's threads with ptrace to scan its
    memory, which it cannot do under strace (it then reports false leaks of libhdf5's).
    The same programs' untraced runs still check for leaks."""
    if "ASAN_OPTIONS" not in os.environ:
        return ["strace"]
    return ["env", f"ASAN_OPTIONS={os.environ['ASAN_OPTIONS']}:detect_leaks=0", "strace"]


def strace_kill_prefix(syscall, count):
    """strace delivers SIGKILL on entering the `count`-th `syscall` of the program's
    main thread: the moment is the same in every run of the same build."""
    return strace_prefix() + ["-qq", "-o", "/dev/null", "-e", f"trace={syscall}",
                              "-e", f"inject={syscall}:signal=KILL:when={count}"]


def syscall_counts(command, folder):
    """How often the program's main thread enters each of KILL_SYSCALLS in one run, and
    the names its renames give, in order."""
    trace = Path(folder) / "strace.txt"
    done = run(strace_prefix() + ["-qq", "-o", str(trace), "-e",
                                  "trace=" + ",".join(KILL_SYSCALLS)] + command, folder)
    if done.status != 0:
        raise RuntimeError(f"{shell_line(command, folder)} under strace: status {done.status}: "
                           f"{done.stderr}")
    counts, renamed = dict.fromkeys(KILL_SYSCALLS, 0), []
    for line in trace.read_text().splitlines():
        name = line.split("(", 1)[0]
        if name in counts:
            counts[name] += 1
        if name == "rename":
            renamed.append(re.match(r'rename\("[^"]*", "([^"]*)"', line).group(1))
    trace.unlink()
    return counts, renamed


def kill_after(command, folder, seconds, timeout=120):
    """Starts `command` in `folder` and sends it SIGKILL after `seconds` (if it still
    runs)."""
    Path(folder).mkdir(parents=True, exist_ok=True)
    started = time.monotonic()
    with open(Path(folder) / "killed-stdout.txt", "w") as out, \
            open(Path(folder) / "killed-stderr.txt", "w") as err:
        process = subprocess.Popen(command, cwd=folder, stdout=out, stderr=err)
        try:
            process.wait(timeout=seconds)
        except subprocess.TimeoutExpired:
            process.send_signal(signal.SIGKILL)
        status = process.wait(timeout=timeout * TIMEOUT_FACTOR)
    return Run(status, "", (Path(folder) / "killed-stderr.txt").read_text(),
               time.monotonic() - started)


def strace_available():
    try:
        return subprocess.run(["strace", "-V"], capture_output=True).returncode == 0
    except FileNotFoundError:
        return False


# ---- a small disk


class SmallDisk:
    """A tmpfs of `kibibytes` mounted on `folder` for the life of a `with` block (as
    root; mounted is False otherwise, and nothing is mounted)."""

    def __init__(self, folder, kibibytes):
        self.folder, self.kibibytes, self.mounted = Path(folder), kibibytes, False

    def __enter__(self):
        self.folder.mkdir(parents=True, exist_ok=True)
        if os.geteuid() == 0:
            done = subprocess.run(["mount", "-t", "tmpfs", "-o", f"size={self.kibibytes}k",
                                   "slide-fault-tmpfs", str(self.folder)], capture_output=True)
            self.mounted = done.returncode == 0
        return self

    def __exit__(self, *_):
        if self.mounted:
            subprocess.run(["umount", str(self.folder)], check=True)
