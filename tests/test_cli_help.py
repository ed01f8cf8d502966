"""What ``-h`` shows works: each command's ``--set`` example applies to a shipped file and
validates, ``machine`` takes ``--set``, and a bad option's hint names the command's help."""

from __future__ import annotations

import argparse
import re
from pathlib import Path

import pytest

from evoplan.cli import build_parser, main
from evoplan.config import parse_config, read_yaml
from evoplan.errors import ConfigError
from evoplan.overrides import apply_settings

ROOT = Path(__file__).resolve().parents[1]


def set_example(command: str) -> list[str]:
    """The ``KEY.PATH=VALUE`` items of the example in ``evoplan COMMAND -h``'s ``--set`` help."""
    parser = build_parser([command])
    sub = next(a for a in parser._actions if isinstance(a, argparse._SubParsersAction))
    action = next(a for a in sub.choices[command]._actions if a.dest == "settings")
    return re.findall(r"--set (\S+)", action.help)


def _validate_run(data, source):
    parse_config(data, source)


def _validate_study(data, source):
    from evoplan.study.config import parse_study

    parse_study(data, source)


def _validate_machine(data, source):
    from evoplan.commands.machine_config import MachineConfig

    MachineConfig.model_validate(data)


@pytest.mark.parametrize("command, shipped, validate", [
    ("run", "runs/kubota_vega.yaml", _validate_run),
    ("study", "runs/kubota_vega_vs_ga.yaml", _validate_study),
    ("machine", "runs/abbas_gentle.yaml", _validate_machine),
])
def test_the_set_example_in_each_help_applies_to_a_shipped_file(command, shipped, validate):
    items = set_example(command)
    assert len(items) == 2
    path = ROOT / shipped
    data = apply_settings(read_yaml(path), items, str(path))
    for item in items:  # the example changed the file
        keys, value = item.split("=")
        node = data
        for k in keys.split("."):
            node = node[k]
        assert str(node) == value
    validate(data, str(path))


def test_machine_refuses_a_bad_set_key_in_one_line(tmp_path, capsys):
    code = main(["machine", str(ROOT / "runs/abbas_gentle.yaml"), "--set", "roughing.max_dept=1",
                 "--out", str(tmp_path / "m")])
    err = capsys.readouterr().err.strip()
    assert code == 2 and err.count("\n") == 0 and "roughing.max_dept" in err and "abbas_gentle.yaml" in err
    assert not (tmp_path / "m").exists()


def test_an_unknown_option_points_to_the_command_s_own_help(capsys):
    with pytest.raises(SystemExit) as stop:
        main(["machine", str(ROOT / "runs/abbas_gentle.yaml"), "--bogus"])
    err = capsys.readouterr().err
    assert stop.value.code == 2 and "(evoplan machine -h for usage)" in err and "--bogus" in err


def test_a_machine_setting_from_the_command_line_reaches_the_config():
    from evoplan.commands.machine import load

    cfg = load(str(ROOT / "runs/abbas_gentle.yaml"), ["roughing.max_depth=1.25"])
    assert cfg.roughing.max_depth == 1.25
    with pytest.raises(ConfigError, match="roughing.max_depth"):
        load(str(ROOT / "runs/abbas_gentle.yaml"), ["roughing.max_depth=1", "roughing.max_depth=2"])
