"""APT CL files: what ``apt_write`` writes reads back as the same toolpath; bad files get one line."""

import numpy as np
import pytest

from evoplan.problems.toolpath.export.apt_read import AptError, read_apt
from evoplan.problems.toolpath.export.apt_write import apt_program


def _path(rng, m=40):
    tip = np.cumsum(rng.uniform(-3, 3, (m, 3)), axis=0) + [0, 0, 50]
    axis = rng.normal(size=(m, 3)) * [0.3, 0.3, 1] + [0, 0, 2]
    axis /= np.linalg.norm(axis, axis=1, keepdims=True)
    return tip, axis, np.repeat(np.arange(4), m // 4)


def test_write_then_read_gives_the_same_toolpath(tmp_path):
    tip, axis, passes = _path(np.random.default_rng(5))
    text = apt_program(tip, axis, passes, diameter=12, corner_radius=2, feed_rate=1500, plunge_feed=300,
                       tool_number=7, spindle_rpm=8000, comments=["x" * 200], clearance=10)
    assert max(map(len, text.splitlines())) <= 72
    (tmp_path / "a.apt").write_text(text)
    tp = read_apt(tmp_path / "a.apt")
    cut = ~tp.rapid
    # approach and retract are the only rapids, 10 mm above the ends along the axis
    assert tp.rapid.tolist() == [True] + [False] * len(tip) + [True]
    np.testing.assert_allclose(tp.tip[0], tip[0] + 10 * axis[0], atol=1e-4)
    np.testing.assert_allclose(tp.tip[cut], tip, atol=5e-5)
    np.testing.assert_allclose(tp.axis[cut], axis, atol=1e-6)
    np.testing.assert_allclose(np.linalg.norm(tp.axis, axis=1), 1, atol=1e-12)
    assert tp.section[cut].tolist() == passes.tolist() and tp.sections == ("PASS 0", "PASS 1", "PASS 2", "PASS 3")
    assert tp.feed[cut][0] == 300 and np.all(tp.feed[cut][1:] == 1500) and np.isnan(tp.feed[0])
    assert (tp.diameter, tp.corner_radius, tp.multax, tp.tip_is_centre) == (12, 2, True, False)
    assert (tp.tool_number, tp.spindle_rpm, tp.coolant) == (7, 8000, "OFF")


def test_centre_statement_and_three_axis_forms(tmp_path):
    text = """PARTNO SOME OTHER CAM
$$ TOOLPOINT CENTRE
UNITS/INCHES
CUTTER/0.5,0.25,0,0.25,0,0,2
TLAXIS/0,3,4
FROM/0,0,4
RAPID
GOTO/1,2,3
FEDRAT/ 10 , IPM
GOTO/1,2,$
 2.5 $$ continued
GODLTA/-0.5
GODLTA/1,0,0
MULTAX/OFF
$$ ZONE 2 PASS 7
GOTO/0,0,0
FINI
GOTO/this is never read
"""
    (tmp_path / "b.cls").write_text(text)
    tp = read_apt(tmp_path / "b.cls")
    mm = 25.4
    np.testing.assert_allclose(tp.tip, np.array([[1, 2, 3], [1, 2, 2.5], [1, 1.7, 2.1], [2, 1.7, 2.1], [0, 0, 0]]) * mm)
    np.testing.assert_allclose(tp.axis, np.tile([0, 0.6, 0.8], (5, 1)))
    assert tp.rapid.tolist() == [True, False, False, False, False]
    assert np.isnan(tp.feed[0]) and np.all(tp.feed[1:] == 10 * mm)
    assert tp.section.tolist() == [-1, -1, -1, -1, 0] and tp.sections == ("ZONE 2 PASS 7",)
    assert (tp.diameter, tp.corner_radius) == (0.5 * mm, 0.25 * mm)
    assert tp.tip_is_centre and not tp.multax and tp.part == "SOME OTHER CAM"
    np.testing.assert_allclose(tp.start, [0, 0, 4 * mm])


BAD = {
    "garbage": ("CUTTER/6\nGOTO/1,2,3\nhello world!\n", 3, "not an APT statement"),
    "unknown word": ("CUTTER/6\nFROBNICATE/1\n", 2, "unknown statement FROBNICATE"),
    "nan": ("CUTTER/6\nGOTO/1,nan,3\n", 2, "non-finite"),
    "inf in continuation": ("CUTTER/6\nGOTO/1,$\n2,inf\n", 2, "non-finite"),
    "no cutter": ("RAPID\nGOTO/0,0,10\nGOTO/0,0,0\n", 3, "before any CUTTER"),
    "empty path": ("PARTNO X\nCUTTER/6\nFINI\n", 3, "no GOTO"),
    "bad count": ("CUTTER/6\nGOTO/1,2\n", 2, "3 or 6"),
    "zero axis": ("CUTTER/6\nGOTO/1,2,3,0,0,0\n", 2, "zero tool axis"),
    "per rev": ("CUTTER/6\nFEDRAT/0.1,MMPR\n", 2, "per revolution"),
}


@pytest.mark.parametrize("case", sorted(BAD))
def test_bad_files_give_one_line_with_the_line_number(tmp_path, case):
    text, line, words = BAD[case]
    (tmp_path / "bad.apt").write_text(text)
    with pytest.raises(AptError) as err:
        read_apt(tmp_path / "bad.apt")
    msg = str(err.value)
    assert "\n" not in msg and msg.startswith(f"LINE {line}: ") and words in msg
    assert isinstance(err.value, ValueError)


def test_non_utf8_names_its_line(tmp_path):
    (tmp_path / "bin.apt").write_bytes(b"CUTTER/6\nGOTO/1,2,3\n$$ caf\xe9\n")
    with pytest.raises(AptError, match=r"^LINE 3: not UTF-8"):
        read_apt(tmp_path / "bin.apt")


def test_centre_programmed_paths_say_so(tmp_path):
    tip, axis, passes = _path(np.random.default_rng(2), m=8)
    text = apt_program(tip, axis, passes, diameter=10, corner_radius=5, feed_rate=900, tip_is_centre=True)
    assert "$$ TOOLPOINT CENTRE" in text.splitlines()
    (tmp_path / "c.apt").write_text(text)
    tp = read_apt(tmp_path / "c.apt")
    assert tp.tip_is_centre and tp.feed[1] == 450          # default plunge feed: half the feed
    (tmp_path / "c.apt").write_text(text.replace("$$ TOOLPOINT CENTRE\n", ""))
    assert not read_apt(tmp_path / "c.apt").tip_is_centre
