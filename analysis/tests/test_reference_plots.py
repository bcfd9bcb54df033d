"""The accuracy sweep's reference.csv and resolution_recommendation.csv each get a plot."""

import csv
import os
import shutil
import unittest

from analysis.tests import reportcheck as rc
from analysis.tests.test_report import MadeFolder, ReportChecks


class ReferenceAndNoRecommendation(ReportChecks, unittest.TestCase):
    """Real accuracy output (flag, --tolerance 1e-30, --resolutions 5,9,13)."""
    folders = (os.path.join(rc.FIXTURES, "accuracy_flag"),)
    must_have = ("reference.csv", "resolution_recommendation.csv")
    extra_args = ("--svg",)

    def test_both_plots_drawn(self):
        self.assertIn("reference", self.expected)
        self.assertIn("resolution_recommendation", self.expected)
        self.assertIn("reference.png", self.result.stdout)
        self.assertIn("resolution_recommendation.png", self.result.stdout)

    def test_reference_plot_names_both_references(self):
        svg = self.svg("reference")
        self.assertIn("reference rk4 at dt = 1.25e-5 s, floor 1.6e-15 m", svg)
        self.assertIn("reference: rk4 on 169 particles at dt = 5e-5 s", svg)

    def test_recommendation_plot_says_nothing_meets_it(self):
        svg = self.svg("resolution_recommendation")
        self.assertIn("no configuration meets the tolerance", svg)
        self.assertIn("tolerance 1e-30 m", svg)


class ResolutionRecommendationFound(MadeFolder, ReportChecks, unittest.TestCase):
    """The same sweep with a tolerance that 81 particles of midpoint meet."""
    extra_args = ("--svg",)

    @staticmethod
    def fill(folder):
        src = os.path.join(rc.FIXTURES, "accuracy_flag")
        for name in os.listdir(src):
            shutil.copy(os.path.join(src, name), folder)
        header = ["scope", "engine", "integrator", "particles", "dt", "error_final",
                  "wall_s_per_sim_s", "tolerance"]
        rows = [["engine", "custom-rk4", "midpoint", "81", "0.0001", "0.0003752578639580358",
                 "0.07848816000000071", "0.001"],
                ["engine", "bullet-deformable-explicit", "", "", "", "", "", "0.001"],
                ["overall", "custom-rk4", "midpoint", "81", "0.0001", "0.0003752578639580358",
                 "0.07848816000000071", "0.001"]]
        with open(os.path.join(folder, "resolution_recommendation.csv"), "w", newline="",
                  encoding="utf-8") as f:
            csv.writer(f).writerows([header] + rows)

    def test_recommendation_is_ringed_and_named(self):
        svg = self.svg("resolution_recommendation")
        self.assertIn("recommended (overall): 81 particles, dt 1e-4 s", svg)
        self.assertIn("recommended (custom-rk4): 81 particles, dt 1e-4 s", svg)
        self.assertIn("tolerance 0.001 m", svg)
        self.assertNotIn("no configuration meets the tolerance", svg)


if __name__ == "__main__":
    unittest.main()
