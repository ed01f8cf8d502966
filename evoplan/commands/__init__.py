"""Sub-commands of the ``evoplan`` CLI: one module each, with ``add_parser(sub)`` and ``main(args)``."""

# module names under evoplan.commands, in the order ``evoplan --help`` lists them
COMMANDS = ["run", "evaluate", "study", "zone", "simulate", "examples", "machine"]
