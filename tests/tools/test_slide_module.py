#!/usr/bin/python3
"""Unit tests of the slide Python module (tools/slide) on the files of the column-short
case chain (tests/cases/case_chain.sh: FE to 1 s, the transfer at 1 s, MPM to 3 s).

    test_slide_module.py SOURCE_DIR CHAIN_DIR
"""
import json
import pathlib
import sys
import unittest

import numpy as np

SOURCE, CHAIN = (pathlib.Path(a) for a in sys.argv[1:3])
sys.path.insert(0, str(SOURCE / "tools"))
import slide  # noqa: E402


class Checkpoints(unittest.TestCase):
    def test_fem_checkpoint_nodes_move_by_their_displacement(self):
        fem = slide.read_checkpoint(CHAIN / "fem" / "fem_t1.000.h5")
        self.assertEqual(fem.kind, "fem")
        self.assertEqual(fem.time, 1.0)
        n = fem.nodes
        np.testing.assert_allclose(n["reference_coordinates"] + n["displacement"],
                                   n["coordinates"], rtol=0, atol=1e-9)
        connectivity = fem.elements["connectivity"]
        self.assertEqual(connectivity.max() + 1, len(n["coordinates"]))
        self.assertEqual(fem.gauss_points["stress"].shape[1], 4)

    def test_particles_come_in_increasing_id_and_keep_the_transferred_mass(self):
        particles = slide.read_checkpoint(CHAIN / "particles.h5")
        ids = particles.particles["id"]
        self.assertTrue(np.all(np.diff(ids) > 0))
        record = json.loads((CHAIN / "particles.transfer.json").read_text())
        self.assertAlmostEqual(particles.particles["mass"].sum() / record["mass_particles"], 1.0,
                               places=12)

    def test_rows_of_ids_match_across_checkpoints(self):
        start = slide.read_checkpoint(CHAIN / "particles.h5")
        end = slide.read_checkpoint(CHAIN / "mpm" / "mpm_final.h5")
        self.assertEqual(end.kind, "mpm")
        np.testing.assert_array_equal(start.particles["id"], end.particles["id"])
        # Mass is carried unchanged by each particle: row by row after the id order.
        np.testing.assert_array_equal(start.particles["mass"], end.particles["mass"])
        picked = end.particles["id"][[7, 2, 11]]
        np.testing.assert_array_equal(end.rows_of(picked), [7, 2, 11])
        with self.assertRaises(KeyError):
            end.rows_of([end.particles["id"].max() + 1])

    def test_solver_attributes_and_other_groups_are_read(self):
        end = slide.read_checkpoint(CHAIN / "mpm" / "mpm_final.h5")
        self.assertGreater(float(end.solver["cell_size"]), 0.0)
        self.assertIn("materials", end.groups)


class Tables(unittest.TestCase):
    def test_history_columns_are_numbers_in_time_order(self):
        history = slide.read_table(CHAIN / "mpm" / "mpm_history.csv")
        for column in ("time", "kinetic_energy", "ke_over_pe0", "x_toe", "max_speed"):
            self.assertIn(column, history)
        self.assertTrue(np.all(np.diff(history["time"]) > 0))
        np.testing.assert_allclose(history["ke_over_pe0"],
                                   history["kinetic_energy"] / history["pe0"], rtol=1e-12)
        # The largest speed is at least the mass-weighted RMS speed sqrt(2 KE / M).
        mass = slide.read_checkpoint(CHAIN / "mpm" / "mpm_final.h5").particles["mass"].sum()
        rms = np.sqrt(2.0 * history["kinetic_energy"] / mass)
        self.assertTrue(np.all(history["max_speed"] >= rms * (1.0 - 1e-12)))
        self.assertTrue(np.all(history["max_speed"] < 10.0 * rms + 1e-9))

    def test_rows_and_missing_tables(self):
        rows = slide.read_rows(CHAIN / "fem" / "fem_history.csv")
        self.assertEqual(float(rows[0]["time"]), 0.0)
        self.assertEqual(slide.read_rows(CHAIN / "no-such.csv", missing_ok=True), [])
        with self.assertRaises(FileNotFoundError):
            slide.read_rows(CHAIN / "no-such.csv")

    def test_text_columns_stay_text(self):
        path = CHAIN / "text-column.csv"
        path.write_text("run,tt,value\ntt0,0,1.5\npure-mpm,,nan\n")
        table = slide.read_table(path)
        self.assertEqual(list(table["run"]), ["tt0", "pure-mpm"])
        self.assertTrue(np.isnan(table["tt"][1]))
        self.assertTrue(np.isnan(table["value"][1]))

    def test_recorder_columns_are_grouped_by_what_they_follow(self):
        path = CHAIN / "recorder.csv"
        path.write_text("time,base_ux,n12_ux,n12_ux_rel,e5_sxx,p7_eq,outflow\n"
                        "0,0,0,0,-1e4,0,0\n0.5,0.1,0.3,0.2,-2e4,0.01,1e-6\n")
        rec = slide.read_recorder(path)
        np.testing.assert_array_equal(rec["time"], [0.0, 0.5])
        self.assertEqual(rec["n12"]["ux_rel"][1], 0.2)
        self.assertEqual(rec["e5"]["sxx"][1], -2e4)
        self.assertEqual(rec["p7"]["eq"][1], 0.01)
        self.assertEqual(rec["base"]["ux"][1], 0.1)
        self.assertEqual(rec["outflow"][1], 1e-6)

    def test_particles_as_a_dataframe_where_pandas_is_installed(self):
        try:
            import pandas  # noqa: F401
        except ImportError:
            self.skipTest("python3-pandas is not installed (to_dataframe needs it)")
        mpm = slide.read_checkpoint(CHAIN / "mpm" / "mpm_final.h5")
        frame = slide.to_dataframe(mpm.particles)
        count = len(mpm.particles["id"])
        self.assertEqual(len(frame), count)
        np.testing.assert_array_equal(frame["id"].to_numpy(), mpm.particles["id"])
        np.testing.assert_array_equal(frame["coordinates_1"].to_numpy(),
                                      mpm.particles["coordinates"][:, 1])
        np.testing.assert_array_equal(frame["stress_3"].to_numpy(),
                                      mpm.particles["stress"][:, 3])

    def test_summary_keeps_words_and_reads_numbers(self):
        summary = slide.read_summary(CHAIN / "fem" / "fem_summary.txt")
        self.assertEqual(summary["element"], "quad4-1gp")
        self.assertEqual(summary["end_time"], 1.0)


if __name__ == "__main__":
    unittest.main(argv=sys.argv[:1])
