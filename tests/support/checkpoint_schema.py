"""The checkpoint schema as common/io/checkpoint-schema.md documents it, parsed from that
page's tables, for the Python tests that read checkpoints with h5py
(tests/common/read_checkpoint_with_h5py.py, tests/faults/)."""
import re
from pathlib import Path

DTYPE_KINDS = {"float64": "f", "int64": "i", "int32": "i"}


def documented_schema(schema_page):
    """The datasets and material attributes the schema page documents, parsed from its
    tables: {kind section: {name: (columns or None, dtype kind, units, optional)}}, with
    the symbolic column count k of the connectivity resolved to 4 (quad samples)."""
    sections, section, group, in_table = {}, None, None, False
    material_attributes = []
    for line in Path(schema_page).read_text(encoding="utf-8").splitlines():
        heading = re.match(r"^## (.*)", line)
        if heading:
            title = heading.group(1)
            section = "fem" if title.startswith('Kind "fem"') else \
                "particles" if title.startswith("Kinds") else \
                "materials" if title.startswith("Materials") else None
            sections.setdefault(section, {})
            group, in_table = None, False
            continue
        sub = re.match(r"^### `/([a-z_]+)`", line)
        if sub:
            group, in_table = sub.group(1), False
            continue
        cells = [c.strip() for c in line.strip().strip("|").split("|")] if line.startswith("|") else []
        if cells and cells[0] in ("dataset", "attribute"):
            in_table = True
            continue
        if not cells:
            in_table = False
            # the boundary node sets are documented in a list, not a table
            bullet = re.match(r"^\s*- dataset `(\w+)`: n_set, (\w+), units `\"(.*)\"`", line)
            if bullet and section == "fem":
                sections["fem"]["boundary/*/" + bullet.group(1)] = (
                    None, DTYPE_KINDS[bullet.group(2)], bullet.group(3), False)
            continue
        if not in_table or set(cells[0]) <= set("-"):
            continue
        name = cells[0].strip("`")
        if section == "materials":
            if "*optional*" not in line:
                material_attributes.append(name)
        elif section in ("fem", "particles") and group and len(cells) >= 5:
            shape = cells[1].split("×")
            columns = None if len(shape) == 1 else shape[1].strip()
            # "k": the documented state width 4; "4k": any multiple of 4 (the multi-yield
            # surfaces, 4 values each).
            columns = 4 if columns == "k" else ("4k" if columns == "4k" else (int(columns) if columns else None))
            optional = "*optional*" in cells[4]
            sections[section][f"{group}/{name}"] = (
                columns, DTYPE_KINDS[cells[2]], cells[3], optional)
    return sections["fem"], sections["particles"], material_attributes
