"""attribution.csv (clothbench run --explain) is said in words on the report page."""

import csv
import os
import shutil
import unittest

from analysis.tests import reportcheck as rc
from analysis.tests.test_report import MadeFolder, ReportChecks

HEADER = ["engine", "reference", "matched", "at", "t", "total_rms", "scheme_rms", "model_rms",
          "note"]
NOTE = "position-based dynamics: no custom time scheme matches it, so its distance is not split"


class AttributionInWords(MadeFolder, ReportChecks, unittest.TestCase):
    """A real run folder with an attribution.csv of known numbers."""

    @staticmethod
    def fill(folder):
        src = os.path.join(rc.FIXTURES, "run")
        for name in os.listdir(src):
            shutil.copy(os.path.join(src, name), folder)
        rows = [
            ["bullet-deformable-explicit", "custom-rk4", "custom-as-bullet-deformable-explicit",
             "final", "3", "0.0276", "0.0004", "0.0272", ""],
            ["bullet-deformable-explicit", "custom-rk4", "custom-as-bullet-deformable-explicit",
             "max", "3", "0.0363", "0.0194", "0.0395", ""],
            ["bullet-softbody-matched", "custom-rk4", "", "final", "3", "0.0737", "", "", NOTE],
            ["bullet-softbody-matched", "custom-rk4", "", "max", "3", "0.164", "", "", NOTE],
        ]
        with open(os.path.join(folder, "attribution.csv"), "w", newline="",
                  encoding="utf-8") as f:
            csv.writer(f).writerows([HEADER] + rows)

    def test_split_in_words(self):
        text = self.page()
        self.assertIn("bullet-deformable-explicit is 27.6 mm from custom-rk4 at the end "
                      "(t = 3 s): of that, 400 µm is the time scheme", text)
        self.assertIn("and 27.2 mm the model", text)
        self.assertIn("largest over the frames, each at its own worst frame: 36.3 mm from "
                      "custom-rk4, time scheme 19.4 mm, model 39.5 mm", text)

    def test_softbody_not_split(self):
        text = self.page()
        self.assertIn("bullet-softbody-matched is 73.7 mm from custom-rk4 at the end (t = 3 s), "
                      "not split: position-based dynamics", text)


if __name__ == "__main__":
    unittest.main()
