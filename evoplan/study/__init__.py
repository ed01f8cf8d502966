"""Studies: many runs (algorithms x problems x seeds x factor levels), their statistics and plots.

Modules, in the order data flows: ``config`` (the study file), ``grid`` (the cells and their
seeds), ``cell`` (one run, where a worker runs it), ``folder`` (results on disk, resume),
``runner`` (backends and progress), ``statistics`` / ``ranking`` / ``curves`` (numbers: pairwise
tests, Friedman and Bayesian tests, runtimes), ``figures`` / ``report`` (what a reader sees),
``ioh_export`` (IOHprofiler files), ``analysis`` (ties them), ``bbob`` (BBOB via ioh).
"""
