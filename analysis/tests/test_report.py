"""End-to-end: report.py on run, sweep and compare folders gives every image and one page.

The same checks run on real folders when CLOTHBENCH_RUN_DIR / CLOTHBENCH_SWEEP_DIR are set.
"""

import csv
import os
import re
import shutil
import tempfile
import unittest

from analysis.tests import reportcheck as rc


class ReportChecks:
    """Mixin: build the report of `folders` once, then check images and page.

    folders      input folders (the second one is passed with --compare)
    extra_args   more command-line arguments
    must_have    CSV files the folder must hold (a real run without them is a failure)
    skipped      plots the page must leave out, saying why (a chain casts no shadow, say);
                 every other plot its files give must be drawn
    """

    folders = ()
    extra_args = ()
    must_have = ()
    skipped = ()

    @classmethod
    def setUpClass(cls):
        cls.tmp = tempfile.mkdtemp(prefix="clothbench-report-")
        cls.out = os.path.join(cls.tmp, "out")
        args = [cls.folders[0]]
        if len(cls.folders) > 1:
            args += ["--compare", cls.folders[1]]
        cls.result = rc.run_report(*args, "--out", cls.out, *cls.extra_args)
        cls.expected = [s for s in rc.expected_images(*cls.folders) if s not in cls.skipped]

    @classmethod
    def tearDownClass(cls):
        shutil.rmtree(cls.tmp, ignore_errors=True)

    def test_folder_holds_the_files(self):
        for name in self.must_have:
            path = os.path.join(self.folders[0], name)
            self.assertTrue(os.path.exists(path) and rc.has_rows(path),
                            f"{path}: missing or without rows")

    def test_exits_zero(self):
        self.assertEqual(self.result.returncode, 0, self.result.stderr)
        self.assertNotIn("Traceback", self.result.stderr)
        self.assertIn("report.html", self.result.stdout)

    def test_every_expected_image_is_a_sensible_png(self):
        self.assertTrue(self.expected, "the folder gives no image at all")
        for stem in self.expected:
            path = os.path.join(self.out, stem + ".png")
            with self.subTest(image=stem):
                self.assertTrue(os.path.exists(path), f"{path} not written")
                width, height = rc.png_size(path)
                self.assertTrue(rc.MIN_W <= width <= rc.MAX_W, f"{path}: width {width}")
                self.assertTrue(rc.MIN_H <= height <= rc.MAX_H, f"{path}: height {height}")

    def test_no_unexpected_image(self):
        written = sorted(f[:-4] for f in os.listdir(self.out) if f.endswith(".png"))
        self.assertEqual(written, sorted(self.expected))

    def page(self):
        with open(os.path.join(self.out, "report.html"), encoding="utf-8") as f:
            return f.read()

    def svg(self, stem):
        """Text of stem.svg (written with --svg; its text stays text, so labels can be read)."""
        with open(os.path.join(self.out, stem + ".svg"), encoding="utf-8") as f:
            return f.read()

    def test_page_is_self_contained(self):
        self.assertEqual(rc.html_problems(self.page(), len(self.expected)), [])

    def test_left_out_plots_say_why(self):
        left_out = rc.skipped_plots(self.page())
        self.assertEqual(sorted(left_out), sorted(self.skipped))
        for stem, reason in left_out.items():
            self.assertTrue(reason.startswith("Not drawn: ") and len(reason) > 30, reason)


class RunFixture(ReportChecks, unittest.TestCase):
    folders = (os.path.join(rc.FIXTURES, "run"),)
    must_have = ("frames.csv", "divergence.csv", "snapshots.csv", "summary.csv")

    def test_verdicts_name_the_unstable_engine(self):
        with open(os.path.join(self.out, "report.html"), encoding="utf-8") as f:
            text = f.read()
        self.assertIn("custom-explicit: UNSTABLE, blew up at t = 0.15 s", text)
        self.assertIn("custom-rk4: stable for the whole run", text)
        self.assertIn("custom-symplectic vs custom-rk4: RMS distance", text)
        self.assertIn("Drape coefficients:", text)

    def test_no_energy_verdict_for_a_position_based_soft_body(self):
        # its dissipated column is its energy balance: an error of 0 J would be no finding
        with open(os.path.join(self.out, "report.html"), encoding="utf-8") as f:
            text = f.read()
        self.assertIn("bullet-softbody: no energy check", text)
        self.assertNotIn("bullet-softbody: energy error at most", text)
        self.assertIn("custom-rk4: energy error at most", text)


class SweepFixture(ReportChecks, unittest.TestCase):
    folders = (os.path.join(rc.FIXTURES, "sweep"),)
    extra_args = ("--svg",)

    def test_svg_besides_png(self):
        for stem in self.expected:
            with open(os.path.join(self.out, stem + ".svg"), encoding="utf-8") as f:
                self.assertIn("<svg", f.read(4000))

    def test_verdicts_in_words(self):
        with open(os.path.join(self.out, "report.html"), encoding="utf-8") as f:
            text = f.read()
        self.assertIn("custom / rk4: measured order 3.99 from 5 points (expected 4)", text)
        self.assertIn("Cheapest within tolerance 1e-4 m overall: custom / midpoint", text)
        self.assertIn("measured / predicted 0.97 (within 10 %)", text)


class CompareFixtures(ReportChecks, unittest.TestCase):
    folders = (os.path.join(rc.FIXTURES, "run"), os.path.join(rc.FIXTURES, "run_after"))
    extra_args = ("--labels", "before,after")

    def test_changes_in_words(self):
        with open(os.path.join(self.out, "report.html"), encoding="utf-8") as f:
            text = f.read()
        self.assertIn("custom-explicit: unstable (blew up at t = 0.15 s) in before, stable in "
                      "after.", text)
        self.assertIn("drawn with solid lines", text)


class ChainFixture(ReportChecks, unittest.TestCase):
    """Real hanging_chain output: a 1 x 11 grid has no area, so no shadow from above."""
    folders = (os.path.join(rc.FIXTURES, "chain"),)
    must_have = ("frames.csv", "divergence.csv", "snapshots.csv", "summary.csv")
    skipped = ("shadow",)

    def test_shadow_left_out_as_a_chain(self):
        self.assertIn("1 × 11 grid, a chain of particles", rc.skipped_plots(self.page())["shadow"])

    def test_drape_draws_the_chain(self):
        self.assertIn("drape", self.expected)
        self.assertIn("custom-implicit-euler: stable for the whole run", self.page())


class EdgeOnFixture(ReportChecks, unittest.TestCase):
    """Real flag output: a cloth hanging in a vertical plane is edge-on from above."""
    folders = (os.path.join(rc.FIXTURES, "edge_on"),)
    must_have = ("frames.csv", "divergence.csv", "snapshots.csv", "summary.csv")
    skipped = ("shadow",)

    def test_shadow_left_out_as_edge_on(self):
        self.assertIn("edge-on from above", rc.skipped_plots(self.page())["shadow"])


class ChainBesideCloth(ReportChecks, unittest.TestCase):
    """--compare of a chain with a draped cloth (two scenarios: --force, and a warning): the
    shadow plot is drawn, the chain's panel says its shadow is empty."""
    folders = (os.path.join(rc.FIXTURES, "chain"), os.path.join(rc.FIXTURES, "run"))
    extra_args = ("--svg", "--force")

    def test_warns_that_the_scenarios_differ(self):
        self.assertIn("report: warning: --compare:", self.result.stderr)

    def test_chain_panel_names_the_empty_shadow(self):
        svg = self.svg("shadow")
        self.assertIn("shadow 0 m² (a chain: no area)", svg)
        self.assertIn("drape coefficient 0.878", svg)


class StabilityLimitsFixture(ReportChecks, unittest.TestCase):
    """Real stability output on the chain: a limit found, a search stopped at --dt-max below the
    prediction (censored), and implicit Euler, unconditionally stable in linear theory."""
    folders = (os.path.join(rc.FIXTURES, "stability_chain"),)
    extra_args = ("--svg",)

    def verdict(self, key):
        found = re.findall(r'<li class="(\w+)"><span class="badge">\w+</span>'
                           + re.escape(key) + r"([^<]*)</li>", self.page())
        self.assertEqual(len(found), 1, key)
        return found[0]

    def test_infinite_prediction_is_unconditional_stability(self):
        kind, text = self.verdict("custom-rk4 / implicit-euler:")
        self.assertEqual(kind, "ok")
        self.assertIn("unconditionally stable in linear theory", text)
        self.assertNotIn("no predicted limit", text)

    def test_censored_ratio_is_a_lower_bound(self):
        kind, text = self.verdict("custom-rk4 / rk4:")
        self.assertEqual(kind, "info")
        self.assertIn("measured / predicted at least 0.78 (a lower bound", text)
        self.assertNotIn("outside", text)

    def test_found_limit_is_compared(self):
        kind, text = self.verdict("custom-rk4 / symplectic-euler:")
        self.assertEqual(kind, "ok")
        self.assertIn("measured / predicted 1.02 (within 10 %)", text)

    def test_plot_labels(self):
        svg = self.svg("stability")
        self.assertIn("unconditionally stable", svg)
        self.assertNotIn("no prediction", svg)
        self.assertIn("≥ 0.78", svg)


class MadeFolder:
    """Mixin (before ReportChecks): the input folder is made in a temporary folder by
    fill(folder), and removed afterwards."""

    @classmethod
    def setUpClass(cls):
        cls.src = tempfile.mkdtemp(prefix="clothbench-made-")
        cls.fill(cls.src)
        cls.folders = (cls.src,)
        super().setUpClass()

    @classmethod
    def tearDownClass(cls):
        super().tearDownClass()
        shutil.rmtree(cls.src, ignore_errors=True)


class StabilityWithoutRatio(MadeFolder, StabilityLimitsFixture):
    """The same, with the ratio of the censored row left empty (as clothbench will write it)."""

    @staticmethod
    def fill(folder):
        with open(os.path.join(rc.FIXTURES, "stability_chain", "stability.csv"),
                  encoding="utf-8") as f:
            rows = list(csv.reader(f))
        k = rows[0].index("ratio_measured_to_predicted")
        for row in rows[1:]:
            if row[rows[0].index("first_unstable_dt")] == "":
                row[k] = ""
        with open(os.path.join(folder, "stability.csv"), "w", newline="", encoding="utf-8") as f:
            csv.writer(f).writerows(rows)


class NothingMeetsTheTolerance(ReportChecks, unittest.TestCase):
    """Real accuracy output with --tolerance 1e-30 (recommendation.csv without a configuration)
    and --resolutions 5,9,13 (resolution.csv)."""
    folders = (os.path.join(rc.FIXTURES, "accuracy_flag"),)
    must_have = ("work_precision.csv", "recommendation.csv", "resolution.csv")
    extra_args = ("--svg",)

    def test_verdicts_say_nothing_meets_it(self):
        text = self.page()
        self.assertIn("Nothing meets the tolerance overall: no stable configuration within "
                      "tolerance 1e-30 m; the smallest max error is", text)
        self.assertIn("Nothing meets the tolerance for bullet-deformable-explicit", text)
        self.assertNotIn("Cheapest", text)
        self.assertNotIn("dt n/a", text)

    def test_legend_names_no_recommendation(self):
        svg = self.svg("work_precision")
        self.assertIn("nothing meets the tolerance overall", svg)
        self.assertNotIn("dt nan", svg)
        self.assertNotIn("dt n/a", svg)

    def test_resolution_plot_and_verdicts(self):
        svg = self.svg("resolution")
        for label in ("final RMS error vs finest-grid reference (m)",
                      "wall time per simulated second (s/s)", "13 × 13", "h 0.125 m",
                      "custom-rk4 / midpoint", "bullet-deformable-explicit"):
            self.assertIn(label, svg)
        self.assertIn("custom-rk4 / symplectic-euler: final error 5.47 mm on 5 × 5, 366 µm on "
                      "9 × 9, 15.4 µm on 13 × 13.", self.page())
        self.assertIn("Every resolution row", self.page())


class PartialFolder(MadeFolder, ReportChecks, unittest.TestCase):
    """A folder with frames.csv alone (no scenario, no summary) still gives its two plots."""

    @staticmethod
    def fill(folder):
        shutil.copy(os.path.join(rc.FIXTURES, "run", "frames.csv"), folder)

    def test_only_frame_plots(self):
        self.assertEqual(sorted(self.expected), ["energy", "strain"])


@unittest.skipUnless(os.environ.get("CLOTHBENCH_RUN_DIR"), "CLOTHBENCH_RUN_DIR not set")
class RealRun(ReportChecks, unittest.TestCase):
    folders = (os.environ.get("CLOTHBENCH_RUN_DIR", ""),)
    must_have = ("frames.csv", "divergence.csv", "snapshots.csv", "summary.csv")
    skipped = tuple(s for s in os.environ.get("CLOTHBENCH_RUN_SKIPPED", "").split(",") if s)


@unittest.skipUnless(os.environ.get("CLOTHBENCH_SWEEP_DIR"), "CLOTHBENCH_SWEEP_DIR not set")
class RealSweep(ReportChecks, unittest.TestCase):
    folders = (os.environ.get("CLOTHBENCH_SWEEP_DIR", ""),)

    def test_folder_holds_sweep_results(self):
        names = ("stability.csv", "work_precision.csv")
        self.assertTrue(any(os.path.exists(os.path.join(self.folders[0], n)) for n in names),
                        f"{self.folders[0]}: neither {' nor '.join(names)}")


if __name__ == "__main__":
    unittest.main()
