#!/usr/bin/env python3
"""Every column the analysis reads exists, in that file, in clothbench's own schema.

The analysis declares what it reads in one place, analysis/csvio.py's SCHEMAS (per file: the
required columns in the order clothbench writes them, and which are text, flags or keys; a file
without a required column is refused), and shows columns under the headers of analysis/page.py's
*_HEADERS tables. This check asks `clothbench schema --outputs --format json` for the columns
the C++ writers use and fails when a declared name is not among them for that file, when the
required columns are not in the writer's order, or when an analysis module subscripts a name
that is a column of some output file but is declared in no SCHEMAS entry (a column read behind
the declaration's back).

Usage: analysis_columns.py CLOTHBENCH SOURCE_DIR
"""

import glob
import os
import re
import sys

from schema_columns import report, schema

# page.py's tables of shown headers, by the file whose columns they show
PAGE_TABLES = {
    "SUMMARY_HEADERS": "summary.csv", "STABILITY_HEADERS": "stability.csv",
    "RECOMMENDATION_HEADERS": "recommendation.csv", "CONVERGENCE_HEADERS": "convergence.csv",
    "WORK_PRECISION_HEADERS": "work_precision.csv", "RESOLUTION_HEADERS": "resolution.csv",
}


def declared_errors(columns, schemas, page):
    errors = []
    for name, s in schemas.items():
        if name not in columns:
            errors.append(f"csvio.SCHEMAS[{name!r}]: clothbench writes no such file")
            continue
        for group in ("required", "text", "flags", "keys", "optional"):
            for c in getattr(s, group):
                if c not in columns[name]:
                    errors.append(f"csvio.SCHEMAS[{name!r}].{group}: {c!r} is not a column of "
                                  f"{name} (columns: {', '.join(columns[name])})")
        order = [c for c in columns[name] if c in s.required]
        if order != [c for c in s.required if c in columns[name]]:
            errors.append(f"csvio.SCHEMAS[{name!r}].required: not in the order clothbench "
                          f"writes them ({', '.join(order)})")
    for table, name in PAGE_TABLES.items():
        for c in getattr(page, table):
            if c not in columns[name]:
                errors.append(f"page.{table}: {c!r} is not a column of {name}")
    return errors


def undeclared_errors(columns, schemas, source):
    """Subscripted names that are output columns but declared in no SCHEMAS entry."""
    every_column = {c for cs in columns.values() for c in cs}
    declared = {c for s in schemas.values() for c in list(s.required) + list(s.optional)}
    errors = []
    files = glob.glob(f"{source}/analysis/*.py") + glob.glob(f"{source}/analysis/plots/*.py")
    for path in sorted(files):
        with open(path, encoding="utf-8") as f:
            for name in sorted(set(re.findall(r'\["([a-z_]+)"\]', f.read()))):
                if name in every_column and name not in declared:
                    errors.append(f"{os.path.relpath(path, source)}: reads column {name!r}, "
                                  "which no csvio.SCHEMAS entry declares")
    return errors


def main(argv):
    if len(argv) != 3:
        print(__doc__, file=sys.stderr)
        return 2
    clothbench, source = argv[1:]
    sys.path.insert(0, source)
    from analysis import csvio, page  # noqa: E402 (the source tree's own analysis)
    columns = schema(clothbench)
    errors = declared_errors(columns, csvio.SCHEMAS, page)
    errors += undeclared_errors(columns, csvio.SCHEMAS, source)
    return report(errors, f"{len(csvio.SCHEMAS)} analysis schemas checked against clothbench's")


if __name__ == "__main__":
    sys.exit(main(sys.argv))
