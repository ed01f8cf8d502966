"""Variable space and the binary codec of Fountas Eq. 8.

A :class:`Space` is an ordered list of named variables (real, integer, categorical), each given a
number of bits. A genotype is a row of a boolean matrix ``G: (n, L)``; decoding gives the
phenotype matrix ``X: (n, d)`` float that a batched problem evaluates.

Decoding rules (per variable, on the unsigned integer ``k`` read from its bits, most
significant bit first, optionally Gray-coded):

- real, Fountas Eq. 8: ``x = l + k * (u - l) / (2**nbits - 1)``; the ends are reachable exactly.
- integer in ``[l, u]`` (``m = u - l + 1`` values): ``x = l + floor(k * m / 2**nbits)``, which
  gives every value the same number of codes when ``m`` divides ``2**nbits`` (rounding Eq. 8
  would give the two end values half as many codes as the others).
- categorical with ``m`` choices: the choice *index* ``floor(k * m / 2**nbits)``; ``X`` holds
  the index, :meth:`Space.named` turns it back into the choice.

Decoding is one matrix product of the bit matrix with a block matrix of powers of two, exact
up to 52 bits per variable (the float64 mantissa), which the constructor enforces.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any, Sequence

import numpy as np

MAX_BITS = 52
# up to this many reals and from this many rows, decoding scales column by column
COLUMNWISE_VARIABLES, COLUMNWISE_ROWS = 8, 512


@dataclass(frozen=True)
class Real:
    """A real variable on ``[low, high]`` decoded by Eq. 8."""

    name: str
    low: float
    high: float
    bits: int = 23

    kind = "real"

    def __post_init__(self) -> None:
        _check_bits(self.name, self.bits)
        if not (np.isfinite(self.low) and np.isfinite(self.high)):
            raise ValueError(f"{self.name}: bounds must be finite, got [{self.low}, {self.high}]")
        if self.low >= self.high:
            raise ValueError(f"{self.name}: lower bound {self.low} must be below upper bound {self.high}")


@dataclass(frozen=True)
class Integer:
    """An integer variable on ``[low, high]`` (both included)."""

    name: str
    low: int
    high: int
    bits: int | None = None

    kind = "integer"

    def __post_init__(self) -> None:
        if self.low >= self.high:
            raise ValueError(f"{self.name}: lower bound {self.low} must be below upper bound {self.high}")
        if self.bits is None:
            object.__setattr__(self, "bits", max(1, math.ceil(math.log2(self.high - self.low + 1))))
        _check_bits(self.name, self.bits)
        if 2**self.bits < self.high - self.low + 1:
            raise ValueError(f"{self.name}: {self.bits} bits cannot code {self.high - self.low + 1} values")


@dataclass(frozen=True)
class Categorical:
    """A choice among ``choices``; the phenotype column holds the choice index."""

    name: str
    choices: tuple = field(default_factory=tuple)
    bits: int | None = None

    kind = "categorical"

    def __post_init__(self) -> None:
        object.__setattr__(self, "choices", tuple(self.choices))
        if len(self.choices) < 2:
            raise ValueError(f"{self.name}: a categorical variable needs at least 2 choices")
        if self.bits is None:
            object.__setattr__(self, "bits", max(1, math.ceil(math.log2(len(self.choices)))))
        _check_bits(self.name, self.bits)
        if 2**self.bits < len(self.choices):
            raise ValueError(f"{self.name}: {self.bits} bits cannot code {len(self.choices)} choices")


Variable = Real | Integer | Categorical


def _check_bits(name: str, bits: int) -> None:
    if not isinstance(bits, (int, np.integer)) or not 1 <= bits <= MAX_BITS:
        raise ValueError(f"{name}: bits must be an integer in [1, {MAX_BITS}], got {bits!r}")


def gray_to_binary(G: np.ndarray) -> np.ndarray:
    """Gray code to plain binary along the last axis (MSB first): ``b_i = g_0 ^ ... ^ g_i``."""
    return np.bitwise_xor.accumulate(G, axis=-1)


def binary_to_gray(B: np.ndarray) -> np.ndarray:
    """Plain binary to Gray code along the last axis (MSB first): ``g_i = b_{i-1} ^ b_i``."""
    G = B.copy()
    G[..., 1:] ^= B[..., :-1]
    return G


class Space:
    """An ordered set of variables with their binary codec.

    ``decode(G: (n, L) bool) -> X: (n, d) float`` and ``encode(X) -> G`` (nearest code).
    A space of no variables is one point (``d = L = 0``): a problem whose every decision is
    fixed, which a run evaluates once (:mod:`evoplan.fixed_run`) instead of searching.
    """

    def __init__(self, variables: Sequence[Variable], gray: bool = False) -> None:
        names = [v.name for v in variables]
        if len(set(names)) != len(names):
            raise ValueError(f"variable names must be unique, got {names}")
        self.variables: tuple[Variable, ...] = tuple(variables)
        self.gray = bool(gray)
        self.bits = np.array([v.bits for v in self.variables], dtype=np.int64)
        self.n_bits = int(self.bits.sum())
        self.offsets = np.concatenate([[0], np.cumsum(self.bits)])
        d = len(self.variables)
        # W[j, i] = 2**(position of bit j within variable i), MSB first; zero outside the block.
        self._weights = np.zeros((self.n_bits, d))
        for i, nb in enumerate(self.bits):
            self._weights[self.offsets[i] : self.offsets[i + 1], i] = 2.0 ** np.arange(nb - 1, -1, -1)
        self._not_block_start = np.ones(self.n_bits, dtype=bool)
        self._not_block_start[self.offsets[:-1]] = False
        self._low = np.array([_low(v) for v in self.variables], dtype=float)
        self._count = np.array([_count(v) for v in self.variables], dtype=float)
        self._levels = 2.0**self.bits
        self._is_real = np.array([v.kind == "real" for v in self.variables])
        self._all_real = bool(self._is_real.all())
        span = np.array([v.high - v.low if v.kind == "real" else 0.0 for v in self.variables])
        self._real_scale = np.where(self._is_real, span / (self._levels - 1), 0.0)

    @property
    def names(self) -> list[str]:
        return [v.name for v in self.variables]

    @property
    def n_var(self) -> int:
        return len(self.variables)

    def integers(self, G: np.ndarray) -> np.ndarray:
        """The unsigned integer coded by each variable's bits, ``(n, L) bool -> (n, d) float``."""
        G = np.asarray(G, dtype=bool)
        if G.ndim != 2 or G.shape[1] != self.n_bits:
            raise ValueError(f"genotypes must have shape (n, {self.n_bits}), got {G.shape}")
        if self.gray:
            G = self._blockwise(G, gray_to_binary)
        return G.astype(np.float64) @ self._weights

    def decode(self, G: np.ndarray) -> np.ndarray:
        """Phenotypes ``X: (n, d)``: Eq. 8 for reals, equal-width bins for integers and choices."""
        K = self.integers(G)
        if self._all_real:
            if K.shape[1] > COLUMNWISE_VARIABLES or K.shape[0] < COLUMNWISE_ROWS:
                return self._low + K * self._real_scale
            for i in range(K.shape[1]):  # the same numbers: numpy's broadcast over a row of a
                column = K[:, i]  # few values runs its inner loop once a row, a column is one loop
                column *= self._real_scale[i]
                column += self._low[i]
            return K
        binned = self._low + np.minimum(np.floor(K * self._count / self._levels), self._count - 1)
        return np.where(self._is_real, self._low + K * self._real_scale, binned)

    def from_unit(self, U: np.ndarray) -> np.ndarray:
        """Phenotypes of unit-cube rows ``U: (n, d)`` in ``[0, 1]`` (clipped): reals on their
        bounds, integers and choices by the equal-width bins :meth:`decode` uses."""
        U = np.clip(np.asarray(U, dtype=float), 0.0, 1.0)
        span = np.array([v.high - v.low if v.kind == "real" else 0.0 for v in self.variables])
        binned = self._low + np.minimum(np.floor(U * self._count), self._count - 1)
        return np.where(self._is_real, self._low + U * span, binned)

    def encode(self, X: np.ndarray) -> np.ndarray:
        """Genotypes of the codes nearest to ``X: (n, d)`` (the inverse of :meth:`decode` on codes)."""
        X = np.atleast_2d(np.asarray(X, dtype=float))
        with np.errstate(divide="ignore", invalid="ignore"):
            k_real = np.rint((X - self._low) / np.where(self._is_real, self._real_scale, 1.0))
        # smallest code of the integer's / choice's bin: ceil(j * 2**nbits / m)
        k_bin = np.ceil((np.rint(X) - self._low) * self._levels / self._count)
        K = np.clip(np.where(self._is_real, k_real, k_bin), 0, self._levels - 1).astype(np.int64)
        G = np.zeros((X.shape[0], self.n_bits), dtype=bool)
        for i, nb in enumerate(self.bits):
            shifts = np.arange(nb - 1, -1, -1, dtype=np.int64)
            G[:, self.offsets[i] : self.offsets[i + 1]] = (K[:, i : i + 1] >> shifts) & 1
        if self.gray:
            G = self._blockwise(G, binary_to_gray)
        return G

    def _blockwise(self, G: np.ndarray, fn) -> np.ndarray:
        """Apply a Gray conversion to every variable's block at once (blocks never mix)."""
        if fn is gray_to_binary:
            C = np.cumsum(G, axis=1, dtype=np.int32)
            before = np.concatenate([np.zeros((G.shape[0], 1), np.int32), C], axis=1)[:, self.offsets[:-1]]
            return ((C - np.repeat(before, self.bits, axis=1)) & 1).astype(bool)
        out = G.copy()
        out[:, 1:] ^= G[:, :-1] & self._not_block_start[1:]
        return out

    def named(self, x: np.ndarray) -> dict[str, Any]:
        """One phenotype row as ``{name: value}``, choices and integers as plain Python values."""
        out: dict[str, Any] = {}
        for v, value in zip(self.variables, np.asarray(x, dtype=float)):
            if v.kind == "real":
                out[v.name] = float(value)
            elif v.kind == "integer":
                out[v.name] = int(round(value))
            else:
                choice = v.choices[int(round(value))]
                out[v.name] = choice.item() if isinstance(choice, np.generic) else choice
        return out

    def describe(self) -> list[dict[str, Any]]:
        """A plain description of every variable (for results files)."""
        rows = []
        for v in self.variables:
            row = {"name": v.name, "kind": v.kind, "bits": int(v.bits)}
            if v.kind == "categorical":
                row["choices"] = list(v.choices)
            else:
                row["low"], row["high"] = v.low, v.high
            rows.append(row)
        return rows


def _low(v: Variable) -> float:
    return 0.0 if v.kind == "categorical" else float(v.low)


def _count(v: Variable) -> float:
    if v.kind == "categorical":
        return float(len(v.choices))
    if v.kind == "integer":
        return float(v.high - v.low + 1)
    return 1.0
