"""Adapters: other libraries' algorithms behind evoplan's ask/tell contract, by name.

``ADAPTERS`` has the shape of :data:`evoplan.algorithms.ALGORITHMS` (name -> (class, settings
model)), so a study (and, once the core's run configuration accepts them, ``evoplan run``)
looks an algorithm up in ``{**ALGORITHMS, **ADAPTERS}``.
"""

from .base import UnitCube, search_space
from ..extras import require
from .deap_config import DeapEaSimpleConfig
from .pymoo_algorithms import PymooAdapter, PymooCMAESConfig, PymooDEConfig, PymooGAConfig, PymooPSOConfig
from .pymoo_multi import NSGA2Config, NSGA3Config, PymooMultiAdapter, SMSEMOAConfig



def deap_easimple(config: DeapEaSimpleConfig, n_bits: int, rng):
    """DEAP's eaSimple split at its evaluation step (``deap_easimple.py``; needs ``evoplan[deap]``)."""
    require("deap", "deap", "the deap_easimple adapter")
    from .deap_easimple import DeapEaSimple

    return DeapEaSimple(config, n_bits, rng)


deap_easimple.extra = ("deap", "deap", "the deap_easimple adapter")  # checked before a run starts


ADAPTERS = {
    "pymoo_ga": (PymooAdapter, PymooGAConfig),
    "pymoo_de": (PymooAdapter, PymooDEConfig),
    "pymoo_cmaes": (PymooAdapter, PymooCMAESConfig),
    "pymoo_pso": (PymooAdapter, PymooPSOConfig),
    "deap_easimple": (deap_easimple, DeapEaSimpleConfig),
    # several objectives (evoplan.multiobjective): evoplan run only
    "nsga2": (PymooMultiAdapter, NSGA2Config),
    "nsga3": (PymooMultiAdapter, NSGA3Config),
    "sms_emoa": (PymooMultiAdapter, SMSEMOAConfig),
}

__all__ = ["ADAPTERS", "UnitCube", "search_space"]
