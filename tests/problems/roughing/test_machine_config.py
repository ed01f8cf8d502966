"""The machining file is validated once, when it is loaded (evoplan/commands/machine_config.py):
one line naming the key path, before any operation is planned."""

import time

import pytest

from evoplan.commands.machine import load
from evoplan.errors import ConfigError

BAD = {
    "finish: {problem: {feed_rat: 3}}":
        "finish.problem.feed_rat: unknown (known: feed_rate, tolerance, feed_angle, allowance, tools, ranges)",
    "finish: {problem: {tolerance: -1}}": "finish.problem.tolerance: must be a finite number > 0, got -1",
    "finish: {problem: {tools: [{id: 1, diameter: 6, corner_radius: 9}]}}": "finish.problem.tools[0].corner_radius",
    "post: {dialect: okuma}": "post.dialect: unknown post 'okuma' (known: fanuc, heidenhain, iso, siemens)",
    "post: {kinematics: {tilt: {name: A, about: x, limits: [30, -30]}}}":
        "post.kinematics: limits of A: lower must be below upper",
}


@pytest.mark.parametrize("text", sorted(BAD))
def test_a_bad_value_is_refused_on_load(tmp_path, text):
    path = tmp_path / "m.yaml"
    path.write_text(f"surface: choi\n{text}\n")
    t0 = time.perf_counter()
    with pytest.raises(ConfigError) as e:
        load(str(path))
    assert time.perf_counter() - t0 < 5.0
    msg = str(e.value)
    assert msg.startswith(f"{path}: ") and BAD[text] in msg and "\n" not in msg, msg


def test_a_three_axis_post_ignores_the_kinematics(tmp_path):
    path = tmp_path / "m.yaml"
    path.write_text("surface: choi\npost: {dialect: iso, kinematics: {tilt: {name: A, about: x, limits: [30, -30]}}}\n"
                    "finish: {source: offset, problem: {feed_rate: 900, tolerance: 0.02}}\n")
    cfg = load(str(path))
    assert cfg.post.dialect == "iso" and cfg.finish.problem == {"feed_rate": 900, "tolerance": 0.02}
