"""plots.colliders: a collider's motion, a box's edges, a plane's patch in the view."""

import unittest

import numpy as np

from analysis.plots.colliders import box_edges, displacement, plane_patch


class Colliders(unittest.TestCase):
    def test_path_is_piecewise_linear_and_held_after_its_end(self):
        e = {"path": [[0.0, 0.0, 0.0, 0.0], [1.0, 0.0, 0.5, 0.0], [3.0, 1.0, 0.5, 0.0]]}
        np.testing.assert_allclose(displacement(e, 0.5), [0.0, 0.25, 0.0])
        np.testing.assert_allclose(displacement(e, 2.0), [0.5, 0.5, 0.0])
        np.testing.assert_allclose(displacement(e, 9.0), [1.0, 0.5, 0.0])

    def test_velocity_without_path(self):
        np.testing.assert_allclose(displacement({"velocity": [1.0, 0.0, 2.0]}, 0.5), [0.5, 0, 1.0])
        np.testing.assert_allclose(displacement({}, 3.0), [0.0, 0.0, 0.0])

    def test_a_box_has_twelve_edges_of_its_sides_lengths(self):
        edges = box_edges(np.zeros(3), np.array([0.5, 0.2, 0.1]))
        self.assertEqual(len(edges), 12)
        lengths = sorted(round(float(np.linalg.norm(s[1] - s[0])), 9) for s in edges)
        self.assertEqual(lengths, [0.2] * 4 + [0.4] * 4 + [1.0] * 4)

    def test_plane_patch_lies_on_the_plane_inside_the_view(self):
        box = ((-1.0, -1.0, -1.0), (1.0, 1.0, 1.0))
        quad = plane_patch(np.array([0.0, 0.2, 0.0]), np.array([0.0, 2.0, 0.0]), box)
        np.testing.assert_allclose(quad[:, 1], 0.2)
        self.assertTrue(np.all(quad >= -1.0) and np.all(quad <= 1.0))
        self.assertIsNone(plane_patch(np.array([0.0, 5.0, 0.0]), np.array([0.0, 1.0, 0.0]), box))


if __name__ == "__main__":
    unittest.main()
