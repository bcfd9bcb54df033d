"""clothbench analysis: plots and an HTML report from the CSV files that clothbench writes.

Entry point: `python3 analysis/report.py DIR [--compare DIR2] [--svg] [--out OUTDIR]`.
Reads only the output folder's CSV files, scenario.toml and run.json; uses matplotlib and numpy.
"""
