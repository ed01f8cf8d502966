"""Every bad input of the corpus: one line ``evoplan: error: ...``, exit 2, nothing written.

The commands run in-process through :func:`evoplan.cli.main`: an exception other than the
CLI's own one-line error escapes and fails the test (a traceback for a user), and the
``--out`` folder must not exist afterwards.
"""

from __future__ import annotations

import sys

import pytest

from evoplan.cli import main

from .corpus import GENERIC, GOOD, SPECIFIC, USER_MODULES, generic_text

CASES = [(cmd, f"generic: {name}", text, []) for cmd in GOOD for name, text in GENERIC] + SPECIFIC


@pytest.fixture
def user_modules(tmp_path, monkeypatch):
    folder = tmp_path / "usercode"
    folder.mkdir()
    for name, text in USER_MODULES.items():
        (folder / f"{name}.py").write_text(text)
    monkeypatch.syspath_prepend(str(folder))
    yield
    for name in USER_MODULES:
        sys.modules.pop(name, None)


def command_line(cmd: str, path, out, extra: list[str]) -> list[str]:
    if cmd == "evaluate":
        return ["evaluate", str(path), *extra] if extra else ["evaluate", str(path), "--set", "x=0", "--set", "y=0"]
    quiet = ["--quiet"] if cmd in ("run", "study") else []
    return [cmd, str(path), "--out", str(out), *quiet, *extra]


def write_case(tmp_path, cmd: str, case: str, text) -> object:
    path = tmp_path / "case.yaml"
    if text is None and case.startswith("generic: "):
        text = generic_text(case.removeprefix("generic: "), GOOD[cmd])
    if text is None:  # a control net whose bad line holds a secret that must not be echoed
        net = tmp_path / "net.csv"
        net.write_text("i,j,x,y,z\n0,0,0,0,0\nSECRET-TOKEN-123,1,2,3,4\n")
        text = GOOD["run"].replace("name: kubota, bits: 12", f"name: toolpath, bits: 8, params: "
                                   f"{{surface: {{type: bezier, poles: '{net}'}}}}")
    if isinstance(text, bytes):
        path.write_bytes(text)
    else:
        path.write_text(text)
    return path


@pytest.mark.parametrize("cmd,case,text,extra", CASES, ids=[f"{c[0]}-{c[1]}" for c in CASES])
def test_bad_input_is_one_line_exit_2_and_nothing_written(cmd, case, text, extra, tmp_path, capsys, user_modules):
    path = write_case(tmp_path, cmd, case, text)
    out = tmp_path / "out"
    try:
        code = main(command_line(cmd, path, out, extra))
    except SystemExit as e:  # argparse's own exit
        code = e.code
    err = capsys.readouterr().err
    assert code == 2, err
    lines = err.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("evoplan: error: "), err[:2000]
    assert len(lines[0]) < 600, "an error line must not echo its input"
    assert "SECRET-TOKEN" not in err and "root:" not in err
    assert not out.exists()


def test_the_good_files_of_the_corpus_run(tmp_path, capsys):
    """The corpus' base files are good, so each bad case is bad for the reason it names."""
    for cmd in ("run", "evaluate"):
        path = tmp_path / f"{cmd}.yaml"
        path.write_text(GOOD[cmd])
        assert main(command_line(cmd, path, tmp_path / f"out-{cmd}", [])) == 0, capsys.readouterr().err
    path = tmp_path / "zone.yaml"
    path.write_text(GOOD["zone"])
    from evoplan.commands.zone import load
    from evoplan.commands.study import main as _  # noqa: F401 - the study command imports
    assert load(path).kmeans.K == 2
