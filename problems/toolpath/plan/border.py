"""Border passes: the stretches of a trimmed footprint's edge that a plan's passes leave high.

A trimmed face (a CAD face's hole or notch, a mesh's outline) has edges that no pass
pattern follows. Where passes cross an edge they run on past it and cut it; where an edge
runs along the passes (a notch's side parallel to the feed), the last pass before it may
lie farther from it than the cutter's reach at the scallop target, and the cells along
the edge stay high: 2.5-4.7 h_c on the sculpted block's notch before these passes.

So after the strategy has laid out its passes, every point of the footprint's loops
(sampled every ``SAMPLE_MM`` mm of arc on the part) is tested: it is **covered** when a feed
move of the plan between two CC points on the part (or the first stretch of a run past the
edge) passes within ``REACH`` times the cutter's half-width at h_c on the point's side of
the move (:class:`PairReach`: where a single pass's profile rises to h_c, across that move;
a ball's is the same at any slope, a vertical torus's is its flat bottom on the level and
shrinks to its corner's on a slope, so a pass that crosses an edge covers it with more than
a pass along it does).
Where it is not, border passes are laid along the loop at inward offsets 0, S, 2S, ... on
the surface (S = 2 COVER w, w the border pass's own half-width across the loop,
:func:`edge_widths`: two passes S apart leave under h_c between them); level k+1 wherever
the test point just beyond level k's reach (``BEYOND`` w inside it) is not covered by the
plan's passes nor by a border pass already laid (at a corner the other edge's), at most
``MAX_LEVELS``. Each level's stretches, widened by the cutter's radius at both ends so that
they meet the passes they join and clipped to the footprint, are cut after the plan's own
passes (the last passes on the border, as contour-parallel plans cut the edge first), the
innermost first; a stretch that spans its whole loop as a closed loop. Plans that cover
their edges (contour plans, whose first loop is the edge) get none.

Only for trimmed footprints and plans spaced by h_c; the whole unit square's edges are cut
by every strategy's own rule (planes and offsets reach them, ``curves.py`` runs on).
"""

from __future__ import annotations

import numpy as np

from ..geometry.footprint import footprint_of
from .batch import PlanBatch, merge_batches
from .curves import Piece, plan_pieces
from .strategies.offsets import march, runs

__all__ = ["BorderLoops", "PairReach", "plan_moves", "covered", "edge_widths", "border_levels", "with_border"]

#: a point is covered when a feed move passes within this share of w(h_c) (a ball's
#: profile there: 1.04 h_c; the points midway between a plan's passes are at about w)
REACH = 1.02
#: border passes lie 2 COVER w apart (0.81 h_c between two ball passes)
COVER = 0.9
#: a level's test point lies this share of w inside it: just beyond its own reach
BEYOND = 1.1
#: arc length (mm) between the loops' test points
SAMPLE_MM = 0.25
#: a loop turning by more than this (degrees) at a point has a corner there, sampled as such
CORNER_DEG = 15.0
#: moves measured at once (their pairs with the loop points: about 40 each)
BLOCK = 20000
#: border passes per edge point at most (the edge itself and inward offsets)
MAX_LEVELS = 6


class BorderLoops:
    """The trimmed footprint's loops sampled on the part every ``sample_mm`` mm of arc:
    ``uv`` (L, 2), ``p`` (L, 3), per point its ``loop`` (the loops one after another from
    ``start``) and ``inward``, the unit tangent across the loop into the material."""

    def __init__(self, surface, sample_mm: float = SAMPLE_MM):
        fp = footprint_of(surface)
        uvs, loop_of = [], []
        for k, uv in enumerate(fp.dense(1.0 / 2048)):
            uv = np.vstack([uv, uv[:1]])  # closed
            p = surface.jet(uv[:, 0], uv[:, 1], order=0).p
            arc = np.r_[0.0, np.cumsum(np.linalg.norm(np.diff(p, axis=0), axis=1))]
            m = max(int(np.ceil(arc[-1] / sample_mm)), 3)
            s = _with_corners(np.linspace(0.0, arc[-1], m, endpoint=False), p, arc, sample_mm)
            m = len(s)
            uvs.append(np.column_stack([np.interp(s, arc, uv[:, 0]), np.interp(s, arc, uv[:, 1])]))
            loop_of.append(np.full(m, k))
        self.surface, self.footprint = surface, fp
        self.uv = np.concatenate(uvs)
        self.loop = np.concatenate(loop_of)
        jet = surface.jet(self.uv[:, 0], self.uv[:, 1], order=1)
        self.p = jet.p
        self.start = np.flatnonzero(np.r_[True, self.loop[1:] != self.loop[:-1]])
        self.end = np.r_[self.start[1:], len(self.p)]
        # into the material: the loop's (u, v) normal on the side ``contains`` holds (per
        # loop, by majority), through the surface's derivatives, square to the loop there
        t_uv = np.empty_like(self.uv)
        for a, e in zip(self.start, self.end):
            t_uv[a:e] = np.roll(self.uv[a:e], -1, axis=0) - np.roll(self.uv[a:e], 1, axis=0)
        n_uv = np.column_stack([-t_uv[:, 1], t_uv[:, 0]])
        n_uv /= np.maximum(np.linalg.norm(n_uv, axis=1, keepdims=True), 1e-300)
        probe = self.uv + 1e-5 * n_uv
        side = np.where(fp.contains(probe[:, 0], probe[:, 1]), 1.0, -1.0)
        for a, e in zip(self.start, self.end):
            side[a:e] = 1.0 if side[a:e].sum() >= 0 else -1.0
        n_uv *= side[:, None]
        t = jet.su * t_uv[:, :1] + jet.sv * t_uv[:, 1:]
        t /= np.maximum(np.linalg.norm(t, axis=1, keepdims=True), 1e-300)
        self.tangent = t
        b = jet.su * n_uv[:, :1] + jet.sv * n_uv[:, 1:]
        b -= np.einsum("ij,ij->i", b, t)[:, None] * t
        self.inward = b / np.maximum(np.linalg.norm(b, axis=1, keepdims=True), 1e-300)

    def offset(self, dist) -> tuple[np.ndarray, np.ndarray]:
        """((L, 2) uv, (L, 3) points): every loop point walked ``dist`` mm (a scalar or (L,))
        into the material on the surface (``offsets.march``)."""
        if np.all(np.asarray(dist) == 0.0):
            return self.uv, self.p
        uv = march(self.surface, self.uv, self.inward, np.broadcast_to(dist, (len(self.uv),)))
        return uv, self.surface.jet(uv[:, 0], uv[:, 1], order=0).p

    def stretches(self, cut: np.ndarray, widen: int) -> list[np.ndarray]:
        """The runs of ``cut`` (L,) along each loop, each widened by ``widen`` points at
        both ends (around the loop), as index arrays in loop order; a run that spans its
        loop is the whole loop, closed (its first point again at the end)."""
        out = []
        for s, e in zip(self.start, self.end):
            m = e - s
            b = cut[s:e]
            if not b.any():
                continue
            wide = np.zeros(m, bool)  # within ``widen`` points of a point to cut
            for off in range(-min(widen, m), min(widen, m) + 1):
                wide |= np.roll(b, off)
            if wide.all():
                out.append(s + np.r_[np.arange(m), 0])
                continue
            # the runs, read from a point not cut (so that none wraps round the loop's start)
            first = int(np.flatnonzero(~wide)[0])
            order = (first + np.arange(m)) % m
            edges = np.diff(np.r_[0, wide[order].astype(np.int8), 0])
            for a, z in zip(np.flatnonzero(edges == 1), np.flatnonzero(edges == -1)):
                if z - a >= 2:
                    out.append(s + order[a:z])
        return out


class PairReach:
    """How far beside a feed move a loop point still counts as covered: ``REACH`` times the
    cutter's half-width at h_c on the point's side of the move. A 3-axis (vertical) cutter's
    is its silhouette on the slope between them (``Cutter.swept_side_width`` with the move's
    |t_z| and the rise of the direction from the move to the point): a pass that crosses an
    edge covers it with its whole cross-feed width (a D10 r2 torus's flat bottom, 3.44 mm at
    h_c 0.05), a pass along a sloping edge only with its corner (0.44-0.6 mm). A 5-axis tool
    square to the surface has ``Cutter.width(h_c)`` on every side.

    A vertical cutter's width is read from a table over (|t_z|, beta) built once per
    cutter (``Cutter.swept_side_width`` at the nodes; the lowest of a cell's four corners,
    or of the two on its side where a value is a node's, so that a look-up never claims
    more reach: a torus's width falls from its flat bottom's to its corner's within a few
    thousandths of the level, where the nodes are densest, and a level move is on the
    nodes t_z = 0 and beta = 0). ``cutters`` maps a tool id to its cutter, ``tool`` (n,)
    is each plan's tool id; ``tables``: a dict of the tables by tool id, read and filled
    (they depend only on the cutter and h_c: a planner keeps them); ``bound`` (n,) the
    largest reach of each plan."""

    #: the table's nodes, densest at the level: |t_z| 0.002 sinh(s) on [0, 1], beta the same
    #: on [-pi / 2, pi / 2]
    T_Z = 0.002 * np.sinh(np.linspace(0.0, 1.0, 61) * np.arcsinh(1.0 / 0.002))
    BETA = 0.002 * np.sinh(np.linspace(-1.0, 1.0, 241) * np.arcsinh(0.5 * np.pi / 0.002))

    def __init__(self, cutters: dict, tool, h_c: float, vertical: bool,
                 tables: dict | None = None):
        self.h_c, self.vertical = float(h_c), bool(vertical)
        self.cutters, self.tool = dict(cutters), np.asarray(tool).astype(np.int64)
        self.flat = {t: float(c.width(self.h_c)) for t, c in self.cutters.items()}
        self.bound = REACH * np.array([self.flat[int(t)] for t in self.tool], float)
        self.tables = {} if tables is None else tables
        if self.vertical:
            tz, beta = np.meshgrid(self.T_Z, self.BETA, indexing="ij")
            for t, c in self.cutters.items():
                if t not in self.tables:  # 14 700 exact widths: about 18 ms a cutter
                    self.tables[t] = np.minimum(c.swept_side_width(
                        self.h_c, tz.ravel(), beta.ravel()), self.flat[t]).reshape(tz.shape)

    def __call__(self, plan: np.ndarray, t_z: np.ndarray, beta: np.ndarray) -> np.ndarray:
        """(m,) the reach (mm) for pairs of plan ``plan`` (m,), the move's |t_z| and the
        rise ``beta`` (radians) of the direction from it to the point."""
        out = np.empty(len(plan))
        tool = self.tool[plan]
        if self.vertical:  # the lowest corner of the cell, or of its side on a node
            i, i2 = self._cell(self.T_Z, t_z)
            j, j2 = self._cell(self.BETA, beta)
        for t in self.cutters:
            m = tool == t
            if not m.any():
                continue
            if not self.vertical:
                out[m] = self.flat[t]
                continue
            w = self.tables[t]
            a, a2, b, b2 = i[m], i2[m], j[m], j2[m]
            out[m] = np.minimum(np.minimum(w[a, b], w[a, b2]), np.minimum(w[a2, b], w[a2, b2]))
        return REACH * out

    @staticmethod
    def _cell(nodes, x):
        """The nodes below and above each x (the same node twice where x is one)."""
        lo = np.clip(np.searchsorted(nodes, x, side="right") - 1, 0, len(nodes) - 2)
        return lo, np.where(nodes[lo] == x, lo, lo + 1)


def plan_moves(batch: PlanBatch, bound: np.ndarray):
    """(a, b, plan) of the feed moves of ``batch`` between two CC points on the part, and of
    the first ``bound[plan]`` mm of each run past the edge (further on, its nominal points
    follow the tangent, where a 3-axis tool kept at its drop height does not cut: a
    notch's side along the run is left 0.1 mm high)."""
    on = batch.on_part
    k = np.flatnonzero((batch.pt_sec[1:] == batch.pt_sec[:-1]) & (on[1:] | on[:-1]))
    ind = batch.sec_ind[batch.pt_sec[k]]
    # a run past the edge counts for its first stretch, as long as the plan's reach (where
    # the pass crosses the edge, the tool cuts the edge beside it as it leaves)
    first = np.where(on[k], k, k + 1)
    a, b = batch.p[first], batch.p[np.where(on[k], k + 1, k)]
    run = ~(on[k] & on[k + 1])
    span = np.linalg.norm(b - a, axis=1)
    cap = bound[ind]
    b[run] = a[run] + (b[run] - a[run]) * np.minimum(1.0, cap[run] / np.maximum(
        span[run], 1e-300))[:, None]
    return a, b, ind


def covered(points: np.ndarray, moves, reach: PairReach, n: int) -> np.ndarray:
    """(n, L) bool: point j of ``points`` (L, 3) lies within ``reach`` (:class:`PairReach`) of a
    move (a, b) of plan i in ``moves`` (a (m, 3), b (m, 3), plan (m,)). Only the moves
    whose midpoint lies within reach of some point are measured."""
    from scipy.spatial import cKDTree

    a, b, ind = moves
    L = len(points)
    out = np.zeros((n, L), bool)
    if not len(a) or not L:
        return out
    tree = cKDTree(points)
    mid, half = 0.5 * (a + b), 0.5 * np.linalg.norm(b - a, axis=1)
    r = reach.bound[ind] + half
    d, _ = tree.query(mid, k=1, distance_upper_bound=float(r.max()))
    near = np.flatnonzero(d <= r)
    if not len(near):
        return out
    for block in np.array_split(near, max(1, int(np.ceil(len(near) / BLOCK)))):
        _cover(out, points, tree.query_ball_point(mid[block], r[block]), block, a, b, ind,
               reach)
    return out


def _cover(out, points, hits, moves, a, b, ind, reach):
    """Mark in ``out`` the points ``hits[k]`` (indices into ``points``) that move
    ``moves[k]`` (a, b, plan ``ind``) reaches."""
    cnt = np.fromiter((len(h) for h in hits), np.int64, len(hits))
    if not cnt.sum():
        return
    mv = np.repeat(moves, cnt)
    j = np.concatenate([np.asarray(h, np.int64) for h in hits if len(h)])
    q, a, b = points[j], a[mv], b[mv]
    ab = b - a
    ab2 = np.maximum(np.einsum("ij,ij->i", ab, ab), 1e-300)
    lam = np.clip(np.einsum("ij,ij->i", q - a, ab) / ab2, 0.0, 1.0)
    e = q - a - lam[:, None] * ab
    dist = np.linalg.norm(e, axis=1)
    t = ab / np.sqrt(ab2)[:, None]
    side = e - np.einsum("ij,ij->i", e, t)[:, None] * t  # across the move, to the point
    side_len = np.linalg.norm(side, axis=1)
    beta = np.arcsin(np.clip(side[:, 2] / np.maximum(side_len, 1e-300), -1.0, 1.0))
    ok = dist <= reach(ind[mv], np.abs(t[:, 2]), np.where(side_len > 1e-9, beta, 0.0))
    out[ind[mv][ok], j[ok]] = True


def edge_widths(loops: BorderLoops, cutter, h_c: float, vertical: bool) -> np.ndarray:
    """(L,) the cutter's half-width at h_c beside each loop point, on the edge's side of a
    pass along it (the border passes' spacing): a vertical (3-axis) cutter's silhouette on
    the slope there (``Cutter.swept_side_width``: a torus on a slope cuts with its corner,
    0.44-0.6 mm for D10 r2 at h_c 0.05 against 3.44 mm on the flat), at most
    ``Cutter.width(h_c)``, the width a 5-axis tool square to the surface has."""
    flat = cutter.width(h_c)
    if not vertical:
        return np.full(len(loops.p), flat)
    beta = np.arcsin(np.clip(-loops.inward[:, 2], -1.0, 1.0))  # towards the edge
    return np.minimum(cutter.swept_side_width(h_c, np.abs(loops.tangent[:, 2]), beta), flat)


def border_levels(loops: BorderLoops, batch: PlanBatch, w: np.ndarray, reach: PairReach,
                  widen: np.ndarray, offsets: dict | None = None) -> np.ndarray:
    """(n, L) int: how many border passes each loop point needs in plan i, the border
    passes' half-width at h_c there ``w[i]`` (L,). 0: a feed move passes within ``reach``
    of it. k: the edge and k - 1 inward offsets 2 ``COVER`` w apart, until the test point
    just beyond the last one's reach (``BEYOND`` w inside it, so that the pass itself does
    not cover it) is within ``reach`` of the plan's passes or of a border pass already laid
    (at a corner, the other edge's), or ``MAX_LEVELS``. ``widen`` (n,): the points each
    stretch is widened by; ``offsets``: a dict that keeps the offset loops ((uv, points)
    per (widths, distance in w)) for the caller."""
    n = batch.n
    moves = [plan_moves(batch, reach.bound)]
    need = (~covered(loops.p, moves[0], reach, n)).astype(np.int64)
    active = need.astype(bool)
    offsets = {} if offsets is None else offsets

    def offset(i, d):  # loop points d w inward for plan i's widths, shared by a tool's rows
        return _offset(loops, offsets, w[i], d)[1]

    for k in range(1, MAX_LEVELS):
        rows = np.flatnonzero(active.any(axis=1))
        if not len(rows):
            break
        for i in rows:  # level k - 1's border passes cover too
            q = offset(i, 2 * (k - 1) * COVER)
            for idx in loops.stretches(need[i] >= k, int(widen[i])):
                moves.append((q[idx[:-1]], q[idx[1:]], np.full(len(idx) - 1, i)))
        every = tuple(np.concatenate(c) for c in zip(*moves))
        groups = {}  # the rows of one tool: one offset of the test points
        for i in rows:
            groups.setdefault(w[i].tobytes(), []).append(i)
        for sel in map(np.asarray, groups.values()):
            m = np.isin(every[2], sel)
            test = offset(sel[0], 2 * (k - 1) * COVER + BEYOND)
            ok = covered(test, tuple(x[m] for x in every), reach, n)[sel]
            grow = active[sel] & ~ok
            need[sel] += grow
            active[sel] = grow
    return need


def _kept(planner) -> dict:
    """What the planner's border passes keep across plans (it depends only on the surface,
    the cutters and h_c): ``loops`` (:class:`BorderLoops`), the reach ``tables`` and the
    ``edge`` widths by tool id."""
    kept = getattr(planner, "_border_kept", None)
    if kept is None:
        kept = planner._border_kept = {"loops": BorderLoops(planner.surface), "tables": {},
                                       "edge": {}}
    return kept


def with_border(planner, batch: PlanBatch, genes: dict, place: bool) -> PlanBatch:
    """``batch`` with the border passes its plans need (see the module doc); the same batch
    when none does."""
    if footprint_of(planner.surface).whole or planner.h_c is None:
        return batch
    kept = _kept(planner)
    loops = kept["loops"]
    tool, n, step, _ = planner.decisions(genes)
    vertical = not planner.machine.genes  # 3-axis: no lead / tilt
    cutters = {int(t): planner.tools.cutter(int(t)) for t in np.unique(tool)}
    for t, c in cutters.items():
        if t not in kept["edge"]:
            kept["edge"][t] = edge_widths(loops, c, planner.h_c, vertical)
    w = np.array([kept["edge"][int(t)] for t in tool], float)
    reach = PairReach(cutters, tool, planner.h_c, vertical, kept["tables"])
    widen = np.array([np.ceil(cutters[int(t)].radius / SAMPLE_MM) for t in tool], np.int64)
    offsets = {}
    need = border_levels(loops, batch, w, reach, widen, offsets)
    if not need.any():
        return batch
    last = np.full(n, -1)  # per plan: its last section (zone, pass, feed of the borders)
    np.maximum.at(last, batch.sec_ind, np.arange(len(batch.sec_ind)))
    pieces_of = [[] for _ in range(n)]
    for i in np.flatnonzero(need.any(axis=1)):
        s = int(last[i])
        zone, pass_k, alpha = ((int(batch.sec_zone[s]), int(batch.sec_pass[s]) + 1,
                                float(batch.sec_alpha[s])) if s >= 0 else (0, 0, 0.0))
        for k in range(int(need[i].max()) - 1, -1, -1):  # the innermost first
            uv_k = _offset(loops, offsets, w[i], 2 * k * COVER)[0]
            for idx in loops.stretches(need[i] > k, int(widen[i])):
                uv = uv_k[idx]
                inside = loops.footprint.contains(uv[:, 0], uv[:, 1]) if k else \
                    np.ones(len(uv), bool)
                for a, e in runs(inside):
                    if e - a >= 2:
                        pieces_of[i].append(Piece(uv[a:e], np.zeros((e - a, 3)),
                                                  np.zeros(e - a), zone, pass_k + k, alpha))
    if not any(pieces_of):
        return batch
    border = plan_pieces(planner, n, np.asarray(batch.zones), pieces_of, tool, genes, step,
                         place)
    rows = np.arange(n)
    return merge_batches(n, [(rows, batch), (rows, border)])


def _offset(loops, offsets, w, d):
    """(uv, points) of the loops ``d`` w inward (w (L,) one plan's widths), kept in
    ``offsets`` (plans of one tool share them)."""
    key = (w.tobytes(), d)
    if key not in offsets:
        offsets[key] = loops.offset(d * w)
    return offsets[key]


def _with_corners(s, p, arc, sample_mm, turn_deg=CORNER_DEG):
    """The arc positions ``s`` with the loop's corners (its dense points where it turns by
    more than ``turn_deg``) put in, and samples within a tenth of ``sample_mm`` of one taken
    out: a chord across a concave corner (the notch's inner corners) would cut into the
    hole."""
    d = np.diff(p, axis=0)  # p is closed: its last point is its first
    d /= np.maximum(np.linalg.norm(d, axis=1, keepdims=True), 1e-300)
    cos = np.einsum("ij,ij->i", d, np.roll(d, 1, axis=0))  # at the dense points 0 .. n - 1
    corners = arc[:-1][cos < np.cos(np.radians(turn_deg))]
    if not len(corners):
        return s
    near = np.abs(s[:, None] - corners[None, :]).min(axis=1) < 0.1 * sample_mm
    return np.sort(np.r_[s[~near], corners])

