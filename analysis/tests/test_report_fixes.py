"""The report's fixes found by a new user: Bullet's uncounted force evaluations, a readable scale
for the energy-difference panel, and drape snapshots coloured by distance to the reference."""

import os
import unittest

import numpy as np

from analysis import verdicts
from analysis.folder import Folder
from analysis.plots import divergence, drape
from analysis.tests import reportcheck as rc

RUN = os.path.join(rc.FIXTURES, "run")


class ReportFixes(unittest.TestCase):
    def test_bullet_force_evaluations_are_not_counted_not_zero(self):
        lines = [text for _, group in verdicts.run_verdicts(Folder(RUN)) for _, text in group
                 if text.startswith("Cost per step")]
        self.assertEqual(len(lines), 1)
        self.assertIn("bullet-softbody", lines[0])
        self.assertRegex(lines[0], r"bullet-softbody [^,]* µs \(force evaluations not counted\)")
        self.assertNotIn("(0 force evaluations)", lines[0])
        self.assertRegex(lines[0], r"custom-rk4 [^,]* µs \(\d+ force evaluations\)")

    def test_energy_difference_axis_is_symlog_only_when_one_engine_dominates(self):
        # the seed scene: bullet-softbody peaks near 800 J, the others at 0.01 to 20 J
        self.assertAlmostEqual(divergence.symlog_threshold([800.0, 20.0, 0.01]), 0.0025)
        self.assertIsNone(divergence.symlog_threshold([3.0, 1.0]))
        self.assertIsNone(divergence.symlog_threshold([5.0]))

    def test_drape_distance_is_zero_for_the_reference_only(self):
        f = Folder(RUN)
        ref = f.reference()
        t = f.snapshot_times(ref)[-1]
        self.assertTrue(np.all(drape.distance_mm(f, ref, t) == 0))
        other = drape.distance_mm(f, "bullet-softbody", t)
        self.assertGreater(float(other.max()), 0.1)  # mm
        a, b = f.snapshot("bullet-softbody", t), f.snapshot(ref, t)
        self.assertAlmostEqual(float(other[2, 3]), 1000 * float(np.linalg.norm(a[2, 3] - b[2, 3])))


if __name__ == "__main__":
    unittest.main()
