"""``evoplan zone`` shows its stages on a terminal; ``--quiet`` silences them."""

from __future__ import annotations

import json

from evoplan.cli import main
from tests.problems.simulation.test_simulate_cli import _on_a_terminal

ZONING = "name: zq\nsurface: choi\nmesh: [16, 16]\nmethod: single\nh_c: 0.5\n"


def test_zone_progress_on_a_terminal_and_quiet_silences_it(tmp_path, capsys):
    (tmp_path / "z.yaml").write_text(ZONING)
    shown = _on_a_terminal(["zone", "z.yaml", "--out", "a"], tmp_path)
    assert "zone: 5/5" in shown and "passes of 1 zone(s)" in shown and "toolpath.apt (" in shown
    assert main(["zone", str(tmp_path / "z.yaml"), "--out", str(tmp_path / "b"), "--quiet"]) == 0
    captured = capsys.readouterr()
    assert captured.err == "" and json.loads(captured.out)["zones"] == 1
    assert json.loads((tmp_path / "a" / "summary.json").read_text())["total_length_mm"] == \
        json.loads((tmp_path / "b" / "summary.json").read_text())["total_length_mm"]
