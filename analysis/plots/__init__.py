"""One module per plot. Each has STEM (file name), TITLE, CAPTION, available(folder) and
draw(folders, ctx) -> PNG path, where folders is one Folder or two (--compare). A plot that can
have nothing to show on some data also has skip_reason(folders) -> None, or the sentence the page
shows in its place."""

from . import (bias_curve, convergence, divergence, drape, energy, reference, resolution,
               resolution_recommendation, self_contact, shadow, stability, stability_map,
               stability_mode, standard_tests, strain, tensile_curve, work_precision)

# in the order the report shows them
ALL = [energy, divergence, strain, self_contact, drape, shadow, standard_tests, tensile_curve,
       bias_curve,
       work_precision, convergence, resolution, stability, stability_mode, stability_map,
       reference, resolution_recommendation]


class Context:
    """Options shared by the plots.

    outdir          folder for the images
    svg             also write SVG
    colors          style.Colors shared by every plot
    snapshot_times  wanted snapshot times (s) for the drape plot, or None for an even spread
    tolerance       error tolerance (m) to draw on the work-precision plot, or None (from the CSV)
    """

    def __init__(self, outdir, svg, colors, snapshot_times=None, tolerance=None):
        self.outdir = outdir
        self.svg = svg
        self.colors = colors
        self.snapshot_times = snapshot_times
        self.tolerance = tolerance
