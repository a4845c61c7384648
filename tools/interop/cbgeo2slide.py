#!/usr/bin/python3
"""CB-Geo MPM output → an mpm checkpoint of this project (tools/interop/README.md).

    cbgeo2slide.py CBGEO_DIR PARTICLES.h5 STEP -o OUT.h5

CBGEO_DIR is the folder mpm2cbgeo wrote and CB-Geo ran in (its mpm.json and
results/<uuid>/particles<STEP>.h5); PARTICLES.h5 the particle file it was made from.
The result holds CB-Geo's particles at that step in the checkpoint schema
(common/io/checkpoint-schema.md), so that `slide-metrics measure`, tools/plots.py and
ParaView's readers of this project treat the two codes' results alike. Particles keep
their ids; CB-Geo's ids are the order mpm2cbgeo wrote them in (material by material,
file order within). Time: the particle file's time plus the steps behind the output
(STEP when CB-Geo resumed from mpm2cbgeo's step-0 file, STEP + 1 otherwise) × dt. Copied from the
particle file: the file attributes (case, pe0), /materials, /transfer, the particle
sizes and source elements. CB-Geo's strains are engineering shear (γxy), as here; its
plastic state is not read (zero).
"""
import argparse
import json
import pathlib
import sys

import h5py
import numpy as np


def string_attribute(obj, name, value):
    obj.attrs.create(name, np.bytes_(value.encode()))


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("cbgeo_dir")
    parser.add_argument("particles")
    parser.add_argument("step", type=int)
    parser.add_argument("-o", "--output", required=True)
    args = parser.parse_args()
    folder = pathlib.Path(args.cbgeo_dir)
    config = json.loads((folder / "mpm.json").read_text())
    analysis = config["analysis"]
    digits = len(str(int(analysis["nsteps"])))
    result = folder / config["post_processing"]["path"] / analysis["uuid"] / f"particles{args.step:0{digits}d}.h5"
    if not result.is_file():
        sys.exit(f"cbgeo2slide: {result}: no such file (steps written: multiples of "
                 f"{config['post_processing']['output_steps']})")
    with h5py.File(result, "r") as f:
        table = f["table"][...]
    with h5py.File(args.particles, "r") as source:
        material = source["particles/material_id"][...]
        order = np.concatenate([np.flatnonzero(material == m) for m in sorted(set(material.tolist()))])
        rows = order[table["id"].astype(np.int64)]  # CB-Geo id → row of the particle file
        output = pathlib.Path(args.output)
        temporary = output.with_name(output.name + ".tmp")
        with h5py.File(temporary, "w", libver=("v108", "latest")) as out:
            for key, value in source.attrs.items():
                out.attrs[key] = value
            string_attribute(out, "kind", "mpm")
            string_attribute(out, "producer", f"CB-Geo MPM, step {args.step} (cbgeo2slide.py)")
            out.attrs["time"] = float(source.attrs["time"]) + steps_done(analysis, args.step) * float(analysis["dt"])
            out.attrs["step"] = np.int64(args.step)
            for group in ("materials", "transfer"):
                if group in source:
                    source.copy(source[group], out, group)
            p = out.create_group("particles")

            def put(name, data, units):
                dataset = p.create_dataset(name, data=data)
                string_attribute(dataset, "units", units)

            column = lambda *names: np.stack([table[n] for n in names], axis=1).astype(float)
            put("coordinates", column("coord_x", "coord_y"), "m")
            put("displacement", source["particles/displacement"][...][rows] + column("displacement_x", "displacement_y"), "m")
            put("velocity", column("velocity_x", "velocity_y"), "m/s")
            put("stress", column("stress_xx", "stress_yy", "stress_zz", "tau_xy"), "Pa")
            strain = column("strain_xx", "strain_yy", "strain_zz", "gamma_xy")
            put("strain", strain, "1")
            mean = strain[:, :3].mean(axis=1, keepdims=True)
            e = strain[:, :3] - mean
            eps_q = np.sqrt(2.0 / 3.0 * ((e ** 2).sum(axis=1) + 0.5 * strain[:, 3] ** 2))
            put("eps_q", eps_q, "1")
            put("pore_pressure", np.zeros(len(table)), "Pa")
            put("volume", table["volume"].astype(float), "m^3/m")
            put("mass", table["mass"].astype(float), "kg/m")
            put("size", source["particles/size"][...][rows], "m")
            put("material_id", table["material_id"].astype(np.int32), "1")
            put("element", source["particles/element"][...][rows], "1")
            put("id", source["particles/id"][...][rows], "1")
            state = p.create_group("state")
            for name in ("plastic_shear_strain", "plastic_volumetric_strain"):
                dataset = state.create_dataset(name, data=np.zeros(len(table)))
                string_attribute(dataset, "units", "1")
        temporary.replace(output)
    print(f"cbgeo2slide: {len(table)} particles at t = {float(source_time(args.particles)) + steps_done(analysis, args.step) * float(analysis['dt']):.6g} s "
          f"→ {output}")


def steps_done(analysis, step):
    """The steps behind CB-Geo's output of `step`: a run resumed from step 0 writes step k
    after k steps; a fresh run writes it after its update of step k, k + 1 steps."""
    resumed = analysis.get("resume", {}).get("resume", False)
    return step if resumed else step + 1


def source_time(path):
    with h5py.File(path, "r") as f:
        return f.attrs["time"]


if __name__ == "__main__":
    main()
