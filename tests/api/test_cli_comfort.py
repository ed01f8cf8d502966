"""CLI comfort: --set on run and study, a quiet broken pipe, resuming a finished run, examples."""

from __future__ import annotations

import json
import subprocess
import sys

import yaml

from evoplan.cli import main

RUN = "problem: {name: kubota, bits: 10}\nalgorithm: {name: ga, population: 10}\n" \
      "termination: {generations: 3}\noutput: {plot: false}\n"


def test_set_changes_run_settings(tmp_path, capsys):
    path = tmp_path / "k.yaml"
    path.write_text(RUN)
    out = tmp_path / "r"
    assert main(["run", str(path), "--out", str(out), "--quiet", "--set", "algorithm.population=14",
                 "--set", "termination.generations=2", "--set", "problem.variables.x={bits: 6}"]) == 0
    saved = yaml.safe_load((out / "config.yaml").read_text())
    assert saved["algorithm"]["population"] == 14 and saved["termination"]["generations"] == 2
    assert saved["problem"]["variables"]["x"]["bits"] == 6
    assert json.loads(capsys.readouterr().out)["generations"] == 2


def test_bad_set_is_one_line_and_leaves_nothing(tmp_path, capsys):
    path = tmp_path / "k.yaml"
    path.write_text(RUN)
    for item, message in [("algorithm.populaton=3", f"{path}: algorithm.populaton: Extra inputs"),
                          ("algorithm.population=1", f"{path}: algorithm.population:"),
                          ("seed.x=1", f"{path}: seed: is 0"),
                          ("nothing", "--set 'nothing': expected KEY.PATH=VALUE")]:
        if item.startswith("seed"):
            path.write_text("seed: 0\n" + RUN)
        assert main(["run", str(path), "--out", str(tmp_path / "r"), "--set", item]) == 2
        err = capsys.readouterr().err
        assert err.startswith("evoplan: error: ") and message in err and err.count("\n") == 1, err
    assert not (tmp_path / "r").exists()


def test_set_on_study(tmp_path):
    study = tmp_path / "s.yaml"
    study.write_text("seed: 1\nseeds: 1\nbudget: {evaluations: 40}\nproblems: [{name: kubota, bits: 8}]\n"
                     "algorithms: [{name: ga, population: 10}]\noutput: {plots: false}\n")
    out = tmp_path / "s"
    assert main(["study", str(study), "--out", str(out), "--quiet", "--set", "seeds=2",
                 "--set", "budget.evaluations=30"]) == 0
    runs = (out / "runs.csv").read_text().splitlines()
    assert len(runs) == 1 + 2  # header + two seeds


def test_resume_of_a_finished_run_says_so(tmp_path, capsys):
    path = tmp_path / "k.yaml"
    path.write_text(RUN)
    out = tmp_path / "r"
    assert main(["run", str(path), "--out", str(out), "--quiet"]) == 0
    first = json.loads(capsys.readouterr().out)
    before = (out / "history.csv").read_bytes()
    assert main(["run", str(path), "--resume", str(out), "--quiet"]) == 0
    captured = capsys.readouterr()
    assert "this run is finished (stopped by generations" in captured.err
    assert json.loads(captured.out) == first and (out / "history.csv").read_bytes() == before


def test_broken_pipe_is_quiet():
    proc = subprocess.Popen([sys.executable, "-m", "evoplan", "examples"], stdout=subprocess.PIPE,
                            stderr=subprocess.PIPE)
    proc.stdout.close()  # the reader goes away before evoplan writes
    err = proc.stderr.read().decode()
    assert proc.wait() == 141 and err == ""


def test_examples_list_and_copy(tmp_path, capsys):
    assert main(["examples"]) == 0
    listed = capsys.readouterr().out
    assert "kubota_vega " in listed and "fountas_toolpath_pareto " in listed
    assert main(["examples", "kubota_vega", "--out", str(tmp_path)]) == 0
    copied = tmp_path / "kubota_vega.yaml"
    assert capsys.readouterr().out.strip() == str(copied)
    assert yaml.safe_load(copied.read_text())["algorithm"]["name"] == "vega"
    assert main(["examples", "kubota_vega", "--out", str(tmp_path)]) == 2  # never overwrites
    assert main(["examples", "nope"]) == 2
    assert "no example 'nope'" in capsys.readouterr().err


def test_examples_describe_each_file_by_a_whole_sentence():
    from evoplan.commands.examples import shipped, summary

    for name, f in shipped().items():
        text = summary(f.read_text())
        assert text.endswith((".", "!", "?")), (name, text)  # never cut mid-sentence
        comment = " ".join(line.lstrip("#").strip() for line in f.read_text().splitlines() if line.startswith("#"))
        assert " ".join(comment.split()).startswith(text), name
    assert summary("# Kubota's function (Eq. 13). Second sentence.\n# more\nseed: 1\n") == \
        "Kubota's function (Eq. 13)."
    assert summary("seed: 1\nalgorithms: []\n") == "study"
