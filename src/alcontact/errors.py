"""Exception types used across alcontact.

Every error raised for bad user input derives from :class:`AlcontactError`
and its message names the offending key or value and the way out.
"""

from __future__ import annotations

__all__ = [
    "AlcontactError",
    "InputError",
    "UnknownNameError",
    "DomainError",
    "NonFiniteError",
    "LawDomainError",
    "ConvergenceError",
    "ConfigError",
    "MeshError",
    "OutputExistsError",
    "OutputInUseError",
    "OutputPathError",
    "InvertedElementError",
]


class AlcontactError(Exception):
    """Base class of every error alcontact raises on purpose."""


class InputError(AlcontactError, ValueError):
    """Inconsistent or out-of-range input (dimensions, material constants, ...)."""


class UnknownNameError(InputError, KeyError):
    """A registry lookup with a name that is not registered.

    The message lists the known names and the closest match.
    """

    def __init__(self, kind: str, name: str, known: list[str]):
        import difflib

        self.kind, self.name, self.known = kind, name, sorted(known)
        close = difflib.get_close_matches(str(name), self.known, n=1)
        hint = f" Did you mean {close[0]!r}?" if close else ""
        msg = f"unknown {kind} {name!r}.{hint} Known {kind}s: {', '.join(self.known)}."
        super().__init__(msg)

    def __str__(self) -> str:  # KeyError would otherwise quote the message
        return self.args[0]


class DomainError(InputError):
    """A point outside the domain of a barrier-type penalty."""


class NonFiniteError(AlcontactError, FloatingPointError):
    """A callback returned NaN or infinity."""


class ConvergenceError(AlcontactError, RuntimeError):
    """Raised by ``raise_for_status()`` when a solver did not converge."""


class ConfigError(InputError):
    """A problem file with a wrong key, type or value (message holds the key path)."""


class MeshError(InputError):
    """An unreadable mesh or a boundary/region name the mesh does not have."""


class OutputExistsError(AlcontactError, FileExistsError):
    """A results folder exists and ``--force`` was not given."""


class OutputInUseError(OutputExistsError):
    """Another run is writing the same results folder (its lock file is held)."""


class OutputPathError(InputError):
    """A results folder that cannot be created: a parent is a file, or the place is read-only."""


class InvertedElementError(AlcontactError, ArithmeticError):
    """A deformation with :math:`J = \\det F \\le 0` in some element (finite deformation).

    Raised by hyperelastic bodies instead of returning NaN; Newton solvers treat it
    as a rejected step (line-search backtracking or load-step cut-back).

    Attributes
    ----------
    elements : ndarray of int
        Indices of the inverted elements.
    """

    def __init__(self, message: str, elements=()):
        import numpy as np

        self.elements = np.asarray(elements, dtype=np.int64)
        super().__init__(message)


class LawDomainError(InvertedElementError):
    """A deformation outside the domain of the material law in some element (e.g. the Gent law's
    locking, I1b - 3 >= Jm): treated like an inverted element (a rejected step)."""
