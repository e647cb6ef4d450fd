"""``alcontact bench``: the benchmark suites of ``benchmarks/`` and the quick-bench time estimate."""

from __future__ import annotations

import datetime as _dt
import os
import time
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from .. import __version__
from ..errors import InputError, UnknownNameError
from ._paths import repo_root

__all__ = ["BenchSuite", "BENCH_SUITES", "quick_bench_estimate", "run_benchmarks"]


@dataclass(frozen=True)
class BenchSuite:
    """A benchmark script of ``benchmarks/`` with ``run(out_dir, [cases,] variants)``."""

    script: str
    report: str
    takes_cases: bool
    quick: dict


#: Benchmark suites of ``alcontact bench``.
BENCH_SUITES: dict[str, BenchSuite] = {
    "hertz": BenchSuite("hertz.py", "hertz.md", True,
                        {"cases": ["2d-10k"], "variants": ["ssn", "simo-laursen", "exp-met1", "log-met2"]}),
    "friction": BenchSuite("friction.py", "friction.md", True,
                           {"cases": ["mindlin-2d"], "variants": ["ssn", "simo-laursen", "exp-met1"]}),
    "nlp": BenchSuite("nlp_hs.py", "nlp_hs.md", False, {"variants": ["rockafellar", "exp-met1", "SLSQP"]}),
    "finite": BenchSuite("finite.py", "finite.md", True,
                         {"cases": ["2d-5k"], "variants": ["ssn", "simo-laursen", "quad-met1"]}),
    "ironing": BenchSuite("ironing.py", "ironing.md", True,
                          {"cases": ["2d-s"], "variants": ["ssn", "simo-laursen", "exp-met1"]}),
    "two-body-ironing": BenchSuite("two_body_ironing.py", "two_body_ironing.md", True,
                                   {"cases": ["tiny"], "variants": ["ssn"]}),
}


def quick_bench_estimate(suites=None) -> tuple[float, str] | None:
    """Seconds ``alcontact bench --quick`` takes for ``suites`` (default all), and where that was measured.

    From the committed calibration (``benchmarks/time_estimates.py --bench`` writes
    ``alcontact/io/time_calibration.json``); ``None`` without one.
    """
    from ..io.preflight import machine_kind, time_calibration

    cal = time_calibration()
    per = ((cal.get("bench_quick") or {}).get("suites_s")) or {}
    names = list(suites or BENCH_SUITES)
    if not per or any(n not in per for n in names if n in BENCH_SUITES):
        return None
    overhead = max(float(cal["bench_quick"].get("total_s", 0.0)) - sum(per.values()), 0.0)  # start, imports
    return overhead + float(sum(per[n] for n in names if n in per)), machine_kind(cal)


def run_benchmarks(out: str | os.PathLike, *, suites=None, quick: bool = False, cases=None, variants=None,
                   benchmarks_dir: str | os.PathLike | None = None, log: Callable[[str], None] | None = None) -> Path:
    """``alcontact bench``: run benchmark scripts of ``benchmarks/`` and write ``bench.md``.

    Each suite's script is loaded with :func:`runpy.run_path` and its ``run``
    function called (``hertz.py``, ``friction.py``, ``finite.py``, ``ironing.py``, ``two_body_ironing.py``:
    ``run(out_dir, cases, variants)``,
    ``nlp_hs.py``: ``run(out_dir, variants)``); each writes its CSV and
    markdown into ``out``; ``bench.md`` joins the markdown reports.

    Raises
    ------
    InputError
        Unknown suite, or the benchmarks folder is missing (pass ``benchmarks_dir``).
    """
    import runpy

    from ..io import write_text_atomic

    names = list(suites or BENCH_SUITES)
    for s in names:
        if s not in BENCH_SUITES:
            raise UnknownNameError("benchmark suite", s, list(BENCH_SUITES))
    folder = Path(benchmarks_dir) if benchmarks_dir is not None else repo_root() / "benchmarks"
    if not folder.is_dir():
        raise InputError(f"benchmarks folder {str(folder)!r} not found; run from a checkout of the repository "
                         "or pass --benchmarks-dir.")
    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    parts = ["# alcontact benchmarks", "",
             f"alcontact {__version__}, {_dt.datetime.now(_dt.timezone.utc).isoformat(timespec='seconds')}"
             + (" (quick)" if quick else ""), ""]
    for s in names:
        suite = BENCH_SUITES[s]
        path = folder / suite.script
        if not path.is_file():
            raise InputError(f"benchmark script {str(path)!r} not found; pass --benchmarks-dir.")
        ns = runpy.run_path(str(path), run_name=f"alcontact_bench_{s}")
        kw: dict[str, Any] = dict(suite.quick) if quick else {}
        if variants:
            kw["variants"] = list(variants)
        if cases and suite.takes_cases:
            kw["cases"] = list(cases)
        if log is not None:
            log(f"benchmark {s}: {', '.join(f'{k}={v}' for k, v in kw.items()) or 'full'}")
        t0 = time.perf_counter()
        if suite.takes_cases:
            ns["run"](out, kw.get("cases"), kw.get("variants"), **({"log": log} if log is not None else {}))
        else:
            ns["run"](out, kw.get("variants"))
        md = out / suite.report
        parts += [f"<!-- {s}: {time.perf_counter() - t0:.1f} s -->", ""]
        if md.is_file():
            text = md.read_text(encoding="utf-8")
            parts += ["#" + text if text.startswith("# ") else text, ""]
    report = out / "bench.md"
    write_text_atomic(report, "\n".join(parts))
    return report
