"""Stability measured by growth (`clothbench stability --method growth|blowup|both`): the growth
limit beside the blow-up one, the growing modes drawn on the cloth, verdicts that say what sets
the limit, older folders without the new columns, and a corrupt mode file named clearly.

The fixture's numbers come from a provisional growth estimator: these tests check the structure
of what is drawn and said, never those numbers.
"""

import csv
import os
import re
import shutil
import tempfile
import unittest

from analysis.tests import reportcheck as rc
from analysis.tests.test_report import MadeFolder, ReportChecks

GROWTH = os.path.join(rc.FIXTURES, "stability_growth")
# the columns a stability.csv had before growth was measured
OLD_COLUMNS = ["engine", "integrator", "stable_dt", "first_unstable_dt", "predicted_dt",
               "ratio_measured_to_predicted", "cause", "runs", "rerun", "rerun_unstable"]
BLOWUP_COLUMNS = ["stable_dt", "first_unstable_dt", "ratio_measured_to_predicted", "cause",
                  "rerun", "rerun_unstable", "blowup_steps"]
GROWTH_COLUMNS = ["growth_stable_dt", "growth_first_unstable_dt", "growth_rate",
                  "physical_rate", "growth_ratio", "growth_cause", "mode_structural",
                  "mode_shear", "mode_bend", "growth_steps"]


def fixture_rows():
    """The fixture's stability.csv as (header, rows of dicts)."""
    with open(os.path.join(GROWTH, "stability.csv"), newline="", encoding="utf-8") as f:
        rows = list(csv.DictReader(f))
    return list(rows[0]), rows


def write_stability(folder, header, rows):
    with open(os.path.join(folder, "stability.csv"), "w", newline="", encoding="utf-8") as f:
        w = csv.DictWriter(f, header, extrasaction="ignore")
        w.writeheader()
        w.writerows(rows)


def verdicts(page):
    """(kind, text) of every verdict line of a report page."""
    return re.findall(r'<li class="(\w+)"><span class="badge">\w+</span>([^<]*)</li>', page)


def stability_verdict(page, integrator):
    found = [(k, t) for k, t in verdicts(page) if t.startswith(f"custom-rk4 / {integrator}:")]
    assert len(found) == 1, (integrator, found)
    return found[0]


class GrowthFixture(ReportChecks, unittest.TestCase):
    """Real `--method both` output on the sphere drape, with the modes of rows 0 and 2."""
    folders = (GROWTH,)
    must_have = ("stability.csv",)
    extra_args = ("--svg",)

    def test_draws_both_plots(self):
        self.assertIn("stability", self.expected)
        self.assertIn("stability_mode", self.expected)

    def test_one_mode_panel_per_row_with_a_mode_file(self):
        svg = self.svg("stability_mode")
        # rows 0 (explicit-euler) and 2 (rk4) have a mode file; 1 and 3 have none
        # titles: "ENGINE INTEGRATOR at dt = ... s:", the spring energy shares, the cause
        titles = re.findall(r">custom-rk4 ([a-z0-9-]+) at dt = [^:<]+ s:</text>", svg)
        self.assertEqual(titles, ["explicit-euler", "rk4"])
        self.assertEqual(len(re.findall(r">structural \d+ %, shear \d+ %, bend \d+ %</text>",
                                        svg)), 2)
        self.assertEqual(svg.count("|u_p| (mode scaled to largest component 1)"), 2)
        self.assertEqual(svg.count("set by contact"), 2)
        for axis in ("x (m)", "z (m)"):  # the cloth lies in xz: seen along y
            self.assertIn(axis, svg)
        self.assertNotIn("y (m)", svg)

    def test_growth_limit_beside_the_blowup_limit(self):
        svg = self.svg("stability")
        for label in ("measured stable dt", "growth limit (no disturbance grows too fast)",
                      "growth: first dt with a growing mode", "growth limit / predicted",
                      "measured / predicted", "contact"):
            self.assertIn(label, svg)

    def test_verdicts_say_the_growth_limit_and_what_sets_it(self):
        page = self.page()
        for integrator in ("explicit-euler", "symplectic-euler", "rk4", "imex-euler"):
            _, text = stability_verdict(page, integrator)
            self.assertIn("largest stable dt", text)
            self.assertIn("; growth limit ", text)
            self.assertRegex(text, r"growth limit / predicted \d+\.\d\d")
        self.assertIn("set by contact", stability_verdict(page, "rk4")[1])
        self.assertIn("set by the free cloth", stability_verdict(page, "symplectic-euler")[1])


class OldStabilityFolder(MadeFolder, ReportChecks, unittest.TestCase):
    """A stability.csv written before growth was measured: the blow-up plot alone, no growth
    words, no mode plot and no note about one."""
    extra_args = ("--svg",)

    @staticmethod
    def fill(folder):
        _, rows = fixture_rows()
        write_stability(folder, OLD_COLUMNS, rows)

    def test_blowup_limits_only(self):
        self.assertEqual(self.expected, ["stability"])
        svg = self.svg("stability")
        self.assertIn("measured stable dt", svg)
        self.assertNotIn("growth", svg)
        for _, text in verdicts(self.page()):
            self.assertNotIn("growth", text)
        _, text = stability_verdict(self.page(), "rk4")
        self.assertIn("measured / predicted", text)


class GrowthOnly(MadeFolder, ReportChecks, unittest.TestCase):
    """--method growth: the blow-up columns are empty, which is not 'never stable'."""
    extra_args = ("--svg",)

    @staticmethod
    def fill(folder):
        header, rows = fixture_rows()
        for row in rows:
            row.update({c: "" for c in BLOWUP_COLUMNS}, method="growth")
        write_stability(folder, header, rows)
        shutil.copytree(os.path.join(GROWTH, "stability_modes"),
                        os.path.join(folder, "stability_modes"))

    def test_growth_markers_without_blowup_ones(self):
        svg = self.svg("stability")
        self.assertIn("growth limit (no disturbance grows too fast)", svg)
        self.assertNotIn("never stable", svg)
        self.assertNotIn("measured stable dt", svg)
        self.assertIn("stability_mode", self.expected)

    def test_verdicts_judge_the_growth_limit(self):
        page = self.page()
        kind, text = stability_verdict(page, "symplectic-euler")
        self.assertIn("measured by growth only", text)
        self.assertIn("against the prediction", text)
        self.assertNotIn("no stable time step found", text)
        # a limit set by contact is not held to the free scene's prediction
        kind, text = stability_verdict(page, "rk4")
        self.assertEqual(kind, "info")
        self.assertIn("set by contact", text)


class BlowupOnly(MadeFolder, ReportChecks, unittest.TestCase):
    """--method blowup: the growth columns are there but empty; nothing about growth."""
    extra_args = ("--svg",)

    @staticmethod
    def fill(folder):
        header, rows = fixture_rows()
        for row in rows:
            row.update({c: "" for c in GROWTH_COLUMNS}, method="blowup")
        write_stability(folder, header, rows)

    def test_no_growth_drawn_or_said(self):
        self.assertEqual(self.expected, ["stability"])
        self.assertNotIn("growth", self.svg("stability"))
        for _, text in verdicts(self.page()):
            self.assertNotIn("growth", text)


class GrowthWithoutModes(MadeFolder, ReportChecks, unittest.TestCase):
    """Growth measured but no stability_modes/: the mode plot is left out, saying why."""
    skipped = ("stability_mode",)

    @staticmethod
    def fill(folder):
        shutil.copy(os.path.join(GROWTH, "stability.csv"), folder)

    def test_reason_names_the_missing_files(self):
        reason = rc.skipped_plots(self.page())["stability_mode"]
        self.assertIn("stability_modes/ROW.npy", reason)


class BadModeFiles(unittest.TestCase):
    """A corrupt, misshapen or stray mode file stops the report with one line naming it."""

    def setUp(self):
        self.tmp = tempfile.mkdtemp(prefix="clothbench-growth-")
        self.folder = os.path.join(self.tmp, "sweep")
        shutil.copytree(GROWTH, self.folder)
        self.modes = os.path.join(self.folder, "stability_modes")
        self.out = os.path.join(self.tmp, "out")

    def tearDown(self):
        shutil.rmtree(self.tmp, ignore_errors=True)

    def assert_fails(self, *fragments):
        result = rc.run_report(self.folder, "--out", self.out)
        self.assertEqual(result.returncode, 2, f"stdout: {result.stdout}\nstderr: {result.stderr}")
        self.assertNotIn("Traceback", result.stderr)
        self.assertEqual(len(result.stderr.strip().splitlines()), 1, result.stderr)
        self.assertTrue(result.stderr.startswith("clothbench: report: "), result.stderr)
        for fragment in fragments:
            self.assertIn(fragment, result.stderr)
        self.assertFalse(os.path.exists(os.path.join(self.out, "report.html")))

    def test_corrupt_npy(self):
        with open(os.path.join(self.modes, "0.npy"), "wb") as f:
            f.write(b"\x93NUMPY garbage, not an array")
        self.assert_fails(os.path.join("stability_modes", "0.npy"), "not a readable .npy")

    def test_truncated_npy(self):
        path = os.path.join(self.modes, "2.npy")
        with open(path, "rb") as f:
            data = f.read()
        with open(path, "wb") as f:
            f.write(data[:len(data) // 2])
        self.assert_fails(os.path.join("stability_modes", "2.npy"))

    def test_wrong_shape(self):
        import numpy as np
        np.save(os.path.join(self.modes, "0.npy"), np.zeros((2, 625), dtype=np.float32))
        self.assert_fails(os.path.join("stability_modes", "0.npy"), "3 by #P", "(2, 625)")
        np.save(os.path.join(self.modes, "0.npy"), np.zeros((3, 624), dtype=np.float32))
        self.assert_fails(os.path.join("stability_modes", "0.npy"), "624 particles")

    def test_mode_of_a_row_that_is_not_there(self):
        shutil.copy(os.path.join(self.modes, "0.npy"), os.path.join(self.modes, "9.npy"))
        self.assert_fails(os.path.join("stability_modes", "9.npy"), "no row 9")

    def test_missing_rest_positions(self):
        os.remove(os.path.join(self.modes, "rest.npy"))
        self.assert_fails(os.path.join("stability_modes", "rest.npy"), "not found")


class GrowthHelpers(unittest.TestCase):
    def test_new_columns_are_read_as_numbers_and_text(self):
        from analysis.csvio import read_table
        t = read_table(os.path.join(GROWTH, "stability.csv"))
        self.assertEqual(t["growth_stable_dt"].dtype.kind, "f")
        self.assertEqual(t["mode_bend"].dtype.kind, "f")
        self.assertEqual(t["method"][0], "both")
        self.assertTrue(str(t["growth_cause"][0]).startswith("set by contact"))

    def test_what_sets_the_growth_limit(self):
        from analysis.verdicts import growth_setting
        self.assertEqual(growth_setting("set by contact: grows at ..."), "contact")
        self.assertEqual(growth_setting("free: grows at start (1/s)"), "free")
        self.assertEqual(growth_setting("no growth past the tolerance up to dt_max"), "none")
        self.assertEqual(growth_setting("free: non-smooth: ..."), "free (non-smooth)")
        self.assertEqual(growth_setting("free: grows at 'start' at 33.2/s; near the physics: "
                                        "no state grows more than 13% faster ..."),
                         "free (near the physics)")
        self.assertEqual(growth_setting(""), "")

    def test_near_the_physics_says_the_rows_percent(self):
        from analysis.verdicts import _growth_text
        row = {"growth_stable_dt": 0.01, "growth_first_unstable_dt": 0.011, "predicted_dt": 0.02,
               "growth_rate": 40.0, "physical_rate": 35.0,
               "growth_cause": "free: grows at 'start' at 40/s; near the physics: no state "
                               "grows more than 13% faster than its physical rate ..."}
        self.assertIn("grows at most 13 % faster", _growth_text(row))
        row["growth_cause"] = "free: grows at 'start' at 40/s"
        self.assertNotIn("near the physics", _growth_text(row))

    def test_short_cause(self):
        from analysis.plots.stability_mode import CAUSE_CHARS, short_cause
        self.assertEqual(short_cause("free: grows at start (587.6216900373003/s)"),
                         "free: grows at start (588/s)")
        long = "set by contact: " + "word " * 40 + "non-smooth: a contact switch"
        short = short_cause(long)
        self.assertLessEqual(len(short), CAUSE_CHARS + len(" (non-smooth)"))
        self.assertTrue(short.endswith("(non-smooth)"), short)
        near = "free: " + "word " * 40 + "near the physics: no state grows more than 1% ..."
        self.assertTrue(short_cause(near).endswith("(near the physics)"), short_cause(near))


if __name__ == "__main__":
    unittest.main()
