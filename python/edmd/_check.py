"""Argument checks for the pure-Python entry points (``edmd.gen``, ``edmd.pack``).

Each raises ``TypeError`` for a value of the wrong kind and ``ValueError`` for one out of
range, naming the argument: the compiled functions behind them would otherwise raise
``OverflowError`` for a negative count, read ``True`` as 1, or name a flag of the command line.
"""

import math
import numbers
import os
import re


def _describe(value):
    return f"{type(value).__name__} {value!r}"


def whole(name, value, lo=None, hi=None):
    """A whole number (not a bool, not a float) in [lo, hi]; None passes."""
    if value is None:
        return None
    if isinstance(value, bool) or not isinstance(value, numbers.Integral):
        raise TypeError(f"{name}: expected a whole number, got {_describe(value)}")
    value = int(value)
    if (lo is not None and value < lo) or (hi is not None and value > hi):
        raise ValueError(f"{name}: expected a whole number from {lo} to {hi}, got {value}")
    return value


def real(name, value, finite=True):
    """A real number (not a bool, a complex number or a str), finite unless told; None
    passes."""
    if value is None:
        return None
    if isinstance(value, bool) or not isinstance(value, numbers.Real):
        raise TypeError(f"{name}: expected a number, got {_describe(value)}")
    value = float(value)
    if finite and not math.isfinite(value):
        raise ValueError(f"{name}: {value!r} is not a finite number")
    return value


def text(name, value):
    """A str; None passes."""
    if value is not None and not isinstance(value, str):
        raise TypeError(f"{name}: expected a str, got {_describe(value)}")
    return value


def flag(name, value):
    """A bool (True or False)."""
    if not isinstance(value, bool):
        raise TypeError(f"{name}: expected True or False, got {_describe(value)}")
    return value


def path(name, value):
    """A file name (str or os.PathLike); None passes."""
    if value is None:
        return None
    if not isinstance(value, (str, os.PathLike)):
        raise TypeError(f"{name}: expected a file name (str or path), got {_describe(value)}")
    value = os.fspath(value)
    if not isinstance(value, str) or value == "":
        raise ValueError(f"{name}: expected a file name, got {value!r}")
    return value


def output_file(name, value):
    """A file to be written: not a folder, in a folder that exists (the checks of the
    command's outputs, made before any work so that the work is not lost to a bad name)."""
    value = path(name, value)
    if value is None:
        return None
    if value.endswith(os.sep) or os.path.isdir(value):
        raise ValueError(f"{name}: {value} names a folder; give a file name")
    folder = os.path.dirname(value) or "."
    if not os.path.isdir(folder):
        raise ValueError(f"{name}: {value} is in a folder that does not exist ({folder})")
    return value


def input_file(name, value):
    """A file to be read: it exists and is not a folder."""
    value = path(name, value)
    if value is None:
        return None
    if not os.path.exists(value):
        raise ValueError(f"{name}: {value} does not exist")
    if os.path.isdir(value):
        raise ValueError(f"{name}: {value} is a folder, not a file")
    return value


# Words with which `edmd gen` and `edmd pack` name some options in their messages, and the
# Python argument each is.
_PHRASES = [("big mass", "big_mass"), ("big radius", "big_radius"), ("size ratio", "size_ratio"),
            ("number fraction of large", "fraction_large"), ("kT", "kt"),
            ("growth rate", "growth_rate"), ("dimension", "dim")]


def naming_the_argument(error, given):
    """The command's `ValueError` with the Python argument's name in front when the message
    names it in words only ("size ratio -1 is outside [1, 10]"); `given` holds the names of
    the arguments the caller gave. None when the message needs nothing."""
    message = str(error)
    for phrase, name in _PHRASES:
        if name in given and phrase in message and not re.search(rf"\b{name}\b", message):
            return ValueError(f"{name}: {message}")
    return None
