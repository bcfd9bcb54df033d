"""The fit page: the engines compared at the fitted values, from fit.csv and the fitted runs;
bad input writes nothing."""

import contextlib
import io
import os
import re
import shutil
import tempfile
import unittest

from analysis import fit_page
from analysis.folder import Folder
from analysis.tests import reportcheck as rc

RUN = os.path.join(rc.FIXTURES, "run")
HEADER = ("engine,parameter,value,metric,target,achieved,relative_error,runs,sensitivity,"
          "sensitivities,status\n")


def quiet(argv):
    """fit_page.main(argv) with its output captured: (exit code, stdout, stderr)."""
    out, err = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        code = fit_page.main(argv)
    return code, out.getvalue(), err.getvalue()


class FitPage(unittest.TestCase):
    def setUp(self):
        self.tmp = tempfile.mkdtemp()
        self.dir = os.path.join(self.tmp, "fit")
        os.makedirs(os.path.join(self.dir, "runs"))
        shutil.copytree(RUN, os.path.join(self.dir, "runs", "cantilever"))
        self.engines = Folder(RUN).engines()
        a, b = self.engines[0], self.engines[-1]
        with open(os.path.join(self.dir, "fit.csv"), "w", encoding="utf-8") as fh:
            fh.write(HEADER)
            # a: both targets met jointly; b: bending length short by 13.7 %, no strip engine
            fh.write(f"{a},cloth.stiffness.bend,52.15,bending_length,0.03,0.0302,"
                     "0.00667,7,1e-5,cloth.stiffness.bend=1e-5 cloth.stiffness.structural_u=2e-7,"
                     "converged\n")
            fh.write(f"{a},cloth.stiffness.structural_u,2218,tensile_stiffness,3000,2993,"
                     "-0.00233,7,1.3,,converged\n")
            fh.write(f"{b},cloth.stiffness.bend,64000,bending_length,0.03,0.02588,-0.1373,3,"
                     ",,unreachable\n")
            fh.write(f"{b},,,tensile_stiffness,3000,,,0,,,no engine\n")

    def tearDown(self):
        shutil.rmtree(self.tmp)

    def test_engines_by_parameters_and_metrics_then_each_run(self):
        code, stdout, _ = quiet([self.dir])
        self.assertEqual(code, 0)
        self.assertIn("2 engines, 1 runs", stdout)
        page = open(os.path.join(self.dir, "fit.html"), encoding="utf-8").read()
        # one column per fitted parameter, one per target (with its value)
        self.assertIn("<th>cloth.stiffness.structural_u</th>", page)
        self.assertIn("bending_length<br>target 0.03", page)
        # the misses as a person reads them: (0.0302 - 0.03) / 0.03 = +0.7 %
        self.assertIn("0.0302 (+0.7 %)", page)
        self.assertIn("<b>unreachable</b>", page)
        self.assertIn("not in the scene", page)
        # the error plot and the run's panels: two images, the table's section and the run's
        self.assertEqual(len(re.findall(r'src="data:image/png;base64,', page)), 2)
        self.assertEqual(page.count("<h2>"), 2)
        self.assertTrue(os.path.getsize(os.path.join(self.dir, "fit-errors.png")) > 1000)

    def test_bad_input_is_one_line_and_writes_nothing(self):
        os.remove(os.path.join(self.dir, "fit.csv"))
        code, _, err = quiet([self.dir])
        self.assertEqual(code, 2)
        self.assertTrue(err.startswith("clothbench: fit page: "), err)
        self.assertIn("fit.csv: no such file", err)
        self.assertFalse(os.path.exists(os.path.join(self.dir, "fit.html")))

    def test_a_fit_without_runs_says_how_to_make_them(self):
        shutil.rmtree(os.path.join(self.dir, "runs"))
        code, _, err = quiet([self.dir])
        self.assertEqual(code, 2)
        self.assertIn("--run", err)


if __name__ == "__main__":
    unittest.main()
