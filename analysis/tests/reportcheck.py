"""Shared checks: run report.py, validate PNG files, know which images a folder should give.

Environment variables (for the ctest wiring; each adds the same checks on a real folder):
    CLOTHBENCH_RUN_DIR      output folder of a small `clothbench run`
    CLOTHBENCH_RUN_SKIPPED  plots that folder's report must leave out with a stated reason,
                            comma separated (e.g. "shadow" for a chain or an edge-on cloth)
    CLOTHBENCH_SWEEP_DIR    output folder of a small sweep (stability and/or accuracy)
"""

import os
import re
import struct
import subprocess
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))
REPORT = os.path.join(ROOT, "analysis", "report.py")
FIXTURES = os.path.join(HERE, "fixtures")
SCREENSHOT = os.path.join(ROOT, "scripts", "screenshot-report")

# CSV file -> images it produces
IMAGES_FROM = {
    "frames.csv": ["energy", "strain"],
    "divergence.csv": ["divergence"],
    "snapshots.csv": ["drape", "shadow"],
    "tests.csv": ["tests"],
    "work_precision.csv": ["work_precision", "convergence"],
    "convergence.csv": ["convergence"],
    "stability.csv": ["stability"],
    "resolution.csv": ["resolution"],
    "reference.csv": ["reference"],
    "resolution_recommendation.csv": ["resolution_recommendation"],
    "map.csv": ["stability_map"],
}

# sensible pixel sizes of a report image (12 in wide at 110 dpi is 1320 px)
MIN_W, MAX_W = 600, 4000
MIN_H, MAX_H = 300, 12000


def run_report(*args, timeout=600):
    """Run report.py as a user would; returns the CompletedProcess (text stdout/stderr)."""
    env = dict(os.environ, MPLBACKEND="Agg")
    return subprocess.run([sys.executable, REPORT, *args], capture_output=True, text=True,
                          timeout=timeout, env=env, cwd=ROOT)


def png_size(path):
    """(width, height) of a PNG file; raises AssertionError if it is not a valid PNG."""
    with open(path, "rb") as f:
        head = f.read(33)
    if len(head) < 33 or head[:8] != b"\x89PNG\r\n\x1a\n":
        raise AssertionError(f"{path}: not a PNG (bad signature)")
    length, kind = struct.unpack(">I4s", head[8:16])
    if kind != b"IHDR" or length != 13:
        raise AssertionError(f"{path}: PNG without an IHDR chunk first")
    width, height = struct.unpack(">II", head[16:24])
    return width, height


def has_rows(path):
    """True when a CSV file has a header and at least one non-blank data line."""
    with open(path, encoding="utf-8-sig") as f:
        lines = [line for line in f if line.strip()]
    return len(lines) > 1


def expected_images(*folders):
    """Image stems that the report of these folders must contain."""
    stems = []
    for folder in folders:
        for name, images in IMAGES_FROM.items():
            path = os.path.join(folder, name)
            if os.path.exists(path) and has_rows(path):
                stems += [s for s in images if s not in stems]
        # a stability sweep measured by growth that saved its growing modes draws them too
        modes = os.path.join(folder, "stability_modes")
        stability = os.path.join(folder, "stability.csv")
        if os.path.isdir(modes) and os.path.exists(stability) and has_rows(stability) \
                and any(n[:-4].isdigit() for n in os.listdir(modes) if n.endswith(".npy")) \
                and "stability_mode" not in stems:
            stems.append("stability_mode")
        # frames.csv written since self-intersection is measured has the self-contact plot too
        frames = os.path.join(folder, "frames.csv")
        if os.path.exists(frames) and has_rows(frames) and "self_contact" not in stems:
            with open(frames, encoding="utf-8") as f:
                if "self_intersections" in f.readline().strip().split(","):
                    stems.append("self_contact")
    return stems


def skipped_plots(text):
    """Stems of the plots a report.html leaves out, each with the reason it gives."""
    return dict(re.findall(r'<p class="skipped" id="skipped-(\w+)">([^<]*)</p>', text))


def html_problems(text, n_images):
    """Reasons why a report.html is not one self-contained page with n_images images."""
    problems = []
    embedded = text.count('src="data:image/png;base64,')
    if embedded != n_images:
        problems.append(f"expected {n_images} embedded PNG images, found {embedded}")
    external = re.findall(r'(?:src|href)="(?!data:|#)([^"]*)"', text)
    if external:
        problems.append(f"refers to outside files: {external[:3]}")
    # the 3D player's scripts are inline; nothing may be loaded from elsewhere
    if re.search(r"<script[^>]*\bsrc\s*=|<link", text, re.I):
        problems.append("loads a script or a stylesheet from a link")
    for needed in ("<h2>Verdicts</h2>", "</html>"):
        if needed not in text:
            problems.append(f"lacks {needed}")
    return problems
