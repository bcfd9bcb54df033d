#!/usr/bin/env python3
"""Every CSV file clothbench writes has the header its schema gives (`clothbench schema
--outputs --format json`), and every file the schema lists is one clothbench writes.

Runs small real commands (run, run --explain, a run with a [test], stability, map, accuracy
with resolutions and a tolerance) into WORK_DIR, then compares the first line of every CSV they wrote with the
schema's columns (map.csv: its --vary keys, then the fixed columns). The baseline files are
the ones recorded in reference/baselines/, which `clothbench check` reads with the same header.

Usage: output_headers.py CLOTHBENCH SOURCE_DIR WORK_DIR
"""

import glob
import os
import shutil
import subprocess
import sys

from schema_columns import VARIED, report, schema


def run(clothbench, *args):
    subprocess.run([clothbench, *args, "--quiet"], check=True, stdout=subprocess.DEVNULL)


def make_outputs(clothbench, source, work):
    """Runs the commands; returns the varied keys of the map."""
    flag = os.path.join(source, "scenarios", "flag.toml")
    chain = os.path.join(source, "scenarios", "hanging_chain.toml")
    short = ["--set", "duration=0.2"]
    run(clothbench, "run", flag, *short, "-o", f"{work}/run", "--explain",
        "-e", "bullet-deformable-explicit")
    # a scenario with a [test] writes tests.csv
    cantilever = os.path.join(source, "scenarios", "fabric", "cantilever.toml")
    run(clothbench, "run", cantilever, "--set", "duration=0.05", "-o", f"{work}/tests",
        "-e", "custom-rk4")
    # a bias-extension [test] writes bias.csv
    bias = os.path.join(source, "scenarios", "fabric", "bias-extension.toml")
    run(clothbench, "run", bias, "--set", "duration=0.04", "-o", f"{work}/bias")
    # a strip-tensile [test] writes tensile.csv
    tensile = os.path.join(source, "scenarios", "fabric", "strip-tensile-warp.toml")
    run(clothbench, "run", tensile, "--set", "duration=0.05", "-o", f"{work}/tensile",
        "-e", "custom-symplectic-euler")
    # a fit writes fit.csv
    run(clothbench, "fit", cantilever, "--set", "duration=0.05", "-o", f"{work}/fit",
        "-e", "custom-implicit-euler", "--target", "bending_length=0.03", "--max-runs", "2")
    run(clothbench, "stability", chain, "--set", "duration=0.05", "-o", f"{work}/stability",
        "-e", "custom-rk4", "-i", "rk4", "--rel-tol", "0.2")
    varied = ["cloth.damping"]
    run(clothbench, "map", chain, "--set", "duration=0.05", "-o", f"{work}/map",
        "-e", "custom-rk4", "-i", "rk4", "--rel-tol", "0.2", "--vary", "cloth.damping=10,20")
    run(clothbench, "accuracy", flag, *short, "-o", f"{work}/accuracy", "-e", "custom-rk4",
        "-i", "symplectic-euler", "--halvings", "2", "--repeats", "1", "--tolerance", "1",
        "--resolutions", "5,9")
    return varied


def header(path):
    with open(path, encoding="utf-8") as f:
        return f.readline().rstrip("\n").split(",")


def main(argv):
    if len(argv) != 4:
        print(__doc__, file=sys.stderr)
        return 2
    clothbench, source, work = argv[1:]
    shutil.rmtree(work, ignore_errors=True)
    os.makedirs(work)
    columns = schema(clothbench)
    varied = make_outputs(clothbench, source, work)
    errors, seen = [], set()
    for path in sorted(glob.glob(f"{work}/*/*.csv")):
        name = os.path.basename(path)
        seen.add(name)
        if name not in columns:
            errors.append(f"{path}: a CSV file the schema does not list")
            continue
        want = [c for c in columns[name] if c != VARIED]
        if VARIED in columns[name]:
            want = varied + want
        if header(path) != want:
            errors.append(f"{path}: header {','.join(header(path))}\n  schema {','.join(want)}")
    for path in sorted(glob.glob(f"{source}/reference/baselines/*/*.csv")):
        name = "baselines/" + os.path.basename(path)
        seen.add(name)
        if name not in columns:
            errors.append(f"{path}: a baseline file the schema does not list")
        elif header(path) != columns[name]:
            errors.append(f"{path}: header {','.join(header(path))}\n  schema "
                          f"{','.join(columns[name])}")
    for name in sorted(set(columns) - seen):
        errors.append(f"{name}: in the schema, but no command here wrote it")
    return report(errors, f"{len(seen)} files checked against the schema")


if __name__ == "__main__":
    sys.exit(main(sys.argv))
