"""Algorithms with an ask/tell interface over whole populations, by name."""

from .base import Algorithm
from .ga import GA, GAConfig
from .vega import VEGA, VEGAConfig

ALGORITHMS = {"ga": (GA, GAConfig), "vega": (VEGA, VEGAConfig)}

__all__ = ["ALGORITHMS", "Algorithm", "GA", "GAConfig", "VEGA", "VEGAConfig"]
