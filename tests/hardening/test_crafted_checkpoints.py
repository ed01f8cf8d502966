"""Crafted checkpoints: a file written by someone who recomputed the checksum (a plain SHA-256
proves only that nobody changed the file after it was written) is still read defensively: its
array sizes are checked against the headers before anything is allocated, and its content
against the run's own state after the checksum. Each is one line, exit 2, and the folder keeps
its checkpoint."""

from __future__ import annotations

import io
import json
import struct
import time
import zipfile
from pathlib import Path

import numpy as np
import pytest

from evoplan.checkpoint import _digest
from evoplan.cli import main

RUN = ("seed: 3\nproblem: {name: kubota, bits: 10}\nalgorithm: {name: ga, population: 8}\n"
       "termination: {generations: 4}\ncheckpoint: {every_generations: 1}\noutput: {plot: false}\n")


@pytest.fixture(scope="module")
def finished(tmp_path_factory):
    root = tmp_path_factory.mktemp("ckpt")
    (root / "run.yaml").write_text(RUN)
    assert main(["run", str(root / "run.yaml"), "--out", str(root / "r"), "--quiet"]) == 0
    return root


def _load(path: Path) -> tuple[dict, dict[str, np.ndarray]]:
    with np.load(path, allow_pickle=False) as npz:
        arrays = {k: npz[k] for k in npz.files}
    meta = json.loads(arrays.pop("__state__").tobytes().decode())
    arrays.pop("__sha256__")
    return meta, arrays


def _write(path: Path, meta_or_body, arrays: dict[str, np.ndarray]) -> None:
    """A checkpoint with a correctly recomputed checksum, as an attacker would write it."""
    body = meta_or_body if isinstance(meta_or_body, bytes) else json.dumps(meta_or_body).encode()
    np.savez(path, __state__=np.frombuffer(body, dtype=np.uint8),
             __sha256__=np.frombuffer(_digest(body, arrays).encode(), dtype=np.uint8), **arrays)


def _crafted(finished, tmp_path, craft) -> Path:
    """A copy of the finished run folder, its checkpoint replaced by ``craft(meta, arrays, path)``,
    ready for ``--resume`` (``best.json`` removed so the run does not read as finished)."""
    out = tmp_path / "r"
    out.mkdir()
    for f in (finished / "r").iterdir():
        if f.name != "best.json":
            (out / f.name).write_bytes(f.read_bytes())
    meta, arrays = _load(out / "checkpoint.npz")
    craft(meta, arrays, out / "checkpoint.npz")
    return out


def _resume(finished, out, capsys) -> str:
    t0 = time.perf_counter()
    code = main(["run", str(finished / "run.yaml"), "--resume", str(out), "--quiet"])
    err = capsys.readouterr().err.strip()
    assert code == 2 and "\n" not in err and "cannot resume" in err, err
    assert time.perf_counter() - t0 < 30
    assert (out / "checkpoint.npz").is_file() and not (out / "best.json").exists()
    return err


def _find(meta, key):
    """The JSON node holding the RunState attribute ``key`` (a [key, value] pair of a $dict)."""
    for pair in meta["state"]["attrs"]["$dict"]:
        if pair[0] == key:
            return pair
    raise KeyError(key)


def test_an_untouched_copy_resumes(finished, tmp_path, capsys):
    out = _crafted(finished, tmp_path, lambda meta, arrays, path: _write(path, meta, arrays))
    assert main(["run", str(finished / "run.yaml"), "--resume", str(out), "--quiet"]) == 0


def test_a_header_claiming_a_terabyte_is_refused_before_allocation(finished, tmp_path, capsys):
    def craft(meta, arrays, path):
        _write(path, meta, arrays)
        header = b"{'descr': '<f8', 'fortran_order': False, 'shape': (1000000000000,), }"
        header += b" " * (63 - len(header) % 64) + b"\n"
        member = b"\x93NUMPY\x01\x00" + struct.pack("<H", len(header)) + header + b"\0" * 512
        with zipfile.ZipFile(path, "a") as zf:
            zf.writestr("huge.npy", member)
    err = _resume(finished, _crafted(finished, tmp_path, craft), capsys)
    assert "huge.npy" in err and "claims" in err


def test_a_compressed_member_is_refused(finished, tmp_path, capsys):
    def craft(meta, arrays, path):
        buf = io.BytesIO()
        np.savez_compressed(buf, **{"__state__": np.frombuffer(json.dumps(meta).encode(), dtype=np.uint8)})
        path.write_bytes(buf.getvalue())
    assert "uncompressed" in _resume(finished, _crafted(finished, tmp_path, craft), capsys)


def test_a_missing_array_is_refused(finished, tmp_path, capsys):
    def craft(meta, arrays, path):
        arrays.pop(sorted(arrays)[0])
        _write(path, meta, arrays)
    assert "array the file does not hold" in _resume(finished, _crafted(finished, tmp_path, craft), capsys)


def test_a_deeply_nested_state_is_refused(finished, tmp_path, capsys):
    def craft(meta, arrays, path):
        body = json.dumps(meta).encode()
        deep = b"[" * 50_000 + b"]" * 50_000
        _write(path, body[:-1] + b', "junk": ' + deep + b"}", arrays)
    assert "nested deeper" in _resume(finished, _crafted(finished, tmp_path, craft), capsys)


def test_deep_nesting_inside_the_state_is_refused(finished, tmp_path, capsys):
    def craft(meta, arrays, path):
        deep: list = []
        for _ in range(200):
            deep = [deep]
        _find(meta, "errors")[1] = deep
        _write(path, meta, arrays)
    assert "nested deeper" in _resume(finished, _crafted(finished, tmp_path, craft), capsys)


def test_a_string_where_an_array_belongs_is_refused(finished, tmp_path, capsys):
    def craft(meta, arrays, path):
        _find(meta, "best_g")[1] = "not an array"
        _write(path, meta, arrays)
    assert "best_g" in _resume(finished, _crafted(finished, tmp_path, craft), capsys)


@pytest.mark.parametrize("key, value", [("evaluations", 1e30), ("evaluations", 10**30), ("failures", -1),
                                        ("evaluations", 10**6)])
def test_counters_beyond_the_budget_are_refused(finished, tmp_path, capsys, key, value):
    def craft(meta, arrays, path):
        _find(meta, key)[1] = value
        _write(path, meta, arrays)
    assert f"state.{key}" in _resume(finished, _crafted(finished, tmp_path, craft), capsys)


def test_a_generation_past_the_run_is_refused(finished, tmp_path, capsys):
    def craft(meta, arrays, path):
        algo = _find(meta, "algorithm")[1]["attrs"]["$dict"]
        next(pair for pair in algo if pair[0] == "generation")[1] = 10**30
        _write(path, meta, arrays)
    assert "generation" in _resume(finished, _crafted(finished, tmp_path, craft), capsys)
