"""VEGA's configurable rules (life_rule, renewal_keeps_rate, infect_every, growth up to the cap)
and the infection that copies its host's own bits, each on a hand-built population."""

import numpy as np

from evoplan.algorithms import VEGA, VEGAConfig
from evoplan.algorithms.vega import VirusConfig
from evoplan.config import parse_config
from evoplan.engine import run
from evoplan.runner import prepare


def vega(**virus) -> VEGA:
    cfg = VEGAConfig(population=4, elitism=1, virus=VirusConfig(**{"count": 2, **virus}))
    algo = VEGA(cfg, 8, np.random.default_rng(0))
    algo.G = np.zeros((4, 8), bool)
    algo.G[:, 6:] = True  # hosts 00000011
    algo.f = np.array([5.0, 4.0, 3.0, 2.0])
    algo.generation = 3
    algo.start[:] = [0, 4]
    algo.length[:] = [2, 2]
    algo.bits[:] = False
    return algo


def test_an_infection_with_the_hosts_own_bits_is_not_evaluated_and_gains_nothing():
    algo = vega(infectivity_force=0.5)
    algo.life[:] = [1.0, 1.0]
    f_before = algo.f.copy()
    # both viruses carry zeros on loci the hosts hold as zeros: every trial equals its host
    assert algo.begin_infection(np.array([0, 0, 1, 1]), np.array([0, 1, 2, 3]))  # generation over
    assert algo.phase == "hosts" and algo.generation == 4
    assert algo.infections_made == 4 and algo.infections_unchanged == 4
    np.testing.assert_array_equal(algo.f, f_before)
    # fitvirus 0: life 0.5 * 1 = 0.5 fell -> both renewed under Fountas' rule
    assert (algo.life == 0).all() and (algo.age == 1).all()  # fresh ones, one generation end ago


def test_host_copies_cost_no_evaluation_in_a_run_even_without_cache():
    cfg = parse_config({"seed": 2, "problem": {"name": "kubota", "bits": 23},
                        "algorithm": {"name": "vega", "population": 20, "virus": {"count": 7}},
                        "termination": {"generations": 30}, "cache": {"size": 0}})
    p = prepare(cfg)
    rows = []

    def counting(X):
        rows.append(len(X))
        return p.evaluator(X)

    s = run(p.new_state(), p.space, counting, p.termination)
    algo = s.algorithm
    assert algo.infections_unchanged > 0
    host_rows = 20 + 30 * 19  # initial population, then population - elitism per generation
    asked = host_rows + algo.infections_made - algo.infections_unchanged
    assert s.evaluations + s.cache_hits == asked  # cache size 0: only repeats inside a batch are hits
    assert sum(rows) == s.evaluations


def test_life_rule_kubota_grows_a_harmless_virus_that_fountas_keeps():
    for rule, length in (("fountas", 2), ("kubota", 5)):
        algo = vega(life_rule=rule, growth=3, max_length=8, infectivity_force=0.001)
        algo.bits[0, :2] = True  # virus 0 writes 11 on loci 0-1: a change
        algo.life[:] = [0.0, 0.0]
        assert not algo.begin_infection(np.array([0]), np.array([2]))
        algo.tell(np.array([3.0]))  # no gain, no loss: life stays 0
        assert algo.length[0] == length, rule
        assert algo.life[0] == 0.0


def test_life_rule_kubota_renews_a_virus_whose_life_is_negative():
    algo = vega(life_rule="kubota", infectivity_force=1.0)
    algo.bits[0, :2] = True
    algo.life[:] = [0.5, 0.0]
    algo.age[:] = [7, 7]
    algo.begin_infection(np.array([0]), np.array([3]))
    algo.tell(np.array([4.0]))  # gain 2 - 4 = -2: life 0.5 - 2 < 0
    assert algo.life[0] == 0.0 and algo.age[0] == 1  # fresh (age 0) one generation ago
    assert algo.age[1] == 8 and algo.length[1] == 2  # virus 1 infected nobody: unchanged


def test_the_length_cap_binds_when_growth_allows_it():
    algo = vega(life_rule="kubota", growth=4, max_length=7)
    algo.bits[0, :2] = True
    for _ in range(4):
        algo.G[2, :] = False  # keep the trial different from its host
        algo.f[2] = 3.0
        algo.begin_infection(np.array([0]), np.array([2]))
        algo.tell(np.array([3.0]))
    assert algo.length[0] == 7 and algo.longest == 7  # 2 -> 6 -> 7 (capped) -> slides at 7


def test_renewal_keeps_the_adapted_rate_only_when_asked():
    for keeps, rate in ((False, 0.7), (True, 0.7 * 0.9)):
        algo = vega(renewal_keeps_rate=keeps, infectivity_force=1.0)
        algo.bits[0, :2] = True
        algo.life[:] = [0.1, 0.0]
        algo.begin_infection(np.array([0]), np.array([3]))
        algo.tell(np.array([10.0]))  # a loss: rate * (1 - 0.1), and life < 0: renewed
        assert algo.life[0] == 0.0 and np.isclose(algo.rate[0], rate), keeps


def test_infect_every_skips_the_generations_between_infections():
    algo = vega(infect_every=3, infection_rate=1.0, min_infection_rate=0.1)
    algo.bits[:, :2] = True
    made = []
    for _ in range(6):
        before = algo.infections_made
        if not algo.hosts_evaluated():
            algo.tell(np.full(int(algo._changed.sum()), 9.0))
        made.append(algo.infections_made > before)
    # generation 3 done; generation g + 1 ends with infections when (g + 1) % 3 == 0: 6 and 9
    assert made == [False, False, True, False, False, True]
    assert algo.generation == 9
