"""Genetic and viral operators: pure functions over numpy arrays of whole populations."""
