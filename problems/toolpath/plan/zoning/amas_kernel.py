"""Numba kernel of one AMAS cycle (``amas.py`` documents the model); plain arrays only.

Cells are flat C-order indices ``c = i*m + j``; zones are ids in ``[0, n*m)``, recycled
through a free stack. A zone holds its size, its count of non-neutral members, its sector
(extremes e1, e2 and gamma = (e2 - e1) mod pi, exact member directions) and a doubly linked
list of its members (``head``, ``nxt``, ``prv``) used to recompute a sector exactly.
"""

from __future__ import annotations

import numpy as np
from numba import njit

__all__ = ["run_cycle", "init_state", "RING"]

PI = np.pi
# The 8-ring in cyclic order N, NE, E, SE, S, SW, W, NW as (di, dj); consecutive cells are
# 4-adjacent. Bits 0, 2, 4, 6 are the 4-neighbours N, E, S, W (the join actions).
RING = np.array([[0, 1], [1, 1], [1, 0], [1, -1], [0, -1], [-1, -1], [-1, 0], [-1, 1]])
_TIE = 1e-12      # leximin: score tolerance
_TIE_SUM = 1e-9   # size-weighted sum: tolerance (sums reach |M| in magnitude)


@njit(cache=True)
def _arc(d, e1):
    """(d - e1) mod pi in [0, pi)."""
    x = (d - e1) % PI
    return 0.0 if x >= PI else x


@njit(cache=True)
def _score(size, gamma, nm, k_cmd, k_lz, printed):
    if printed:
        return min(k_cmd * (1.0 - gamma / PI), k_lz * size / nm)
    return -max(k_cmd * gamma / PI, k_lz * (1.0 - size / nm))


@njit(cache=True)
def _extend(e1, e2, g, cnt, d):
    """Minimal extension of the sector [e1, e2] (gamma g) to contain d: (e1, e2, gamma)."""
    if cnt == 0:
        return d, d, 0.0
    fwd = _arc(d, e1)
    if fwd <= g:
        return e1, e2, g
    if fwd <= g + _arc(e1, d):
        return e1, d, fwd
    return d, e2, _arc(e2, d)


@njit(cache=True)
def _recompute(z, head, nxt, dirs, neu, buf, ze1, ze2, zg, zcnt):
    """Exact minimal sector of zone z: pi minus the largest circular gap of its directions."""
    k = 0
    c = head[z]
    while c >= 0:
        if not neu[c]:
            buf[k] = dirs[c]
            k += 1
        c = nxt[c]
    zcnt[z] = k
    if k == 0:
        zg[z] = 0.0
        return
    v = np.sort(buf[:k])
    best = v[0] + PI - v[k - 1]  # the wrap gap: sector [v0, v_last]
    e1, e2 = v[0], v[k - 1]
    for t in range(k - 1):
        gap = v[t + 1] - v[t]
        if gap > best:
            best, e1, e2 = gap, v[t + 1], v[t]
    ze1[z], ze2[z] = e1, e2
    zg[z] = _arc(e2, e1)


def init_state(dirs, neu):
    """Every mesh its own zone (the paper's start state); the state tuple of ``run_cycle``."""
    nc = dirs.size
    lab = np.arange(nc, dtype=np.int64)
    zcnt = (~neu).astype(np.int64)
    none = -np.ones(nc, np.int64)
    return (lab, np.ones(nc, np.int64), zcnt, dirs.copy(), dirs.copy(), np.zeros(nc),
            lab.copy(), none, none.copy(), np.zeros(nc, np.int64), np.zeros(1, np.int64))


@njit(cache=True)
def _lexcmp(x, nx, y, ny):
    """Leximin compare of two ascending score vectors (+inf padded): 1, 0 (tie) or -1."""
    for t in range(max(nx, ny)):
        a = x[t] if t < nx else np.inf
        b = y[t] if t < ny else np.inf
        if a > b + _TIE:
            return 1
        if b > a + _TIE:
            return -1
    return 0


@njit(cache=True)
def _isort(x, k):
    """Sort x[:k] in place (insertion sort: k <= 10, and cheaper to compile than np.sort)."""
    for t in range(1, k):
        v = x[t]
        u = t - 1
        while u >= 0 and x[u] > v:
            x[u + 1] = x[u]
            u -= 1
        x[u + 1] = v


@njit(cache=True)
def _future(cur, nz, sc_a, sa, ib, sc_b, out):
    """Sorted scores of the situation ``cur[:nz]`` (own zone first) once the own zone has
    score sc_a (dropped if its size sa is 0) and zone ib (-1: a new zone) has score sc_b."""
    k = 0
    if sa > 0:
        out[0] = sc_a
        k = 1
    for t in range(1, nz):
        out[k] = sc_b if t == ib else cur[t]
        k += 1
    if ib < 0:
        out[k] = sc_b
        k += 1
    _isort(out, k)
    return k


@njit(cache=True)
def run_cycle(n, m, dirs, neu, lut, k_cmd, k_lz, printed, leximin, order, unif, state, buf):
    """One cycle: each agent, in ``order``, perceives, decides (NextAct) and acts at once.

    ``unif`` holds one uniform per agent for tie-breaking. Returns the number of actions.
    """
    lab, zsize, zcnt, ze1, ze2, zg, head, nxt, prv, free, nfree = state
    nm = float(n * m)
    zs = np.empty(9, np.int64)
    cur = np.empty(9)
    fut = np.empty((5, 10))
    nfut = np.empty(5, np.int64)
    gain = np.empty(5)
    target = np.empty(5, np.int64)
    best_idx = np.empty(5, np.int64)
    acts = 0
    for step in range(order.size):
        c = order[step]
        i, j = c // m, c % m
        a = lab[c]
        d, isneu = dirs[c], neu[c]
        # perception: own zone first, then the 8-ring; mask of the same-zone ring cells
        zs[0] = a
        nz = 1
        mask = 0
        for r in range(8):
            ii, jj = i + RING[r, 0], j + RING[r, 1]
            if ii < 0 or ii >= n or jj < 0 or jj >= m:
                continue
            z = lab[ii * m + jj]
            if z == a:
                mask |= 1 << r
            else:
                new = True
                for t in range(nz):
                    if zs[t] == z:
                        new = False
                if new:
                    zs[nz] = z
                    nz += 1
        sa = zsize[a]
        if sa > 1 and not lut[mask]:
            continue  # leaving would disconnect the zone: no action allowed
        for t in range(nz):
            cur[t] = _score(zsize[zs[t]], zg[zs[t]], nm, k_cmd, k_lz, printed)
        sc_a_now = cur[0]
        sc_a = _score(sa - 1, zg[a], nm, k_cmd, k_lz, printed)  # kept sector: "probable"
        d_a = (sa - 1) * sc_a - sa * sc_a_now
        # FutureSituation of each action: joins N, E, S, W then create
        na = 0
        for r in range(0, 8, 2):
            ii, jj = i + RING[r, 0], j + RING[r, 1]
            if ii < 0 or ii >= n or jj < 0 or jj >= m:
                continue
            b = lab[ii * m + jj]
            if b == a:
                continue
            ib = 0
            for t in range(nz):
                if zs[t] == b:
                    ib = t
            sb = zsize[b]
            gb = zg[b] if isneu else _extend(ze1[b], ze2[b], zg[b], zcnt[b], d)[2]
            sc_b = _score(sb + 1, gb, nm, k_cmd, k_lz, printed)
            target[na] = b
            if leximin:
                nfut[na] = _future(cur, nz, sc_a, sa - 1, ib, sc_b, fut[na])
            else:
                gain[na] = d_a + (sb + 1) * sc_b - sb * cur[ib]
            na += 1
        if sa > 1:
            sc_new = _score(1, 0.0, nm, k_cmd, k_lz, printed)
            target[na] = -1
            if leximin:
                nfut[na] = _future(cur, nz, sc_a, sa - 1, -1, sc_new, fut[na])
            else:
                gain[na] = d_a + sc_new
            na += 1
        if na == 0:
            continue
        # NextAct: the best future, strictly better than the present; random among ties
        best = 0
        for t in range(1, na):
            if leximin:
                if _lexcmp(fut[t], nfut[t], fut[best], nfut[best]) > 0:
                    best = t
            elif gain[t] > gain[best]:
                best = t
        if leximin:
            _isort(cur, nz)
            if _lexcmp(fut[best], nfut[best], cur, nz) <= 0:
                continue
        elif gain[best] <= _TIE_SUM:
            continue
        nb = 0
        for t in range(na):
            if leximin:
                tie = _lexcmp(fut[t], nfut[t], fut[best], nfut[best]) == 0
            else:
                tie = gain[t] >= gain[best] - _TIE_SUM
            if tie:
                best_idx[nb] = t
                nb += 1
        b = target[best_idx[min(int(unif[step] * nb), nb - 1)]]
        # action: move c from zone a to zone b (a new zone if b < 0), exact state update
        if b < 0:
            nfree[0] -= 1
            b = free[nfree[0]]
            zsize[b] = 0
            zcnt[b] = 0
            zg[b] = 0.0
            head[b] = -1
        p, q = prv[c], nxt[c]
        if p >= 0:
            nxt[p] = q
        else:
            head[a] = q
        if q >= 0:
            prv[q] = p
        zsize[a] -= 1
        if zsize[a] == 0:
            free[nfree[0]] = a
            nfree[0] += 1
        elif not isneu:
            zcnt[a] -= 1
            if zcnt[a] == 0:
                zg[a] = 0.0
            elif d == ze1[a] or d == ze2[a] or zg[a] > 0.5 * PI - 1e-9:
                _recompute(a, head, nxt, dirs, neu, buf, ze1, ze2, zg, zcnt)
        q = head[b]
        prv[c], nxt[c] = -1, q
        if q >= 0:
            prv[q] = c
        head[b] = c
        lab[c] = b
        zsize[b] += 1
        if not isneu:
            if zcnt[b] > 0 and _arc(d, ze1[b]) > zg[b] and zg[b] > PI / 3.0:
                zcnt[b] += 1
                _recompute(b, head, nxt, dirs, neu, buf, ze1, ze2, zg, zcnt)
            else:
                ze1[b], ze2[b], zg[b] = _extend(ze1[b], ze2[b], zg[b], zcnt[b], d)
                zcnt[b] += 1
        acts += 1
    return acts
