"""Adapters: other libraries' algorithms behind evoplan's ask/tell contract, by name.

``ADAPTERS`` has the shape of :data:`evoplan.algorithms.ALGORITHMS` (name -> (class, settings
model)), so a study (and, once the core's run configuration accepts them, ``evoplan run``)
looks an algorithm up in ``{**ALGORITHMS, **ADAPTERS}``.
"""

from .base import UnitCube, search_space
from .deap_easimple import DeapEaSimple, DeapEaSimpleConfig
from .pymoo_algorithms import PymooAdapter, PymooCMAESConfig, PymooDEConfig, PymooGAConfig, PymooPSOConfig
from .pymoo_multi import NSGA2Config, NSGA3Config, PymooMultiAdapter, SMSEMOAConfig

ADAPTERS = {
    "pymoo_ga": (PymooAdapter, PymooGAConfig),
    "pymoo_de": (PymooAdapter, PymooDEConfig),
    "pymoo_cmaes": (PymooAdapter, PymooCMAESConfig),
    "pymoo_pso": (PymooAdapter, PymooPSOConfig),
    "deap_easimple": (DeapEaSimple, DeapEaSimpleConfig),
    # several objectives (evoplan.multiobjective): evoplan run only
    "nsga2": (PymooMultiAdapter, NSGA2Config),
    "nsga3": (PymooMultiAdapter, NSGA3Config),
    "sms_emoa": (PymooMultiAdapter, SMSEMOAConfig),
}

__all__ = ["ADAPTERS", "UnitCube", "search_space"]
