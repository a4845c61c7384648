"""slide: read what the programs write, into numpy arrays (and pandas where it is installed).

    import slide
    fem = slide.read_checkpoint("out/fem/fem_t2.000.h5")      # kind "fem"
    fem.nodes["coordinates"], fem.elements["connectivity"], fem.gauss_points["stress"]
    mpm = slide.read_checkpoint("out/tt2/mpm_final.h5")        # kind "mpm" or "particles"
    mpm.particles["coordinates"]            # rows in increasing particle id
    mpm.rows_of(ids)                        # the rows of these ids
    history = slide.read_table("out/tt2/mpm_history.csv")     # {column: numpy array}
    sweep = slide.read_rows("out/sweep.csv")                   # [{column: text}]
    slide.read_pvd("out/tt2/mpm.pvd")                          # [(time, frame path)]
    crest = slide.read_recorder("out/tt2/recorders/crest.csv") # {"time": …, "p3322": {"ux": …}}
    slide.read_summary("out/fem/fem_summary.txt")             # {key: value}
    slide.to_dataframe(mpm.particles)                          # pandas, when installed

The checkpoint's names and units are those of common/io/checkpoint-schema.md; every
array is read whole (a checkpoint is tens of MB at most). Particle rows are put in
increasing `id`, so two checkpoints of one run compare row by row (the programs reorder
particles between checkpoints). Uses Debian's python3-numpy and python3-h5py;
python3-pandas only for to_dataframe.

From the source tree: PYTHONPATH=tools; installed: PYTHONPATH=PREFIX/share/slide/tools.
"""
from slide.io import (Checkpoint, read_checkpoint, read_pvd, read_recorder, read_rows,
                      read_summary, read_table, to_dataframe)

__all__ = ["Checkpoint", "read_checkpoint", "read_pvd", "read_recorder", "read_rows",
           "read_summary", "read_table", "to_dataframe"]
