#!/usr/bin/python3
"""The checks of outputs.py find what they are for: on copies of the reference runs'
outputs (faults.py reference), each damaged in one way, the check meant for that damage
reports it, and none reports anything on an undamaged copy.

    outputs_self_test.py SOURCE WORK
"""
import shutil
import sys
from pathlib import Path

import h5py

sys.path.insert(0, str(Path(__file__).resolve().parent))
import outputs  # noqa: E402


def truncate(path, keep_fraction):
    data = path.read_bytes()
    path.write_bytes(data[:int(len(data) * keep_fraction)])


def cut_end(path, count):
    path.write_bytes(path.read_bytes()[:-count])


def delete_dataset(path, name):
    with h5py.File(path, "r+") as f:
        del f[name]


def change_value(path, name):
    with h5py.File(path, "r+") as f:
        f[name][0, 0] += 1.0


def change_attribute(path, name):
    with h5py.File(path, "r+") as f:
        f.attrs[name] = f.attrs[name] + 1


def change_history_row(path):
    lines = path.read_text().splitlines(keepends=True)
    lines[3] = lines[3].replace(",", ",1", 1)
    path.write_text("".join(lines))


def drop_last_rows(path, count):
    lines = path.read_text().splitlines(keepends=True)
    path.write_text("".join(lines[:-count]))


def drop_last_frame(path):
    lines = path.read_text().splitlines(keepends=True)
    path.write_text("".join(lines[:-3] + lines[-2:]))


def drop_cell(path):
    lines = path.read_text().splitlines(keepends=True)
    lines[2] = lines[2].rsplit(",", 1)[0] + "\n"
    path.write_text("".join(lines))


# (what is damaged, how, the check that must report it, a word its report contains; no
# word: an earlier state of a growing file, which the check must accept)
FEM_DAMAGES = [
    ("fem_t0.500.h5", lambda p: truncate(p, 0.5), "complete", "h5py"),
    ("fem_t0.500.h5", lambda p: delete_dataset(p, "gauss_points/stress"), "complete", "missing"),
    ("fem_t0.500.h5", lambda p: change_value(p, "nodes/velocity"), "difference", "values differ"),
    ("fem_t0.500.h5", lambda p: change_attribute(p, "step"), "difference", "attribute step"),
    ("fem_t0.500.h5", lambda p: change_value(p, "gauss_points/stress"), "reference", "differs"),
    ("vtk/fem_000007.vtu", lambda p: cut_end(p, 20), "complete", "</VTKFile>"),
    ("fem.pvd", lambda p: cut_end(p, 12), "complete", "</VTKFile>"),
    ("fem_history.csv", lambda p: cut_end(p, 1), "complete", "newline"),
    ("fem_history.csv", drop_cell, "complete", "cells"),
    ("fem_history.csv", change_history_row, "reference", "earlier state"),
    ("fem_history.csv", lambda p: drop_last_rows(p, 2), "reference", None),
    ("fem.pvd", drop_last_frame, "reference", None),
    ("fem.pvd", drop_last_frame, "difference", "differs"),
    ("fem_history.csv", lambda p: cut_end(p, 1), "difference", "differs"),
    ("vtk/.fem_000014.vtu.tmp-4242", lambda p: p.write_bytes(b"<VTK"), "difference", "only in"),
]
TRANSFER_DAMAGES = [
    ("particles.transfer.json", lambda p: cut_end(p, 3), "complete", "JSON"),
    ("particles.h5", lambda p: truncate(p, 0.9), "complete", "h5py"),
    ("particles.h5", lambda p: delete_dataset(p, "particles/mass"), "complete", "missing"),
]


def reports(check, folder, reference, schema):
    if check == "complete":
        return outputs.complete_file_problems(folder, schema)
    if check == "reference":
        return outputs.reference_problems(folder, reference)
    return outputs.difference_problems(folder, reference)


def damage_found(number, damage, reference, work, schema):
    name, how, check, word = damage
    copy = work / str(number)
    shutil.rmtree(copy, ignore_errors=True)
    shutil.copytree(reference, copy)
    how(copy / name)
    found = reports(check, copy, reference, schema)
    if word is None:
        print(f"{'FAIL' if found else 'ok  '} {name}, an earlier state: {check} check says "
              f"{found or 'nothing'}")
        return not found
    hit = [p for p in found if p.startswith(name) and word in p]
    print(f"{'ok  ' if hit else 'FAIL'} {name}, damaged: {check} check says "
          f"{hit[0] if hit else found or 'nothing'}")
    return bool(hit)


def main():
    source, work = Path(sys.argv[1]), Path(sys.argv[2]).resolve()
    schema = outputs.Schema(source / "common" / "io" / "checkpoint-schema.md")
    failures = 0
    for folder, damages in (("fem", FEM_DAMAGES), ("transfer", TRANSFER_DAMAGES)):
        reference = work / "reference" / folder / "out"
        clean = [p for check in ("complete", "reference", "difference")
                 for p in reports(check, reference, reference, schema)]
        print(f"{'ok  ' if not clean else 'FAIL'} {folder}: undamaged, no check says anything"
              f"{': ' + str(clean) if clean else ''}")
        failures += bool(clean)
        for number, damage in enumerate(damages):
            failures += not damage_found(number, damage, reference,
                                         work / "self-test" / folder, schema)
    if not failures:
        shutil.rmtree(work / "self-test")
    print(f"outputs_self_test: {failures} failure(s)")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
