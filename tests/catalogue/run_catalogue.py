#!/usr/bin/python3
"""Runs the bad-input catalogue: every entry of entries.toml must be refused cleanly.

For each entry (made by make_catalogue.py into WORK/entries/<id>/) the program must
  - exit with a status in 1..127 within the entry's timeout (not 0: "accepted"; not a
    signal or a status >= 128: "crash"; not still running: "hang"),
  - write exactly one line to stderr, valid UTF-8, that contains the entry's fragment
    (the key, dataset or problem it must name; else "wrong message"),
  - leave every file of the entry's folder (its inputs and its output folder) as it was:
    no file with a final name created, changed or removed ("file changed"); hidden
    temporaries .NAME.tmp-PID are not final names and are ignored.
Entries marked expected_failure = "reason" are known program bugs: they are reported as
XFAIL, and as XPASS (a failure, so that the mark is removed) once the program passes.

    /usr/bin/python3 tests/catalogue/run_catalogue.py --bin BUILD/bin --work WORK [ID ...]

Exit status 0 when every entry is clean or XFAIL, 1 otherwise.
"""

import argparse
import hashlib
import os
import re
import signal
import subprocess
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
import make_catalogue  # noqa: E402  (next to this file)

TEMPORARY = re.compile(r"^\..+\.tmp-[0-9]+$")


def snapshot(folder):
    """relative path -> (size, sha256) of every final-named file under folder, and
    relative path + "/" -> "folder" for every folder (an output folder left behind)."""
    entries = {}
    for root, dirs, names in os.walk(folder):
        for name in dirs:
            entries[str((Path(root) / name).relative_to(folder)) + "/"] = "folder"
        for name in names:
            path = Path(root) / name
            if TEMPORARY.match(name) or not path.is_file() or path.is_symlink():
                continue
            data = path.read_bytes()
            entries[str(path.relative_to(folder))] = (len(data), hashlib.sha256(data).hexdigest())
    return entries


def file_changes(before, after):
    changes = [f"created {p}" for p in sorted(after.keys() - before.keys())]
    changes += [f"removed {p}" for p in sorted(before.keys() - after.keys())]
    changes += [f"changed {p}" for p in sorted(before.keys() & after.keys())
                if before[p] != after[p]]
    return changes


# Instrumented builds (tools/sanitize.sh) run the programs 10-25 times slower: ctest
# passes the build's factor on the entries' time limits.
TIMEOUT_FACTOR = float(os.environ.get("SLIDE_TEST_TIMEOUT_FACTOR", "1"))


def run_program(record):
    """(exit status or None after the timeout, stderr bytes, seconds)."""
    start = time.monotonic()
    process = subprocess.Popen(record["argv"], cwd=record["folder"], stdin=subprocess.DEVNULL,
                               stdout=subprocess.DEVNULL, stderr=subprocess.PIPE,
                               env=dict(os.environ, OMP_NUM_THREADS="1"),
                               start_new_session=True)
    try:
        _, err = process.communicate(timeout=record["timeout"] * TIMEOUT_FACTOR)
        status = process.returncode
    except subprocess.TimeoutExpired:
        os.killpg(process.pid, signal.SIGKILL)
        _, err = process.communicate()
        status = None
    return status, err, time.monotonic() - start


def run_entry(record):
    """Runs one entry; returns (result, detail, seconds, status, stderr text).

    The result is the first of hang, crash, accepted, file changed, wrong message that
    applies (clean if none); the detail lists every problem found."""
    folder = Path(record["folder"])
    before = snapshot(folder)
    status, err, seconds = run_program(record)
    text = err.decode("utf-8", "replace")
    problems = []  # (result, detail)
    if status is None:
        problems.append(("hang", f"still running after {record['timeout'] * TIMEOUT_FACTOR:g} s (killed)"))
    elif status < 0 or status >= 128:
        name = signal.Signals(-status).name if status < 0 else f"status {status}"
        problems.append(("crash", name))
    elif status == 0:
        problems.append(("accepted", "exit status 0"))
    changes = file_changes(before, snapshot(folder))
    if changes:
        problems.append(("file changed", "; ".join(changes)))
    message = message_problem(err, record["expect"])
    if message:
        problems.append(("wrong message", message))
    if not problems:
        return "clean", "", seconds, status, text
    return problems[0][0], "; ".join(d for _, d in problems), seconds, status, text


def message_problem(err, fragment):
    """Why stderr is not one valid UTF-8 line containing fragment (None if it is)."""
    try:
        text = err.decode("utf-8")
    except UnicodeDecodeError as e:
        return f"stderr is not valid UTF-8 ({e.reason} at byte {e.start})"
    lines = text.splitlines()
    if len(lines) != 1:
        return f"{len(lines)} stderr lines, expected one"
    if not text.endswith("\n"):
        return "the stderr line does not end with a newline"
    if fragment not in text:
        return f"does not name {fragment!r}"
    return None


def verdict(record, result):
    """Table label and whether it counts as a failure."""
    if record["expected_failure"]:
        return ("XPASS", True) if result == "clean" else (f"XFAIL ({result})", False)
    return result, result != "clean"


def print_row(record, label, detail, seconds, status, err, verbose):
    print(f"{record['id']:<48} {label:<22} {seconds:6.2f} s", flush=True)
    if verbose and label == "clean":
        print(f"    stderr: {err.rstrip()}")
    if label != "clean":
        print(f"    {record['description']}")
        print(f"    $ {' '.join(record['argv'])}")
        print(f"    exit {status}: {detail}")
        for line in err.splitlines()[:4]:
            print(f"    stderr: {line[:300]}")
        if record["expected_failure"]:
            print(f"    expected failure: {record['expected_failure']}")
    sys.stdout.flush()


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--bin", required=True, help="the build's bin folder")
    parser.add_argument("--work", required=True, help="work folder (erased and rewritten)")
    parser.add_argument("--verbose", action="store_true", help="print every entry's stderr")
    parser.add_argument("only", nargs="*", help="entry ids to run (default: all)")
    args = parser.parse_args()
    start = time.monotonic()
    try:
        records = make_catalogue.generate(args.bin, args.work, args.only)
    except make_catalogue.CatalogueError as e:
        sys.exit(f"run_catalogue: {e}")
    made = time.monotonic() - start
    print(f"{len(records)} entries made in {made:.1f} s (valid inputs from the programs)")
    print(f"{'id':<48} {'result':<22} {'time':>8}")
    counts, failures = {}, 0
    for record in records:
        result, detail, seconds, status, err = run_entry(record)
        label, failed = verdict(record, result)
        print_row(record, label, detail, seconds, status, err, args.verbose)
        key = label.split(" ")[0] if label.startswith("XFAIL") else label
        counts[key] = counts.get(key, 0) + 1
        failures += failed
    summary = ", ".join(f"{counts[k]} {k}" for k in sorted(counts, key=lambda k: -counts[k]))
    print(f"summary: {len(records)} entries: {summary}; {failures} failure(s); "
          f"{time.monotonic() - start:.1f} s")
    sys.exit(1 if failures else 0)


if __name__ == "__main__":
    main()
