"""Issues of a problem file: one ``(key path, message)`` pair per problem, and the helpers that word them.

Shared by the schema pass (:mod:`alcontact.io.config`), the section builders
(:mod:`alcontact.io._sections`) and the checks before a run
(:mod:`alcontact.io.preflight`); all issues of a file are raised together in one
:class:`~alcontact.errors.ConfigError`.
"""

from __future__ import annotations

import difflib
from dataclasses import dataclass

from .._options import BAD
from ..errors import ConfigError, InputError

__all__ = ["Issue"]


@dataclass(frozen=True)
class Issue:
    """One problem of a problem file: the key path and what is wrong (with the fix)."""

    path: str
    message: str

    def __str__(self) -> str:
        if not self.path:
            return self.message
        sep = " " if self.message.startswith("= ") else ": "  # "key = value: ..." or "key: ..."
        return f"{self.path}{sep}{self.message}"


def _raise(issues: list[Issue], source: str) -> None:
    """Raise every issue together: a :class:`ConfigError` headed by ``source`` and the count, ``exc.issues``."""
    n = len(issues)
    head = f"{source}: {n} error{'s' if n != 1 else ''} (nothing was solved)"
    exc = ConfigError(head + "\n" + "\n".join(f"  {i}" for i in issues))
    exc.issues = list(issues)  # type: ignore[attr-defined]
    raise exc


def _did_you_mean(name: str, known) -> str:
    close = difflib.get_close_matches(str(name), [str(k) for k in known], n=1, cutoff=0.6)
    return f" Did you mean {close[0]!r}?" if close else ""


def _known(names) -> str:
    names = sorted(str(n) for n in names)
    return ", ".join(names) if names else "(none)"


def _ok(d) -> bool:
    """A table that the schema pass accepted whole: present, and no value marked :data:`~alcontact._options.BAD`."""
    return d is not None and d is not BAD and all(v is not BAD for v in d.values())


def _num(issues, path, fn, *args, **kwargs):
    """Call a builder, turning its InputError into an issue at ``path``."""
    try:
        return fn(*args, **kwargs)
    except InputError as exc:
        issues.append(Issue(path, str(exc)))
        return None
