"""What a plan is worth: the one table of criteria (``table.py``), the analytic criteria of a
``PlanBatch`` (``analytic.py``: chord, scallop, gouge, lengths, time, Djebali Eq. 4), the
simulated ones (``simulated.py``, the cut simulation, same names), and Fountas Eq. 9 over
them (``objective.py``)."""
