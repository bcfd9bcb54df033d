"""The report's strip-tensile section (tensile.csv): a line per engine with its tensile stiffness
from tests.csv in the legend, "no value" where tests.csv has none, and no plot without the file."""

import csv
import os
import shutil
import tempfile
import unittest

from analysis.folder import Folder
from analysis.plots import Context, style, tensile_curve
from analysis.tests import reportcheck as rc

RUN = os.path.join(rc.FIXTURES, "run")


def write(path, rows):
    with open(path, "w", newline="", encoding="utf-8") as f:
        csv.writer(f, lineterminator="\n").writerows(rows)


class TensileCurveReport(unittest.TestCase):
    def setUp(self):
        self.tmp = tempfile.mkdtemp()

    def tearDown(self):
        shutil.rmtree(self.tmp)

    def folder(self):
        """The fixture run with a straight curve per engine, slope 1000 N/m for the first."""
        dst = os.path.join(self.tmp, "run")
        shutil.copytree(RUN, dst)
        engines = Folder(RUN).engines()
        curve = [["engine", "t", "strain", "force_per_width"]]
        tests = [["engine", "metric", "value", "unit"]]
        for k, e in enumerate(engines):
            curve += [[e, str(0.1 * i), str(0.001 * i), str(1000 * 0.001 * i)] for i in range(20)]
            tests += [[e, "tensile_stiffness", "1000" if k == 0 else "", "N/m"],
                      [e, "fit_strain", "0.01", "1"]]
        write(os.path.join(dst, "tensile.csv"), curve)
        write(os.path.join(dst, "tests.csv"), tests)
        return Folder(dst), engines

    def test_stiffness_reads_the_slope_and_the_fit_range(self):
        f, engines = self.folder()
        slopes = tensile_curve.stiffness(f)
        self.assertEqual(slopes[engines[0]], (1000.0, 0.01))
        self.assertNotEqual(slopes[engines[-1]][0], slopes[engines[-1]][0])  # NaN

    def test_the_plot_names_each_engine_with_its_stiffness(self):
        f, engines = self.folder()
        self.assertTrue(tensile_curve.available(f))
        self.assertFalse(tensile_curve.available(Folder(RUN)))
        ctx = Context(self.tmp, True, style.Colors(engines))
        png = tensile_curve.draw([f], ctx)
        self.assertTrue(os.path.getsize(png) > 1000)
        with open(os.path.join(self.tmp, "tensile.svg"), encoding="utf-8") as svg:
            text = svg.read()
        for words in (f"{engines[0]}: tensile_stiffness 1000 N/m", "no value", "fit range",
                      "force per width (N/m)"):
            self.assertIn(words, text)


if __name__ == "__main__":
    unittest.main()
