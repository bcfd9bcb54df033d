"""The report's section for tests.csv (a scenario's [test]): every metric gets a panel with a bar
per engine, an empty value is shown as "no value", and a run without tests.csv gets no plot."""

import csv
import os
import shutil
import tempfile
import unittest

from analysis.folder import Folder
from analysis.plots import Context, standard_tests, style
from analysis.tests import reportcheck as rc

RUN = os.path.join(rc.FIXTURES, "run")


def with_tests(src, dst, rows):
    """Copies run folder src to dst with a tests.csv of rows (engine, metric, value, unit)."""
    shutil.copytree(src, dst)
    with open(os.path.join(dst, "tests.csv"), "w", newline="", encoding="utf-8") as f:
        csv.writer(f, lineterminator="\n").writerows([["engine", "metric", "value", "unit"]] + rows)


class StandardTestsReport(unittest.TestCase):
    def setUp(self):
        self.tmp = tempfile.mkdtemp()

    def tearDown(self):
        shutil.rmtree(self.tmp)

    def folder(self):
        engines = Folder(RUN).engines()
        rows = []
        for k, e in enumerate(engines):
            # the last engine has no bending length (a chord angle the elastica cannot invert)
            rows += [[e, "chord_angle", str(40 + k), "deg"],
                     [e, "bending_length", "" if k == len(engines) - 1 else str(0.05 - 0.001 * k),
                      "m"]]
        dst = os.path.join(self.tmp, "run")
        with_tests(RUN, dst, rows)
        return Folder(dst), engines

    def test_metrics_in_file_order_with_empty_values_as_nan(self):
        f, engines = self.folder()
        metrics = standard_tests.metrics(f)
        self.assertEqual([m for m, _, _ in metrics], ["chord_angle", "bending_length"])
        self.assertEqual(metrics[0][1], "deg")
        self.assertEqual(metrics[0][2][engines[1]], 41.0)
        self.assertNotEqual(metrics[1][2][engines[-1]], metrics[1][2][engines[-1]])  # NaN

    def test_the_plot_names_each_metric_and_the_missing_value(self):
        f, engines = self.folder()
        self.assertTrue(standard_tests.available(f))
        self.assertFalse(standard_tests.available(Folder(RUN)))
        ctx = Context(self.tmp, True, style.Colors(engines))
        png = standard_tests.draw([f], ctx)
        self.assertTrue(os.path.getsize(png) > 1000)
        with open(os.path.join(self.tmp, "tests.svg"), encoding="utf-8") as svg:
            text = svg.read()
        for words in ("chord_angle (deg)", "bending_length (m)", "no value"):
            self.assertIn(words, text)

    def test_the_report_draws_it(self):
        f, _ = self.folder()
        out = os.path.join(self.tmp, "out")
        result = rc.run_report(f.path, "--out", out)
        self.assertEqual(result.returncode, 0, result.stderr)
        self.assertTrue(os.path.exists(os.path.join(out, "tests.png")))


if __name__ == "__main__":
    unittest.main()
