"""The toolpath simulator: parameter sets in, CC patterns and every raw criterion out.

A parameter set is one row of X (n, 5): tool index into the database (rounded), step-over
(% of D, spacing in XY between the planes), lead and tilt (degrees, relative to the surface
normal in the travel frame: lead about the cross-feed axis, then tilt about the feed, the
axis leaning to the left of the travel direction), maximum discretization step (mm).

Criteria (each (n,), see :data:`CRITERIA`), per toolpath:

- ``cc_count`` CC points; ``n_passes`` passes.
- ``chord_error_mean`` / ``chord_error_max``: true curve-to-chord distance per segment
  (``chord.py``; not Fountas Eq. 3 as printed).
- ``r_eff``: 5-axis effective radius (``Cutter.effective_radius_lead_tilt``; inf for a flat
  bottom).
- ``scallop_max`` / ``scallop_mean``: material left at the middle of each gap between
  adjacent passes, from the projected cutter profile, the surface spacing of the CC points
  across the feed and the normal curvature across the feed (``scallop.py`` on the cutter's
  silhouette, ``Cutter.swept_profile``), per CC point.
- ``gouge_max``: depth cut below the surface there (profile flatter than a concave section).
- ``undercut_max``: for cutters with a sharp rim (flat-end, ``Cutter.sharp_rim``), the
  scallop (left by the rim and the inclined bottom: Fountas' h_u after Bedi et al. 1996);
  0 for the other tools.
- ``machining_error`` / ``machining_error_mean``: combined surface machining error at a CC
  point (Fountas Fig. 1) = chord error (larger of its two segments) + scallop + gouge; max
  and mean over the CC points.
- ``cutting_length``, ``link_length``, ``path_length`` (mm), ``machining_time`` (min at the
  feed rate) (``length.py``).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .clpath import CLPath
from .plan.length import cutting_length, link_length, machining_time, travel_order
from .plan.pattern import PassGeometry, PatternBatch, cc_pattern_batch
from .criteria.scallop import gap_heights
from .geometry.surface import Surface, normal_curvature, unit_normal
from .tools import ToolDatabase

__all__ = ["ToolpathSimulator", "CCPattern", "CRITERIA"]

CRITERIA = (
    "cc_count", "n_passes", "chord_error_mean", "chord_error_max", "r_eff",
    "scallop_max", "scallop_mean", "gouge_max", "undercut_max",
    "machining_error", "machining_error_mean",
    "cutting_length", "link_length", "path_length", "machining_time",
)


@dataclass
class CCPattern:
    """One toolpath in machining order: points (m, 3) CC points, normals (m, 3) surface
    normals, pass_index (m,), tangent (m, 3) unit travel direction, axis (m, 3) unit tool
    axis, tool_tip (m, 3) centre of the cutter's end (the APT tool-tip point),
    uv (m, 2) surface parameters, chord_error (m,), scallop (m,) signed material height in
    the gap after the point's pass (negative: gouge)."""

    points: np.ndarray
    normals: np.ndarray
    pass_index: np.ndarray
    tangent: np.ndarray
    axis: np.ndarray
    tool_tip: np.ndarray
    uv: np.ndarray
    chord_error: np.ndarray
    scallop: np.ndarray


class ToolpathSimulator:
    """Surface + tool database + strategy settings -> batched criteria.

    tolerance: cut tolerance (mm); feed_rate (mm/min); feed_angle (deg from +X);
    allowance: finishing stock (mm), the height left where no pass reaches.
    """

    def __init__(self, surface: Surface, tools: ToolDatabase, feed_angle: float = 0.0,
                 tolerance: float = 0.01, feed_rate: float = 1000.0, allowance: float = 0.5,
                 max_rounds: int = 6):
        self.surface = surface
        self.tools = tools
        self.tolerance = float(tolerance)
        self.feed_rate = float(feed_rate)
        self.allowance = float(allowance)
        self.max_rounds = int(max_rounds)
        self.geometry = PassGeometry(surface, feed_angle)
        self._sharp_rim = np.array([c.sharp_rim for c in tools.cutters], dtype=bool)

    def decode(self, X) -> dict:
        """Columns of X (n, 5) to per-row arrays: tool index, R, sharp_rim (the cutter's),
        delta (XY step-over, mm), lead, tilt (radians), step (mm)."""
        X = np.atleast_2d(np.asarray(X, float))
        ti = np.clip(np.rint(X[:, 0]).astype(int), 0, len(self.tools) - 1)
        R = self.tools.R[ti]
        return dict(tool=ti, R=R, sharp_rim=self._sharp_rim[ti], delta=X[:, 1] / 100 * 2 * R,
                    lead=np.radians(X[:, 2]), tilt=np.radians(X[:, 3]), step=X[:, 4])

    def run(self, X):
        """(PatternBatch, per-point arrays, criteria dict) for X (n, 5)."""
        g = self.decode(X)
        pb = cc_pattern_batch(self.geometry, g["delta"], g["step"], self.tolerance,
                              self.max_rounds)
        n = pb.n
        jet = self.surface.jet(pb.u, pb.v, order=2)
        nrm = unit_normal(jet, self.surface.normal_sign)
        c3 = np.array([*self.geometry.c, 0.0])
        nc = nrm @ c3
        bvec = c3 - nc[:, None] * nrm
        bc = np.linalg.norm(bvec, axis=-1)  # = b.c, b the unit cross-feed tangent
        kappa = normal_curvature(jet, bvec / bc[:, None], self.surface.normal_sign)
        pt_pass = pb.pt_pass
        ind = pb.pass_ind[pt_pass]
        k = pb.pass_k[pt_pass]
        n_int = np.bincount(pb.pass_ind, minlength=n) - 1
        last = k == n_int[ind]
        direction = np.where(last, -1, 1)
        sigma = np.where(k % 2 == 0, 1, -1)
        w = pb.pass_spacing[pt_pass] / bc
        tables = self._swept_profiles(g["tool"], g["lead"], g["tilt"])
        h = gap_heights(tables, ind, sigma * direction, w, kappa, self.allowance)
        h = np.where(n_int[ind] > 0, h, 0.0)
        scallop = np.maximum(h, 0.0)
        gouge = np.maximum(-h, 0.0)
        err = pb.chord + scallop + gouge
        crit = self._reduce(pb, ind, scallop, gouge, err)
        crit["r_eff"] = self._effective_radii(g["tool"], g["lead"], g["tilt"])
        crit["undercut_max"] = np.where(g["sharp_rim"], crit["scallop_max"], 0.0)
        crit["cutting_length"] = cutting_length(pb)
        crit["link_length"] = link_length(pb)
        crit["path_length"] = crit["cutting_length"] + crit["link_length"]
        crit["machining_time"] = machining_time(crit["path_length"], self.feed_rate)
        point = dict(normal=nrm, h=h, kappa=kappa, w=w, sigma=sigma)
        return pb, point, {name: crit[name] for name in CRITERIA}

    def _effective_radii(self, ti, lead, tilt):
        """R_eff of every row from its tool's cutter (``Cutter.effective_radius_lead_tilt``)."""
        out = np.empty(len(ti))
        for t in np.unique(ti):
            rows = np.flatnonzero(ti == t)
            out[rows] = self.tools.cutter(t).effective_radius_lead_tilt(lead[rows], tilt[rows])
        return out

    def _swept_profiles(self, ti, lead, tilt):
        """Profile tables (x, z, reach) of every row (rows 2i, 2i + 1 for row i of X): each
        tool's cutter gives the tables of its rows (``Cutter.swept_profile``); a shorter
        table is padded with its last point (the profile is vertical beyond its reach)."""
        parts = []
        for t in np.unique(ti):
            rows = np.flatnonzero(ti == t)
            parts.append((rows, self.tools.cutter(t).swept_profile(lead[rows], tilt[rows])))
        m = max(p[1][0].shape[1] for p in parts)
        x = np.empty((2 * len(ti), m))
        z = np.empty((2 * len(ti), m))
        reach = np.empty(2 * len(ti))
        for rows, (xt, zt, rt) in parts:
            at = np.stack([2 * rows, 2 * rows + 1], axis=1).ravel()
            pad = ((0, 0), (0, m - xt.shape[1]))
            x[at], z[at], reach[at] = np.pad(xt, pad, mode="edge"), np.pad(zt, pad, mode="edge"), rt
        return x, z, reach

    @staticmethod
    def _reduce(pb: PatternBatch, ind, scallop, gouge, err) -> dict:
        n = pb.n
        counts = np.bincount(ind, minlength=n)
        starts = np.cumsum(counts) - counts
        seg_ind = pb.pass_ind[pb.seg_pass]
        seg_counts = np.bincount(seg_ind, minlength=n)
        seg_starts = np.cumsum(seg_counts) - seg_counts
        return {
            "cc_count": counts.astype(float),
            "n_passes": np.bincount(pb.pass_ind, minlength=n).astype(float),
            "chord_error_mean": np.bincount(seg_ind, pb.seg_err, n) / seg_counts,
            "chord_error_max": np.maximum.reduceat(pb.seg_err, seg_starts),
            "scallop_max": np.maximum.reduceat(scallop, starts),
            "scallop_mean": np.bincount(ind, scallop, n) / counts,
            "gouge_max": np.maximum.reduceat(gouge, starts),
            "machining_error": np.maximum.reduceat(err, starts),
            "machining_error_mean": np.bincount(ind, err, n) / counts,
        }

    def criteria(self, X) -> dict:
        """Every raw criterion, each (n,), for X (n, 5) (an empty batch gives empty arrays)."""
        if np.asarray(X).size == 0:
            return {name: np.zeros(0) for name in CRITERIA}
        return self.run(X)[2]

    def pattern(self, x) -> CCPattern:
        """The CC pattern of ONE parameter set x (5,), in machining order."""
        x = np.asarray(x, float).reshape(1, -1)
        pb, pt, _ = self.run(x)
        g = self.decode(x)
        order = travel_order(pb, 0)
        nrm = pt["normal"][order]
        c3 = np.array([*self.geometry.c, 0.0])
        t_plus = np.cross(c3, nrm)
        t_plus /= np.linalg.norm(t_plus, axis=-1, keepdims=True)
        sigma = pt["sigma"][order][:, None]
        t = sigma * t_plus
        b = np.cross(nrm, t)
        lead, tilt = g["lead"][0], g["tilt"][0]
        axis = (np.sin(lead) * t + np.cos(lead) * np.sin(tilt) * b
                + np.cos(lead) * np.cos(tilt) * nrm)
        points = pb.p[order]
        tip = self.tools.cutter(g["tool"][0]).cc_to_tip(points, nrm, axis)
        return CCPattern(points=points, normals=nrm, pass_index=pb.pass_k[pb.pt_pass][order],
                         tangent=t, axis=axis, tool_tip=tip,
                         uv=np.stack([pb.u, pb.v], axis=1)[order],
                         chord_error=pb.chord[order], scallop=pt["h"][order])

    def cl_path(self, x) -> CLPath:
        """The toolpath of ONE parameter set x (5,) as the machine runs it: tool tips and axes
        in machining order, every pass and link one feed motion (as the APT program has it)."""
        x = np.asarray(x, float).reshape(-1)
        cc = self.pattern(x)
        tool = self.tools.tools[int(np.clip(np.rint(x[0]), 0, len(self.tools) - 1))]
        return CLPath(cc.tool_tip, cc.axis, tool.diameter, tool.corner_radius,
                      pass_index=cc.pass_index, feed_rate=self.feed_rate)
