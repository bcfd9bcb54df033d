"""Reading clothbench's CSV files into column arrays, with errors that name the file.

Each known file has a schema: its required columns, which of them hold text, which are flags
(0/1) and which must never be empty. Extra columns are kept (as text) and ignored by the plots.
Numbers accept what C++ streams print, including nan and inf; an empty numeric field is NaN.
"""

import argparse
import csv
import os

import numpy as np


class ReportError(Exception):
    """A problem with the user's input (missing or malformed file): one line, exit code 2."""


def message(command, text):
    """A line to stderr as every clothbench command writes it: 'clothbench: COMMAND: TEXT'."""
    return f"clothbench: {command}: {text}"


class ArgumentParser(argparse.ArgumentParser):
    """argparse named as the command the user typed ('clothbench report'), whose errors are
    one line in clothbench's form with exit code 2."""

    def __init__(self, command, **kwargs):
        super().__init__(prog=f"clothbench {command}", **kwargs)
        self.command = command

    def error(self, text):
        self.exit(2, message(self.command, f"{text} (see clothbench {self.command} --help)") + "\n")


class Schema:
    """What one CSV file must contain.

    required  column names in the order clothbench writes them
    text      columns kept as strings
    flags     columns holding 0 or 1 (true/false also accepted), read as float 0.0 / 1.0
    keys      columns that must not be empty in any row
    optional  columns an older run lacks, read when present (as numbers unless also in text)
    """

    def __init__(self, required, text=(), flags=(), keys=(), optional=()):
        self.required = list(required)
        self.text = set(text)
        self.flags = set(flags)
        self.keys = set(keys)
        self.optional = set(optional)


# the columns `clothbench stability --method growth|blowup|both` adds after the blow-up search's
# (older folders lack them): which search ran, the growth limit (s), the growing mode's rate and
# the physical one (1/s), growth limit / predicted, why, the mode's share of spring energy by
# kind, and the engine steps each search took; a search that did not run leaves its own empty
STABILITY_GROWTH_TEXT = ["method", "growth_cause"]
STABILITY_GROWTH_NUMBERS = ["growth_stable_dt", "growth_first_unstable_dt", "growth_rate",
                            "physical_rate", "growth_ratio", "mode_structural", "mode_shear",
                            "mode_bend", "growth_steps", "blowup_steps"]

SCHEMAS = {
    "frames.csv": Schema(
        ["engine", "t", "kinetic", "gravity_potential", "elastic_potential", "dissipated",
         "contact_work", "unbooked", "total_energy", "energy_error", "max_strain", "mean_strain",
         "com_x", "com_y", "com_z",
         "min_y", "max_penetration", "shadow_area", "stable"],
        text=["engine"], flags=["stable"], keys=["engine", "t", "stable"],
        optional=["contacts", "contact_fx", "contact_fy", "contact_fz", "max_stretch",
                  "max_compression", "self_intersections", "min_self_distance", "handle_work",
                  "collider_work"]),
    "divergence.csv": Schema(
        ["engine", "reference", "t", "rms_distance", "max_distance", "com_distance",
         "energy_difference", "shadow_area_difference"],
        text=["engine", "reference"], keys=["engine", "reference", "t"]),
    "snapshots.csv": Schema(
        ["engine", "t", "i", "j", "x", "y", "z"],
        text=["engine"], keys=["engine", "t", "i", "j"]),
    "summary.csv": Schema(
        ["engine", "kind", "integrator", "dt", "steps", "wall_s", "us_per_step", "force_evals",
         "stable", "blowup_t", "max_energy_error", "final_rms_vs_reference",
         "max_rms_vs_reference", "drape_coefficient"],
        text=["engine", "kind", "integrator"], flags=["stable"], keys=["engine", "kind", "stable"]),
    "stability.csv": Schema(
        ["engine", "integrator", "stable_dt", "first_unstable_dt", "predicted_dt",
         "ratio_measured_to_predicted", "cause"],
        text=["engine", "integrator", "cause"] + STABILITY_GROWTH_TEXT, keys=["engine"],
        optional=STABILITY_GROWTH_NUMBERS + STABILITY_GROWTH_TEXT),
    # clothbench map: the varied keys' columns come first and are kept as text
    "map.csv": Schema(
        ["engine", "integrator", "stable_dt", "first_unstable_dt", "predicted_dt",
         "ratio_measured_to_predicted", "cause"],
        text=["engine", "integrator", "cause"] + STABILITY_GROWTH_TEXT, keys=["engine"],
        optional=STABILITY_GROWTH_NUMBERS + STABILITY_GROWTH_TEXT),
    "work_precision.csv": Schema(
        ["engine", "integrator", "dt", "stable", "error_final", "error_max", "wall_s",
         "wall_s_per_sim_s", "force_evals", "cg_iterations"],
        text=["engine", "integrator"], flags=["stable"], keys=["engine", "dt", "stable"]),
    "convergence.csv": Schema(
        ["engine", "integrator", "order", "points"],
        text=["engine", "integrator"], keys=["engine"]),
    # when nothing meets the tolerance a row keeps its scope and tolerance only (and the engine
    # of an "engine" row): "engine,custom-rk4,,,,,1e-30", "overall,,,,,,1e-30"
    "recommendation.csv": Schema(
        ["scope", "engine", "integrator", "dt", "error_max", "wall_s_per_sim_s", "tolerance"],
        text=["scope", "engine", "integrator"], keys=["scope"]),
    "resolution.csv": Schema(
        ["engine", "integrator", "particles", "dt", "stable", "error_final", "wall_s_per_sim_s",
         "force_evals"],
        text=["engine", "integrator"], flags=["stable"], keys=["engine", "particles", "stable"]),
    "reference.csv": Schema(
        ["study", "engine", "integrator", "dt", "particles", "error_floor"],
        text=["study", "engine", "integrator"], keys=["study", "engine"]),
    "resolution_recommendation.csv": Schema(
        ["scope", "engine", "integrator", "particles", "dt", "error_final", "wall_s_per_sim_s",
         "tolerance"],
        text=["scope", "engine", "integrator"], keys=["scope"]),
    # a scenario's [test]: one metric of one engine a row; an undefined value is empty
    "tests.csv": Schema(
        ["engine", "metric", "value", "unit"],
        text=["engine", "metric", "unit"], keys=["engine", "metric", "unit"]),
    # a strip-tensile [test]: one frame of one engine's force-strain curve
    "tensile.csv": Schema(
        ["engine", "t", "strain", "force_per_width"], text=["engine"], keys=["engine", "t"]),
    # clothbench fit: one target metric of one engine; an engine without the metric's scene
    # ("no engine") or a target unreachable before any run leaves value and achieved empty
    "fit.csv": Schema(
        ["engine", "parameter", "value", "metric", "target", "achieved", "relative_error", "runs",
         "sensitivity", "sensitivities", "status"],
        text=["engine", "parameter", "metric", "sensitivities", "status"],
        keys=["engine", "metric", "target", "status"]),
    # a bias-extension [test]: one frame of one engine's curve (forces empty but the custom's)
    "bias.csv": Schema(
        ["engine", "t", "displacement", "force", "angle_pin_jointed", "angle", "shear_force",
         "shear_force_pin_jointed"],
        text=["engine"], keys=["engine", "t"]),
    "attribution.csv": Schema(
        ["engine", "reference", "matched", "at", "t", "total_rms", "scheme_rms", "model_rms",
         "note"],
        text=["engine", "reference", "matched", "at", "note"], keys=["engine", "at"]),
}

_TRUE = {"1", "true", "True", "TRUE"}
_FALSE = {"0", "false", "False", "FALSE"}


class Table:
    """Columns of one CSV file: numpy float arrays for numbers, object arrays for text.

    path     the file it came from (for messages)
    columns  name -> 1-D array, every array #rows long
    """

    def __init__(self, path, columns, order):
        self.path = path
        self.columns = columns
        self.order = order

    def __len__(self):
        return len(next(iter(self.columns.values()))) if self.columns else 0

    def __getitem__(self, name):
        return self.columns[name]

    def __contains__(self, name):
        return name in self.columns

    def where(self, mask):
        """The rows where the boolean #rows array mask is true, as a new Table."""
        return Table(self.path, {k: v[mask] for k, v in self.columns.items()}, self.order)

    def select(self, **equal):
        """The rows whose text columns equal the given values, e.g. select(engine="custom-rk4")."""
        mask = np.ones(len(self), dtype=bool)
        for name, value in equal.items():
            mask &= self.columns[name] == value
        return self.where(mask)

    def unique(self, name):
        """Distinct values of a column in order of first appearance."""
        seen = {}
        for value in self.columns[name]:
            seen.setdefault(value, None)
        return list(seen)

    def rows(self):
        """Rows as dicts (name -> value), in file order."""
        for k in range(len(self)):
            yield {name: self.columns[name][k] for name in self.order}


def _parse_number(text):
    """float of a CSV field; '' is NaN. Raises ValueError for anything else that is not a number."""
    if text == "":
        return float("nan")
    value = float(text)  # accepts nan, inf, -inf, 1e-3 ...
    return value


def _numbered_rows(path, schema):
    """The file's non-blank rows as (line number, fields), the header first."""
    try:
        with open(path, newline="", encoding="utf-8-sig") as f:
            lines = list(csv.reader(f))
    except FileNotFoundError:
        raise ReportError(f"{path}: file not found") from None
    except (OSError, UnicodeDecodeError, csv.Error) as e:
        raise ReportError(f"{path}: cannot read: {e}") from None

    # drop blank lines (a trailing newline, say) but keep line numbers for messages
    numbered = [(n + 1, row) for n, row in enumerate(lines) if any(cell.strip() for cell in row)]
    if not numbered:
        raise ReportError(f"{path}: empty file (expected a header line: "
                          f"{','.join(schema.required)})")
    return numbered


def _checked_header(path, fields, schema):
    """The header's column names, once each, with every required column."""
    header = [cell.strip() for cell in fields]
    missing = [c for c in schema.required if c not in header]
    if missing:
        which = ", ".join(f"'{c}'" for c in missing)
        plural = "s" if len(missing) > 1 else ""
        raise ReportError(f"{path}: missing required column{plural} {which} "
                          f"(header has: {','.join(header)})")
    duplicates = sorted({c for c in header if header.count(c) > 1})
    if duplicates:
        raise ReportError(f"{path}: duplicate column '{duplicates[0]}' in the header")
    return header


def _parsed_column(path, c, cells, schema):
    """Column c's cells [(line number, text)] as a numpy array: text, flags or numbers."""
    for line_no, cell in cells:
        if c in schema.keys and cell == "":
            raise ReportError(f"{path} line {line_no}, column '{c}': empty value (required)")
    if c in schema.text or (c not in schema.required and c not in schema.optional):
        return np.array([cell for _, cell in cells], dtype=object)
    values = []
    for line_no, cell in cells:
        if c in schema.flags:
            if cell in _TRUE:
                values.append(1.0)
            elif cell in _FALSE:
                values.append(0.0)
            elif cell == "":
                values.append(float("nan"))
            else:
                raise ReportError(f"{path} line {line_no}, column '{c}': expected 0 or 1, "
                                  f"got '{cell}'")
            continue
        try:
            values.append(_parse_number(cell))
        except ValueError:
            raise ReportError(f"{path} line {line_no}, column '{c}': expected a number, "
                              f"got '{cell}'") from None
    return np.array(values, dtype=float)


def read_table(path, schema_name=None):
    """Read one CSV file against the schema of its name (or schema_name).

    Raises ReportError naming the file (and line and column) for a missing file, an empty file,
    a missing required column, a row with the wrong number of fields or an unparsable value.
    """
    name = schema_name or os.path.basename(path)
    schema = SCHEMAS[name]
    numbered = _numbered_rows(path, schema)
    header = _checked_header(path, numbered[0][1], schema)

    raw = {c: [] for c in header}
    for line_no, row in numbered[1:]:
        if len(row) != len(header):
            raise ReportError(f"{path} line {line_no}: {len(row)} fields, but the header has "
                              f"{len(header)} (a truncated or malformed row?)")
        for c, cell in zip(header, row):
            raw[c].append((line_no, cell.strip()))

    columns = {c: _parsed_column(path, c, raw[c], schema) for c in header}
    return Table(path, columns, header)
