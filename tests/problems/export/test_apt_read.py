"""APT CL files: what ``apt_write`` writes reads back as the same toolpath; bad files get one line."""

from pathlib import Path

import numpy as np
import pytest

from evoplan.problems.toolpath.cutters import make_cutter
from evoplan.problems.toolpath.export.apt_read import AptError, read_apt
from evoplan.problems.toolpath.export.apt_write import apt_program


def _path(rng, m=40):
    tip = np.cumsum(rng.uniform(-3, 3, (m, 3)), axis=0) + [0, 0, 50]
    axis = rng.normal(size=(m, 3)) * [0.3, 0.3, 1] + [0, 0, 2]
    axis /= np.linalg.norm(axis, axis=1, keepdims=True)
    return tip, axis, np.repeat(np.arange(4), m // 4)


def test_write_then_read_gives_the_same_toolpath(tmp_path):
    tip, axis, passes = _path(np.random.default_rng(5))
    text = apt_program(tip, axis, passes, cutter=make_cutter(12, 2), feed_rate=1500, plunge_feed=300,
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
    assert (tp.cutter.diameter, tp.cutter.corner_radius, tp.multax, tp.tip_is_centre) == (12, 2, True, False)
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
    assert (tp.cutter.diameter, tp.cutter.corner_radius) == (0.5 * mm, 0.25 * mm)
    assert tp.tip_is_centre and not tp.multax and tp.part == "SOME OTHER CAM"
    np.testing.assert_allclose(tp.start, [0, 0, 4 * mm])


BAD = {
    "garbage": ("CUTTER/6\nGOTO/1,2,3\nhello world!\n", 3, "not an APT statement"),
    "unknown motion": ("CUTTER/6\nGOTO/0,0,0\nGOFWD/(CIRCLE/0,0,0,5),TANTO,L1\n", 3,
                       "motion statement GOFWD is not supported"),
    "canned cycle": ("CUTTER/6\nCYCLE/DRILL,5,100,MMPM\n", 2, "CYCLE/"),
    "arc off its circle": ("CUTTER/6\nGOTO/10,0,0\nCIRCLE/0,0,0,0,0,1,10\nGOTO/0,7,0\n", 4, "from the axis"),
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
    text = apt_program(tip, axis, passes, cutter=make_cutter(10, 5), feed_rate=900, tip_is_centre=True)
    assert "$$ TOOLPOINT CENTRE" in text.splitlines()
    (tmp_path / "c.apt").write_text(text)
    tp = read_apt(tmp_path / "c.apt")
    assert tp.tip_is_centre and tp.feed[1] == 450          # default plunge feed: half the feed
    (tmp_path / "c.apt").write_text(text.replace("$$ TOOLPOINT CENTRE\n", ""))
    assert not read_apt(tmp_path / "c.apt").tip_is_centre


NX = """TOOL PATH/ZLEVEL_PROFILE,TOOL,MILL_D10R1
TLDATA/MILL,10.0000,1.0000,75.0000,0.0000,0.0000
MSYS/0.0000,0.0000,0.0000,1.0000000,0.0000000,0.0000000,0.0000000,1.0000000,0.0000000
$$ centerline data
PAINT/PATH
PAINT/SPEED,10
SELECT/TOOL,4
SPINDL/RPM,6000,CLW
FROM/0.0D+00,0.0D+00,5.0D+01
RAPID
GOTO/1.0D+01,0.0000,5.0000,0.0000000,0.0000000,1.0000000
FEDRAT/MMPM,1.2D+03
INDIRV/0.0,1.0,0.0
CIRCLE/0.0000,0.0000,5.0000,0.0000000,0.0000000,1.0000000,10.0000,0.0600,0.5000,10.0000,0.0000
GOTO/0.0000,10.0000,5.0000
INTOL/0.0050
GOTO/0.0000,10.0000,2.0D+00
PAINT/COLOR,186
GOHOME
END-OF-PATH
"""


def test_nx_and_creo_statements_read_to_the_expected_path(tmp_path):
    (tmp_path / "nx.cls").write_text(NX)
    tp = read_apt(tmp_path / "nx.cls")
    assert (tp.cutter.diameter, tp.cutter.corner_radius, tp.tool_number, tp.spindle_rpm) == (10.0, 1.0, 4, 6000.0)
    np.testing.assert_allclose(tp.start, [0, 0, 50])
    np.testing.assert_allclose(tp.tip[0], [10, 0, 5])
    np.testing.assert_allclose(tp.tip[-2], [0, 10, 2])          # the plunge after the arc
    np.testing.assert_allclose(tp.tip[-1], [0, 0, 50])          # GOHOME: a rapid back to FROM
    assert tp.rapid[0] and tp.rapid[-1] and not tp.rapid[1:-1].any()
    arc = tp.tip[1:-2]                                          # the quarter circle, counter-clockwise
    r = np.linalg.norm(arc[:, :2], axis=1)
    np.testing.assert_allclose(r, 10, atol=1e-9)
    ang = np.arctan2(arc[:, 1], arc[:, 0])
    assert np.all(np.diff(ang) > 0) and ang[-1] == pytest.approx(np.pi / 2)
    # every chord of the arc within the 0.01 mm default chord tolerance
    mids = 0.5 * (arc[1:] + arc[:-1])
    sag = 10 - np.linalg.norm(mids[:, :2], axis=1)
    assert sag.max() <= 0.01 + 1e-12 and sag.max() > 0.004     # not needlessly dense either
    assert tp.feed[1] == 1200
    assert tp.ignored == {"TOOL PATH": 1, "MSYS": 1, "PAINT": 3, "INDIRV": 1, "INTOL": 1, "END-OF-PATH": 1}


def test_creo_spindle_and_clockwise_arc_by_a_reversed_axis(tmp_path):
    text = """PARTNO CREO
UNITS/MM
LOADTL/2
SPINDL/RPM,6000,CLW
CUTTER/12.000000
COOLNT/ON
FEDRAT/MMPM,800
GOTO/0,5,0
CIRCLE/0,0,0,0,0,-1,5,0.01
GOTO/5,0,0
FINI
"""
    (tmp_path / "creo.ncl").write_text(text)
    tp = read_apt(tmp_path / "creo.ncl")
    assert tp.spindle_rpm == 6000 and tp.cutter.diameter == 12 and tp.ignored == {}
    # about -Z, counter-clockwise is clockwise seen from above: (0, 5) -> (5, 0) the short way
    ang = np.arctan2(tp.tip[:, 1], tp.tip[:, 0])
    assert np.all(np.diff(ang) < 0) and len(tp.tip) < 40


def test_words_with_spaces_need_their_slash(tmp_path):
    (tmp_path / "t.apt").write_text("CUTTER/6\nGOTO/0,0,0\nthis is not apt\n")
    with pytest.raises(AptError, match=r"^LINE 3: not an APT statement"):
        read_apt(tmp_path / "t.apt")


# statements that change the motion of what follows: refused with their line, not counted as ignored
MOTION_CHANGES = {
    "TRANS/10,0,0": "TRANS", "ORIGIN/5,5,0": "ORIGIN", "ROTABL/90,CLW": "ROTABL", "COPY/1,SAME,2": "COPY",
    "INDEX/1": "INDEX", "ROTATE/ZAXIS,90": "ROTATE", "CUTCOM/LEFT": "CUTCOM", "RETRCT": "RETRCT",
    "TRACUT/MATRIX1": "TRACUT", "REFSYS/MAT1": "REFSYS", "ROTHED/ATANGL,30": "ROTHED",
}


@pytest.mark.parametrize("statement", sorted(MOTION_CHANGES))
def test_statements_that_change_motion_are_refused_with_their_line(tmp_path, statement):
    text = f"PARTNO X\nCUTTER/6\nFEDRAT/500\nGOTO/0,0,0\n{statement}\nGOTO/1,0,0\n"
    (tmp_path / "m.apt").write_text(text)
    with pytest.raises(AptError) as err:
        read_apt(tmp_path / "m.apt")
    msg = str(err.value)
    assert "\n" not in msg and msg.startswith("LINE 5: ") and MOTION_CHANGES[statement] in msg, msg


def test_cancelling_a_motion_change_is_not_refused(tmp_path):
    # the cancel of a compensation or transformation that never started changes nothing
    (tmp_path / "c.apt").write_text("CUTTER/6\nCUTCOM/OFF\nTRACUT/NOMORE\nFEDRAT/500\nGOTO/0,0,0\nGOTO/1,0,0\n")
    tp = read_apt(tmp_path / "c.apt")
    assert len(tp) == 2 and tp.ignored == {"CUTCOM": 1, "TRACUT": 1}


def test_a_refused_statement_names_the_file_and_its_line(tmp_path, capsys):
    from evoplan.cli import main

    run = Path(__file__).resolve().parents[3] / "runs" / "fountas_toolpath_vega.yaml"
    apt = tmp_path / "cam.apt"
    apt.write_text("PARTNO X\nCUTTER/12,6\nFEDRAT/500\nGOTO/0,0,10\nTRANS/10,0,0\nGOTO/1,0,10\n")
    out = tmp_path / "sim"
    assert main(["simulate", str(run), "--apt", str(apt), "--out", str(out)]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and f"{apt}: LINE 5: TRANS" in err[0] and not out.exists(), err


CREO_HEAD = """$$* Pro/CLfile Version Creo 8.0
PARTNO / PRT0001
$$->FEATNO / 35
UNITS / MM
LOADTL / 1
CUTTER / 10.000000
$$-> CSYS / 1.0000000000, 0.0000000000, 0.0000000000, 0.0000000000, $
        0.0000000000, 1.0000000000, 0.0000000000, 0.0000000000, $
        0.0000000000, 0.0000000000, 1.0000000000, 0.0000000000
$$-> CSYS / 1.0, 0.0, 0.0, 0.0, $
$$->        0.0, 1.0, 0.0, 0.0, $
$$->        0.0, 0.0, 1.0, 0.0
$$ ******** $$
SPINDL / RPM, 1000.000000,  CLW
FEDRAT / 500.000000,  MMPM
"""


def test_a_creo_comment_continued_with_dollar_is_comment_on_all_its_lines(tmp_path):
    (tmp_path / "creo.ncl").write_text(CREO_HEAD + "GOTO / 1.0, 2.0, 3.0\nFINI\n")
    tp = read_apt(tmp_path / "creo.ncl")
    assert tp.tip.tolist() == [[1, 2, 3]] and tp.ignored == {} and tp.spindle_rpm == 1000
    # what follows a continued comment is read as statements again
    (tmp_path / "bad.ncl").write_text(CREO_HEAD + "GOTO / 1.0, 2.0, 3.0\nnot apt\n")
    with pytest.raises(AptError, match=r"^LINE 17: not an APT statement"):
        read_apt(tmp_path / "bad.ncl")


def test_a_goto_split_over_two_lines_reads_to_its_point(tmp_path):
    (tmp_path / "g.ncl").write_text(CREO_HEAD + "GOTO / 1.5, 2.0, $\n   -3.25\nGOTO / 4, 5, 6\n")
    tp = read_apt(tmp_path / "g.ncl")
    assert tp.tip.tolist() == [[1.5, 2.0, -3.25], [4, 5, 6]]
