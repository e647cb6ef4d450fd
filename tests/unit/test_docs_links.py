"""README.md and docs/: every relative link and every named repository file exists in the repository."""

from __future__ import annotations

import re
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
PAGES = [ROOT / "README.md", *sorted((ROOT / "docs").rglob("*.md"))]
LINK = re.compile(r"\]\(\s*<?([^)>\s]+)>?(?:\s+\"[^\"]*\")?\s*\)")  # [text](target "title")
NAMED = re.compile(r"`((?:docs|examples)/[\w./-]+\.(?:md|toml|csv))`")  # `docs/x.md`, `examples/y.toml`


def _targets(page: Path) -> list[str]:
    return _targets_of(page.read_text(encoding="utf-8"))


@pytest.mark.parametrize("page", PAGES, ids=[str(p.relative_to(ROOT)) for p in PAGES])
def test_relative_links_resolve_inside_the_repository(page):
    for target in _targets(page):
        path = (page.parent / target.split("#")[0]).resolve()
        assert path.is_relative_to(ROOT), f"{page.name}: link {target!r} leaves the repository"
        assert path.exists(), f"{page.name}: link {target!r} points to a missing file"


@pytest.mark.parametrize("page", PAGES, ids=[str(p.relative_to(ROOT)) for p in PAGES])
def test_named_repository_files_exist_and_nothing_outside_is_referenced(page):
    text = page.read_text(encoding="utf-8")
    for name in NAMED.findall(text):
        assert (ROOT / name).exists(), f"{page.name} names {name!r}, which is not in the repository"
    assert "shared/docs" not in text and "/work/" not in text, f"{page.name} refers to files outside the repository"


def test_the_checker_finds_links():
    targets = _targets(ROOT / "README.md")
    assert "docs/dissertation.md" in targets and "docs/problem-file.md" in targets
    assert _targets_of("see [a](missing.md) and [b](https://x.org) [c](#top)") == ["missing.md"]


def _targets_of(text: str) -> list[str]:
    """Relative link targets of markdown ``text`` (code blocks hold no links; URLs and anchors skipped)."""
    text = re.sub(r"```.*?```", "", text, flags=re.S)
    return [t for t in LINK.findall(text) if not re.match(r"^[a-z][a-z0-9+.-]*:|^#", t)]
