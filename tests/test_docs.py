"""The documentation site builds from ``docs/`` with ``mkdocs build --strict``: a broken link, a
missing anchor or an API reference that does not resolve fails the suite; every page is in the
navigation; the README stays an entry point, not the manual."""

from __future__ import annotations

import re
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

pytest.importorskip("mkdocs")
pytest.importorskip("mkdocstrings")
ROOT = Path(__file__).resolve().parent.parent


def build(root: Path, out: Path) -> subprocess.CompletedProcess:
    return subprocess.run([sys.executable, "-m", "mkdocs", "build", "--strict",
                           "-f", str(root / "mkdocs.yml"), "-d", str(out)],
                          capture_output=True, text=True, timeout=300, cwd=root,
                          env={"NO_MKDOCS_2_WARNING": "1", "PATH": "/usr/bin:/bin"})


def test_the_site_builds_strictly_with_its_api_reference(tmp_path):
    done = build(ROOT, tmp_path / "site")
    assert done.returncode == 0, done.stderr
    reference = (tmp_path / "site" / "reference" / "index.html").read_text()
    assert "FixedN" in reference and "PrimitiveEnv" in reference
    # nothing the pages load comes from another host: the site works offline (links may leave)
    loads = re.compile(r"<(?:link|script|img|iframe|source)\b[^>]*\b(?:href|src)=\"(?:https?:)?//"
                       r"|url\(\s*['\"]?(?:https?:)?//|@import\s+['\"]?(?:url\()?['\"]?(?:https?:)?//")
    outside = [str(page.relative_to(tmp_path)) for page in (tmp_path / "site").rglob("*")
               if page.suffix in (".html", ".css", ".js") and loads.search(page.read_text())]
    assert outside == []


def test_a_broken_link_fails_the_build(tmp_path):
    copy = tmp_path / "repo"
    shutil.copytree(ROOT / "docs", copy / "docs")
    shutil.copy(ROOT / "mkdocs.yml", copy / "mkdocs.yml")
    page = copy / "docs" / "statistics.md"
    page.write_text(page.read_text() + "\nSee [nowhere](no_such_page.md).\n")
    done = build(copy, tmp_path / "site")
    assert done.returncode != 0 and "no_such_page.md" in done.stderr


def test_every_page_is_in_the_navigation_and_the_readme_is_short():
    nav = (ROOT / "mkdocs.yml").read_text()
    pages = sorted(p.name for p in (ROOT / "docs").glob("*.md"))
    assert [p for p in pages if p not in nav] == []
    assert len((ROOT / "README.md").read_text().splitlines()) <= 250


def test_the_public_api_table_is_each_packages_all():
    """docs/python.md's table of what to import lists exactly each package's ``__all__``, and
    every name there imports."""
    import importlib

    text = (ROOT / "docs" / "python.md").read_text()
    rows = re.findall(r"^\| `(vlb_gym[\w.]*)` \| [^\n]*\| ([^|\n]+) \|$", text, re.MULTILINE)
    assert {module for module, _ in rows} == {"vlb_gym", "vlb_gym.wrappers", "vlb_gym.verify",
                                              "vlb_gym.core"}
    for module, names in rows:
        package = importlib.import_module(module)
        listed = set(re.findall(r"`([\w]+)`", names))
        assert listed == set(package.__all__), module
        for name in listed:
            assert getattr(package, name) is not None, f"{module}.{name}"
