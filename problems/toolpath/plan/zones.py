"""Zone layouts: the zones of a plan, each with its feed direction, memoized per decision.

A layout depends only on the zoning gene's value and the tool, so it is computed once per
(value, tool) and reused by every individual that shares them (a population's zoned
evaluations mostly hit this memo):

1. zone labels on the parametric mesh: the registered method (``zoning/methods``: single,
   kmeans, amas) with its settings and the gene's value, then the merging of
   ``zoning/merge.py`` (a minimum zone area, then Djebali Eq. 4 merging):
   ``zoning/plan.label_zones``, the function ``plan_zones`` runs too;
2. per zone, the feed direction (``zoning/plan.zone_direction``): the configured angle, or
   Herraz Eq. 3 (the zone's cutting length at h_c minimized over the direction,
   ``zoning/direction.py``) started from the zone's steepest-slope direction, searched to
   and rounded to the ``ALPHA_STEP_DEG`` grid (``plan_zones`` keeps the optimum as found);
3. per zone, the adaptive planes at h_c (``zoning/passes.py``: each plane as far from the
   previous one as the worst point of its pass allows) and the zone's extent across its
   feed (``sections.py`` cuts the planes into sections from the labels);
4. what the plans of the layout need and no gene changes, built with it: the pass-plane
   tables of each zone's direction (``planes.PassGeometry``, memoized per direction) and
   the table cells that can reach each zone (``sections.layout_zone_cells``).
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from .planes import PassGeometry
from .sections import layout_zone_cells
from .zoning.features import check_mesh, mesh_features
from .zoning.merge import MergeSettings
from .zoning.methods import get_method
from .zoning.plan import ALPHA_STEP_DEG, DirectionRule, label_zones, zone_direction
from .zoning.samples import sample_surface
from .zoning.stepover import ScallopTarget

__all__ = ["ZoningSpec", "ZoneLayout", "ZoneLayouts", "ALPHA_STEP_DEG", "DEFAULT_H_C"]

#: mm: Choi's and Djebali's scallop limit (0.01 in), the zones' direction search's target
#: when a plan has none of its own
DEFAULT_H_C = 0.254


@dataclass(frozen=True)
class ZoningSpec:
    """How a plan is zoned: a registered ``method`` with its fixed ``settings`` (the gene, if
    the method has one, comes from the decisions), the parametric ``mesh``, the ``merge``
    post-process (None: the method's zones as they are), the Eq. 4 penalty ``delta_l`` used
    by the merging (mm), the ``seed`` of any randomness, and the direction search: the
    step-over ``model`` of ``zoning/stepover.py`` (profile | circle), the ``scan`` of
    ``zoning/direction.py`` and the XY ``sample_spacing`` of the zones' samples (mm)."""

    method: str = "single"
    settings: dict = field(default_factory=dict)
    mesh: tuple[int, int] = (70, 70)
    merge: MergeSettings | None = field(default_factory=MergeSettings)
    delta_l: float = 40.0
    seed: int = 0
    model: str = "profile"
    scan: int = 12
    sample_spacing: float = 0.25


@dataclass
class ZoneLayout:
    """The zones of one (gene value, tool): ``labels`` (n, m) on the mesh, per zone the feed
    direction ``alpha`` (radians), the adaptive planes ``planes`` at h_c (offsets along the
    zone's cross-feed c, mm) and its extent ``extent`` (lo, hi) along c; ``info`` the
    merging facts."""

    labels: np.ndarray
    alpha: list[float]
    planes: list[np.ndarray]
    extent: list[tuple[float, float]]
    info: dict

    @property
    def count(self) -> int:
        return len(self.alpha)


class ZoneLayouts:
    """Memoized layouts of a surface for one zoning spec (None: a single zone)."""

    def __init__(self, surface, tools, spec: ZoningSpec | None, h_c: float | None,
                 feed_angle: float | None):
        self.surface, self.tools = surface, tools
        self.spec = spec or ZoningSpec()
        self.method = get_method(self.spec.method)
        self.settings = self.method.settings(self.spec.settings)
        self.gene = None if self.method.gene is None else self.method.gene.name
        self.single = self.method.name == "single" and feed_angle is not None
        self.h_c = DEFAULT_H_C if h_c is None else float(h_c)
        self.feed_angle = feed_angle
        self.rule = DirectionRule(model=self.spec.model, scan=self.spec.scan,
                                  feed_angle=feed_angle)
        self.mesh = check_mesh(*self.spec.mesh)
        self._features = self._samples = None
        self._memo: dict = {}
        self._geoms: dict[float, PassGeometry] = {}

    def __getstate__(self):
        """Pickled without the memo, the samples and the pass-plane tables (megabytes a
        worker process rebuilds faster than it unpickles them, and the same numbers either
        way)."""
        state = dict(self.__dict__)
        state.update(_features=None, _samples=None, _memo={}, _geoms={})
        return state

    @property
    def features(self):
        if self._features is None:
            self._features = mesh_features(self.surface, *self.mesh)
        return self._features

    @property
    def samples(self):
        if self._samples is None:
            self._samples = sample_surface(self.surface, self.spec.sample_spacing)
        return self._samples

    def key(self, value):
        """The gene value as the method's setting (an int for an integer gene)."""
        if self.gene is None:
            return None
        return int(round(float(value))) if self.method.gene.integer else round(float(value), 9)

    def keys(self, values) -> np.ndarray:
        """:meth:`key` of many values, as floats (0 without a gene): what groups plans."""
        values = np.asarray(values, float)
        if self.gene is None:
            return np.zeros_like(values)
        return np.rint(values) if self.method.gene.integer else np.round(values, 9)

    def get(self, value, tool: int) -> ZoneLayout:
        """The layout of one gene value and tool index (memoized)."""
        key = (self.key(value), int(tool))
        if key not in self._memo:
            layout = self._layout(key[0], ScallopTarget(self.tools.cutter(tool), self.h_c))
            for z, a in enumerate(layout.alpha):  # step 4 of the module docstring
                layout_zone_cells(self.geometry(a), layout, z)
            self._memo[key] = layout
        return self._memo[key]

    def geometry(self, alpha: float) -> PassGeometry:
        """Pass-plane tables for the feed direction alpha (radians), memoized."""
        key = round(float(np.degrees(alpha)) % 360.0, 9)
        if key not in self._geoms:
            self._geoms[key] = PassGeometry(self.surface, key)
        return self._geoms[key]

    # ---------------------------------------------------------------------------------
    def _labels(self, value, target):
        settings = self.settings.model_dump()
        if self.gene is not None:
            settings[self.method.gene.setting] = value
        return label_zones(self.features, self.samples, self.method, target,
                           seed=self.spec.seed, merge=self.spec.merge,
                           delta_l=self.spec.delta_l, rule=self.rule, **settings)

    def _layout(self, value, target) -> ZoneLayout:
        labels, info = self._labels(value, target)
        cell_of = self.samples.cell(*self.mesh)
        zone_of = labels.ravel()[cell_of]
        alpha, planes, extent = [], [], []
        for z in range(int(labels.max()) + 1):
            mask = labels == z
            sub = self.samples.take(zone_of == z)
            best = zone_direction(sub, self.features, mask, target, self.rule)
            a = best.alpha
            off = -np.sin(a) * sub.x + np.cos(a) * sub.y
            alpha.append(a)
            planes.append(np.asarray(best.passes.s, float))
            extent.append((float(off.min()), float(off.max())))
        return ZoneLayout(labels, alpha, planes, extent, info)
