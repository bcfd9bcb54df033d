"""The stability map plot (`clothbench map`'s map.csv): one varied key draws measured limits
over the predicted curve per integrator, log-log; two draw one heat map per integrator with
the predicted contours."""

import csv
import os
import unittest

from analysis.tests.test_report import MadeFolder, ReportChecks

HEADER = ["engine", "integrator", "stable_dt", "first_unstable_dt", "predicted_dt",
          "ratio_measured_to_predicted", "cause", "runs", "rerun", "rerun_unstable"]


def limit(k, integrator):
    """A limit that falls as 1/sqrt(k), as an explicit integrator's does with stiffness."""
    return (2.0 if integrator == "rk4" else 1.4) / (k ** 0.5)


def write_map(folder, keys, points):
    with open(os.path.join(folder, "map.csv"), "w", newline="", encoding="utf-8") as f:
        w = csv.writer(f)
        w.writerow(keys + HEADER)
        for values in points:
            k = float(values[0]) * (1 + 0.01 * float(values[-1]) if len(values) == 2 else 1)
            for i in ("symplectic-euler", "rk4"):
                pred = limit(k, i)
                meas = pred * 0.98
                w.writerow(values + ["custom-rk4", i, meas, meas * 1.01, pred, meas / pred,
                                     "strain", 12, "", ""])


class OneKeyMap(MadeFolder, ReportChecks, unittest.TestCase):
    extra_args = ("--svg",)

    @staticmethod
    def fill(folder):
        write_map(folder, ["cloth.stiffness.structural"],
                  [[str(k)] for k in (100, 1000, 10000, 100000)])

    def test_loglog_key_and_both_integrators(self):
        svg = self.svg("stability_map")
        self.assertIn("cloth.stiffness.structural", svg)
        for i in ("symplectic-euler", "rk4"):
            self.assertIn(f"custom-rk4 / {i} measured", svg)
            self.assertIn(f"custom-rk4 / {i} predicted", svg)


class TwoKeyMap(MadeFolder, ReportChecks, unittest.TestCase):
    extra_args = ("--svg",)

    @staticmethod
    def fill(folder):
        write_map(folder, ["cloth.stiffness.structural", "cloth.damping"],
                  [[str(k), str(c)] for k in (100, 1000, 10000) for c in (0, 10, 20)])

    def test_one_heat_map_per_integrator_with_contours(self):
        svg = self.svg("stability_map")
        for i in ("symplectic-euler", "rk4"):
            self.assertIn(f"custom-rk4 / {i}", svg)
        self.assertIn("cloth.damping", svg)
        self.assertIn("log10 measured stable dt", svg)


if __name__ == "__main__":
    unittest.main()
