"""The readers of the slide package (see __init__.py)."""
import csv
import math
import pathlib
import xml.etree.ElementTree as ElementTree

import numpy as np


def read_rows(path, missing_ok=False):
    """A CSV with a header line as a list of {column: text} rows; [] for a missing file
    when missing_ok (a table a stage has not written yet)."""
    path = pathlib.Path(path)
    if missing_ok and not path.exists():
        return []
    with open(path, newline="") as f:
        return list(csv.DictReader(f))


def _number(text):
    try:
        return float(text)
    except ValueError:
        return math.nan


def read_table(path):
    """A CSV with a header line as {column: numpy array}: numbers as float64 (an empty
    cell or "nan" is NaN), a column with any non-number text as an array of str. A
    header without rows gives empty arrays."""
    with open(path, newline="") as f:
        reader = csv.DictReader(f)
        rows = list(reader)
        header = reader.fieldnames or []
    table = {}
    for name in header:
        texts = [r[name] for r in rows]
        numbers = [_number(t) for t in texts]
        text_column = any(math.isnan(v) and t.strip().lower() not in ("", "nan")
                          for v, t in zip(numbers, texts))
        table[name] = np.array(texts if text_column else numbers,
                               dtype=str if text_column else np.float64)
    return table


def read_recorder(path):
    """A recorder's CSV (OUT/recorders/<name>.csv of fem-solve or mpm-solve) grouped by what
    each column follows: {"time": array, "n12": {"ux": array, "ux_rel": …}, "e5": {"sxx": …},
    "p3322": {"x": …, "ux": …, "eq": …}, "base": {"ux": …}}; a column without a prefix
    ("outflow") stays an array at the top."""
    grouped = {}
    for name, values in read_table(path).items():
        owner, _, quantity = name.partition("_")
        if quantity and owner != "time":
            grouped.setdefault(owner, {})[quantity] = values
        else:
            grouped[name] = values
    return grouped


def read_summary(path):
    """A `key = value` file (fem_summary.txt, strength_reduction.txt's head): values as
    float where they are numbers, else the text ("none" stays "none")."""
    values = {}
    for line in pathlib.Path(path).read_text().splitlines():
        if line.startswith("#") or " = " not in line:
            continue
        key, value = (part.strip() for part in line.split(" = ", 1))
        number = _number(value)
        values[key] = value if math.isnan(number) and value.lower() != "nan" else number
    return values


def read_pvd(path):
    """A ParaView collection (fem.pvd, mpm.pvd) as [(time, frame path)], in time order."""
    path = pathlib.Path(path)
    root = ElementTree.parse(path).getroot()
    frames = [(float(d.get("timestep")), path.parent / d.get("file"))
              for d in root.iter("DataSet")]
    return sorted(frames, key=lambda frame: frame[0])


def _group(h5, name):
    """Every dataset under a group (recursively, "state/..." for nested ones) as arrays."""
    import h5py
    arrays = {}
    if name not in h5:
        return arrays

    def visit(key, item):
        if isinstance(item, h5py.Dataset):
            arrays[key] = item[()]
    h5[name].visititems(visit)
    return arrays


def _text(value):
    return value.decode() if isinstance(value, bytes) else value


class Checkpoint:
    """One checkpoint: `attrs` (the root attributes: kind, time, case, producer, ...) and
    its groups as {dataset: numpy array}: `nodes`, `elements`, `gauss_points` (kind
    "fem"), `particles` (kinds "particles" and "mpm", rows in increasing id), `solver`
    (the root of /solver's attributes) and `groups` (every other top-level group)."""

    def __init__(self, path):
        import h5py
        self.path = pathlib.Path(path)
        with h5py.File(self.path, "r") as h5:
            self.attrs = {key: _text(value) for key, value in h5.attrs.items()}
            self.nodes = _group(h5, "nodes")
            self.elements = _group(h5, "elements")
            self.gauss_points = _group(h5, "gauss_points")
            self.particles = _group(h5, "particles")
            self.solver = ({key: _text(value) for key, value in h5["solver"].attrs.items()}
                           if "solver" in h5 else {})
            known = {"nodes", "elements", "gauss_points", "particles"}
            self.groups = {name: _group(h5, name) for name in h5 if name not in known
                           and isinstance(h5[name], h5py.Group)}
        if "id" in self.particles:
            order = np.argsort(self.particles["id"], kind="stable")
            n = len(order)
            self.particles = {key: (value[order] if len(value) == n else value)
                              for key, value in self.particles.items()}

    @property
    def kind(self):
        return self.attrs.get("kind")

    @property
    def time(self):
        return float(self.attrs.get("time", math.nan))

    def rows_of(self, ids):
        """The particle rows of `ids` (KeyError naming an id the file does not hold)."""
        all_ids = self.particles["id"]
        rows = np.searchsorted(all_ids, ids)
        ids = np.asarray(ids)
        bad = (rows >= len(all_ids)) | (all_ids[np.minimum(rows, len(all_ids) - 1)] != ids)
        if np.any(bad):
            raise KeyError(f"{self.path}: no particle with id {ids[bad][0]}")
        return rows


def read_checkpoint(path):
    """The checkpoint at `path` (a Checkpoint)."""
    return Checkpoint(path)


def to_dataframe(arrays):
    """A group's {name: array} as a pandas DataFrame: one column per 1-D array and one
    per component of a 2-D one (`coordinates_0`, `coordinates_1`, ...). Needs pandas
    (Debian's python3-pandas)."""
    import pandas
    columns = {}
    for name, value in arrays.items():
        value = np.asarray(value)
        if value.ndim == 1:
            columns[name] = value
        elif value.ndim == 2:
            for k in range(value.shape[1]):
                columns[f"{name}_{k}"] = value[:, k]
    lengths = {len(v) for v in columns.values()}
    if len(lengths) > 1:
        longest = max(lengths)
        columns = {k: v for k, v in columns.items() if len(v) == longest}
    return pandas.DataFrame(columns)
