"""pymoo's GA, DE, CMA-ES and PSO as evoplan ask/tell algorithms.

:class:`PymooAdapter` drives a pymoo algorithm through pymoo's own ask/tell interface
(``algorithm.ask()`` -> evaluate -> ``algorithm.tell(infills=pop)``) and hands the evaluation
to evoplan's engine: :meth:`~PymooAdapter.ask` returns the rows of the infill population that
pymoo would evaluate (those not evaluated yet, pymoo's ``skip_already_evaluated`` rule), and
:meth:`~PymooAdapter.tell` stores the engine's values in the population through pymoo's own
``Evaluator`` (so ``n_eval``, ``CV`` and ``feas`` are kept as pymoo keeps them) before telling
the algorithm. One ask/tell round is one generation (pymoo's ``n_iter``).

pymoo's own termination is switched off (the engine's budget rules); an algorithm that stops by
itself before the budget is spent (CMA-ES converging on ``tolfun``/``tolx``) is restarted from a
fresh seed drawn from the run's generator, so every algorithm uses the budget it is given.
Failed evaluations reach pymoo as ``inf`` as they reach evoplan's algorithms.
"""

from __future__ import annotations

from typing import Literal

import numpy as np
from pydantic import Field
from pymoo.core.problem import Problem
from pymoo.core.termination import NoTermination

from ..algorithms.base import Algorithm
from .base import AdapterConfig, child_seed


class _Told(Problem):
    """A pymoo problem that returns the values the engine computed for the rows asked for."""

    def __init__(self, n_var: int, binary: bool, n_obj: int = 1) -> None:
        super().__init__(n_var=n_var, n_obj=n_obj, xl=0.0, xu=1.0, vtype=bool if binary else float)
        self.values: np.ndarray | None = None

    def _evaluate(self, X, out, *args, **kwargs):
        if self.values is None or len(self.values) != len(X):
            raise RuntimeError("pymoo evaluated rows the adapter did not ask for")
        out["F"] = self.values.reshape(len(X), self.n_obj)


class PymooConfig(AdapterConfig):
    """Settings every pymoo adapter accepts."""

    pop_size: int = Field(20, ge=2, description="population (swarm) size")


class PymooGAConfig(PymooConfig):
    """pymoo GA: real-coded (SBX, polynomial mutation: pymoo's defaults) or binary."""

    name: Literal["pymoo_ga"] = "pymoo_ga"
    eliminate_duplicates: bool = Field(False, description="pymoo's default is True (1.5-2x slower)")


class PymooDEConfig(PymooConfig):
    name: Literal["pymoo_de"] = "pymoo_de"
    representation: Literal["real"] = "real"
    variant: str = Field("DE/rand/1/bin", pattern=r"^DE/(rand|best|target-to-best)/[12]/(bin|exp)$")
    CR: float = Field(0.9, ge=0, le=1)
    F: float | None = Field(None, gt=0, le=2, description="None: pymoo's default, a fixed 0.5 with a variant string")


class PymooCMAESConfig(AdapterConfig):
    name: Literal["pymoo_cmaes"] = "pymoo_cmaes"
    representation: Literal["real"] = "real"
    sigma: float = Field(0.1, gt=0, le=1, description="initial step size on the unit cube")
    pop_size: int | None = Field(None, ge=2, description="None: CMA-ES's 4 + 3 ln d")
    restarts: int = Field(0, ge=0, description="pymoo's IPOP restarts (further restarts: see module)")


class PymooPSOConfig(PymooConfig):
    name: Literal["pymoo_pso"] = "pymoo_pso"
    representation: Literal["real"] = "real"
    pop_size: int = Field(25, ge=2)
    w: float = Field(0.9, ge=0)
    c1: float = Field(2.0, ge=0)
    c2: float = Field(2.0, ge=0)
    adaptive: bool = True


def _ga(config: PymooGAConfig, seed: int):
    from pymoo.algorithms.soo.nonconvex.ga import GA

    return GA(pop_size=config.pop_size, eliminate_duplicates=config.eliminate_duplicates, seed=seed,
              **binary_operators(config))


def binary_operators(config) -> dict:
    """pymoo's binary sampling, single-point crossover and bit-flip mutation, for
    ``representation: binary`` (none for real-coded search: pymoo's SBX and PM defaults)."""
    if config.representation != "binary":
        return {}
    from pymoo.operators.crossover.pntx import SinglePointCrossover
    from pymoo.operators.mutation.bitflip import BitflipMutation
    from pymoo.operators.sampling.rnd import BinaryRandomSampling

    return {"sampling": BinaryRandomSampling(), "crossover": SinglePointCrossover(), "mutation": BitflipMutation()}


def _de(config: PymooDEConfig, seed: int):
    from pymoo.algorithms.soo.nonconvex.de import DE

    extra = {} if config.F is None else {"F": config.F}
    return DE(pop_size=config.pop_size, variant=config.variant, CR=config.CR, seed=seed, **extra)


def _cmaes(config: PymooCMAESConfig, seed: int):
    from pymoo.algorithms.soo.nonconvex.cmaes import CMAES

    return CMAES(sigma=config.sigma, pop_size=config.pop_size, restarts=config.restarts, seed=seed)


def _pso(config: PymooPSOConfig, seed: int):
    from pymoo.algorithms.soo.nonconvex.pso import PSO

    return PSO(pop_size=config.pop_size, w=config.w, c1=config.c1, c2=config.c2, adaptive=config.adaptive, seed=seed)


FACTORIES = {"pymoo_ga": _ga, "pymoo_de": _de, "pymoo_cmaes": _cmaes, "pymoo_pso": _pso}


class PymooAdapter(Algorithm):
    """A pymoo single-objective algorithm behind evoplan's ask/tell contract.

    ``n_bits`` is the width of a search row: ``d`` on the unit cube, the genotype length for
    ``representation: binary``.
    """

    n_obj = 1

    def __init__(self, config: PymooConfig, n_bits: int, rng: np.random.Generator) -> None:
        super().__init__(n_bits, rng)
        self.config = config
        self.name = config.name
        self.problem = _Told(n_bits, config.representation == "binary", self.n_obj)
        self.restarts = 0
        self._start()

    def _start(self) -> None:
        """Set up a fresh pymoo algorithm (at the start, and after it stopped by itself)."""
        self.inner = self.build(child_seed(self.rng))
        self.inner.termination = NoTermination()  # the engine's Termination decides
        self.inner.setup(self.problem)
        self._pop = None
        self._todo = None

    def build(self, seed: int):
        """A fresh pymoo algorithm for this adapter's settings, seeded with ``seed``."""
        return FACTORIES[self.config.name](self.config, seed)

    def ask(self) -> np.ndarray:
        while True:
            if not self.inner.has_next():
                self.restarts += 1
                self._start()
            pop = self.inner.ask()
            if pop is None:  # pymoo asks nothing: it is done
                self.inner.termination.force_termination = True
                continue
            todo = np.array([i for i, ind in enumerate(pop) if "F" not in ind.evaluated], dtype=np.intp)
            if todo.size:
                self._pop, self._todo = pop, todo
                X = pop.get("X")[todo]
                return X.astype(bool) if self.config.representation == "binary" else X.astype(float)
            self.inner.tell(infills=pop)  # nothing to evaluate: let pymoo move on

    def told_values(self, rows: np.ndarray, f: np.ndarray) -> np.ndarray:
        """What pymoo is told for the search ``rows`` the engine scored ``f`` (here: ``f``)."""
        return f

    def population_values(self, pop) -> np.ndarray:
        """The engine's values of a pymoo population (one objective: its F)."""
        return pop.get("F")[:, 0].astype(float)

    def tell(self, f: np.ndarray) -> bool:
        pop, todo = self._pop, self._todo
        f = np.asarray(f, dtype=float)
        self.problem.values = self.told_values(pop.get("X")[todo], f)
        self.inner.evaluator.eval(self.problem, pop[todo], algorithm=self.inner)
        self.problem.values = None
        pop[todo].set("scalar", f)  # the engine's value, kept with the individual
        self.inner.tell(infills=pop)
        current = self.inner.pop if self.inner.pop is not None and len(self.inner.pop) else pop
        self.G, self.f = current.get("X"), self.population_values(current)
        self._pop = self._todo = None
        self.generation += 1
        return True
