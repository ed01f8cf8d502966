"""Safety check of a 5-axis NC program, read back from its text (``check_program``).

The rules a machinist asks of a repositioning 5-axis program, verified on what the program
does (the post's own reader turns the text into moves), not on what the writer meant:

1. a move that turns a rotary axis by more than the kinematics' ``rotary_threshold`` starts
   and ends at or above the clearance plane; so does a turn split over consecutive
   non-cutting blocks below the plane (rapids, and feed blocks that leave the tip where it is):
   each rotary's turns are summed over such a run, and the run fails when a sum passes the
   threshold. A feed block that moves the tip ends the run and is not summed: 5-axis finishing
   turns the rotaries while it cuts (the posts split a turn into ``max_step`` blocks), which is
   the tool axis following the surface, not a repositioning;
2. the last move before tool-centre-point control is cancelled (``G49``, ``TRAFOOF``,
   ``FUNCTION RESET TCPM``) is at or above the clearance plane, and so is the first move;
   no move after the cancel goes below it (the table may still be tilted);
3. while |tilt| is below ``pole_angle`` the rotary table does not turn (only with the hold on;
   the one step of a move leaving or entering that cone may turn it).

``rotary_travel`` sums the rotary table's turning (deg), in all and in blocks near the pole.
"""

from __future__ import annotations

import re
from dataclasses import dataclass, field

import numpy as np

TCP_OFF = ("G49", "TRAFOOF", "FUNCTION RESET TCPM")
TOL = 1e-3


@dataclass
class SafetyReport:
    violations: list[str] = field(default_factory=list)
    c_travel: float = 0.0
    c_travel_pole: float = 0.0
    repositions: int = 0

    @property
    def ok(self) -> bool:
        return not self.violations


def _cancel_line(text: str) -> int:
    """Index of the last line that cancels TCP (len(lines) if none; the safe-start line of
    the header cancels G49 too, before any move)."""
    lines = text.splitlines()
    for i in range(len(lines) - 1, -1, -1):
        code = re.sub(r"\([^()]*\)", " ", lines[i].upper().split(";")[0])
        if any(re.search(rf"(^|[\s\d])({re.escape(w)})(\s|$)", code) for w in TCP_OFF):
            return i
    return len(lines)


def rotary_travel(angles: np.ndarray, pole_angle: float) -> tuple[float, float]:
    """(total, near the pole) rotary-table travel (deg) of moves' angles (k, 2)."""
    ang = angles[np.isfinite(angles).all(axis=1)]
    dc = np.abs(np.diff(ang[:, 1]))
    near = (np.abs(ang[:-1, 0]) < max(pole_angle, 5.0)) & (np.abs(ang[1:, 0]) < max(pole_angle, 5.0))
    return float(dc.sum()), float(dc[near].sum())


def _split_turns(mv, low: np.ndarray, single: np.ndarray,
                 threshold: float) -> list[tuple[int, int, int, float]]:
    """Runs of consecutive non-cutting blocks below the clearance plane (rapids, and feed
    blocks whose tip moves less than ``TOL``) whose summed turn of one rotary passes
    ``threshold``: (first move, last move, blocks that turn, largest sum) of its turning
    blocks each; block ``i`` goes from move ``i`` to ``i + 1``. A run holding a block already
    over the threshold on its own (``single``) is reported there, not again."""
    step = np.nan_to_num(np.abs(np.diff(mv.angles, axis=0)))
    moved = np.nan_to_num(np.abs(np.diff(np.where(np.isfinite(mv.tip), mv.tip, 0.0), axis=0)).max(axis=1))
    idle = (mv.rapid[1:] | (moved < TOL)) & low
    edges = np.diff(np.r_[0, idle.astype(np.int8), 0])
    starts, ends = np.flatnonzero(edges == 1), np.flatnonzero(edges == -1)  # run [start, end)
    cum = np.vstack([np.zeros((1, step.shape[1])), np.cumsum(step, axis=0)])
    total = (cum[ends] - cum[starts]).max(axis=1, initial=0.0)
    singles = np.r_[0, np.cumsum(single)]
    hit = (total > threshold + TOL) & (singles[ends] == singles[starts])
    runs = []
    for a, e, t in zip(starts[hit], ends[hit], total[hit]):
        turning = a + np.flatnonzero(step[a:e].max(axis=1) > 0)
        runs.append((int(turning[0]), int(turning[-1]) + 1, len(turning), float(t)))
    return runs


def check_program(post, text: str, safe_z: float) -> SafetyReport:
    """The rules of the module docstring on program ``text`` written by ``post`` (a 5-axis
    post with its machine's kinematics) for the clearance plane ``safe_z``."""
    kin = post.machine.kinematics
    lines = text.splitlines()
    cut = _cancel_line(text)
    mv = post.read("\n".join(lines[:cut]))
    rep = SafetyReport()
    z, ang = mv.tip[:, 2], mv.angles
    known = np.isfinite(z)
    if not known.any():
        rep.violations.append("no move with a Z before TCP is cancelled")
        return rep
    # a move before any Z (rotaries set at the tool-change position) counts as high
    zz = np.where(known, z, np.inf)
    first = int(np.flatnonzero(known)[0])
    if zz[first] < safe_z - TOL:
        rep.violations.append(f"move {first}: the first positioning is at Z {zz[first]:.3f}, "
                              f"below the clearance plane {safe_z:.3f}")
    if zz[-1] < safe_z - TOL:
        rep.violations.append(f"move {len(zz) - 1}: TCP is cancelled at Z {zz[-1]:.3f}, "
                              f"below the clearance plane {safe_z:.3f}")
    after = post.read(text).tip[len(z):, 2]
    after = after[np.isfinite(after)]
    if len(after) and after.min() < safe_z - TOL:
        rep.violations.append(f"after TCP is cancelled a move goes down to Z {after.min():.3f}, "
                              f"below the clearance plane {safe_z:.3f}")
    turn = np.abs(np.diff(ang, axis=0)).max(axis=1)
    low = np.minimum(zz[:-1], zz[1:]) < safe_z - TOL
    for i in np.flatnonzero((turn > kin.rotary_threshold + TOL) & low)[:5]:
        rep.violations.append(f"move {i + 1}: rotaries turn by {turn[i]:.2f} deg at Z {min(zz[i], zz[i + 1]):.3f}, "
                              f"below the clearance plane {safe_z:.3f}")
    single = (turn > kin.rotary_threshold + TOL) & low
    rep.repositions = int((turn > kin.rotary_threshold + TOL).sum())
    for i, j, k, total in _split_turns(mv, low, single, kin.rotary_threshold)[:5]:
        rep.violations.append(f"moves {i + 1}-{j}: rotaries turn by {total:.2f} deg in {k} non-cutting blocks "
                              f"at Z {zz[i:j + 1].min():.3f}, below the clearance plane {safe_z:.3f}")
    if kin.pole_angle > 0:
        inside = np.abs(ang[:, 0]) < kin.pole_angle - TOL
        near = inside[:-1] & inside[1:]
        # a move leaving or entering the cone (split in steps: the step beside the outside point) may turn
        beside = np.r_[False, ~inside[:-2]] | np.r_[~inside[2:], False]
        spin = near & ~beside & (np.abs(np.diff(ang[:, 1])) > TOL) & low
        for i in np.flatnonzero(spin)[:5]:
            rep.violations.append(f"move {i + 1}: the table turns near the pole "
                                  f"(|{post.axis_names[0]}| < {kin.pole_angle:g} deg)")
    rep.c_travel, rep.c_travel_pole = rotary_travel(ang, kin.pole_angle)
    return rep
