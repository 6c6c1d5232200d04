"""Bounds on what a command takes: each check raises one ValueError naming the field and its valid range.

The run specs and the commands call these before anything is built, so that any value a user
can type (a count past the int32 step counters, NaN, infinity, a word for a number, a path
that cannot be written) is refused in one line, and nothing is written by the check itself.
"""

import math
import os
from numbers import Integral, Real
from pathlib import Path

INT32_MAX = 2**31 - 1
"""The step counters, replay indices and seeds of a run are int32 on the device."""


class Refused(ValueError):
    """A run refused once it has looked at its own files (a damaged one, another run writing them): exit 2."""


def traced(value) -> bool:
    """A JAX value (a sweep builds its members' configs with their swept values as tracers, checked before as numbers)."""
    return getattr(value, "aval", None) is not None


def integer(name: str, value, low: int, high: int, why: str = "") -> int:
    """`value` if it is an integer in low..high, else ValueError naming `name` and the range."""
    if traced(value):
        return value
    if isinstance(value, bool) or not isinstance(value, Integral) or not low <= value <= high:
        because = f" ({why})" if why else ""
        raise ValueError(f"{name} must be an integer in {low}..{high}{because}, not {value!r}")
    return value


def number(name: str, value, low: float = -math.inf, high: float = math.inf, low_open: bool = False,
           why: str = "") -> float:
    """`value` if it is a finite number in [low, high] ((low, high] with `low_open`), else ValueError."""
    if traced(value):
        return value
    real = isinstance(value, Real) and not isinstance(value, bool)
    inside = real and math.isfinite(value) and (low < value if low_open else low <= value) and value <= high
    if not inside:
        span = f" in {'(' if low_open else '['}{low:g}, {high:g}]" if math.isfinite(low) or math.isfinite(high) else ""
        because = f" ({why})" if why else ""
        raise ValueError(f"{name} must be a finite number{span}{because}, not {value!r}")
    return value


def like(what: str, name: str, value, default) -> None:
    """ValueError unless `value` is of the kind of `default` (the field's value before the change), finite if a number.

    A bool takes a bool, an int an int (a positive one where the default is positive: a size or a
    count), a float any finite number, a tuple a non-empty tuple of such, a string a string;
    a default of None takes None or a finite number.
    """
    field = f"{what} {name}"
    if isinstance(default, bool):
        if not isinstance(value, bool):
            raise ValueError(f"{field} must be True or False, not {value!r}")
    elif isinstance(default, Integral):
        integer(field, value, 1 if default > 0 else -INT32_MAX, INT32_MAX)
    elif isinstance(default, Real):
        number(field, value)
    elif isinstance(default, tuple):
        if not isinstance(value, tuple) or not value:
            raise ValueError(f"{field} must be a non-empty list like {list(default)}, not {value!r}")
        for item in value:
            like(what, f"{name} entry", item, default[0] if default else 0.0)
    elif isinstance(default, str):
        if not isinstance(value, str):
            raise ValueError(f"{field} must be a word like {default!r}, not {value!r}")
    elif default is None and value is not None:
        number(field, value)


def like_any(what: str, name: str, value, defaults: list) -> None:
    """`like` for a field whose value differs between its owners (a protocol's None, the other's number):
    the kind of any of `defaults` will do; the error is the first's."""
    errors = []
    for default in defaults:
        try:
            return like(what, name, value, default)
        except ValueError as error:
            errors.append(error)
    raise errors[0]


def params(what: str, pairs: tuple) -> None:
    """Every NAME=VALUE of `pairs` a finite number."""
    for name, value in pairs:
        number(f"{what} {name}", value)


def nearest_existing(path: Path) -> Path:
    """`path` or the nearest of its parents that exists."""
    path = Path(os.path.abspath(path))
    while not path.exists() and path != path.parent:
        path = path.parent
    return path


def writable_dir(path: Path, what: str) -> None:
    """ValueError unless `path` is a folder this process can write, or could create: nothing is created here."""
    path = Path(path)
    if path.exists() and not path.is_dir():
        raise ValueError(f"{what} {str(path)!r} is a file, not a folder")
    found = nearest_existing(path)
    if not found.is_dir():
        raise ValueError(f"{what} {str(path)!r} is not writable: {str(found)!r} is a file")
    if not os.access(found, os.W_OK | os.X_OK):
        raise ValueError(f"{what} {str(path)!r} is not writable: no write permission in {str(found)!r}")


def writable_file(path: Path, what: str) -> None:
    """ValueError unless a file can be written at `path` (its folder writable or creatable, not a folder itself)."""
    path = Path(path)
    if path.is_dir():
        raise ValueError(f"{what} {str(path)!r} is a folder, not a file")
    if path.exists() and not os.access(path, os.W_OK):
        raise ValueError(f"{what} {str(path)!r} is not writable")
    writable_dir(path.parent, f"the folder of {what}")
