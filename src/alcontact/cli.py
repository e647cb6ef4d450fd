"""Command line interface: ``alcontact run``, ``alcontact list``.

Each command is a thin wrapper over one function of :mod:`alcontact.runner`
(:func:`~alcontact.runner.run_problem`, :func:`~alcontact.runner.list_components`):
this module parses options, shows progress and prints; it is the only module
of the package that prints.

Exit codes: 0 success; 1 the solver did not converge (message and what to
try on stderr; result files are still written) or another alcontact error;
2 bad input: an unknown name, a value out of range, or a non-empty results
folder without ``--force``.

New commands are added with ``@app.command()``.
"""

from __future__ import annotations

import contextlib
import logging
from collections.abc import Iterator
from pathlib import Path
from typing import Annotated, Optional

import typer
from rich.console import Console
from rich.table import Table
from rich.text import Text

from . import __version__
from .errors import AlcontactError, InputError, OutputExistsError

__all__ = ["app", "main"]

app = typer.Typer(
    name="alcontact",
    help="Augmented Lagrangian methods for elastic contact with rigid obstacles.",
    no_args_is_help=True,
    add_completion=False,
    pretty_exceptions_enable=False,
    context_settings={"help_option_names": ["-h", "--help"]},
)

EXIT_FAILED = 1
EXIT_USAGE = 2


def _consoles() -> tuple[Console, Console]:
    # created per call so that redirected streams (tests, pipes) are honoured
    return Console(), Console(stderr=True)


@contextlib.contextmanager
def _cli_logging(err: Console, level: int) -> Iterator[None]:
    """Route the library's log records (``alcontact.*``) to stderr through rich.

    The logger's level and handlers are restored afterwards, so calling the
    app in-process (tests, notebooks) leaves logging as it was.
    """
    from rich.logging import RichHandler

    log = logging.getLogger("alcontact")
    old_level = log.level
    handler = RichHandler(console=err, show_time=False, show_path=False, markup=False)
    handler.setLevel(level)
    log.addHandler(handler)
    log.setLevel(level)
    try:
        yield
    finally:
        log.removeHandler(handler)
        log.setLevel(old_level)


def _fail(err: Console, exc: Exception, code: int) -> typer.Exit:
    err.print(f"[bold red]error:[/] {exc}", highlight=False)
    return typer.Exit(code)


def _version(value: bool) -> None:
    if value:
        typer.echo(f"alcontact {__version__}")
        raise typer.Exit()


@app.callback()
def _root(
    version: Annotated[
        bool, typer.Option("--version", callback=_version, is_eager=True, help="Print the version and exit.")
    ] = False,
) -> None:
    """Augmented Lagrangian methods for elastic contact with rigid obstacles.

    `alcontact run` solves the built-in 2D Hertz problem and writes a results
    folder; `alcontact list` shows the registered algorithms, penalties,
    obstacles and problems.
    """


def _fmt(x, spec: str = ".5g") -> str:
    if x is None:
        return "-"
    if isinstance(x, float):
        return format(x, spec)
    return str(x)


def _summary_table(s: dict) -> Table:
    ok = s["status"] == "converged"
    table = Table(title=f"alcontact run: {s.get('problem_label') or s.get('problem')}", title_justify="left")
    table.add_column("quantity")
    table.add_column("computed", justify="right")
    table.add_column("exact", justify="right")
    table.add_column("error %", justify="right")
    table.add_row("status", f"[{'green' if ok else 'bold red'}]{s['status']}[/]", "", "")
    table.add_row("algorithm / penalty", Text(f"{s['algorithm']} / {s['penalty']}"), "", "")
    table.add_row("DOFs", _fmt(s["dofs"]), "", "")
    table.add_row("outer / Newton iterations", f"{s['outer_iterations']} / {s['newton_iterations']}", "", "")
    table.add_row("linear solves", _fmt(s["linear_solves"]), "", "")
    table.add_row("contact half-width a", _fmt(s["contact_half_width"]), _fmt(s["contact_half_width_exact"]),
                  _fmt(s.get("contact_half_width_error_pct"), "+.2f"))
    table.add_row("peak pressure p0", _fmt(s["peak_pressure"]), _fmt(s["peak_pressure_exact"]),
                  _fmt(s.get("peak_pressure_error_pct"), "+.2f"))
    table.add_row("total contact force P", _fmt(s["total_contact_force"]), "", "")
    table.add_row("max penetration / h", _fmt(s.get("penetration"), ".2e"), "", "")
    table.add_row("wall time (s)", _fmt(s["wall_time_s"], ".3f"), "", "")
    table.add_row("linear solve time (s)", _fmt(s["linear_solve_time_s"], ".3f"), "", "")
    table.add_row("contact / linear time", _fmt(s.get("time_ratio_contact_to_linear"), ".2f"), "", "")
    return table


@app.command("run")
def run_command(
    out: Annotated[Path, typer.Option("--out", "-o", help="Results folder (created if missing).")] = Path("results"),
    problem: Annotated[str, typer.Option("--problem", help="Built-in problem (see `alcontact list`).")] = "hertz-2d",
    algorithm: Annotated[
        Optional[str], typer.Option("--algorithm", "-a", help="Contact algorithm (default simo-laursen).")
    ] = None,
    penalty: Annotated[
        Optional[str], typer.Option("--penalty", "-p", help="Penalty of the family-p algorithm (default exp-met1).")
    ] = None,
    level: Annotated[
        Optional[int], typer.Option("--level", "-l", min=0, help="Mesh refinement level (default: the problem's).")
    ] = None,
    order: Annotated[int, typer.Option("--order", min=1, max=2, help="Polynomial order, 1 (P1) or 2 (P2).")] = 1,
    maxiter: Annotated[Optional[int], typer.Option("--maxiter", min=1, help="Outer iteration limit.")] = None,
    penalty_scale: Annotated[
        Optional[float], typer.Option("--penalty-scale", help="Multiplier of the automatic penalty stiffness E'/h.")
    ] = None,
    force: Annotated[bool, typer.Option("--force", "-f", help="Overwrite the result files in a non-empty --out.")] = False,
    quiet: Annotated[bool, typer.Option("--quiet", "-q", help="Print nothing unless something fails.")] = False,
    verbose: Annotated[bool, typer.Option("--verbose", "-v", help="Log the solver's progress.")] = False,
) -> None:
    """Solve a contact problem (default: 2D Hertz) and write a results folder.

    Files in --out: solution.vtu (displacement, contact_pressure, gap, von_mises),
    pressure.png, convergence.png, history.csv, summary.json.
    """
    from .runner import run_problem, what_to_try

    console, err = _consoles()
    if quiet and verbose:
        raise _fail(err, InputError("--quiet and --verbose exclude each other; give one."), EXIT_USAGE)
    level_ = logging.INFO if verbose else logging.ERROR if quiet else logging.WARNING
    kwargs = dict(problem=problem, out=out, algorithm=algorithm, penalty=penalty, force=force, level=level,
                  order=order, maxiter=maxiter, penalty_scale=penalty_scale)
    try:
        with _cli_logging(err, level_):
            if quiet:
                _, summary = run_problem(**kwargs)
            else:
                with err.status("starting", spinner="dots") as status:
                    _, summary = run_problem(**kwargs, progress=lambda msg: status.update(f"{msg} ..."))
    except OutputExistsError as exc:
        raise _fail(err, exc, EXIT_USAGE) from None
    except InputError as exc:
        raise _fail(err, exc, EXIT_USAGE) from None
    except AlcontactError as exc:
        raise _fail(err, exc, EXIT_FAILED) from None

    if not quiet:
        console.print(_summary_table(summary))
        console.print(f"results written to [bold]{out}[/]", highlight=False)
    if summary["status"] != "converged":
        err.print(f"[bold red]not converged ({summary['status']}):[/] {summary['message']}", highlight=False)
        err.print(f"[yellow]what to try:[/] {what_to_try(summary['status'])}", highlight=False)
        if out is not None:
            err.print(f"the result files in {out} show the last iterate.", highlight=False)
        raise typer.Exit(EXIT_FAILED)


@app.command("list")
def list_command(
    what: Annotated[
        Optional[str],
        typer.Argument(help="Only one section: algorithms, penalties, obstacles or problems."),
    ] = None,
) -> None:
    """List the registered algorithms, penalties, obstacles and built-in problems."""
    from .runner import list_components

    console, err = _consoles()
    sections = list_components()
    if what is not None and what not in sections:
        raise _fail(err, InputError(f"unknown section {what!r}; use one of {', '.join(sections)}."), EXIT_USAGE)
    for name, entries in sections.items():
        if what is not None and name != what:
            continue
        table = Table(title=name, title_justify="left", show_header=False, box=None, pad_edge=False)
        table.add_column("name", style="bold cyan", no_wrap=True)
        table.add_column("description")
        for key, doc in entries.items():
            table.add_row(Text(key), Text(doc))  # Text: no markup in docs like "[contact]"
        console.print(table)
        console.print()
    if what in (None, "penalties"):
        console.print("[contact]: usable with --algorithm family-p --penalty NAME", highlight=False, markup=False)


def main(argv: list[str] | None = None) -> None:
    """Console-script entry point (``alcontact``)."""
    app(args=argv, prog_name="alcontact")


if __name__ == "__main__":  # pragma: no cover
    main()
