"""Sub-commands of the ``evoplan`` CLI: one module each, with ``add_parser(sub)`` and ``main(args)``.

``COMMANDS`` maps each module name under ``evoplan.commands`` to its one-line help, in the
order ``evoplan --help`` lists them. The CLI imports only the module of the command being run
(``evoplan.cli.build_parser``), so ``evoplan --help`` loads none of them.
"""

COMMANDS = {
    "run": "run one optimization from a YAML file",
    "evaluate": "evaluate one parameter set of a run file's problem",
    "study": "run a comparison study (algorithms x problems x seeds) and analyze it",
    "zone": "zone a surface and optimize each zone's feed direction",
    "simulate": "cut a toolpath in simulation and measure scallop and gouge",
    "examples": "list the shipped run and study files, or copy one",
    "machine": "roughing, semi-finish and finish NC programs for one surface",
    "report": "one self-contained HTML report (plots, tables, 3D toolpath) of a results folder",
}
