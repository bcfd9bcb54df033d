"""player.player_script: analysis/player/*.js joined into the report's one inline script."""

import os
import shutil
import subprocess
import tempfile
import unittest
from unittest import mock

from analysis import player

NODE = shutil.which("node")


class PlayerScript(unittest.TestCase):
    def test_every_file_is_joined_once_in_order(self):
        script = player.player_script()
        heads = [line[len("// --- player/"):] for line in script.split("\n")
                 if line.startswith("// --- player/")]
        self.assertEqual(heads, player.PLAYER_SCRIPTS)
        self.assertTrue(script.startswith('(function () {\n"use strict";\n'))
        self.assertTrue(script.endswith("})();\n"))

    def test_no_module_syntax(self):
        # the page is opened from file://, where module scripts do not load
        for line in player.player_script().split("\n"):
            self.assertFalse(line.startswith(("import ", "export ")), line)

    def test_a_file_left_out_of_the_order_is_an_error(self):
        with tempfile.TemporaryDirectory() as tmp:
            for name in player.PLAYER_SCRIPTS + ["extra.js"]:
                with open(os.path.join(tmp, name), "w", encoding="utf-8") as fh:
                    fh.write("// empty\n")
            with mock.patch.object(player, "PLAYER_DIR", tmp):
                with self.assertRaisesRegex(RuntimeError, "extra.js"):
                    player.player_script()

    @unittest.skipUnless(NODE, "needs node (only to check the syntax)")
    def test_joined_script_is_valid_javascript(self):
        with tempfile.TemporaryDirectory() as tmp:
            path = os.path.join(tmp, "player.js")
            with open(path, "w", encoding="utf-8") as fh:
                fh.write(player.player_script())
            result = subprocess.run([NODE, "--check", path], capture_output=True, text=True)
            self.assertEqual(result.returncode, 0, result.stderr)


if __name__ == "__main__":
    unittest.main()
