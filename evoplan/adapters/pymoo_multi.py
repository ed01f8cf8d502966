"""pymoo's NSGA-II, NSGA-III and SMS-EMOA as evoplan ask/tell algorithms (several objectives).

The same adapter as :class:`~evoplan.adapters.pymoo_algorithms.PymooAdapter` (pymoo's own
ask/tell, the engine evaluates and counts every row), with two differences:

- pymoo is told the objective *vectors*: the engine hands an algorithm one value per row (the
  weighted sum of :mod:`evoplan.multiobjective`), so the vectors are read from the ledger the
  :class:`~evoplan.multiobjective.MultiEvaluator` fills, keyed by the decoded rows;
- the adapter keeps the archive of every non-dominated point evaluated so far (``front_X``
  phenotypes, ``front_F`` objective vectors) and its hypervolume after every generation
  (``hypervolumes``), against a reference point fixed at the first generation (the worst value
  of each objective plus 10 % of its range) unless ``ref_point`` is given.

A multi-objective VEGA is not offered: VEGA's virus fitness (Fountas Eq. 11-12) is the gain
``f(host) - f(infected host)`` of ONE objective, and its life and infection-rate rules steer by
its sign; with several objectives that gain is only defined after a scalarization, which is
exactly the single-objective VEGA on Eq. 9. A dominance-based virus fitness is not in the
papers, and evoplan does not invent one.
"""

from __future__ import annotations

from typing import Literal

import numpy as np
from pydantic import Field

from ..multiobjective import Ledger, hypervolume, nondominated, reference_point
from .pymoo_algorithms import PymooAdapter, PymooConfig, binary_operators


class PymooMultiConfig(PymooConfig):
    """Settings every multi-objective pymoo adapter accepts."""

    representation: Literal["real", "binary"] = "real"
    ref_point: list[float] | None = Field(None, description="hypervolume reference point; "
                                                            "None: fixed from the first generation")


class NSGA2Config(PymooMultiConfig):
    name: Literal["nsga2"] = "nsga2"


class NSGA3Config(PymooMultiConfig):
    name: Literal["nsga3"] = "nsga3"
    partitions: int = Field(12, ge=1, description="Das-Dennis reference directions: partitions per objective")


class SMSEMOAConfig(PymooMultiConfig):
    name: Literal["sms_emoa"] = "sms_emoa"


def _nsga2(config: NSGA2Config, seed: int, n_obj: int):
    from pymoo.algorithms.moo.nsga2 import NSGA2

    return NSGA2(pop_size=config.pop_size, seed=seed, **binary_operators(config))


def _nsga3(config: NSGA3Config, seed: int, n_obj: int):
    from pymoo.algorithms.moo.nsga3 import NSGA3
    from pymoo.util.ref_dirs import get_reference_directions

    dirs = get_reference_directions("das-dennis", n_obj, n_partitions=config.partitions)
    return NSGA3(ref_dirs=dirs, pop_size=max(config.pop_size, len(dirs)), seed=seed, **binary_operators(config))


def _sms_emoa(config: SMSEMOAConfig, seed: int, n_obj: int):
    from pymoo.algorithms.moo.sms import SMSEMOA

    return SMSEMOA(pop_size=config.pop_size, seed=seed, **binary_operators(config))


MULTI_FACTORIES = {"nsga2": _nsga2, "nsga3": _nsga3, "sms_emoa": _sms_emoa}


class ModuleFunction:
    """A module-level function held by module and name, so that it pickles.

    pymoo 0.6.2 decorates the tournament comparators of NSGA-III and SMS-EMOA with a wrapper
    that pickle cannot find by name; a checkpoint holds the algorithm, so the adapter keeps
    this stand-in instead.
    """

    def __init__(self, module: str, name: str) -> None:
        self.module, self.name = module, name

    def __call__(self, *args, **kwargs):
        import importlib

        return getattr(importlib.import_module(self.module), self.name)(*args, **kwargs)


def picklable_comparator(algorithm) -> None:
    """Replace an unpicklable tournament comparator of ``algorithm`` by a :class:`ModuleFunction`."""
    import sys

    selection = getattr(getattr(algorithm, "mating", None), "selection", None)
    func = getattr(selection, "func_comp", None)
    if func is None or "<locals>" not in getattr(func, "__qualname__", ""):
        return
    module = type(algorithm).__module__
    names = [k for k, v in vars(sys.modules[module]).items() if v is func]
    if names:
        selection.func_comp = ModuleFunction(module, names[0])


class PymooMultiAdapter(PymooAdapter):
    """A pymoo multi-objective algorithm; see the module docstring."""

    multi_objective = True

    def __init__(self, config: PymooMultiConfig, n_bits: int, rng: np.random.Generator, n_obj: int = 2) -> None:
        if config.ref_point is not None and len(config.ref_point) != n_obj:
            raise ValueError(f"ref_point: expected {n_obj} values (one per objective), got {len(config.ref_point)}")
        self.n_obj = int(n_obj)
        self.ledger = Ledger()
        self.decode = None  # set by evoplan.multiobjective.connect when a run starts or resumes
        self.ref_point = None if config.ref_point is None else np.asarray(config.ref_point, dtype=float)
        self.front_X = np.zeros((0, n_bits))
        self.front_F = np.zeros((0, n_obj))
        self.hypervolumes: list[float] = []
        super().__init__(config, n_bits, rng)

    def build(self, seed: int):
        algorithm = MULTI_FACTORIES[self.config.name](self.config, seed, self.n_obj)
        picklable_comparator(algorithm)
        return algorithm

    def __getstate__(self):
        return {**self.__dict__, "decode": None}  # reconnected when the run resumes

    def told_values(self, rows: np.ndarray, f: np.ndarray) -> np.ndarray:
        if self.decode is None:
            raise RuntimeError("the multi-objective adapter is not connected to its evaluator")
        X = self.decode(rows.astype(bool) if self.config.representation == "binary" else rows.astype(float))
        F = self.ledger.lookup(X, self.n_obj)
        F[~np.isfinite(f)] = np.inf  # a failure is a failure in every objective
        self._archive(X, F)
        return F

    def population_values(self, pop) -> np.ndarray:
        return pop.get("scalar").astype(float)

    def _archive(self, X: np.ndarray, F: np.ndarray) -> None:
        if self.ref_point is None:
            self.ref_point = reference_point(F)
        allX = np.vstack([self.front_X, X])
        allF = np.vstack([self.front_F, F])
        _, first = np.unique(allX, axis=0, return_index=True)
        keep = np.zeros(len(allX), dtype=bool)
        keep[first] = True
        keep &= nondominated(allF)
        self.front_X, self.front_F = allX[keep], allF[keep]

    def tell(self, f: np.ndarray) -> bool:
        ended = super().tell(f)
        ref = self.ref_point
        self.hypervolumes.append(hypervolume(self.front_F, ref) if ref is not None else 0.0)
        return ended
