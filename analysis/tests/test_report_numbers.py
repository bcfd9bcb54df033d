"""The report's numbers: the energy verdict's scale does not depend on where a potential's zero lies: the same run
with its gravity potential shifted by a constant (the floor moved from y = 0 to y = 10, in the
potential only) gets the same scale and the same percentage."""

import math
import os
import unittest

import numpy as np

from analysis import verdicts
from analysis.csvio import Table, read_table
from analysis.tests import reportcheck as rc


class EnergyScale(unittest.TestCase):
    def setUp(self):
        frames = read_table(os.path.join(rc.FIXTURES, "run", "frames.csv"))
        engine = frames.unique("engine")[0]
        self.rows = frames.select(engine=engine)

    def shifted(self, offset):
        columns = {name: self.rows[name] for name in self.rows.columns}
        columns["gravity_potential"] = columns["gravity_potential"] + offset
        columns["total_energy"] = columns["total_energy"] + offset
        return Table(self.rows.path, columns, self.rows.order)

    def test_gauge_independent(self):
        base = verdicts.energy_scale(self.rows)
        self.assertTrue(math.isfinite(base) and base > 0, base)
        for offset in (-1e3, -1.0, 1e-3, 1e3):
            with self.subTest(offset=offset):
                self.assertAlmostEqual(verdicts.energy_scale(self.shifted(offset)), base,
                                       delta=1e-9 * max(1.0, abs(offset)))

    def test_is_the_largest_energy_moved(self):
        # at least the largest kinetic energy, and the largest drop in gravity potential
        scale = verdicts.energy_scale(self.rows)
        gp = self.rows["gravity_potential"]
        self.assertGreaterEqual(scale, float(np.max(self.rows["kinetic"])))
        self.assertGreaterEqual(scale, float(np.max(np.abs(gp - gp[0]))))


if __name__ == "__main__":
    unittest.main()


class UncountedForceEvaluations(unittest.TestCase):
    """A summary row with steps taken and 0 force evaluations (an engine that counts none) shows
    n/a with a note, never 0; a counted engine shows its count."""

    def test_summary_table(self):
        from analysis import page
        summary = read_table(os.path.join(rc.FIXTURES, "run", "summary.csv"))
        columns = dict(summary.columns)
        evals = np.array(columns["force_evals"], dtype=float)
        evals[0] = 0.0
        columns["force_evals"] = evals
        html = page.table(Table(summary.path, columns, summary.order), page.SUMMARY_HEADERS)
        self.assertIn("n/a*", html)
        self.assertIn(page.UNCOUNTED_NOTE, html)
        self.assertEqual(html.count(">n/a*</td>"), 1)
        plain = page.table(summary, page.SUMMARY_HEADERS)
        self.assertNotIn("n/a*", plain)
