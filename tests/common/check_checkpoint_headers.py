#!/usr/bin/python3
"""Holds the files the programs really write to what common/io/checkpoint-schema.md says
of their `producer` and `step` attributes.

The case chains (tests/cases/case_chain.sh) leave in each WORK folder what fem-solve,
fem2mpm and mpm-solve wrote: fem/fem_t*.h5, particles.h5 (with /transfer), mpm/mpm_*.h5,
and the programs' summary lines in fem.log and mpm.log. For every checkpoint there:

- `producer` matches the regular expression the schema page gives for its kind (read
  from the page's table, whose examples must match too), and carries the version the
  programs' --version prints;
- `step`: 0 in fem_t0.000.h5; in the FE checkpoint at the end of the FE run, the steps
  of fem-solve's summary line; in the particle file, the step of the FE checkpoint it was
  made from (with the same time, case and pe0); in mpm_final.h5, the steps of mpm-solve's
  summary line (the MPM run's own count); 0 in an MPM checkpoint at the run's start.

At least one chain must transfer after t = 0, so that the particle file's step is not 0
by accident.

Usage: check_checkpoint_headers.py BIN_DIR SCHEMA_PAGE WORK_DIR...
"""
import re
import subprocess
import sys
from pathlib import Path

import h5py

PROGRAMS = {"fem": "fem-solve", "particles": "fem2mpm", "mpm": "mpm-solve"}
failures = []


def check(condition, message):
    if not condition:
        failures.append(message)


def documented_producers(schema_page):
    """{kind: (program, compiled regex)} from the page's `producer` table."""
    forms = {}
    in_table = False
    for line in Path(schema_page).read_text(encoding="utf-8").splitlines():
        cells = [c.strip() for c in line.strip().strip("|").split("|")] if line.startswith("|") else []
        if cells[:3] == ["kind", "written by", "`producer` matches"]:
            in_table = True
            continue
        if not cells:
            in_table = False
            continue
        if not in_table or set(cells[0]) <= set("-"):
            continue
        kind, program, pattern, example = cells[0], cells[1], cells[2].strip("`"), cells[3].strip("`")
        try:
            regex = re.compile(pattern)
        except re.error as e:
            failures.append(f"{schema_page}: producer pattern {pattern!r} of kind {kind}: {e}")
            continue
        check(regex.fullmatch(example) is not None,
              f"{schema_page}: the example {example!r} of kind {kind} does not match {pattern!r}")
        forms[kind] = (program, regex)
    check(set(forms) == set(PROGRAMS),
          f"{schema_page}: producer table for kinds {sorted(forms)}, expected {sorted(PROGRAMS)}")
    for kind, (program, _) in forms.items():
        check(PROGRAMS.get(kind) == program, f"{schema_page}: kind {kind} written by {program}")
    return forms


def text(value):
    return value.decode("utf-8") if isinstance(value, bytes) else value


def header(path):
    with h5py.File(path, "r") as f:
        a = {key: text(value) for key, value in f.attrs.items()}
        if "transfer" in f:
            a["transfer_time"] = float(f["transfer"].attrs["transfer_time"])
    return a


def summary_steps(log):
    """n of the `summary: steps=n ...` line a program printed."""
    found = re.findall(r"^summary: steps=(\d+) ", Path(log).read_text(), flags=re.M)
    check(len(found) == 1, f"{log}: {len(found)} summary lines, expected 1")
    return int(found[0]) if found else None


def check_producer(path, a, forms, versions):
    kind = a.get("kind")
    if kind not in forms:
        failures.append(f"{path}: kind {kind!r}")
        return
    program, regex = forms[kind]
    producer = a.get("producer", "")
    check(regex.fullmatch(producer) is not None,
          f"{path}: producer {producer!r} does not match the documented {regex.pattern!r}")
    check(versions[program] in producer,
          f"{path}: producer {producer!r} lacks {versions[program]!r} ({program} --version)")


def check_chain(work, forms, versions):
    work = Path(work)
    fem_files = sorted((work / "fem").glob("fem_t*.h5"))
    mpm_files = sorted((work / "mpm").glob("mpm_*.h5"))
    particle_file = work / "particles.h5"
    if not (fem_files and particle_file.exists() and (work / "mpm" / "mpm_final.h5").exists()):
        failures.append(f"{work}: the chain's files are missing (has case_chain.sh run there?)")
        return None
    headers = {p: header(p) for p in fem_files + [particle_file] + mpm_files}
    for path, a in headers.items():
        check_producer(path, a, forms, versions)

    geostatic = headers.get(work / "fem" / "fem_t0.000.h5")
    check(geostatic is not None and int(geostatic["step"]) == 0 and geostatic["time"] == 0.0,
          f"{work}/fem/fem_t0.000.h5: step {geostatic and geostatic['step']}, expected 0")
    last = max(fem_files, key=lambda p: headers[p]["time"])
    fem_steps = summary_steps(work / "fem.log")
    check(int(headers[last]["step"]) == fem_steps,
          f"{last}: step {headers[last]['step']}, fem-solve's summary says steps={fem_steps}")

    particles = headers[particle_file]
    source = work / "fem" / f"fem_t{particles['transfer_time']:.3f}.h5"
    check(source in headers, f"{particle_file}: no FE checkpoint {source.name} to compare with")
    if source in headers:
        fem = headers[source]
        for key in ("step", "time", "case", "pe0"):
            check(particles[key] == fem[key],
                  f"{particle_file}: {key} = {particles[key]!r}, but {fem[key]!r} in {source.name}, "
                  f"the FE checkpoint it was made from")

    final = work / "mpm" / "mpm_final.h5"
    mpm_steps = summary_steps(work / "mpm.log")
    check(int(headers[final]["step"]) == mpm_steps,
          f"{final}: step {headers[final]['step']}, mpm-solve's summary says steps={mpm_steps}")
    for path in mpm_files:
        if headers[path]["time"] == particles["time"]:
            check(int(headers[path]["step"]) == 0,
                  f"{path}: step {headers[path]['step']} at the run's start, expected 0")
    return int(particles["step"])


def main():
    bin_dir, schema_page, works = Path(sys.argv[1]), sys.argv[2], sys.argv[3:]
    forms = documented_producers(schema_page)
    versions = {}
    for program in PROGRAMS.values():
        done = subprocess.run([str(bin_dir / program), "--version"], capture_output=True, text=True)
        versions[program] = done.stdout.strip()
        check(done.returncode == 0
              and re.fullmatch(r"slide [0-9]+\.[0-9]+\.[0-9]+ \(commit [0-9A-Za-z._-]+\)",
                               versions[program]),
              f"{program} --version: status {done.returncode}, {versions[program]!r}")
    particle_steps = [check_chain(work, forms, versions) for work in works] if forms else []
    check(any(step for step in particle_steps),
          f"no chain transferred after t = 0 (particle steps {particle_steps}): the step check "
          f"would hold for a file that always says 0")
    for message in failures:
        print(f"FAIL {message}")
    print(f"check_checkpoint_headers: {len(works)} chains, particle file steps {particle_steps}, "
          f"{len(failures)} failures")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
