"""Field types of the toolpath specification whose checks keep today's one-line wording."""

from __future__ import annotations

from typing import Annotated

from pydantic import BeforeValidator

from ..checks import interval, number
from .errors import HERE

__all__ = ["Number", "Positive", "NonNegative", "WholeNumber", "Interval"]


def _nonnegative(value) -> float:
    x = number(value, HERE)
    if x < 0:
        raise ValueError(f"{HERE}: must be >= 0, got {x:g}")
    return x


def _whole(value) -> int:
    if isinstance(value, bool) or not isinstance(value, int) or value < 0:
        raise ValueError(f"{HERE}: expected an integer >= 0, got {value!r}")
    return value


#: a finite number (a bool or a string is refused)
Number = Annotated[float, BeforeValidator(lambda v: number(v, HERE))]
#: a finite number > 0
Positive = Annotated[float, BeforeValidator(lambda v: number(v, HERE, positive=True))]
#: a finite number >= 0
NonNegative = Annotated[float, BeforeValidator(_nonnegative)]
#: an integer >= 0 (a bool or a float is refused)
WholeNumber = Annotated[int, BeforeValidator(_whole)]
#: [lo, hi] with lo < hi
Interval = Annotated[tuple[float, float], BeforeValidator(lambda v: interval(v, HERE))]
