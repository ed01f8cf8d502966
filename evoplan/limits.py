"""Memory estimated before large allocations: a setting that cannot fit is refused up front.

A population of 10^12 or a 200000 x 200000 zoning mesh would otherwise fail inside numpy
after a results folder has been created and partly written. The estimates are deliberately
rough (the main arrays and their working copies); they only need the right order of magnitude
to separate "large" from "impossible on this machine".
"""

from __future__ import annotations

import os

from .errors import ConfigError

GIB = 1024**3


def available_bytes() -> int:
    """Memory a new allocation can get: ``MemAvailable`` (Linux), else the physical memory."""
    try:
        with open("/proc/meminfo") as fh:
            for line in fh:
                if line.startswith("MemAvailable:"):
                    return int(line.split()[1]) * 1024
    except (OSError, ValueError, IndexError):
        pass
    try:
        return os.sysconf("SC_PHYS_PAGES") * os.sysconf("SC_PAGE_SIZE")
    except (ValueError, OSError, AttributeError):
        return 64 * GIB


def require(nbytes: float, where: str, what: str) -> None:
    """``ConfigError`` ``where: what need about N GiB (M GiB available)`` if ``nbytes`` cannot fit."""
    have = available_bytes()
    if nbytes > have:
        raise ConfigError(f"{where}: {what} need about {_gib(nbytes)} of memory; "
                          f"this machine has {_gib(have)} available")


def _gib(n: float) -> str:
    return f"{n / GIB:.3g} GiB"


def population_bytes(population: int, n_bits: int, n_var: int) -> float:
    """Genotypes (parents, children, masks: bool) + phenotypes and objective work arrays (float64)."""
    return float(population) * (3 * n_bits + 2 * 8 * n_var + 6 * 8)


def check_population(algorithm_config, n_bits: int, n_var: int, source: str) -> None:
    """Refuse a population (``population`` or ``pop_size``) whose arrays cannot fit in memory."""
    for key in ("population", "pop_size"):
        size = getattr(algorithm_config, key, None)
        if isinstance(size, int):
            require(population_bytes(size, n_bits, n_var), f"{source}: algorithm.{key}",
                    f"{size} individuals of {n_bits} genes")
            return


def mesh_bytes(n: int, m: int, arrays: int = 24) -> float:
    """A parametric mesh of ``n x m`` cells with ``arrays`` float64 fields (points, normals, features)."""
    return float(n) * float(m) * arrays * 8
