"""Control-net files are read with limits: no aliases (an alias bomb), no runaway nesting,
UTF-8 only, at most 4 MiB; every refusal is one line that names the key and the file."""

import pytest

from evoplan.problems.toolpath.geometry.spec import MAX_NET_BYTES, load_poles

CASES = {
    "alias_bomb.yaml": "a: &a [1, 2, 3]\nb: &b [*a, *a, *a]\npoles: [*b, *b]\n",
    "deep.yaml": "poles: " + "[" * 5000 + "]" * 5000 + "\n",
    "binary.yaml": b"\xff\xfe\x00\x01poles",
    "big.json": "[" + " " * (MAX_NET_BYTES + 1) + "]",
}


@pytest.mark.parametrize("name", sorted(CASES))
def test_bad_control_net_files_are_refused_in_one_line(name, tmp_path):
    path = tmp_path / name
    data = CASES[name]
    path.write_bytes(data if isinstance(data, bytes) else data.encode())
    with pytest.raises(ValueError) as err:
        load_poles(str(path))
    msg = str(err.value)
    assert msg.startswith("surface.poles: ") and "\n" not in msg and len(msg) < 300


def test_a_good_yaml_net_still_loads(tmp_path):
    path = tmp_path / "net.yaml"
    path.write_text("poles: [[[0, 0, 0], [0, 1, 0]], [[1, 0, 0], [1, 1, 1]]]\n")
    assert load_poles(str(path)).shape == (2, 2, 3)


def test_a_zoning_mesh_too_large_for_memory_is_refused_before_allocation():
    from evoplan.problems.toolpath import ToolpathSpec
    from tests.choi_zoning import choi_zoning

    with pytest.raises(ValueError, match=r"^zoning.mesh: a 200000 x 200000 mesh needs about [0-9.]+ GiB"):
        ToolpathSpec.from_params(choi_zoning(mesh=(200000, 200000)))
