"""scripts/screenshot-report renders report.html to a PNG of the whole page (headless Chromium)."""

import os
import shutil
import subprocess
import tempfile
import unittest

from analysis.tests import reportcheck as rc

CHROMIUM = os.environ.get("CHROMIUM", "/usr/bin/chromium")


class Screenshot(unittest.TestCase):
    def setUp(self):
        self.tmp = tempfile.mkdtemp(prefix="clothbench-shot-")

    def tearDown(self):
        shutil.rmtree(self.tmp, ignore_errors=True)

    def test_usage_error(self):
        result = subprocess.run([rc.SCREENSHOT], capture_output=True, text=True)
        self.assertEqual(result.returncode, 2)
        self.assertIn("usage:", result.stderr)

    def test_missing_page(self):
        result = subprocess.run([rc.SCREENSHOT, os.path.join(self.tmp, "none.html"),
                                 os.path.join(self.tmp, "x.png")], capture_output=True, text=True)
        self.assertEqual(result.returncode, 2)
        self.assertIn("none.html", result.stderr)

    @unittest.skipUnless(os.access(CHROMIUM, os.X_OK), f"{CHROMIUM} not installed")
    def test_whole_page(self):
        out = os.path.join(self.tmp, "out")
        built = rc.run_report(os.path.join(rc.FIXTURES, "run"), "--out", out)
        self.assertEqual(built.returncode, 0, built.stderr)
        png = os.path.join(self.tmp, "page.png")
        result = subprocess.run([rc.SCREENSHOT, os.path.join(out, "report.html"), png],
                                capture_output=True, text=True, timeout=300)
        self.assertEqual(result.returncode, 0, result.stderr)
        width, height = rc.png_size(png)
        self.assertEqual(width, 1400)
        # five plots and the tables: the measured page is several thousand pixels tall
        self.assertGreater(height, 3000)


if __name__ == "__main__":
    unittest.main()
