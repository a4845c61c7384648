"""Checks of what a stopped program left in its output folder (tests/faults/README.md).

Three questions, each a function that returns a list of problems (empty: none):

- complete_file_problems: is every file under its final name complete by its own
  format? HDF5 opens with h5py, holds every dataset and attribute the schema page
  documents for its kind and reads back whole; VTK XML ends with its closing tag; CSV
  ends with a newline and every row has the header's columns; JSON parses.
- reference_problems: is every final-named file the reference run's file of that name,
  or (for the files rewritten as they grow: histories, .pvd collections) an earlier
  state of it?
- difference_problems: are two folders the same outputs, bit for bit?

Hidden temporaries (`.NAME.tmp-PID`, common/io/atomic_file.hpp) are listed by
temporaries() and kept out of the first two checks.
"""
import json
import re
import sys
from pathlib import Path

import h5py
import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "support"))
from checkpoint_schema import documented_schema  # noqa: E402

TEMPORARY = re.compile(r"^\..+\.tmp-(\d+)$")
ROOT_ATTRIBUTES = ("schema", "schema_version", "producer", "kind", "time", "step", "dimension",
                   "case", "pe0")
VTK_CLOSING_TAG = b"</VTKFile>"
# run.txt says how the folder's last run started (a restart: from its checkpoint) and
# the run's log (<program>.log) holds its wall times and its restarts, so a restarted
# folder's differ from an uninterrupted one's by design; they are provenance, not
# outputs of the physics.
PROVENANCE = {Path("run.txt"), Path("fem-solve.log"), Path("mpm-solve.log")}
# Lines and fields that hold wall-clock times, which no two runs share.
WALL_CLOCK_LINE = re.compile(r"^(wall_s|started_utc) = ")  # run.txt: when a run started
WALL_CLOCK_FIELDS = ("seconds_interpolation", "seconds_total")


class Schema:
    """The datasets of each kind and the material attributes, from the schema page."""

    def __init__(self, schema_page):
        fem, particles, material_attributes = documented_schema(schema_page)
        self.datasets = {"fem": fem, "particles": particles, "mpm": particles}
        self.material_attributes = material_attributes


def files_of(folder):
    """Every file under `folder`, as paths relative to it, temporaries included."""
    folder = Path(folder)
    if not folder.is_dir():
        return []
    return sorted(p.relative_to(folder) for p in folder.rglob("*") if p.is_file())


def temporaries(folder):
    """The hidden temporaries of write_atomically under `folder`."""
    return [p for p in files_of(folder) if TEMPORARY.match(p.name)]


# The output lock a run holds while it writes (common/run/output_lock.hpp): not an output;
# a killed run leaves it, the next run takes it over and removes it when it ends.
LOCK = ".slide-lock"


def locks(folder):
    return [p for p in files_of(folder) if p.name == LOCK]


def final_files(folder):
    return [p for p in files_of(folder) if not TEMPORARY.match(p.name) and p.name != LOCK]


# ---- complete by its own format


def checkpoint_problems(path, schema):
    """Why the HDF5 file `path` is not a complete checkpoint (empty list: it is)."""
    try:
        with h5py.File(path, "r") as f:
            problems = [f"attribute {a} missing" for a in ROOT_ATTRIBUTES if a not in f.attrs]
            if problems:
                return problems
            kind = f.attrs["kind"]
            kind = kind.decode("utf-8") if isinstance(kind, bytes) else kind  # fixed-length
            if kind not in schema.datasets:
                return [f"unknown kind {kind!r}"]
            problems += dataset_problems(f, schema.datasets[kind])
            problems += material_problems(f, schema.material_attributes)
            return problems
    except Exception as error:  # h5py raises OSError, KeyError, ... on a damaged file
        return [f"cannot be read with h5py ({error})"]


def dataset_problems(f, documented):
    """Every required dataset of the kind present with its documented columns and type,
    as many rows as its group's defining dataset, and readable to its end."""
    problems, rows = [], {}
    for name, (columns, kind, _units, optional) in documented.items():
        if name.startswith("boundary/*/"):
            for node_set in f.get("boundary", {}):
                problems += one_dataset_problems(f, name.replace("*", node_set), None, kind, None)
            continue
        if name not in f:
            if not optional:
                problems.append(f"/{name}: missing")
            continue
        group = name.split("/")[0]
        rows.setdefault(group, f[name].shape[0] if f[name].shape else None)
        problems += one_dataset_problems(f, name, columns, kind, rows[group])
    return problems


def one_dataset_problems(f, name, columns, kind, rows):
    if name not in f:
        return [f"/{name}: missing"]
    d = f[name]
    problems = []
    if rows is not None and (not d.shape or d.shape[0] != rows):
        problems.append(f"/{name}: shape {d.shape}, expected {rows} rows")
    if columns == "4k":
        if len(d.shape) != 2 or d.shape[1] % 4 != 0:
            problems.append(f"/{name}: shape {d.shape}, expected a multiple of 4 columns")
    elif columns is not None and (len(d.shape) != 2 or d.shape[1] != columns):
        problems.append(f"/{name}: shape {d.shape}, expected {columns} columns")
    if d.dtype.kind != kind:
        problems.append(f"/{name}: dtype {d.dtype}, expected kind {kind}")
    d[...]  # a file cut short fails here
    return problems


def material_problems(f, attributes):
    if "materials" not in f or len(f["materials"]) == 0:
        return ["/materials: missing or empty"]
    return [f"/materials/{m}: attribute {a} missing"
            for m, group in f["materials"].items() for a in attributes if a not in group.attrs]


def text_problems(path):
    """A CSV, VTK XML, JSON or plain text file that is not complete."""
    data = path.read_bytes()
    suffix = path.suffix
    if suffix in (".vtu", ".pvd"):
        return [] if data.rstrip().endswith(VTK_CLOSING_TAG) else ["does not end with </VTKFile>"]
    if suffix == ".json":
        try:
            json.loads(data)
            return []
        except ValueError as error:
            return [f"not valid JSON ({error})"]
    if not data.endswith(b"\n"):
        return ["does not end with a newline"]
    if suffix == ".csv":
        lines = data.decode().splitlines()
        width = len(lines[0].split(","))
        return [f"line {i + 1}: {len(line.split(','))} cells, the header has {width}"
                for i, line in enumerate(lines) if len(line.split(",")) != width]
    return []


def complete_file_problems(folder, schema):
    """'FILE: problem' for every final-named file under `folder` that is not complete."""
    problems = []
    for relative in final_files(folder):
        path = Path(folder) / relative
        found = checkpoint_problems(path, schema) if path.suffix == ".h5" else text_problems(path)
        problems += [f"{relative}: {p}" for p in found]
    return problems


# ---- the reference run's files


def without_wall_clock(path):
    """The file's content without its wall-clock times (fem_summary.txt's wall_s line,
    run.txt's started_utc, the transfer report's timing fields)."""
    if path.suffix == ".json":
        fields = json.loads(path.read_bytes())
        return {k: v for k, v in fields.items() if k not in WALL_CLOCK_FIELDS}
    if path.suffix == ".txt":
        return [line for line in path.read_text().splitlines() if not WALL_CLOCK_LINE.match(line)]
    return path.read_bytes()


def growing_file_parts(path):
    """A file rewritten whole as it grows, as (its rows, its fixed ending): a history's
    lines, a .pvd collection's lines before its two closing lines."""
    lines = path.read_text().splitlines(keepends=True)
    return (lines[:-2], lines[-2:]) if path.suffix == ".pvd" else (lines, [])


def reference_problems(folder, reference):
    """Every final-named file under `folder` must be the reference's file of that name
    (wall-clock times aside), or for a history or .pvd an earlier state of it (its rows a
    prefix of the reference's)."""
    problems = []
    for relative in final_files(folder):
        if relative in PROVENANCE:
            continue
        path, expected = Path(folder) / relative, Path(reference) / relative
        if not expected.exists():
            problems.append(f"{relative}: the reference run has no such file")
        elif path.suffix in (".csv", ".pvd"):
            (rows, ending), (all_rows, all_ending) = (growing_file_parts(path),
                                                      growing_file_parts(expected))
            if ending != all_ending or rows != all_rows[:len(rows)]:
                problems.append(f"{relative}: not an earlier state of the reference's file")
        elif without_wall_clock(path) != without_wall_clock(expected):
            problems.append(f"{relative}: differs from the reference's file")
    return problems


# ---- two folders, bit for bit


def attribute_differences(label, a, b):
    differences = [f"{label}: attribute {k} in one file only"
                   for k in sorted(set(a.attrs) ^ set(b.attrs))]
    for k in sorted(set(a.attrs) & set(b.attrs)):
        va, vb = np.asarray(a.attrs[k]), np.asarray(b.attrs[k])
        if va.dtype != vb.dtype or va.shape != vb.shape or va.tobytes() != vb.tobytes():
            differences.append(f"{label}: attribute {k}: {a.attrs[k]!r} against {b.attrs[k]!r}")
    return differences


def checkpoint_differences(path, other):
    """Every dataset (type, shape, bits) and every attribute (type, value) of two HDF5
    files, group by group."""
    with h5py.File(path, "r") as a, h5py.File(other, "r") as b:
        names_a, names_b = [], []
        a.visit(names_a.append)
        b.visit(names_b.append)
        differences = [f"/{n}: in one file only" for n in sorted(set(names_a) ^ set(names_b))]
        differences += attribute_differences("/", a, b)
        for name in sorted(set(names_a) & set(names_b)):
            oa, ob = a[name], b[name]
            differences += attribute_differences(f"/{name}", oa, ob)
            if isinstance(oa, h5py.Dataset):
                da, db = np.asarray(oa[()]), np.asarray(ob[()])
                if da.dtype != db.dtype or da.shape != db.shape or da.tobytes() != db.tobytes():
                    differences.append(f"/{name}: values differ")
        return differences


def difference_problems(folder, reference):
    """Two output folders as the same outputs: the same files; every HDF5 file the same
    datasets and attributes (checkpoint_differences) and the same bytes; every other
    file the same bytes, but for its wall-clock times (without_wall_clock) and run.txt's
    start (PROVENANCE)."""
    files, expected = set(files_of(folder)), set(files_of(reference))
    files, expected = files - PROVENANCE, expected - PROVENANCE
    problems = [f"{f}: only in the run" for f in sorted(files - expected)]
    problems += [f"{f}: only in the reference run" for f in sorted(expected - files)]
    for relative in sorted(files & expected):
        path, other = Path(folder) / relative, Path(reference) / relative
        if path.suffix == ".h5":
            problems += [f"{relative}: {d}" for d in checkpoint_differences(path, other)]
            if path.read_bytes() != other.read_bytes():
                problems.append(f"{relative}: same datasets and attributes, other bytes")
        elif without_wall_clock(path) != without_wall_clock(other):
            problems.append(f"{relative}: differs")
    return problems
