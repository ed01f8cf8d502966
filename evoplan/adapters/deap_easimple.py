"""DEAP's ``eaSimple`` as an evoplan ask/tell algorithm.

One generation of :func:`deap.algorithms.eaSimple` is ``select -> varAnd -> evaluate the
individuals whose fitness is invalid -> replace the population by the offspring``. The adapter
runs exactly those DEAP calls (``toolbox.select``, :func:`deap.algorithms.varAnd`) and stops at
the evaluation: :meth:`DeapEaSimple.ask` returns the invalid individuals as one batch for the
engine to evaluate and count, :meth:`DeapEaSimple.tell` sets their fitness and replaces the
population. With the same random state the populations are those ``eaSimple`` itself makes
(``tests/study/test_adapters.py`` checks it). Like ``eaSimple``, only changed individuals are
re-evaluated, and the population is not elitist (the engine keeps the best ever evaluated).

DEAP draws from the module-level :mod:`random` functions. The adapter owns a private
``random.Random`` (seeded from the run's generator) and puts it in place of the ``random``
name inside DEAP's modules around each DEAP call, so a run is reproducible whatever else draws
from the global generator meanwhile (a Dask worker's own threads do: swapping the global state
instead made 2 of 330 DEAP cells differ between backends). Two DEAP adapters must not run at
once in threads of one process: evoplan's pools use one thread per worker. Individuals are plain list subclasses defined here, not classes made by
``deap.creator`` at run time (those do not pickle across processes).
"""

from __future__ import annotations

import random
from contextlib import contextmanager

import numpy as np
from deap import algorithms, base, tools
from deap.tools import crossover, mutation, selection

from ..algorithms.base import Algorithm
from .base import child_seed
from .deap_config import DeapEaSimpleConfig


class FitnessMin(base.Fitness):
    """One objective, minimized."""

    weights = (-1.0,)


class Individual(list):
    """A DEAP individual: a list of genes with a ``fitness`` attribute."""

    def __init__(self, genes=()) -> None:
        super().__init__(genes)
        self.fitness = FitnessMin()


DEAP_MODULES = (algorithms, crossover, mutation, selection)  # each does ``import random``


def make_toolbox(config: DeapEaSimpleConfig, length: int, rnd=random) -> base.Toolbox:
    """DEAP's toolbox for ``config`` over genomes of ``length`` genes (bits or unit-cube reals);
    ``rnd`` draws the initial genes (the :mod:`random` module or a ``random.Random``)."""
    tb = base.Toolbox()
    indpb = config.indpb or 1.0 / length
    if config.representation == "binary":
        tb.register("gene", rnd.randint, 0, 1)
        tb.register("mate", tools.cxOnePoint if config.crossover == "one_point" else tools.cxTwoPoint)
        tb.register("mutate", tools.mutFlipBit, indpb=indpb)
    else:
        tb.register("gene", rnd.random)
        tb.register("mate", tools.cxSimulatedBinaryBounded, eta=config.eta_crossover, low=0.0, up=1.0)
        tb.register("mutate", tools.mutPolynomialBounded, eta=config.eta_mutation, low=0.0, up=1.0, indpb=indpb)
    tb.register("individual", tools.initRepeat, Individual, tb.gene, length)
    tb.register("population", tools.initRepeat, list, tb.individual)
    tb.register("select", tools.selTournament, tournsize=config.tournament)
    return tb


class DeapEaSimple(Algorithm):
    """``eaSimple`` split at its evaluation step (see the module docstring)."""

    name = "deap_easimple"

    def __init__(self, config: DeapEaSimpleConfig, n_bits: int, rng: np.random.Generator) -> None:
        super().__init__(n_bits, rng)
        self.config = config
        self._random = random.Random(child_seed(rng))
        self.toolbox = make_toolbox(config, n_bits, self._random)
        self.population_: list[Individual] = []
        self._offspring: list[Individual] | None = None
        self._invalid: list[Individual] = []

    @contextmanager
    def _deap_random(self):
        """DEAP's modules draw from this run's private generator for the duration of a call."""
        saved = [m.random for m in DEAP_MODULES]
        for m in DEAP_MODULES:
            m.random = self._random
        try:
            yield
        finally:
            for m, r in zip(DEAP_MODULES, saved):
                m.random = r

    def ask(self) -> np.ndarray:
        with self._deap_random():
            if self.generation < 0:
                self._offspring = self.toolbox.population(n=self.config.population)
            else:
                while True:  # a generation where nothing changed evaluates nothing: go on
                    offspring = self.toolbox.select(self.population_, len(self.population_))
                    offspring = algorithms.varAnd(offspring, self.toolbox, self.config.cxpb, self.config.mutpb)
                    if any(not ind.fitness.valid for ind in offspring):
                        break
                    self.population_[:] = offspring
                self._offspring = offspring
        self._invalid = [ind for ind in self._offspring if not ind.fitness.valid]
        rows = np.array(self._invalid, dtype=float)
        return rows.astype(bool) if self.config.representation == "binary" else rows

    def tell(self, f: np.ndarray) -> bool:
        for ind, value in zip(self._invalid, np.asarray(f, dtype=float)):
            ind.fitness.values = (float(value),)
        self.population_[:] = self._offspring
        self._offspring, self._invalid = None, []
        self.G = np.array(self.population_, dtype=float)
        self.f = np.array([ind.fitness.values[0] for ind in self.population_])
        self.generation += 1
        return True
