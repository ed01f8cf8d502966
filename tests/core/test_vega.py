"""Each VEGA rule on its own, on hand-built populations."""

import numpy as np
import pytest

from evoplan.algorithms import GA, GAConfig, VEGA, VEGAConfig
from evoplan.algorithms.vega import VirusConfig


def vega(**virus) -> VEGA:
    cfg = VEGAConfig(population=4, elitism=1, virus=VirusConfig(**{"count": 2, **virus}))
    algo = VEGA(cfg, 8, np.random.default_rng(0))
    algo.G = np.zeros((4, 8), bool)
    algo.f = np.array([5.0, 4.0, 3.0, 2.0])
    algo.generation = 3
    return algo


def test_virus_fitness_equals_sum_of_host_improvements_through_tell():
    algo = vega(infectivity_force=0.5)
    algo.start[:] = [0, 4]
    algo.length[:] = [2, 2]
    algo.bits[:] = False
    algo.bits[0, :2] = True
    algo.life[:] = [1.0, 1.0]
    # virus 0 infects hosts 0 and 1, virus 1 infects host 2 with host 2's own bits (unchanged)
    assert not algo.begin_infection(np.array([0, 0, 1]), np.array([0, 1, 2]))
    trials = algo.ask()
    assert trials.shape == (2, 8)  # the unchanged infection is not asked for
    assert trials[:, :2].all() and not trials[:, 2:].any()
    assert algo.tell(np.array([3.0, 4.5]))  # gains: +2, -0.5 ; 0
    # Eq. 12: fitvirus_0 = 2 - 0.5 = 1.5 ; life_0 = 0.5 * 1 + 1.5 = 2.0 (rose: partial transduction)
    assert algo.life[0] == pytest.approx(2.0)
    assert algo.length[0] == 3  # grew by one locus
    # virus 1: fitvirus 0, life 0.5 * 1 = 0.5 fell -> renewed: a fresh virus with life 0
    assert algo.life[1] == 0.0
    # replacement "improve": host 0 improved (5 -> 3) and was replaced, host 1 (4 -> 4.5) was not
    np.testing.assert_allclose(algo.f, [3.0, 4.0, 3.0, 2.0])
    assert algo.G[0, :2].all() and not algo.G[1].any()
    assert algo.generation == 4


def test_replacement_always_takes_the_infected_host_even_if_worse():
    algo = vega(replacement="always")
    algo.start[:] = [0, 0]
    algo.length[:] = [8, 8]
    algo.bits[:] = True
    algo.begin_infection(np.array([0, 1]), np.array([1, 1]))
    algo.ask()
    algo.tell(np.array([9.0, 7.0]))
    assert algo.f[1] == 7.0  # the better of its two infections, although worse than 4.0
    assert algo.G[1].all()


def test_negative_life_kills_the_virus():
    algo = vega(infectivity_force=1.0)
    algo.life[:] = [0.1, 0.0]
    algo.start[:] = [0, 0]
    algo.length[:] = [8, 8]
    algo.bits[:] = True
    algo.begin_infection(np.array([0]), np.array([3]))
    algo.ask()
    algo.tell(np.array([10.0]))  # gain 2 - 10 = -8: life 0.1 - 8 < 0
    assert algo.life[0] == 0.0 and algo.rate[0] == pytest.approx(0.7)  # replaced by a fresh one
    assert algo.length[0] <= algo.vc.fresh_length


def test_creation_targets_elite_and_random_hosts():
    cfg = VEGAConfig(population=10, virus=VirusConfig(count=4, creation={"elite_share": 0.5, "elite_pool": 1}))
    algo = VEGA(cfg, 16, np.random.default_rng(5))
    algo.f = np.arange(10.0)
    src = algo.source_hosts(4, exact=True)
    assert (src[:2] == 0).all() and (src[2:] != 0).all()
    cfg_random = VEGAConfig(population=10, virus=VirusConfig(count=4, creation={"elite_share": 0.0}))
    algo = VEGA(cfg_random, 16, np.random.default_rng(5))
    algo.f = np.arange(10.0)
    assert not np.isin(algo.source_hosts(200, exact=False), [0, 1]).any()


def test_infection_rate_bounds_are_validated():
    with pytest.raises(ValueError):
        VirusConfig(min_infection_rate=0.6)
    with pytest.raises(ValueError):
        VirusConfig(max_infection_rate=0.4)
    with pytest.raises(ValueError, match="infection_rate"):
        VirusConfig(infection_rate=0.05, min_infection_rate=0.1)


def test_infections_follow_the_rate():
    algo = vega()
    algo.f = np.zeros(1000)
    algo.rate[:] = [0.0, 1.0]
    virus, host = algo.infections()
    assert (virus == 1).all() and host.size == 1000


def test_ga_generation_keeps_population_size_and_elite():
    cfg = GAConfig(population=10, elitism=2)
    algo = GA(cfg, 12, np.random.default_rng(1))
    G0 = algo.ask()
    algo.tell(np.arange(10.0)[::-1])
    elite = G0[[9, 8]]
    children = algo.ask()
    assert children.shape == (8, 12)
    algo.tell(np.full(8, 100.0))
    assert np.array_equal(algo.G[:2], elite) and algo.f[:2].tolist() == [0.0, 1.0]
    assert algo.G.shape == (10, 12) and algo.generation == 1
