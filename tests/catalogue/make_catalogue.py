#!/usr/bin/python3
"""Builds the work folder of the bad-input catalogue (tests/catalogue/README.md).

Every entry of entries.toml is a mutated copy of a valid input plus the command line
that must refuse it. The valid inputs are made here, at test time, by the programs
themselves: a tiny variant of cases/column-short (a 5 m x 4 m column, 1 m elements, FE
to 0.2 s, MPM to 0.3 s) and cases/geostatic-4x4 (another case, for the cross-case
entries). Each entry then gets its own folder WORK/entries/<id>/ holding case.toml (the
base case, edited as the entry says), its HDF5 input (a copied checkpoint, edited with
h5py or byte by byte) and any extra file; the output folder is WORK/entries/<id>/out.
The resolved command lines go to WORK/manifest.json, which run_catalogue.py runs.

    /usr/bin/python3 tests/catalogue/make_catalogue.py BUILD/bin WORK [ID ...]
"""

import argparse
import json
import os
import random
import re
import shutil
import subprocess
import sys
import tomllib
from pathlib import Path

import h5py
import numpy as np

HERE = Path(__file__).resolve().parent
SOURCE = HERE.parent.parent
ENTRIES_FILE = HERE / "entries.toml"


class CatalogueError(Exception):
    """A base run failed or an entry's edit does not apply to its base file."""


# ---------------------------------------------------------------------------------------
# Case-file edits: line-based, so that everything else of the file (comments, layout)
# stays as the user wrote it. A dotted name "fem.damping.ratio" is the key `ratio` of the
# table [fem.damping]; "materials.density" is in the first [[materials]] table.

HEADER = re.compile(r"^\s*\[\[?\s*([A-Za-z0-9_.\-]+)\s*\]\]?\s*(#.*)?$")


def table_span(lines, table):
    """(header index, end index) of the first table `table` (end: the next header)."""
    for i, line in enumerate(lines):
        match = HEADER.match(line)
        if match and match.group(1) == table:
            end = next((j for j in range(i + 1, len(lines)) if HEADER.match(lines[j])),
                       len(lines))
            return i, end
    return None


def split_key(lines, dotted):
    parts = dotted.split(".")
    table, key = ".".join(parts[:-1]), parts[-1]
    span = table_span(lines, table)
    if span is None:
        raise CatalogueError(f"no table [{table}] for key {dotted}")
    return span, key


def key_line(lines, span, key):
    pattern = re.compile(rf"^\s*{re.escape(key)}\s*=")
    return next((i for i in range(span[0] + 1, span[1]) if pattern.match(lines[i])), None)


def set_key(lines, dotted, value):
    span, key = split_key(lines, dotted)
    i = key_line(lines, span, key)
    if i is None:
        lines.insert(span[0] + 1, f"{key} = {value}")
    else:
        lines[i] = f"{key} = {value}"


def remove_key(lines, dotted):
    span, key = split_key(lines, dotted)
    i = key_line(lines, span, key)
    if i is None:
        raise CatalogueError(f"no key {dotted} to remove")
    del lines[i]


def remove_table(lines, table):
    span = table_span(lines, table)
    if span is None:
        raise CatalogueError(f"no table [{table}] to remove")
    del lines[span[0]:span[1]]


def replace_once(text, old, new):
    if text.count(old) != 1:
        raise CatalogueError(f"{old!r} occurs {text.count(old)} times, expected once")
    return text.replace(old, new)


def edit_case_text(text, edits):
    """The case file `text` with the entry's `toml` edits applied, as bytes."""
    for edit in edits:
        lines = text.split("\n")
        if "set" in edit:
            set_key(lines, edit["set"], edit["value"])
        elif "remove" in edit:
            remove_key(lines, edit["remove"])
        elif "remove_table" in edit:
            remove_table(lines, edit["remove_table"])
        elif "replace" in edit:
            lines = replace_once(text, edit["replace"], replacement(edit)).split("\n")
        elif "append" in edit:
            lines.append(edit["append"])
        elif "pad_to" in edit:  # comment lines up to this many bytes
            padding = "# " + "padding " * 9 + "\n"
            lines.append(padding * (edit["pad_to"] // len(padding) + 1))
        elif "text" in edit:
            lines = edit["text"].split("\n")
        elif "random_bytes" in edit:
            return random_bytes(edit["random_bytes"], edit.get("seed", 0))
        else:
            raise CatalogueError(f"unknown case-file edit {edit}")
        text = "\n".join(lines)
    return text.encode("utf-8", "surrogateescape")


def replacement(edit):
    """The `by` text of a replace edit; `by_hex` gives raw bytes (e.g. not UTF-8)."""
    if "by_hex" in edit:
        return bytes.fromhex(edit["by_hex"]).decode("utf-8", "surrogateescape")
    return edit["by"]


def random_bytes(count, seed):
    return random.Random(seed).randbytes(count)


# ---------------------------------------------------------------------------------------
# HDF5 edits with h5py: the file stays a valid HDF5 file, one dataset or attribute of the
# checkpoint schema is wrong.

def parse_value(value):
    """TOML value -> number, with the strings "nan", "inf", "-inf" as floats."""
    if isinstance(value, str) and value in ("nan", "inf", "-inf"):
        return float(value)
    if isinstance(value, list):
        return [parse_value(v) for v in value]
    return value


def attribute_value(edit):
    if "hex" in edit:  # raw bytes, e.g. not UTF-8: a fixed-length byte string
        return np.bytes_(bytes.fromhex(edit["hex"]))
    value = parse_value(edit["value"])
    if isinstance(value, bool):
        return value
    if isinstance(value, int):
        return np.int64(value)
    if isinstance(value, float):
        return np.float64(value)
    return value


def replace_dataset(f, path, data):
    """Writes `data` in place of dataset `path`, keeping its attributes."""
    attributes = dict(f[path].attrs)
    del f[path]
    dataset = f.create_dataset(path, data=data)
    for name, value in attributes.items():
        dataset.attrs[name] = value


def reshaped(data, edit):
    if "rows" in edit:  # keep (or repeat to) this many rows; negative: drop rows
        rows = edit["rows"] if edit["rows"] >= 0 else len(data) + edit["rows"]
        return np.resize(data, (rows,) + data.shape[1:])
    if "columns" in edit:
        return np.resize(data[:, :edit["columns"]], (data.shape[0], edit["columns"]))
    if "flatten" in edit:
        return data.reshape(-1)
    raise CatalogueError(f"reshape needs rows, columns or flatten: {edit}")


def retyped(data, dtype):
    if dtype == "string":
        strings = np.array([str(v) for v in data.reshape(-1)], dtype=object)
        return strings.reshape(data.shape).astype(h5py.string_dtype())
    return data.astype(dtype)


def modify_array(f, path, change):
    """Reads dataset `path`, applies change(array) in place and writes it back."""
    data = f[path][...]
    change(data)
    f[path][...] = data


def set_values(f, path, edit):
    def change(data):
        data[tuple(edit["index"])] = parse_value(edit["value"])
    modify_array(f, path, change)


def copy_element(f, path, edit):  # element `from` of the dataset over element `to`
    def change(data):
        data[edit["to"]] = data[edit["from"]]
    modify_array(f, path, change)


def reverse_row(f, path, edit):  # e.g. an element's nodes clockwise
    def change(data):
        data[edit["index"]] = data[edit["index"]][::-1].copy()
    modify_array(f, path, change)


def rename(f, path, edit):
    name = bytes.fromhex(edit["hex"]) if "hex" in edit else edit["to"].encode()
    f[path].parent.move(path.rsplit("/", 1)[1].encode(), name)


def delete_attribute(f, path, edit):
    if edit["name"] not in f[path].attrs:
        raise CatalogueError(f"{f.filename}: {path} has no attribute {edit['name']} to delete")
    del f[path].attrs[edit["name"]]


HDF5_EDITS = {
    "delete": lambda f, path, edit: f.__delitem__(path),
    "attr": lambda f, path, edit: f[path].attrs.__setitem__(edit["name"], attribute_value(edit)),
    "delete_attr": delete_attribute,
    "set": set_values,
    "copy": copy_element,
    "reverse_row": reverse_row,
    "reshape": lambda f, path, edit: replace_dataset(f, path, reshaped(f[path][...], edit)),
    "retype": lambda f, path, edit: replace_dataset(f, path, retyped(f[path][...], edit["dtype"])),
    "rename": rename,
}


def edit_hdf5(path, edits):
    with h5py.File(path, "r+") as f:
        for edit in edits:
            target = edit.get("path", "/")
            if edit["op"] not in HDF5_EDITS:
                raise CatalogueError(f"unknown HDF5 edit {edit}")
            if target not in f:
                raise CatalogueError(f"{path.name}: no {target} to edit")
            HDF5_EDITS[edit["op"]](f, target, edit)


# Byte-level damage, after the h5py edits: the file is no longer valid HDF5 throughout.

def damage_bytes(path, edits):
    data = bytearray(path.read_bytes())
    for edit in edits:
        if edit["op"] == "truncate":
            data = data[: int(len(data) * edit["keep"])]
        elif edit["op"] == "zero":
            start = signature_offset(data, edit["signature"], path)
            data[start:start + edit["size"]] = bytes(min(edit["size"], len(data) - start))
        else:
            raise CatalogueError(f"unknown byte edit {edit}")
    path.write_bytes(bytes(data))


def signature_offset(data, signature, path):
    """Offset of the middle occurrence of an HDF5 structure signature (TREE, OHDR, FRHP, …)."""
    offsets = [m.start() for m in re.finditer(re.escape(signature.encode()), bytes(data))]
    if not offsets:
        raise CatalogueError(f"{path.name}: no {signature} signature to damage")
    return offsets[len(offsets) // 2]


BYTE_OPS = ("truncate", "zero")


# ---------------------------------------------------------------------------------------
# The valid inputs: run the programs once on the base cases.

def run_program(command, log):
    result = subprocess.run([str(c) for c in command], capture_output=True, text=True,
                            env=dict(os.environ, OMP_NUM_THREADS="1"))
    log.write_text(result.stdout + result.stderr)
    if result.returncode != 0:
        raise CatalogueError(f"base run failed ({result.returncode}): {' '.join(map(str, command))}"
                             f"\n{result.stderr}")


def make_bases(bin_dir, base, bases):
    """Writes the base case files and runs each base's programs; returns name -> file."""
    files = {}
    for name, spec in bases["case"].items():
        folder = base / name
        folder.mkdir(parents=True)
        text = (SOURCE / spec["from"]).read_text()
        case = folder / "case.toml"
        case.write_bytes(edit_case_text(text, spec.get("toml", [])))
        files[f"case:{name}"] = case
        for number, step in enumerate(spec["runs"]):
            command = [bin_dir / step[0]] + [arg.format(case=case, dir=folder) for arg in step[1:]]
            run_program(command, folder / f"run{number}-{step[0]}.log")
    for name, relative in bases["file"].items():
        path = base / relative
        if not path.is_file():
            raise CatalogueError(f"base file {name} = {relative} was not written")
        files[name] = path
    return files


# ---------------------------------------------------------------------------------------
# The entries.

def make_entry(entry, folder, files):
    """Writes one entry's inputs into `folder`; returns its manifest record."""
    folder.mkdir(parents=True)
    case_name = entry.get("case", "tiny")
    case = folder / "case.toml"
    case.write_bytes(edit_case_text(files[f"case:{case_name}"].read_text(), entry.get("toml", [])))
    values = {"case": str(case), "out": str(folder / "out"), "entry": str(folder)}
    if "input" in entry:
        source = files[entry["input"]]
        target = folder / source.name
        shutil.copyfile(source, target)
        h5_edits = entry.get("h5", [])
        edit_hdf5(target, [e for e in h5_edits if e["op"] not in BYTE_OPS])
        damage_bytes(target, [e for e in h5_edits if e["op"] in BYTE_OPS])
        values["input"] = str(target)
    for extra in entry.get("files", []):
        make_extra_file(folder / extra["name"], extra)
    return {
        "id": entry["id"],
        "description": entry["description"],
        "program": entry["program"],
        "argv": [entry["program"]] + [arg.format(**values) for arg in entry["args"]],
        "expect": entry["expect"],
        "expected_failure": entry.get("expected_failure"),
        "timeout": entry.get("timeout", 10),
        "folder": str(folder),
    }


def make_extra_file(path, spec):
    if spec.get("directory"):
        path.mkdir()
    elif "random_bytes" in spec:
        path.write_bytes(random_bytes(spec["random_bytes"], spec.get("seed", 0)))
    else:
        path.write_text(spec["text"])


def check_entries(entries):
    ids = [e["id"] for e in entries]
    duplicates = sorted({i for i in ids if ids.count(i) > 1})
    if duplicates:
        raise CatalogueError(f"duplicate entry ids: {', '.join(duplicates)}")
    for entry in entries:
        missing = [k for k in ("id", "description", "program", "args", "expect") if k not in entry]
        if missing:
            raise CatalogueError(f"entry {entry.get('id', '?')}: missing {', '.join(missing)}")
        if not re.fullmatch(r"[a-z0-9][a-z0-9.\-]*", entry["id"]):
            raise CatalogueError(f"entry id {entry['id']!r}: use a-z, 0-9, '-', '.'")


def load_catalogue():
    with open(ENTRIES_FILE, "rb") as f:
        catalogue = tomllib.load(f)
    check_entries(catalogue["entry"])
    return catalogue


def generate(bin_dir, work, only=()):
    """Makes WORK afresh (bases, entries) and returns the manifest's records."""
    bin_dir, work = Path(bin_dir).resolve(), Path(work).resolve()
    catalogue = load_catalogue()
    if work.exists():
        shutil.rmtree(work)
    work.mkdir(parents=True)
    files = make_bases(bin_dir, work / "base", catalogue["base"])
    records = []
    for entry in catalogue["entry"]:
        if only and entry["id"] not in only:
            continue
        record = make_entry(entry, work / "entries" / entry["id"], files)
        record["argv"][0] = str(bin_dir / record["program"])
        records.append(record)
    (work / "manifest.json").write_text(json.dumps(records, indent=1, ensure_ascii=False))
    return records


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("bin", help="the build's bin folder (fem-solve, fem2mpm, mpm-solve)")
    parser.add_argument("work", help="work folder (erased and rewritten)")
    parser.add_argument("only", nargs="*", help="entry ids to make (default: all)")
    args = parser.parse_args()
    try:
        records = generate(args.bin, args.work, args.only)
    except CatalogueError as e:
        sys.exit(f"make_catalogue: {e}")
    print(f"{len(records)} entries in {Path(args.work) / 'entries'}")


if __name__ == "__main__":
    main()
