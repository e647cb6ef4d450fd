"""Where the repository's folders are (examples, benchmarks), seen from an installed-in-place package."""

from __future__ import annotations

from pathlib import Path

__all__ = ["repo_root"]


def repo_root() -> Path:
    """The repository root of an in-place (editable) install: ``src/alcontact/app`` three levels down."""
    return Path(__file__).resolve().parents[3]
