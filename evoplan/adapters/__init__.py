"""Adapters: other libraries' algorithms behind evoplan's ask/tell contract, by name.

``ADAPTERS`` has the shape of :data:`evoplan.algorithms.ALGORITHMS` (name -> (class, settings
model)), so a study (and, once the core's run configuration accepts them, ``evoplan run``)
looks an algorithm up in ``{**ALGORITHMS, **ADAPTERS}``.
"""

from .base import UnitCube, search_space
from .deap_easimple import DeapEaSimple, DeapEaSimpleConfig
from .pymoo_algorithms import PymooAdapter, PymooCMAESConfig, PymooDEConfig, PymooGAConfig, PymooPSOConfig

ADAPTERS = {
    "pymoo_ga": (PymooAdapter, PymooGAConfig),
    "pymoo_de": (PymooAdapter, PymooDEConfig),
    "pymoo_cmaes": (PymooAdapter, PymooCMAESConfig),
    "pymoo_pso": (PymooAdapter, PymooPSOConfig),
    "deap_easimple": (DeapEaSimple, DeapEaSimpleConfig),
}

__all__ = ["ADAPTERS", "UnitCube", "search_space"]
