"""What a plan is worth: the analytic criteria (chord, scallop, gouge, lengths, time), the
simulated ones (the cut simulation, same names), and Fountas Eq. 9 over them."""
