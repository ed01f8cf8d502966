"""Zoning of a meshed surface by the Adaptive Multi-Agent System of Djebali et al. (Sec. 5).

Each mesh of an (n, m) grid is an agent with an optimal feed direction, an AXIAL angle
(alpha and alpha + pi are the same feed, so directions live on a circle of circumference
pi). Mesh (i, j): i indexes u (E = i+1, W = i-1), j indexes v (N = j+1, S = j-1).

Start state: every mesh is its own zone (Sec. 6.2). A zone z has a size and a direction
sector: the minimal arc of the axial circle holding the directions of its non-neutral
meshes, of extremes e1, e2 and size gamma in [0, pi) (0 if it has no non-neutral mesh).
The criteria (Sec. 5.2): CMD(z) = 1 - gamma/pi, LZ(z) = size / |M| with |M| = n*m.

Zone score, ``satisfaction``:
- "printed": min(k_cmd CMD, k_lz LZ), the paper's Sat (Sec. 5.3.2). As LZ <= 1, k_lz LZ is
  tiny, so the LZ term is the minimum unless gamma > (1 - k_lz LZ) pi: the CMD criterion
  never acts and k_lz barely changes the result, contrary to the paper's Tables 1-2
  (k_lz 0.15 gives more zones than 0.35).
- "weighted" (default): -max(k_cmd (1 - CMD), k_lz (1 - LZ)), the worst WEIGHTED
  DISSATISFACTION. A zone stops growing when its sector exceeds about k_lz/k_cmd pi
  (0.15 -> 27 deg), the behaviour the paper describes.

Agent (Sec. 5.1-5.3). Perception: the situation is the set of the zones of the agent and of
its 8 neighbours N, NE, E, SE, S, SW, W, NW. Actions: join^N/E/S/W (the zone of that
4-neighbour, if not its own) and create (a zone of itself, if its zone has size > 1). No
action may disconnect the zone it leaves, by the local simple-point test (a 256-entry table
over the 8-neighbour mask, outside = other zone): the same-zone 4-neighbours must be
4-connected through same-zone cells of the 8-ring. Zones therefore stay 4-connected.
FutureSituation (the paper's "probable" situation, from local knowledge only): the left zone
gets size - 1 (gone at 0) and KEEPS its sector (the agent cannot know whether its direction
was the only extreme); the joined zone gets size + 1 and its sector minimally extended to
the agent's direction (unless neutral); create adds a zone of size 1, gamma 0.
NextAct: the agent takes the best future situation if STRICTLY better than the present one
(tolerance 1e-12 on scores, 1e-9 on sums), ties among the best broken uniformly at random.
Scores fall as gamma grows and the predicted sectors are never smaller than the true ones
(a minimal extension is exact while gamma <= pi/3), so every action truly improves the
situation and the global order: the run terminates.

Situation satisfaction, ``aggregate``:
- "mean" (default): the size-weighted mean of the zone scores of the perceived zones, i.e.
  the mean satisfaction of their meshes (the perceived sizes sum to a constant, so this is
  sum(size * score); only the left and joined zones change it).
- "leximin": the zone scores sorted ascending, compared lexicographically (its first term is
  the paper's Sat = min; a zone that vanished counts as +inf). Plain min has plateaus (from
  the all-singletons start no single move changes it, so no agent would ever act); leximin
  refines it. But any min-first order forbids a mesh to leave a zone smaller than the one it
  joins (the smaller zone's score drops), so two zones of several meshes can never merge:
  a constant field ends as a patchwork of balanced zones. "mean" keeps the per-zone worst
  criterion of the paper and lets zones merge (sum(size^2) is convex), so a constant field
  gives one zone and two half-planes two zones.

Cycle: every agent perceives, decides and acts once, SEQUENTIALLY (each action is seen by
the next agent) in a random order; the true zone state is updated exactly after each action
(a sector is recomputed from the members when a bound may have changed). The run stops after
a cycle without action (``settled``) or at ``max_cycles``. All randomness comes from
``numpy.random.default_rng(seed)``: per cycle a permutation and one uniform per agent for
tie-breaking, passed to the numba kernel ``amas_kernel.run_cycle``.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ...checks import number
from .amas_kernel import init_state, run_cycle

__all__ = ["AmasResult", "amas_zoning", "simple_point_lut"]


@dataclass(frozen=True)
class AmasResult:
    """Zone ids 0..Z-1 (first occurrence in a C-order scan), cycles, actions, settled."""

    labels: np.ndarray
    cycles: int
    actions: int
    settled: bool


def simple_point_lut() -> np.ndarray:
    """(256,) bool: may the centre leave its zone, for each 8-ring mask (bit r = RING[r])?

    True when the set 4-neighbours (bits 0, 2, 4, 6) lie in one run of consecutive set bits
    of the cyclic ring (consecutive ring cells are the only 4-adjacent pairs in the ring).
    """
    lut = np.zeros(256, bool)
    for mask in range(256):
        bits = [(mask >> r) & 1 for r in range(8)]
        run = list(range(8))  # run id of each set bit: union of consecutive set bits
        for _ in range(8):
            for r in range(8):
                if bits[r] and bits[(r + 1) % 8]:
                    run[r] = run[(r + 1) % 8] = min(run[r], run[(r + 1) % 8])
        lut[mask] = len({run[r] for r in (0, 2, 4, 6) if bits[r]}) <= 1
    return lut


_LUT = simple_point_lut()


def _unit(value, key: str) -> float:
    x = number(value, key)
    if not 0.0 <= x <= 1.0:
        raise ValueError(f"{key}: must be in [0, 1], got {value!r}")
    return x


def _choice(value, key: str, options: tuple[str, ...]) -> str:
    if value not in options:
        raise ValueError(f"{key}: expected one of {', '.join(options)}, got {value!r}")
    return value


def amas_zoning(direction, k_cmd=1.0, k_lz=0.15, seed=0, satisfaction="weighted",
                neutral=None, max_cycles=1000, aggregate="mean") -> AmasResult:
    """Zone an (n, m) field of axial feed directions (radians) with the AMAS (module doc).

    ``neutral``: optional (n, m) bool, meshes whose direction does not count in a sector.
    """
    try:
        d = np.array(direction, dtype=float)
    except (TypeError, ValueError):
        raise ValueError(f"direction: expected an (n, m) array of floats, got {direction!r}") from None
    if d.ndim != 2 or d.size < 2:
        raise ValueError(f"direction: expected an (n, m) array with n*m >= 2, got shape {d.shape}")
    if not np.all(np.isfinite(d)):
        raise ValueError("direction: must be finite")
    k_cmd = _unit(k_cmd, "k_cmd")
    k_lz = _unit(k_lz, "k_lz")
    satisfaction = _choice(satisfaction, "satisfaction", ("weighted", "printed"))
    aggregate = _choice(aggregate, "aggregate", ("mean", "leximin"))
    if isinstance(max_cycles, bool) or not isinstance(max_cycles, (int, np.integer)) or max_cycles < 1:
        raise ValueError(f"max_cycles: expected an integer >= 1, got {max_cycles!r}")
    if neutral is None:
        neu = np.zeros(d.size, bool)
    else:
        neu = np.asarray(neutral)
        if neu.shape != d.shape:
            raise ValueError(f"neutral: expected shape {d.shape}, got {neu.shape}")
        neu = neu.astype(bool).ravel()
    try:
        rng = np.random.default_rng(seed)
    except (TypeError, ValueError) as err:
        raise ValueError(f"seed: {err}") from None
    n, m = d.shape
    dirs = np.mod(d, np.pi).ravel()
    dirs[dirs >= np.pi] = 0.0
    state = init_state(dirs, neu)
    buf = np.empty(d.size)
    cycles = actions = 0
    settled = False
    while cycles < max_cycles and not settled:
        order = rng.permutation(d.size)
        unif = rng.random(d.size)
        acted = run_cycle(n, m, dirs, neu, _LUT, k_cmd, k_lz, satisfaction == "printed",
                          aggregate == "leximin", order, unif, state, buf)
        cycles += 1
        actions += acted
        settled = acted == 0
    _, first, inverse = np.unique(state[0], return_index=True, return_inverse=True)
    rank = np.empty(first.size, np.int64)
    rank[np.argsort(first)] = np.arange(first.size)
    labels = rank[inverse].reshape(n, m)
    labels.setflags(write=False)
    return AmasResult(labels, cycles, actions, settled)
