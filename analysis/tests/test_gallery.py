"""The gallery page: one section per run folder with an image of every engine's final shape,
the run's summary and its tests.csv as a table; bad input writes nothing."""

import contextlib
import io
import os
import re
import shutil
import tempfile
import unittest

from analysis import gallery
from analysis.folder import Folder
from analysis.tests import reportcheck as rc
from analysis.tests.test_standard_tests import with_tests

RUN = os.path.join(rc.FIXTURES, "run")


def quiet(argv):
    """gallery.main(argv) with its output captured: (exit code, stdout, stderr)."""
    out, err = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        code = gallery.main(argv)
    return code, out.getvalue(), err.getvalue()


class Gallery(unittest.TestCase):
    def setUp(self):
        self.tmp = tempfile.mkdtemp()

    def tearDown(self):
        shutil.rmtree(self.tmp)

    def test_one_section_per_run_with_image_summary_and_tests(self):
        engines = Folder(RUN).engines()
        tested = os.path.join(self.tmp, "tested")
        with_tests(RUN, tested, [[e, "folds", str(6 + k), "1"] for k, e in enumerate(engines)])
        out = os.path.join(self.tmp, "out")
        code, stdout, _ = quiet([RUN, tested, "--out", out, "--title", "two runs"])
        self.assertEqual(code, 0)
        self.assertIn("2 runs", stdout)
        page = open(os.path.join(out, "gallery.html"), encoding="utf-8").read()
        self.assertIn("<title>two runs</title>", page)
        self.assertEqual(page.count("<h2>"), 2)
        self.assertEqual(len(re.findall(r'src="data:image/png;base64,', page)), 2)
        for k in (1, 2):
            self.assertTrue(os.path.getsize(os.path.join(out, f"gallery-{k:02d}.png")) > 1000)
        # the second run's test metrics: a column for folds, a row per engine with its value
        self.assertIn("folds (1)", page)
        for k, e in enumerate(engines):
            self.assertIn(f"<td>{e}</td>", page)
        self.assertEqual(page.count("folds (1)"), 1)  # the first run has no tests.csv
        self.assertIn(f'<td class="num">{6 + len(engines) - 1}</td>', page)

    def test_bad_input_is_one_line_and_writes_nothing(self):
        out = os.path.join(self.tmp, "out")
        code, _, err = quiet([RUN, os.path.join(self.tmp, "missing"), "--out", out])
        self.assertEqual(code, 2)
        self.assertTrue(err.startswith("clothbench: gallery: "), err)
        self.assertIn("no such folder", err)
        self.assertFalse(os.path.exists(out))
        # a folder that is not a run's
        empty = os.path.join(self.tmp, "empty")
        os.makedirs(empty)
        code, _, err = quiet([empty, "--out", out])
        self.assertEqual(code, 2)
        self.assertIn("no snapshots.csv", err)
        self.assertFalse(os.path.exists(out))


if __name__ == "__main__":
    unittest.main()
