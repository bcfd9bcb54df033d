"""The output files' columns as `clothbench schema --outputs --format json` gives them, shared by
the checks in this folder."""

import json
import subprocess
import sys

# the name map.csv's schema gives its leading columns, one per --vary key
VARIED = "<varied key>"


def schema(clothbench):
    """file name -> list of column names, in order."""
    out = subprocess.run([clothbench, "schema", "--outputs", "--format", "json"], check=True,
                         capture_output=True, text=True).stdout
    return {f["name"]: [c["name"] for c in f["columns"]] for f in json.loads(out)["files"]}


def report(errors, summary):
    """Prints the errors on stderr and the summary; the exit status."""
    for e in errors:
        print(e, file=sys.stderr)
    print(summary)
    return 1 if errors else 0
