"""The report's bias-extension section (bias.csv): force, shear force and angle per engine, the
shear stiffness from tests.csv in the legend, "no value" where tests.csv has none, an engine
without forces drawn in the angle panel only, and no plot without the file."""

import csv
import math
import os
import shutil
import tempfile
import unittest

from analysis.folder import Folder
from analysis.plots import Context, bias_curve, style
from analysis.tests import reportcheck as rc

RUN = os.path.join(rc.FIXTURES, "run")


def write(path, rows):
    with open(path, "w", newline="", encoding="utf-8") as f:
        csv.writer(f, lineterminator="\n").writerows(rows)


class BiasCurveReport(unittest.TestCase):
    def setUp(self):
        self.tmp = tempfile.mkdtemp()

    def tearDown(self):
        shutil.rmtree(self.tmp)

    def folder(self):
        """The fixture run: the first engine with forces (slope 20 N/m/rad), the last without."""
        dst = os.path.join(self.tmp, "run")
        shutil.copytree(RUN, dst)
        engines = Folder(RUN).engines()
        curve = [["engine", "t", "displacement", "force", "angle_pin_jointed", "angle",
                  "shear_force", "shear_force_pin_jointed"]]
        tests = [["engine", "metric", "value", "unit"]]
        for k, e in enumerate(engines):
            forces = k == 0
            for i in range(20):
                g = 0.005 * i
                curve.append([e, str(0.1 * i), str(0.0005 * i), str(0.1 * i) if forces else "",
                              str(1.2 * g), str(g), str(20 * g) if forces else "",
                              str(16 * g) if forces else ""])
            tests += [[e, "shear_stiffness", "20" if forces else "", "N/m/rad"],
                      [e, "fit_angle", "5", "deg"]]
        write(os.path.join(dst, "bias.csv"), curve)
        write(os.path.join(dst, "tests.csv"), tests)
        return Folder(dst), engines

    def test_stiffness_reads_the_slope_and_the_fit_range(self):
        f, engines = self.folder()
        slopes = bias_curve.stiffness(f)
        self.assertEqual(slopes[engines[0]], (20.0, 5.0))
        self.assertTrue(math.isnan(slopes[engines[-1]][0]))

    def test_the_plot_names_each_engine_with_its_stiffness(self):
        f, engines = self.folder()
        self.assertTrue(bias_curve.available(f))
        self.assertFalse(bias_curve.available(Folder(RUN)))
        ctx = Context(self.tmp, True, style.Colors(engines))
        png = bias_curve.draw([f], ctx)
        self.assertTrue(os.path.getsize(png) > 1000)
        with open(os.path.join(self.tmp, "bias.svg"), encoding="utf-8") as svg:
            text = svg.read()
        for words in (f"{engines[0]}: shear_stiffness 20 N/m/rad", "pin-jointed net",
                      "fit range", "shear force per unit length (N/m)"):
            self.assertIn(words, text)
        # the engine without forces has no shear-force line
        self.assertNotIn(f"{engines[-1]}: shear_stiffness", text)


if __name__ == "__main__":
    unittest.main()
