"""The virus-evolutionary GA (VEGA) of Fountas et al., after Kubota et al. (1996).

Hosts evolve as in :class:`~evoplan.algorithms.ga.GA`; a population of viruses (substrings of
hosts) infects them every ``infect_every`` generations. Each rule is a named method and a
setting of ``virus``:

1. **Creation** (:meth:`create_viruses`, Fountas "targeted and random"): a share
   ``creation.elite_share`` of new viruses is transduced from the elite hosts (the best
   ``creation.elite_pool`` of the population), the rest from hosts drawn uniformly among the
   others. Kubota's purely random creation is ``elite_share: 0``.
2. **Infection** (:meth:`infections`, Kubota): virus ``i`` infects each host with probability
   ``rate_i`` (reverse transcription, Fig. 3b), every ``infect_every`` generations (Fountas:
   "in every several generations"; default 1, every generation). All infections of a
   generation are made on the hosts as they were after the GA step. An infection whose virus
   carries the host's own bits leaves the host unchanged: its gain is 0 without evaluating
   it, and it is not asked for (:meth:`begin_infection`). The others are evaluated in one
   batch and count in the budget.
3. **Replacement** (:meth:`end_infection`, a choice the papers leave open): each infected host
   takes its best infected version, either only if it is better (``replacement: improve``,
   the default: elitist, no host is made worse) or always (``always``, Kubota's vertical
   transmission of harmful viruses as well).
4. **Virus fitness** (Eq. 11-12): ``fitvirus_ij = f(host_j) - f(infected host_j)`` (an
   objective to minimize, so a gain is positive), summed over the hosts each virus infected.
5. **Life / infectivity force** (:meth:`update_viruses`): Kubota's
   ``life_i(t+1) = r * life_i(t) + fitvirus_i``, with the life reduction rate ``r`` being
   Fountas' infectivity force parameter (Table 1: 0.001 ... 1.0). What follows is
   ``life_rule``:

   - ``fountas`` (default): if ``life`` fell since the previous generation, or turned
     negative, the virus is replaced by a fresh transduction; if it rose, the virus does a
     partial transduction (Fig. 3c) from the infected host it improved most;
   - ``kubota``: a virus whose life is negative is replaced; every other virus that infected
     a host this generation does a partial transduction (from the infected host it improved
     most, or harmed least).

   A partial transduction adds ``growth`` loci, up to ``max_length`` (``VrsLgth``); a virus
   at the cap slides its window instead. Under ``fountas`` at ``r = 0.001`` a virus rarely
   rises twice in a row, so the cap rarely binds; ``kubota`` lets a virus that does no harm
   grow every generation it infects.
6. **Infection rate** (Kubota's self-adaptation, Fountas' bounds): ``rate_i *= 1 + step``
   after a gain, ``1 - step`` after a loss, clipped to ``[min_infection_rate,
   max_infection_rate]`` with ``0 <= min <= 0.5 <= max <= 1``; a new virus starts at
   ``infection_rate``, a renewed one too unless ``renewal_keeps_rate`` (then the adapted
   rate of the virus it replaces carries over).

Counters (plain integers and arrays): ``infections_made``, ``infections_unchanged`` (the
host-copy infections not evaluated), ``age`` of each virus in generations and ``longest``,
the longest virus there has been.
"""

from __future__ import annotations

from typing import Literal

import numpy as np
from pydantic import Field, model_validator

from ..compiled import use_compiled
from ..operators import viral
from ..operators.viral_outcome import infect_pairs, infection_outcome
from ..operators.ranking import stable_order
from .ga import GA, GAConfig, _Strict


class CreationConfig(_Strict):
    elite_share: float = Field(0.5, ge=0, le=1, description="share of viruses taken from elite hosts")
    elite_pool: int = Field(2, ge=1, description="how many of the best hosts count as elite")


class VirusConfig(_Strict):
    count: int = Field(7, ge=1, description="virus population size (Table 1: 2, 5, 7, 10)")
    max_length: int = Field(40, ge=1, description="VrsLgth, longest virus in bits (Table 1: 10..40)")
    initial_length: int | None = Field(
        None, ge=1, description="longest freshly transduced virus; default max_length // 4"
    )
    growth: int = Field(1, ge=1, description="loci a partial transduction adds")
    infectivity_force: float = Field(
        0.001, ge=0, le=1, description="life reduction rate r (Table 1: 0.001, 0.01, 0.1, 1.0)"
    )
    infection_rate: float = Field(0.7, ge=0, le=1, description="initial rate (Table 1: 0.1..1.0)")
    min_infection_rate: float = Field(0.1, ge=0, le=0.5)
    max_infection_rate: float = Field(1.0, ge=0.5, le=1)
    rate_step: float = Field(0.1, ge=0, lt=1, description="Kubota's adaptation step a")
    replacement: Literal["improve", "always"] = "improve"
    life_rule: Literal["fountas", "kubota"] = Field(
        "fountas", description="fountas: renew when life falls, grow when it rises; kubota: renew when "
        "life < 0, else grow")
    renewal_keeps_rate: bool = Field(False, description="a renewed virus keeps the adapted infection rate")
    infect_every: int = Field(1, ge=1, description="infect every g generations")
    creation: CreationConfig = CreationConfig()

    @model_validator(mode="after")
    def _rate_in_bounds(self):
        if not self.min_infection_rate <= self.infection_rate <= self.max_infection_rate:
            raise ValueError(
                f"infection_rate {self.infection_rate} must lie in [min_infection_rate, "
                f"max_infection_rate] = [{self.min_infection_rate}, {self.max_infection_rate}]"
            )
        return self

    @property
    def fresh_length(self) -> int:
        return self.initial_length or max(1, self.max_length // 4)


class VEGAConfig(GAConfig):
    name: Literal["vega"] = "vega"
    virus: VirusConfig = VirusConfig()


class VEGA(GA):
    """Host GA plus a virus population; a generation is two ask/tell rounds."""

    name = "vega"

    def __init__(self, config: VEGAConfig, n_bits: int, rng: np.random.Generator) -> None:
        super().__init__(config, n_bits, rng)
        v = config.virus
        self.vc = v
        self.start = np.zeros(v.count, dtype=np.int64)
        self.length = np.zeros(v.count, dtype=np.int64)
        self.bits = np.zeros((v.count, n_bits), dtype=bool)
        self.life = np.zeros(v.count)
        self.rate = np.full(v.count, v.infection_rate)
        self.age = np.zeros(v.count, dtype=np.int64)
        self.longest = 0
        self.infections_made = 0
        self.infections_unchanged = 0
        self.phase = "hosts"
        self._pairs: tuple[np.ndarray, np.ndarray] | None = None
        self._trials = np.zeros((0, n_bits), dtype=bool)
        self._changed = np.zeros(0, dtype=bool)

    # -- rule 1: creation --------------------------------------------------------------------
    def source_hosts(self, count: int, exact: bool) -> np.ndarray:
        """Hosts to transduce ``count`` new viruses from: elite with ``elite_share``, else random.

        ``exact``: the first ``round(elite_share * count)`` are elite (initial creation);
        otherwise each new virus is elite with probability ``elite_share`` (renewals).
        """
        c = self.vc.creation
        N = self.f.size
        pool = min(c.elite_pool, N)
        order = stable_order(self.f)
        if exact:
            from_elite = np.arange(count) < round(c.elite_share * count)
        else:
            from_elite = self.rng.random(count) < c.elite_share
        rank = np.where(from_elite, self.rng.integers(0, pool, count),
                        pool + self.rng.integers(0, max(N - pool, 1), count))
        return order[np.minimum(rank, N - 1)]

    def create_viruses(self, which: np.ndarray, exact: bool = False, renewal: bool = False) -> None:
        """Fresh transduction (Fig. 3a) for the viruses ``which``; they start with life 0 and age 0,
        and at ``infection_rate`` unless this is a renewal under ``renewal_keeps_rate``."""
        if which.size == 0:
            return
        hosts = self.G[self.source_hosts(which.size, exact)]
        s, n, b = viral.transduction(hosts, min(self.vc.fresh_length, self.vc.max_length), self.rng)
        self.start[which], self.length[which], self.bits[which] = s, n, b
        self.life[which] = 0.0
        self.age[which] = 0
        if not (renewal and self.vc.renewal_keeps_rate):
            self.rate[which] = self.vc.infection_rate
        self.longest = max(self.longest, int(n.max()))

    # -- rule 2: infection -----------------------------------------------------------------------
    def infections(self) -> tuple[np.ndarray, np.ndarray]:
        """``(virus, host)`` index pairs: virus ``i`` infects each host with probability ``rate_i``."""
        u = self.rng.random((self.vc.count, self.f.size))
        if use_compiled():
            from ..operators.viral_kernels import pairs_below  # numba: imported only when it pays

            return pairs_below(u, self.rate)
        return np.nonzero(u < self.rate[:, None])

    # -- rules 4-6: virus bookkeeping ------------------------------------------------------------
    def update_viruses(self, fitvirus: np.ndarray, infected: np.ndarray, best_pair: np.ndarray,
                       trials: np.ndarray) -> None:
        """Life force, infection-rate adaptation, then renew or extend viruses.

        ``fitvirus: (V,)`` Eq. 12; ``infected: (V,)`` whether each virus infected a host;
        ``best_pair: (V,)`` the row of ``trials`` (the infected hosts) each virus improved most.
        """
        vc = self.vc
        if use_compiled():  # the same numbers in one pass (operators/viral_kernels.py)
            from ..operators.viral_kernels import life_and_rate

            self.life, self.rate, renew, idx = life_and_rate(
                self.life, fitvirus, float(vc.infectivity_force), self.rate, float(vc.rate_step),
                float(vc.min_infection_rate), float(vc.max_infection_rate), infected, vc.life_rule == "kubota")
        else:
            old_life = self.life
            self.life = viral.update_life(old_life, fitvirus, vc.infectivity_force)
            self.rate = viral.adapt_infection_rate(
                self.rate, fitvirus, vc.rate_step, vc.min_infection_rate, vc.max_infection_rate)
            if vc.life_rule == "kubota":
                renew = self.life < 0
                grow = ~renew & infected
            else:
                renew = (self.life < 0) | (self.life < old_life)
                grow = (self.life > old_life) & infected  # life rose: a gain this generation
            renew, idx = np.flatnonzero(renew), np.flatnonzero(grow)
        if idx.size:
            # the infected host (its infected version) each growing virus improved most
            s, n, b = viral.partial_transduction(
                self.start[idx], self.length[idx], self.bits[idx], trials[best_pair[idx]],
                self.vc.max_length, self.rng, self.vc.growth,
            )
            self.start[idx], self.length[idx], self.bits[idx] = s, n, b
            self.longest = max(self.longest, int(n.max()))
        self.create_viruses(renew, renewal=True)

    # -- ask / tell ------------------------------------------------------------------------------
    def begin_infection(self, virus: np.ndarray, host: np.ndarray) -> bool:
        """Make the infected hosts of the ``(virus, host)`` pairs; True if some must be evaluated.

        A trial equal to its host (the virus carries the host's own bits) is not asked for: its
        value is the host's and its gain 0. With none left, the generation ends here.
        """
        self._pairs = (virus, host)
        self._trials, self._changed = infect_pairs(self.G, host, virus, self.start, self.length, self.bits)
        self.infections_made += int(virus.size)
        self.infections_unchanged += int(virus.size - self._changed.sum())
        if self._changed.any():
            self.phase = "infection"
            return False
        self.end_infection(np.zeros(0))
        return True

    def end_infection(self, f_changed: np.ndarray) -> None:
        """Rules 3-6 with the values of the changed trials (the others are their hosts')."""
        virus, host = self._pairs
        trials = self._trials
        f = self.f[host]  # (a copy: fancy indexing)
        f[self._changed] = f_changed
        # rule 3 (each host takes its best infected version) and the Eq. 11/12 virus fitness
        take, best, best_f, fitvirus, infected, best_pair = infection_outcome(
            virus, host, self._changed, f, self.f, self.vc.count, self.vc.replacement == "improve")
        rows = np.flatnonzero(take)
        self.G[rows] = np.take(trials, best[rows], axis=0)  # np.take: 4x faster than trials[...]
        self.f[rows] = best_f[rows]
        self.update_viruses(fitvirus, infected, best_pair, trials)
        self._pairs, self.phase = None, "hosts"
        self._trials, self._changed = trials[:0], self._changed[:0]
        self.end_generation()

    def end_generation(self) -> None:
        self.age += 1
        self.generation += 1

    # -- ask / tell ------------------------------------------------------------------------------
    def ask(self) -> np.ndarray:
        if self.phase == "hosts":
            return super().ask()
        return np.compress(self._changed, self._trials, axis=0)  # 4x faster than a mask

    def hosts_evaluated(self) -> bool:
        if self.generation < 0:  # initial population: create the viruses (rule 1)
            self.create_viruses(np.arange(self.vc.count), exact=True)
            self.generation += 1
            return True
        if (self.generation + 1) % self.vc.infect_every:  # not an infection generation
            self.end_generation()
            return True
        virus, host = self.infections()
        if virus.size == 0:
            V = self.vc.count
            self.update_viruses(np.zeros(V), np.zeros(V, bool), np.full(V, -1), np.zeros((0, self.n_bits), bool))
            self.end_generation()
            return True
        return self.begin_infection(virus, host)

    def tell(self, f: np.ndarray) -> bool:
        if self.phase == "hosts":
            return super().tell(f)
        self.end_infection(np.asarray(f, dtype=float))
        return True
