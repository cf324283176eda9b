"""Checks of the numbers a Python call passes on to the C++ core: whole counts, finite positive
step sizes and times, scheme degrees, and expression text, each refused with a UsageError or
ExpressionError naming the argument (instead of silent truncation, ZeroDivisionError or a
pybind11 TypeError)."""

import math
import numbers

from .errors import ExpressionError, UsageError

# The largest count a call takes (steps, every, threads): C++'s long long and size_t hold it,
# and no run is that long (the tool's own limit on steps is 1e15).
MOST = 10**15


def count(value, name, lowest=1, highest=MOST):
    """value as an int when it is a whole number in [lowest, highest]."""
    if isinstance(value, bool) or not isinstance(value, numbers.Real):
        raise UsageError(f"{name} must be a whole number, got {value!r}")
    if not math.isfinite(value) or value != math.floor(value):
        raise UsageError(f"{name} must be a whole number, got {value!r}")
    if not lowest <= value <= highest:
        most = str(highest) if highest < 10**6 else f"{highest:.0e}".replace("e+", "e")
        raise UsageError(f"{name} must be from {lowest} to {most}, got {value!r}")
    return int(value)


def positive(value, name):
    """value as a float when it is finite and > 0."""
    try:
        x = float(value)
    except (TypeError, ValueError):
        raise UsageError(f"{name} must be a number, got {value!r}") from None
    if not (math.isfinite(x) and x > 0):
        raise UsageError(f"{name} must be a finite positive number, got {value!r}")
    return x


def degree(value):
    """A scheme's degree: None (the scheme's default) or a whole number from 1 to 8."""
    return None if value is None else count(value, "degree", 1, 8)


def ascii_expression(text, what="expression"):
    """text when it is ASCII; names are ASCII letters, digits and _ (θ is not one)."""
    for k, c in enumerate(text):
        if ord(c) > 127:
            raise ExpressionError(f"{what}: the character {c!r} at column {k + 1} is not ASCII "
                                  f"(names are letters a-z, A-Z, digits and _: write theta, "
                                  f"not θ)", k)
    return text
