"""``toolpath.npz`` of ``evoplan evaluate --out`` on the trimmed STEP sample (a hole and a
notch): ``cc`` holds every CL point's CC point, the run-on points past the face's edge
included, and ``on_part`` flags the ones on the part."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest
import yaml

pytest.importorskip("OCP")

from evoplan.cli import main  # noqa: E402
from evoplan.problems.toolpath.geometry.cad_faces import DEFLECTION  # noqa: E402
from tests.problems.toolpath.test_trimmed_face import off_face  # noqa: E402

ROOT = Path(__file__).resolve().parents[3]
RUN = ROOT / "runs" / "step_block_zoned_vega.yaml"


def test_on_part_flags_the_run_on_points_in_the_hole_and_the_notch(tmp_path, capsys):
    cfg = yaml.safe_load(RUN.read_text())
    params = cfg["problem"]["params"]
    params["surface"]["file"] = str(ROOT / "runs" / "parts" / "sculpted_block.step")
    params["zoning"]["mesh"] = [12, 12]  # a small mesh and fixed bounds: a cheap evaluation
    del params["normalization_samples"]
    params["normalization"] = {"machining_error": [0, 0.3], "cc_count": [100, 3000]}
    run = tmp_path / "step.yaml"
    run.write_text(yaml.safe_dump(cfg))
    out = tmp_path / "ev"
    sets = ["--set", "tool=2", "--set", "stepover=45", "--set", "step=6", "--set", "zones=1"]
    assert main(["evaluate", str(run), *sets, "--out", str(out)]) == 0
    crit = json.loads(capsys.readouterr().out)["criteria"]
    with np.load(out / "toolpath.npz", allow_pickle=False) as data:
        cc, on_part, inserted = data["cc"], data["on_part"], data["inserted"]
        assert on_part.dtype == bool and on_part.shape == inserted.shape == (len(cc),)
        assert len(data["zone"]) == len(cc)
    off = off_face(cc[:, :2], 2 * DEFLECTION)
    assert on_part.sum() > 200 and not off[on_part].any()  # no point on the part in the hole
    assert (~on_part).any() and off[~on_part].sum() > 10  # the run-on into the hole / notch
    # cc_count counts the plan's points on the part (docs/outputs.md), not the run-on
    assert crit["cc_count"] == (on_part & ~inserted).sum() < len(cc)
