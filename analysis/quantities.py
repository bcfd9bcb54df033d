"""Numbers and distances as text, as the verdicts, the page and the plots write them.

Its own module so that verdicts.py and attribution.py both import it without importing
each other."""

import math


def num(x, sig=3):
    """A number with 3 significant digits and a short exponent (2e-4)."""
    if isinstance(x, str):
        return x
    if x is None or (isinstance(x, float) and math.isnan(x)):
        return "n/a"
    if x == 0:
        return "0"
    if math.isinf(x):
        return "infinite"
    if 1e-3 <= abs(x) < 1e6:
        text = f"{x:.{sig}g}"
        return text if "e" not in text else f"{x:.0f}"
    mant, exp = f"{x:.{sig - 1}e}".split("e")
    return f"{mant.rstrip('0').rstrip('.')}e{int(exp)}"


def length(x):
    """A distance in m, mm or µm."""
    if x is None or not math.isfinite(x):
        return num(x)
    a = abs(x)
    if a == 0:
        return "0 m"
    if a >= 1:
        return f"{x:.3g} m"
    if a >= 1e-3:
        return f"{x * 1e3:.3g} mm"
    if a >= 1e-6:
        return f"{x * 1e6:.3g} µm"
    return f"{num(x)} m"
