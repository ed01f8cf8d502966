"""evoplan: evolutionary optimization of free-form surface toolpaths."""

__version__ = "0.1.0"
