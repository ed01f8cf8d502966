"""The documentation: the site builds in strict mode, lists every key, and code cites existing files."""

from __future__ import annotations

import re
import subprocess
import sys
from pathlib import Path

import yaml

from evoplan.config import REGISTRY, RunConfig

ROOT = Path(__file__).resolve().parents[2]
WRITTEN_BY_EVOPLAN = {"report.md"}  # files the code writes, not documents it cites


def test_site_builds_strict_with_every_page_and_key(tmp_path):
    site = tmp_path / "site"
    done = subprocess.run([sys.executable, "-m", "mkdocs", "build", "--strict", "-f", str(ROOT / "mkdocs.yml"),
                           "-d", str(site)], cwd=ROOT, capture_output=True, text=True, timeout=300)
    assert done.returncode == 0, done.stderr[-3000:]
    nav = yaml.safe_load((ROOT / "mkdocs.yml").read_text())["nav"]

    def pages(entries):
        for entry in entries:
            for value in entry.values():
                yield from pages(value) if isinstance(value, list) else [value]

    for page in pages(nav):
        assert (site / page.removesuffix(".md") / "index.html").is_file() or page == "index.md", page
    run_files = (site / "run-files" / "index.html").read_text()
    for key in RunConfig.model_fields:
        assert f"<code>{key}</code>" in run_files, key
    for name in REGISTRY:  # one table of settings per algorithm, generated from its model
        assert f"algorithm.name: {name}</code>" in run_files, name
    assert "<code>algorithm.virus.infectivity_force</code>" in run_files
    reference = (site / "reference" / "index.html").read_text()
    assert "minimize" in reference and "AskTell" in reference and "ToolpathProblem" in reference
    # docstrings' Sphinx roles render as links (docs/_hooks/sphinx_roles.py), never raw
    assert not re.search(r":(func|class|meth|mod|attr):", reference)
    assert 'href="#evoplan.api.minimize"><code>minimize</code></a>' in reference


def test_code_cites_only_files_in_the_repository():
    cited = re.compile(r"[A-Za-z0-9_./-]+\.md\b")
    missing = []
    for folder in ("evoplan", "operators", "problems", "tests"):
        for path in (ROOT / folder).rglob("*.py"):
            if path == Path(__file__).resolve():  # names the site's pages, cites nothing
                continue
            for name in set(cited.findall(path.read_text())):
                if name in WRITTEN_BY_EVOPLAN:
                    continue
                if not (ROOT / name).is_file():
                    missing.append(f"{path.relative_to(ROOT)}: {name}")
    assert not missing, missing


def test_every_package_folder_is_installed():
    """A folder with an __init__.py that pyproject's package list lacks would be missing from a
    wheel (an editable install still finds it, so only this test notices)."""
    import tomllib

    listed = set(tomllib.loads((ROOT / "pyproject.toml").read_text())["tool"]["setuptools"]["packages"])
    prefix = {"evoplan": "evoplan", "problems": "evoplan.problems", "operators": "evoplan.operators"}
    for top, name in prefix.items():
        for init in (ROOT / top).rglob("__init__.py"):
            parts = init.parent.relative_to(ROOT / top).parts
            assert ".".join((name, *parts)) in listed, init
