"""scripts/screenshot-report renders report.html to a PNG of the whole page (headless Chromium)
and finds images that did not load and content wider than the window."""

import os
import shutil
import subprocess
import tempfile
import unittest

from analysis.tests import reportcheck as rc

CHROMIUM = os.environ.get("CHROMIUM", "/usr/bin/chromium")
# ctest runs the browser tests as their own test (analysis.browser), which is reported as
# skipped where there is no browser; the unit-test run leaves them to it
BROWSER = os.access(CHROMIUM, os.X_OK) and os.environ.get("CLOTHBENCH_BROWSER_TESTS") != "0"
NO_BROWSER = (f"{CHROMIUM} not installed" if not os.access(CHROMIUM, os.X_OK)
              else "CLOTHBENCH_BROWSER_TESTS=0 (ctest's analysis.browser runs them)")


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

    @unittest.skipUnless(BROWSER, NO_BROWSER)
    def test_whole_page(self):
        page = self.build()
        png = os.path.join(self.tmp, "page.png")
        result = self.shoot(page, png)
        self.assertEqual(result.returncode, 0, result.stderr)
        # the fixture's report has five plots, and every one of them must have loaded
        self.assertIn("; 5 of 5 images loaded, no horizontal overflow)", result.stdout)
        width, height = rc.png_size(png)
        self.assertEqual(width, 1400)
        # five plots and the tables: the measured page is several thousand pixels tall
        self.assertGreater(height, 3000)

    @unittest.skipUnless(BROWSER, NO_BROWSER)
    def test_broken_image_and_overflow_are_found(self):
        with open(self.build(), encoding="utf-8") as f:
            text = f.read()
        # one image whose data is not a PNG, and a banner wider than the 1400 px window
        marker = 'src="data:image/png;base64,'
        self.assertIn(marker, text)
        text = text.replace(marker, marker + "AAAA", 1)
        text = text.replace("<h2>Verdicts</h2>",
                            '<h2>Verdicts</h2><div class="banner" style="width:2400px">x</div>', 1)
        page = os.path.join(self.tmp, "bad.html")
        with open(page, "w", encoding="utf-8") as f:
            f.write(text)
        png = os.path.join(self.tmp, "bad.png")
        result = self.shoot(page, png, "600")
        self.assertEqual(result.returncode, 3, result.stdout + result.stderr)
        self.assertIn("1 of 5 images did not load (energy.png)", result.stderr)
        self.assertIn("wider than the 1400 px window (div.banner sticks out)", result.stderr)
        self.assertEqual(rc.png_size(png), (1400, 600))

    def build(self):
        """report.html of the run fixture, in the test's folder."""
        out = os.path.join(self.tmp, "out")
        built = rc.run_report(os.path.join(rc.FIXTURES, "run"), "--out", out)
        self.assertEqual(built.returncode, 0, built.stderr)
        return os.path.join(out, "report.html")

    def shoot(self, page, png, *height):
        return subprocess.run([rc.SCREENSHOT, page, png, *height], capture_output=True, text=True,
                              timeout=300)

if __name__ == "__main__":
    unittest.main()
