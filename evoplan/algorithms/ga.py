"""The plain genetic algorithm of Fountas et al. ("Weighted objective evaluation utility").

One generation: Eq. 10 exponential ranked fitness -> selection into a mating pool -> crossover
-> mutation -> elitism. Every named piece is configurable; the defaults are the paper's
(roulette, single-point crossover, single-point mutation, a small elite).
"""

from __future__ import annotations

import math
from typing import Literal

import numpy as np
from pydantic import AliasChoices, BaseModel, ConfigDict, Field, model_validator

from ..operators import crossover, elitism, fitness, mutation, selection
from ..operators.breeding import breed, breed_ranked_single_point
from ..operators.ranking import stable_order
from .base import Algorithm


class _Strict(BaseModel):
    model_config = ConfigDict(extra="forbid", frozen=True, allow_inf_nan=False)


class FitnessConfig(_Strict):
    """Eq. 10 scaling: normalization of the objective first (see operators.fitness)."""

    normalize: Literal["rank", "minmax"] = "rank"
    pressure: float = Field(2.0, gt=0)


class SelectionConfig(_Strict):
    kind: Literal["roulette", "tournament"] = "roulette"
    size: int = Field(2, ge=2, description="tournament size")


class CrossoverConfig(_Strict):
    kind: Literal["single_point", "two_point"] = "single_point"
    rate: float = Field(0.9, ge=0, le=1)


class MutationConfig(_Strict):
    kind: Literal["single_point", "per_bit"] = "single_point"
    rate: float = Field(0.5, ge=0, le=1, description="per individual (single_point) or per bit")


class GAConfig(_Strict):
    name: Literal["ga"] = "ga"
    population: int = Field(20, ge=2, validation_alias=AliasChoices("population", "pop_size"),
                            description="host population size (pymoo's name pop_size is accepted too)")
    elitism: int = Field(1, ge=0, description="fittest individuals copied unchanged")
    fitness: FitnessConfig = FitnessConfig()
    selection: SelectionConfig = SelectionConfig()
    crossover: CrossoverConfig = CrossoverConfig()
    mutation: MutationConfig = MutationConfig()

    @model_validator(mode="before")
    @classmethod
    def _one_population_name(cls, data):
        if isinstance(data, dict) and "population" in data and "pop_size" in data:
            raise ValueError(f"give population or pop_size, not both ({data['population']} and {data['pop_size']})")
        return data

    @model_validator(mode="after")
    def _elite_below_population(self):
        if self.elitism >= self.population:
            raise ValueError(f"elitism ({self.elitism}) must be below population ({self.population})")
        return self


# what each kind draws (crossover: one segment a pair; mutation: the flips of each child)
CROSSOVERS = {"single_point": crossover.single_point_segments, "two_point": crossover.two_point_segments}
MUTATIONS = {"single_point": mutation.single_point_loci, "per_bit": mutation.per_bit_mask}


class GA(Algorithm):
    """Generational GA over binary genotypes with Eq. 10 fitness and elitism."""

    name = "ga"

    def __init__(self, config: GAConfig, n_bits: int, rng: np.random.Generator) -> None:
        super().__init__(n_bits, rng)
        self.config = config
        self._pending_elite = np.empty(0, dtype=np.intp)
        self._next: np.ndarray | None = None  # the next population when the breeding pass made it whole

    @property
    def _paper_operators(self) -> bool:
        """Rank Eq. 10, roulette, single-point crossover and mutation (what
        :func:`~evoplan.operators.breeding.breed_ranked_single_point` breeds in one pass)."""
        c = self.config
        return (c.fitness.normalize == "rank" and c.selection.kind == "roulette"
                and c.crossover.kind == "single_point" and c.mutation.kind == "single_point")

    # -- one generation of host evolution, as named steps ------------------------------------
    def scaled_fitness(self, f: np.ndarray, order: np.ndarray | None = None) -> np.ndarray:
        c = self.config.fitness
        return fitness.exponential_fitness(f, c.normalize, c.pressure, order)

    def select(self, fit: np.ndarray, n: int) -> np.ndarray:
        c = self.config.selection
        if c.kind == "tournament":
            return selection.tournament(fit, n, self.rng, c.size)
        return selection.roulette(fit, n, self.rng)

    def offspring(self, order: np.ndarray | None = None) -> np.ndarray:
        """Mating pool -> crossover -> mutation: ``population - elitism`` children (``order``:
        the population's stable sort when every value is finite)."""
        cfg = self.config
        n_children = cfg.population - cfg.elitism
        if order is not None and self._paper_operators:  # the defaults: one compiled pass
            elite = self._pending_elite
            nxt = breed_ranked_single_point(self.G, self.f, order, cfg.fitness.pressure, cfg.crossover.rate,
                                            cfg.mutation.rate, n_children, self.rng, elite)
            if nxt is not None:  # the next population, the elite's rows first
                self._next = nxt
                return nxt[elite.size:]
        n_pairs = (n_children + 1) // 2
        parents = self.select(self.scaled_fitness(self.f, order), 2 * n_pairs)
        L = self.G.shape[1]
        lo, hi = CROSSOVERS[cfg.crossover.kind](n_pairs, L, cfg.crossover.rate, self.rng)
        flips = MUTATIONS[cfg.mutation.kind](n_children, L, cfg.mutation.rate, self.rng)
        return breed(self.G, parents[:n_pairs], parents[n_pairs:], lo, hi, flips, n_children)

    # -- ask / tell ----------------------------------------------------------------------------
    def ask(self) -> np.ndarray:
        if self.generation < 0:
            self._batch = self.rng.random((self.config.population, self.n_bits)) < 0.5
        else:
            f = self.f  # one stable sort gives the elite and the ranks (every value finite: a
            # finite sum says so in one pass; a sum that overflows takes the general path, which
            # gives the same numbers)
            order = stable_order(f, finite=True) if math.isfinite(np.add.reduce(f)) else None
            k = self.config.elitism
            self._pending_elite = order[:k] if order is not None else elitism.elite_indices(f, k)
            self._batch = self.offspring(order)
        return self._batch

    def tell(self, f: np.ndarray) -> bool:
        f = np.asarray(f, dtype=float)
        if self.generation < 0:
            self.G, self.f = self._batch, f
        else:
            keep = self._pending_elite
            self.G = np.concatenate([self.G[keep], self._batch]) if self._next is None else self._next
            self.f = np.concatenate([self.f[keep], f])
        self._batch = self._next = None
        return self.hosts_evaluated()

    def hosts_evaluated(self) -> bool:
        """Hook after the hosts' batch is told; the plain GA ends its generation here."""
        self.generation += 1
        return True
