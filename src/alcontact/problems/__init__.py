"""Benchmark problems with known reference solutions.

- :mod:`alcontact.problems.hock_schittkowski` -- a selection of inequality-constrained
  problems from the Hock-Schittkowski collection (nonlinear programming, chapter 5).

Sub-modules are imported explicitly by their users; nothing heavy is imported here.
"""

from __future__ import annotations

__all__: list[str] = []
