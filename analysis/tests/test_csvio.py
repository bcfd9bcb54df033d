"""csvio: schemas, tolerance of extra columns, C++ number spellings, quoted fields."""

import math
import os
import shutil
import tempfile
import unittest

import numpy as np

from analysis.csvio import SCHEMAS, ReportError, read_table
from analysis.quantities import length, num


class ReadTable(unittest.TestCase):
    def setUp(self):
        self.tmp = tempfile.mkdtemp(prefix="clothbench-csv-")

    def tearDown(self):
        shutil.rmtree(self.tmp, ignore_errors=True)

    def write(self, name, text):
        path = os.path.join(self.tmp, name)
        with open(path, "w", encoding="utf-8") as f:
            f.write(text)
        return path

    def test_extra_columns_are_kept_as_text(self):
        header = ",".join(SCHEMAS["convergence.csv"].required) + ",note"
        t = read_table(self.write("convergence.csv", header + "\ncustom,rk4,3.98,5,fine\n"))
        self.assertEqual(t["note"][0], "fine")
        self.assertAlmostEqual(t["order"][0], 3.98)

    def test_columns_in_any_order(self):
        t = read_table(self.write("convergence.csv",
                                  "points,order,integrator,engine\n4,2.0,midpoint,custom\n"))
        self.assertEqual(t["integrator"][0], "midpoint")
        self.assertEqual(t["points"][0], 4.0)

    def test_cpp_number_spellings_and_empty_fields(self):
        header = ",".join(SCHEMAS["stability.csv"].required)
        t = read_table(self.write("stability.csv",
                                  header + '\ncustom,rk4,1e-4,inf,,nan,"strain, mode 3"\n'))
        self.assertEqual(t["stable_dt"][0], 1e-4)
        self.assertTrue(math.isinf(t["first_unstable_dt"][0]))
        self.assertTrue(math.isnan(t["predicted_dt"][0]))
        self.assertTrue(math.isnan(t["ratio_measured_to_predicted"][0]))
        self.assertEqual(t["cause"][0], "strain, mode 3")

    def test_recommendation_that_found_nothing(self):
        # as clothbench accuracy writes it when no configuration meets --tolerance
        header = ",".join(SCHEMAS["recommendation.csv"].required)
        t = read_table(self.write("recommendation.csv", header + "\nengine,custom-rk4,,,,,1e-30\n"
                                  "overall,,,,,,1e-30\n"))
        self.assertEqual(list(t["engine"]), ["custom-rk4", ""])
        self.assertTrue(np.all(np.isnan(t["dt"])))
        self.assertEqual(t["tolerance"][1], 1e-30)

    def test_recommendation_needs_a_scope(self):
        header = ",".join(SCHEMAS["recommendation.csv"].required)
        with self.assertRaisesRegex(ReportError, "line 2, column 'scope': empty value"):
            read_table(self.write("recommendation.csv", header + "\n,custom,rk4,1e-4,1,1,1\n"))

    def test_resolution_rows(self):
        header = ",".join(SCHEMAS["resolution.csv"].required) + ",rerun"
        t = read_table(self.write("resolution.csv", header + '\ncustom-rk4,midpoint,81,0.0001,1,'
                                  '0.000375,0.0786,4000,"--set cloth.particles=[9,9]"\n'))
        self.assertEqual(t["particles"][0], 81.0)
        self.assertEqual(t["stable"][0], 1.0)
        self.assertEqual(t["rerun"][0], "--set cloth.particles=[9,9]")

    def test_blank_lines_and_crlf(self):
        header = ",".join(SCHEMAS["convergence.csv"].required)
        t = read_table(self.write("convergence.csv", header + "\r\ncustom,rk4,4,5\r\n\r\n"))
        self.assertEqual(len(t), 1)

    def test_missing_file(self):
        with self.assertRaisesRegex(ReportError, "frames.csv: file not found"):
            read_table(os.path.join(self.tmp, "frames.csv"))

    def test_every_missing_column_is_named(self):
        with self.assertRaisesRegex(ReportError, "columns 'order', 'points'"):
            read_table(self.write("convergence.csv", "engine,integrator\ncustom,rk4\n"))

    def test_select_and_unique(self):
        header = ",".join(SCHEMAS["convergence.csv"].required)
        t = read_table(self.write("convergence.csv", header + "\nb,rk4,4,5\na,x,1,3\nb,y,2,4\n"))
        self.assertEqual(t.unique("engine"), ["b", "a"])
        np.testing.assert_array_equal(t.select(engine="b")["order"], [4.0, 2.0])


class Formatting(unittest.TestCase):
    def test_numbers(self):
        self.assertEqual(num(2e-4), "2e-4")
        self.assertEqual(num(20000.0), "20000")
        self.assertEqual(num(0.15), "0.15")
        self.assertEqual(num(float("nan")), "n/a")

    def test_lengths(self):
        self.assertEqual(length(0.00128), "1.28 mm")
        self.assertEqual(length(2.5e-5), "25 µm")
        self.assertEqual(length(1.5), "1.5 m")


class StabilityAgreement(unittest.TestCase):
    """Measured against predicted stable time steps (s), in words."""

    def agree(self, measured, predicted, ratio=math.nan, censored=False):
        from analysis.verdicts import stability_agreement
        return stability_agreement(measured, predicted, ratio, censored)

    def test_found_limit(self):
        self.assertEqual(self.agree(0.97e-3, 1e-3, 0.97)[0], "ok")
        kind, text = self.agree(0.5e-3, 1e-3)
        self.assertEqual(kind, "bad")
        self.assertIn("0.50 (outside 10 %)", text)

    def test_censored_ratio_is_a_lower_bound(self):
        kind, text = self.agree(0.5e-3, 1e-3, 0.5, censored=True)
        self.assertEqual(kind, "info")
        self.assertIn("at least 0.50 (a lower bound", text)
        # stable beyond the prediction by more than 10 %: a disagreement even as a bound
        kind, text = self.agree(1.5e-3, 1e-3, math.nan, censored=True)
        self.assertEqual(kind, "bad")
        self.assertIn("at least 1.50", text)

    def test_unconditionally_stable(self):
        kind, text = self.agree(0.01, math.inf, censored=True)
        self.assertEqual(kind, "ok")
        self.assertIn("unconditionally stable in linear theory", text)
        kind, text = self.agree(0.01, math.inf, censored=False)
        self.assertEqual(kind, "bad")
        self.assertIn("yet a larger step failed", text)

    def test_no_theory(self):
        self.assertEqual(self.agree(1e-3, math.nan), ("info", "; no predicted limit"))


class PlotHelpers(unittest.TestCase):
    def test_pareto_front(self):
        from analysis.plots.work_precision import pareto
        x = np.array([1.0, 2.0, 3.0, 4.0, 0.5])
        y = np.array([1e-2, 1e-3, 2e-3, 1e-5, 1e-1])
        self.assertEqual(pareto(x, y), [4, 0, 1, 3])

    def test_triangle_areas(self):
        from analysis.plots.shadow import casts_shadow, triangle_areas
        # a flat 2 x 3 grid, 1 m by 2 m in the xz plane: four triangles of 0.5 m²
        i, j = np.meshgrid([0.0, 1.0], [0.0, 1.0, 2.0], indexing="ij")
        flat = np.stack([i, np.zeros_like(i), j], axis=-1)
        np.testing.assert_allclose(triangle_areas(flat), [0.5] * 4)
        np.testing.assert_allclose(triangle_areas(flat, [0, 2]), [0.5] * 4)
        self.assertTrue(casts_shadow(flat, [0, 2]))
        # the same grid stood up in the xy plane is edge-on from above
        upright = flat[:, :, [0, 2, 1]]
        self.assertFalse(casts_shadow(upright, [0, 2]))
        # a chain has no triangles
        self.assertEqual(len(triangle_areas(flat[:1])), 0)
        self.assertFalse(casts_shadow(flat[:1], [0, 2]))

    def test_snapshot_choice(self):
        from analysis.plots.drape import choose_times
        times = [0.0, 0.5, 1.0, 1.5, 2.0, 2.5, 3.0]
        self.assertEqual(choose_times(times), [0.0, 1.0, 2.0, 3.0])
        self.assertEqual(choose_times(times, wanted=[0.4, 2.9]), [0.5, 3.0])
        self.assertEqual(choose_times([0.0, 3.0]), [0.0, 3.0])


if __name__ == "__main__":
    unittest.main()
