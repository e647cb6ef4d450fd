"""Command line interface: ``alcontact run``, ``check``, ``list``, ``bench``, ``study``, ``docs``.

Each command is a thin wrapper over one function of :mod:`alcontact.app`
(:func:`~alcontact.app.run_problem`, :func:`~alcontact.app.run_setup`,
:func:`~alcontact.app.list_components`) or :mod:`alcontact.io.config`:
this module parses options, shows progress and prints; it is the only module
of the package that prints.

Exit codes: 0 success; 1 the solver did not converge (message and what to
try on stderr; result files are still written) or another alcontact error;
2 bad input: an unknown name, a value out of range, a non-empty results
folder without ``--force``, an ``--out`` that cannot be created; 130 / 143
interrupted by SIGINT (Ctrl+C) / SIGTERM: a message says whether the results
folder was written; it is never left half written (see
:class:`alcontact.io.ResultsFolder`).

New commands are added with ``@app.command()``.
"""

from __future__ import annotations

import contextlib
import logging
import signal
import threading
import warnings
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


def _check_launch(err: Console) -> None:
    """Refuse `alcontact run` started as several MPI ranks (alcontact.distributed.check_launch); rank 0 says why."""
    from .distributed import check_launch, launch_rank

    try:
        check_launch("alcontact run")
    except InputError as exc:
        if launch_rank() == 0:
            raise _fail(err, exc, EXIT_USAGE) from None
        raise typer.Exit(EXIT_USAGE) from None


#: names of the exceptions of bad input (a DistributedError carries the failed ranks' messages as text)
_INPUT_ERRORS = ("InputError", "UnknownNameError", "DomainError", "ConfigError", "MeshError", "OutputPathError",
                 "OutputExistsError", "OutputInUseError")


def _distributed_launch() -> bool:
    """Started as several MPI ranks in an environment with the MPI extras (the distributed path runs)."""
    from .distributed import launch_size, mpi_extras_missing

    return launch_size() > 1 and not mpi_extras_missing()


def _run_mpi(problem_file: Path, out, console: Console, err: Console, level: int, quiet: bool, *, force: bool,
             algorithm, penalty, overrides) -> None:
    """``mpirun -n N alcontact run PROBLEM.toml``: the distributed contact path; rank 0 prints, every rank exits
    with the one status (:func:`alcontact.app.distributed.run_distributed`)."""
    from .app.distributed import headline, run_distributed
    from .distributed import DistributedError, world

    comm = world()
    try:
        with _cli_logging(err, level if comm.rank == 0 else logging.ERROR):
            summary = run_distributed(problem_file, out, force, algorithm=algorithm, penalty=penalty,
                                      overrides=overrides, comm=comm)
    except DistributedError as exc:
        # bad input on every failed rank (the messages start with the exception's name): the usage code
        code = EXIT_USAGE if all(m.startswith(_INPUT_ERRORS) for m in exc.failures.values()) else EXIT_FAILED
        if comm.rank == 0:
            raise _fail(err, exc, code) from None
        raise typer.Exit(code) from None
    except KeyboardInterrupt:
        raise
    except Exception as exc:  # noqa: BLE001 - one rank failed outside the agreed phases: stop every rank
        err.print(f"error on MPI rank {comm.rank}: {type(exc).__name__}: {exc}", highlight=False)
        comm.Abort(EXIT_FAILED)
        raise
    if comm.rank == 0 and not quiet:
        console.print(headline(summary), highlight=False)
    if summary["status_code"] < 0:
        raise typer.Exit(EXIT_FAILED)


class _NoteWarnings(logging.Filter):
    """Appends ``note`` to the warnings shown (e.g. that a benchmark's failed solve is expected)."""

    def __init__(self, note: str):
        super().__init__()
        self._note = note

    def filter(self, record: logging.LogRecord) -> bool:
        if record.levelno >= logging.WARNING and not getattr(record, "_noted", False):
            record.msg, record.args, record._noted = f"{record.getMessage()} {self._note}", (), True
        return True


@contextlib.contextmanager
def _cli_logging(err: Console, level: int, note: str | None = None) -> Iterator[None]:
    """Route the library's log records (``alcontact.*``) to stderr through rich.

    The logger's level and handlers are restored afterwards, so calling the
    app in-process (tests, notebooks) leaves logging as it was. ``note`` is
    appended to every warning shown.
    """
    from rich.logging import RichHandler

    log = logging.getLogger("alcontact")
    old_level = log.level
    handler = RichHandler(console=err, show_time=False, show_path=False, markup=False)
    handler.setLevel(level)
    if note:
        handler.addFilter(_NoteWarnings(note))
    log.addHandler(handler)
    log.setLevel(level)
    try:
        with warnings.catch_warnings():
            # NumPy/Matplotlib warnings (overflow in a trial step, a flat plot) are no message for the user:
            # they become debug records of the library (shown with --verbose at DEBUG level, never raw on stderr)
            warnings.simplefilter("always")
            warnings.showwarning = _warning_to_log
            yield
    finally:
        log.removeHandler(handler)
        log.setLevel(old_level)


def _warning_to_log(message, category, filename, lineno, file=None, line=None) -> None:
    logging.getLogger("alcontact.warnings").debug("%s: %s (%s:%s)", category.__name__, message, filename, lineno)


class Interrupted(KeyboardInterrupt):
    """Raised in the main thread by SIGINT or SIGTERM during ``alcontact run``.

    A ``KeyboardInterrupt``, so that every ``with`` block on the way out (the
    results folder above all) cleans up as for Ctrl+C.
    """

    def __init__(self, signum: int):
        super().__init__(signal.Signals(signum).name)
        self.signum = int(signum)


def _raise_interrupted(signum: int, frame) -> None:
    raise Interrupted(signum)


_SIGNALS = tuple(getattr(signal, n) for n in ("SIGINT", "SIGTERM") if hasattr(signal, n))


@contextlib.contextmanager
def _signals_raise() -> Iterator[None]:
    """SIGINT and SIGTERM raise :class:`Interrupted` during the block (main thread only); handlers restored.

    A signal the process ignores (e.g. SIGINT of a background job ``alcontact run ... &``
    started by a script) stays ignored.
    """
    if threading.current_thread() is not threading.main_thread():
        yield
        return
    old = {s: signal.signal(s, _raise_interrupted) for s in _SIGNALS if signal.getsignal(s) is not signal.SIG_IGN}
    try:
        yield
    finally:
        for s, handler in old.items():
            signal.signal(s, handler if handler is not None else signal.SIG_DFL)


def _interrupted(err: Console, exc: KeyboardInterrupt, out) -> typer.Exit:
    """Say what an interrupt left behind; exit 128 + the signal number (130 SIGINT, 143 SIGTERM)."""
    signum = getattr(exc, "signum", int(signal.SIGINT))
    name = signal.Signals(signum).name
    where = f"'{out}'" if out is not None else "the results folder"
    if getattr(exc, "results_state", None) == "written":
        msg = f"interrupted by {name} after the complete results were written to {where}."
    else:
        msg = (f"interrupted by {name}: the run stopped before its results were complete; {where} was left "
               "as it was (no partial or temporary files).")
    err.print(Text(msg, style="bold red"), highlight=False)
    return typer.Exit(128 + signum)


def _fail(err: Console, exc: Exception, code: int) -> typer.Exit:
    msg = Text("error: ", style="bold red")
    msg.append(str(exc))  # plain text: messages hold TOML table names like [mesh]
    err.print(msg, highlight=False)
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

    `alcontact run` solves the built-in 2D Hertz problem (or a TOML problem
    file) and writes a results folder; `alcontact check FILE` validates a
    problem file; `alcontact list` shows the registered algorithms, penalties,
    obstacles and problems; `alcontact bench` runs the benchmarks; `alcontact
    study` measures every method over problems and penalty parameters; `alcontact
    docs` regenerates docs/problem-file.md.
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
    units = s.get("units") or {}
    length = f" ({units['length']})" if units.get("length") else ""
    stress = f" ({units['stress']})" if units.get("stress") else ""
    force = f" ({units['force']})" if units.get("force") else ""
    loaded_zone = s.get("contact_half_width_measure") == "half the extent of the loaded zone"
    table.add_row(f"contact half-width a{' (half the loaded zone)' if loaded_zone else ''}{length}",
                  _fmt(s["contact_half_width"]),
                  _fmt(s["contact_half_width_exact"]), _fmt(s.get("contact_half_width_error_pct"), "+.2f"))
    table.add_row(f"peak pressure p0{stress}", _fmt(s["peak_pressure"]), _fmt(s["peak_pressure_exact"]),
                  _fmt(s.get("peak_pressure_error_pct"), "+.2f"))
    table.add_row(f"total contact force P{force}", _fmt(s["total_contact_force"]), "", "")
    if s.get("friction"):
        table.add_row("tangential force |Q| = |sum q_i| (model)", _fmt(s.get("tangential_force")),
                      f"<= mu N = {_fmt(s.get('coulomb_limit'))}", "")
        if s.get("tangential_force_magnitude_sum") is not None:  # = mu N where every loaded point slips
            table.add_row("sum |q_i| (model)", _fmt(s["tangential_force_magnitude_sum"]),
                          f"<= mu N = {_fmt(s.get('coulomb_limit'))}", "")
        table.add_row("stick / slip / open points",
                      f"{s.get('stick_points')} / {s.get('slip_points')} / {s.get('open_points')}", "", "")
        if s.get("stick_half_width_exact") is not None:
            table.add_row("stick half-width c", _fmt(s.get("stick_half_width")), _fmt(s["stick_half_width_exact"]),
                          _fmt(s.get("stick_half_width_error_pct"), "+.2f"))
    if s.get("kinematics") == "finite":
        table.add_row("kinematics / material", f"finite / {s.get('material_model')}", "", "")
        table.add_row("Newton iterations per step", Text(" ".join(map(str, s.get("step_newton_iterations", [])))
                                                         or "-"), "", "")
        table.add_row("cut-backs", _fmt(s.get("cutbacks")), "", "")
        table.add_row(f"final contact force{force}", Text(", ".join(_fmt(x) for x in s.get("final_contact_force", []))),
                      "", "")
        table.add_row("equilibrium residual", _fmt(s.get("equilibrium_residual"), ".2e"), "", "")
    stepped = s.get("load_steps", 1) > 1
    if stepped:
        table.add_row("load steps (converged)", f"{s.get('converged_steps')} / {s['load_steps']}", "", "")
    table.add_row("max penetration / h", _fmt(s.get("penetration"), ".2e"), "", "")
    table.add_row("wall time, all steps (s)" if stepped else "wall time (s)", _fmt(s["wall_time_s"], ".3f"), "", "")
    if s.get("linear_solve_time_kind") == "mean Newton linear solve":  # finite: the solver times all solves
        table.add_row(f"one Newton linear solve, mean of {s.get('linear_solve_count')} (s)",
                      _fmt(s["linear_solve_time_s"], ".3g"), "", "")
    else:
        table.add_row("one linear solve (s)", _fmt(s["linear_solve_time_s"], ".3f"), "", "")
    table.add_row("wall time / linear solve", _fmt(s.get("time_ratio_contact_to_linear"), ".2f"), "", "")
    return table


@app.command("run")
def run_command(
    problem_file: Annotated[
        Optional[Path], typer.Argument(help="TOML problem file (see examples/ and docs/problem-file.md); "
                                            "default: the built-in --problem.", show_default=False)
    ] = None,
    out: Annotated[
        Optional[Path], typer.Option("--out", "-o", help="Results folder (created if missing); default `results`, "
                                                         "or [output] folder of the problem file.")
    ] = None,
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
    order: Annotated[
        Optional[int], typer.Option("--order", min=1, max=2, help="Polynomial order of a built-in problem, 1 or 2.")
    ] = None,
    maxiter: Annotated[Optional[int], typer.Option("--maxiter", min=1, help="Outer iteration limit.")] = None,
    penalty_scale: Annotated[
        Optional[float], typer.Option("--penalty-scale", help="Multiplier of the automatic penalty stiffness E'/h.")
    ] = None,
    force: Annotated[bool, typer.Option("--force", "-f", help="Overwrite the result files in a non-empty --out.")] = False,
    quiet: Annotated[bool, typer.Option("--quiet", "-q", help="Print nothing unless something fails.")] = False,
    verbose: Annotated[bool, typer.Option("--verbose", "-v", help="Log the solver's progress.")] = False,
) -> None:
    """Solve a contact problem and write a results folder.

    Without PROBLEM_FILE: the built-in 2D Hertz problem (or --problem). With a
    TOML file: the file is validated first (see `alcontact check`); --algorithm,
    --penalty, --maxiter and --penalty-scale override it.

    Files in --out: solution.vtu (displacement, stress, contact_pressure, gap, ...),
    pressure.png, convergence.png, history.csv, report.md, summary.json; problem
    files add steps.csv and, for load steps, solution.pvd, steps/ and
    load_displacement.png; finite-deformation files (kinematics = "finite") write
    the VTU files in the deformed configuration and add reaction_force.csv and
    reaction_force.png. The folder appears only when complete; --force
    replaces the files of an earlier run (listed in its summary.json) and keeps
    other files. Ctrl+C / SIGTERM: exit 130 / 143, the folder left as it was.
    """
    from .app import run_problem, what_to_try

    console, err = _consoles()
    if quiet and verbose:
        raise _fail(err, InputError("--quiet and --verbose exclude each other; give one."), EXIT_USAGE)
    level_ = logging.INFO if verbose else logging.ERROR if quiet else logging.WARNING
    if problem_file is not None and _distributed_launch():
        overrides = {k: v for k, v in (("maxiter", maxiter), ("penalty_scale", penalty_scale)) if v is not None}
        return _run_mpi(problem_file, out, console, err, level_, quiet, force=force, algorithm=algorithm,
                        penalty=penalty, overrides=overrides)
    _check_launch(err)
    if problem_file is not None:
        if problem != "hertz-2d" or level is not None or order is not None:
            raise _fail(err, InputError("--problem, --level and --order select a built-in problem; with a problem "
                                        "file set the mesh in the file instead."), EXIT_USAGE)
        try:
            with _signals_raise():
                summary, out = _run_file(problem_file, out, console, err, level_, quiet, force=force,
                                         algorithm=algorithm, penalty=penalty, maxiter=maxiter,
                                         penalty_scale=penalty_scale)
        except KeyboardInterrupt as exc:
            raise _interrupted(err, exc, out) from None
    else:
        out = out if out is not None else Path("results")
        kwargs = dict(problem=problem, out=out, algorithm=algorithm, penalty=penalty, force=force, level=level,
                      order=order or 1, maxiter=maxiter, penalty_scale=penalty_scale)
        try:
            from .io.results import output_lock

            with _signals_raise(), _cli_logging(err, level_), output_lock(out):
                _check_builtin_size(problem, level, order or 1)  # what `alcontact check` checks in a file
                if quiet:
                    _, summary = run_problem(**kwargs)
                elif not err.is_terminal:  # batch job, pipe: one line per phase with the elapsed time
                    _, summary = run_problem(**kwargs, progress=_LineProgress(err, problem).phase)
                else:
                    with err.status("starting", spinner="dots") as status:
                        _, summary = run_problem(**kwargs, progress=lambda msg: status.update(f"{msg} ..."))
        except KeyboardInterrupt as exc:
            raise _interrupted(err, exc, out) from None
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


def _builtin_meshes() -> dict:
    """Mesh of each built-in problem by name: (dimension, elements per contact half-width by level)."""
    from .problems import hertz

    return {"hertz-2d": (2, hertz.LEVELS_2D), "hertz-3d": (3, hertz.LEVELS_3D)}


def _check_builtin_size(name: str, level: int | None, order: int) -> None:
    """Refuse a built-in problem too large for this machine, before meshing, as ``alcontact check`` refuses a file.

    The mesh is counted from its axes (:func:`alcontact.problems.hertz.mesh_spec`,
    :func:`alcontact.io.preflight.estimate_size`) and judged by
    :func:`alcontact.io.preflight.size_issues` (DOF, time and memory limits).

    Raises
    ------
    InputError
        Naming ``--problem``, ``--level`` and ``--order``, the size, the reason
        and the lower levels to use.
    """
    from .io import preflight
    from .problems import hertz
    from .app import BUILTIN_PROBLEMS

    spec, mesh = BUILTIN_PROBLEMS.get(name), _builtin_meshes().get(name)
    if spec is None or mesh is None or order not in (1, 2):
        return  # run_problem names the unknown problem or order
    lvl = spec.default_level if level is None else level
    dim, per_a = mesh
    if not 0 <= lvl < min(spec.levels, len(per_a)):
        return  # build_problem says which levels exist
    md = hertz.mesh_spec(dim, per_a[lvl], order)
    est = preflight.estimate_size({"mesh": {**md, "generator": "rectangle" if dim == 2 else "box", "order": order}})
    issues = preflight.size_issues(est)
    if not issues:
        return
    body = issues[0].message
    body = body[body.index(": ") + 2:] if body.startswith("= ") else body
    cut = body.rfind(". Use ")
    body = body[:cut] if cut > 0 else body.rstrip(".")
    lower = f"a lower --level (0 .. {lvl - 1})" if lvl > 0 else ""
    ways = " or ".join(w for w in (lower, "--order 1" if order == 2 else "") if w) or "a smaller problem file"
    raise InputError(f"--problem {name} --level {lvl} --order {order}: {body}. Use {ways}.")


class _StatusHandler(logging.Handler):
    """Shows the library's latest debug/info record (iteration status) in the progress line."""

    def __init__(self, update):
        super().__init__(logging.DEBUG)
        self._update = update

    def emit(self, record: logging.LogRecord) -> None:
        try:
            self._update(record.getMessage())
        except Exception:  # pragma: no cover - never let the display break a solve
            pass


def _clock(seconds: float) -> str:
    s = int(round(max(seconds, 0.0)))
    return f"{s // 3600}:{s // 60 % 60:02d}:{s % 60:02d}"


class _LineProgress:
    """Progress as plain lines, for output that is not a terminal (batch jobs, ``| tee``, log files).

    One line per finished load step with the elapsed time and the ETA (elapsed per
    step times the steps left), and the solver's latest status at most every
    ``every`` seconds in between, so a long step still shows it is alive.
    """

    def __init__(self, err: Console, name: str, every: float = 5.0, clock=None):
        import time

        self._err, self._name, self._every = err, name, float(every)
        self._now = clock or time.monotonic
        self._t0 = self._now()
        self._last = self._t0
        self._done = -1

    def _print(self, msg: str) -> None:
        self._last = self._now()
        self._err.print(Text(msg), soft_wrap=True, highlight=False)

    def step(self, done: int, total: int, t: float) -> None:
        if done == self._done:
            return
        self._done = done
        el = self._now() - self._t0
        if done <= 0:
            self._print(f"{self._name}: {total} load step{'s' if total != 1 else ''}, started")
            return
        eta = el / done * (total - done)
        self._print(f"{self._name}: step {done}/{total} done (t = {t:.4g}), elapsed {_clock(el)}, "
                    f"ETA {_clock(eta)}")

    def phase(self, msg: str) -> None:
        """A phase of the run (building, solving, writing): always printed, with the elapsed time."""
        self._print(f"{self._name}: elapsed {_clock(self._now() - self._t0)}: {msg}")

    def status(self, msg: str) -> None:
        if self._now() - self._last >= self._every:
            self._print(f"{self._name}: elapsed {_clock(self._now() - self._t0)}: {msg}")


def _bar_columns(width: int):
    """Columns of the progress bar: step count, elapsed time and ETA first, so they fit 80 columns.

    The problem name and the solver's status come last and are cut (with an ellipsis)
    to what is left of ``width``.
    """
    from rich.progress import BarColumn, MofNCompleteColumn, SpinnerColumn, TextColumn, TimeElapsedColumn, \
        TimeRemainingColumn
    from rich.table import Column

    return (SpinnerColumn(), MofNCompleteColumn(), TextColumn("steps"), TimeElapsedColumn(), TextColumn("ETA"),
            TimeRemainingColumn(), BarColumn(bar_width=10),
            TextColumn("{task.description}", table_column=Column(no_wrap=True, overflow="ellipsis", max_width=18)),
            TextColumn("[dim]{task.fields[status]}",
                       table_column=Column(no_wrap=True, overflow="ellipsis", max_width=max(width - 72, 0))))


def _run_file(problem_file: Path, out, console: Console, err: Console, level: int, quiet: bool, **kwargs):
    """``alcontact run PROBLEM.toml``: validate, solve with a progress bar (lines without a terminal), write."""
    from rich.progress import Progress

    from .io.preflight import check_problem
    from .io.results import output_lock
    from .app import run_setup

    force = kwargs.pop("force")
    algorithm = kwargs.pop("algorithm")
    penalty = kwargs.pop("penalty")
    try:
        with _cli_logging(err, level), contextlib.ExitStack() as stack:
            setup = check_problem(problem_file).setup  # what `alcontact check` checks, before solving
            out = out if out is not None else Path(setup.output["folder"])
            stack.enter_context(output_lock(out))  # a second run into `out` is refused now, not after its solve
            if quiet:
                result = run_setup(setup, out, force, algorithm=algorithm, penalty=penalty, **kwargs)
            elif not err.is_terminal:
                lines = _LineProgress(err, setup.name)
                status = _StatusHandler(lines.status)
                lib = logging.getLogger("alcontact.contact")
                old = lib.level
                lib.addHandler(status)
                lib.setLevel(min(old or logging.WARNING, logging.INFO))
                try:
                    result = run_setup(setup, out, force, algorithm=algorithm, penalty=penalty, progress=lines.status,
                                       on_step=lines.step, **kwargs)
                finally:
                    lib.removeHandler(status)
                    lib.setLevel(old)
            else:
                with Progress(*_bar_columns(err.width), console=err, transient=True) as bar:
                    task = bar.add_task(setup.name, total=len(setup.times), status="")

                    def on_step(done: int, total: int, t: float) -> None:
                        bar.update(task, completed=done, total=total, description=f"{setup.name} t={t:.3g}")

                    status = _StatusHandler(lambda msg: bar.update(task, status=msg[:70]))
                    lib = logging.getLogger("alcontact.contact")
                    old = lib.level
                    lib.addHandler(status)
                    lib.setLevel(logging.DEBUG)
                    try:
                        result = run_setup(setup, out, force, algorithm=algorithm, penalty=penalty,
                                           progress=lambda msg: bar.update(task, status=msg[:70]),
                                           on_step=on_step, **kwargs)
                    finally:
                        lib.removeHandler(status)
                        lib.setLevel(old)
    except (OutputExistsError, InputError) as exc:
        raise _fail(err, exc, EXIT_USAGE) from None
    except AlcontactError as exc:
        raise _fail(err, exc, EXIT_FAILED) from None
    return result.summary, out


@app.command("check")
def check_command(
    problem_file: Annotated[Path, typer.Argument(help="TOML problem file to validate.", show_default=False)],
    quiet: Annotated[bool, typer.Option("--quiet", "-q", help="Print nothing unless something is wrong (the exit "
                                                              "code says OK: 0).")] = False,
) -> None:
    """Validate a problem file without solving it: everything `run` would reject.

    Prints OK, a one-line summary, the size and the run-time estimate (calibrated
    on the examples, docs/benchmarks/time_estimates.md), or every error found
    with its key path and the way out (exit code 2; --quiet: only the errors): the schema, the mesh size
    against this machine's memory (estimated before the mesh is built), mesh
    quality, boundary names, conflicting supports, supports or obstacle contact
    restraining every rigid motion on the solver's path (direct, AMG,
    frictional), and number ranges of the material and loads.
    """
    from .io.preflight import check_problem

    console, err = _consoles()
    try:
        with _cli_logging(err, logging.WARNING):
            report = check_problem(problem_file)
    except InputError as exc:
        raise _fail(err, exc, EXIT_USAGE) from None
    except AlcontactError as exc:
        raise _fail(err, exc, EXIT_FAILED) from None
    if quiet:
        return
    first, *rest = report.summary_lines()
    console.print(Text(f"OK {first}"))
    for line in rest:
        console.print(Text(f"   {line}"))


@app.command("bench")
def bench_command(
    out: Annotated[Path, typer.Option("--out", "-o", help="Report folder.")] = Path("benchmarks/out"),
    suite: Annotated[
        Optional[list[str]],
        typer.Option("--suite", "-s", help="hertz, friction, nlp, finite, ironing (repeatable; default all)."),
    ] = None,
    quick: Annotated[bool, typer.Option("--quick", help="Small sizes and a few variants (1-2 min on a 2-core "
                                                        "machine; the calibrated time is printed at the start).")]
    = False,
    cases: Annotated[
        Optional[list[str]],
        typer.Option("--case", help="Case of the hertz, friction, finite or ironing suite, e.g. 2d-10k, mindlin-2d, "
                                    "3d-100k (repeatable)."),
    ] = None,
    variants: Annotated[
        Optional[list[str]], typer.Option("--variant", help="Variant of the chosen suites (repeatable).")
    ] = None,
    benchmarks_dir: Annotated[
        Optional[Path], typer.Option("--benchmarks-dir", help="Folder with the benchmark scripts "
                                                              "(default: the repository's benchmarks/).")
    ] = None,
) -> None:
    """Run the benchmark suite and write its report (bench.md plus each suite's CSV and markdown).

    Benchmarks include cases that fail on purpose or by the method's nature (e.g. a
    Hock-Schittkowski problem an algorithm does not solve): their warnings are marked
    as expected; each failure is listed in the suite's report.
    """
    import time

    from .app import quick_bench_estimate, run_benchmarks

    console, err = _consoles()
    est = quick_bench_estimate(suite) if quick and not cases and not variants else None
    if est is not None:
        err.print(Text(f"bench --quick: about {_clock(est[0])} (h:mm:ss), measured on {est[1]}"), highlight=False)
    t0 = time.perf_counter()
    note = "[expected: the benchmark records failed solves; see the Failures list of its report]"
    try:
        with _cli_logging(err, logging.WARNING, note=note):
            report = run_benchmarks(out, suites=suite, quick=quick, cases=cases, variants=variants,
                                    benchmarks_dir=benchmarks_dir, log=lambda msg: err.print(Text(msg)))
    except InputError as exc:
        raise _fail(err, exc, EXIT_USAGE) from None
    except AlcontactError as exc:
        raise _fail(err, exc, EXIT_FAILED) from None
    took = time.perf_counter() - t0
    console.print(f"report written to [bold]{report}[/] ({_clock(took)} h:mm:ss"
                  + (f", estimated {_clock(est[0])})" if est is not None else ")"), highlight=False)


@app.command("study")
def study_command(
    out: Annotated[Path, typer.Option("--out", "-o", help="Study folder (resumed if it holds a study).")]
    = Path("study"),
    quick: Annotated[bool, typer.Option("--quick", help="Two meshes per problem, three eps scales, four update "
                                                        "rules (about 10 min on 2 cores with --jobs 2).")] = False,
    only: Annotated[
        Optional[list[str]],
        typer.Option("--only", help="A problem or a method (label or algorithm) to keep (repeatable), e.g. "
                                    "--only hertz-2d --only ssn --only exp-met1."),
    ] = None,
    jobs: Annotated[int, typer.Option("--jobs", "-j", help="Cells solved at once, each in its own process.")] = 1,
    timeout: Annotated[
        Optional[float], typer.Option("--timeout", help="Seconds per cell (default 60 with --quick, else 600).")
    ] = None,
    meshes: Annotated[
        Optional[int], typer.Option("--meshes", help="Keep the N smallest mesh sizes of each problem (default: all).")
    ] = None,
    publish: Annotated[
        Optional[Path], typer.Option("--publish", help="Also write the report as this file (e.g. docs/study.md), its "
                                                       "CSV and heat maps in the folder of the same name.")
    ] = None,
) -> None:
    """Run the study: problems x methods x eps scales x update rules; results.csv, report.md, heat maps.

    A re-run into the same folder skips the cells already in results.csv; an interrupted
    study keeps every finished cell.
    """
    from rich.progress import BarColumn, MofNCompleteColumn, Progress, TextColumn, TimeElapsedColumn, \
        TimeRemainingColumn

    from .app.study import run_study

    console, err = _consoles()
    bar = Progress(TextColumn("study"), BarColumn(), MofNCompleteColumn(), TimeElapsedColumn(),
                   TextColumn("ETA"), TimeRemainingColumn(), TextColumn("{task.description}"), console=err)
    task = bar.add_task("", total=None)
    started: dict = {}

    def progress(done: int, total: int, row: dict) -> None:
        if not started:  # cells already in the CSV do not count for the ETA; the bar starts once the input is valid
            started["skipped"] = done
            bar.start()
            bar.update(task, total=total - done, completed=0)
            return
        bar.update(task, completed=done - started["skipped"],
                   description=f"{row.get('problem')} {row.get('method')} {row.get('status')}")

    try:
        if publish is not None:  # refused before hours of cells, not after
            from .app.study_report import check_publish_target

            check_publish_target(publish)
        with _cli_logging(err, logging.WARNING), _signals_raise():
            try:
                run = run_study(out, quick=quick, only=only, jobs=jobs, timeout=timeout, progress=progress,
                                meshes=meshes)
            finally:
                bar.stop()
    except KeyboardInterrupt as exc:
        err.print(Text(f"interrupted: every finished cell is in {out / 'results.csv'}; run the same command again "
                       "to resume.", style="bold red"), highlight=False)
        raise typer.Exit(128 + getattr(exc, "signum", int(signal.SIGINT))) from None
    except InputError as exc:
        raise _fail(err, exc, EXIT_USAGE) from None
    except AlcontactError as exc:
        raise _fail(err, exc, EXIT_FAILED) from None
    console.print(f"{run.planned} cells: {run.skipped} already done, {run.solved} solved; report written to "
                  f"[bold]{run.report}[/]", highlight=False)
    if publish is not None:
        from .app.study import STUDY_VERSION
        from .app.study_report import publish_report

        words = ["alcontact study"] + (["--quick"] if quick else []) + [f"--only {n}" for n in only or ()] + \
            ([f"--meshes {meshes}"] if meshes is not None else [])
        try:
            path = publish_report(out, publish, command=" ".join(words),
                                  title=f"alcontact study (version {STUDY_VERSION}{', quick' if quick else ''})")
        except InputError as exc:
            raise _fail(err, exc, EXIT_USAGE) from None
        console.print(f"published [bold]{path}[/] (data in {path.with_suffix('')})", highlight=False)


@app.command("docs")
def docs_command(
    out: Annotated[
        Optional[Path], typer.Option("--out", "-o", help="Target file (default: docs/problem-file.md of the "
                                                         "repository).")
    ] = None,
    check: Annotated[bool, typer.Option("--check", help="Only check that the file is up to date (exit 1 if not).")]
    = False,
) -> None:
    """Regenerate docs/problem-file.md from the problem-file schema (alcontact.io.schema)."""
    from .io import schema

    console, err = _consoles()
    target = out if out is not None else schema.repo_root() / schema.DOCS_PATH
    if check:
        current = target.read_text(encoding="utf-8") if target.is_file() else ""
        if current != schema.render_markdown():
            err.print(f"{target} is out of date; run `alcontact docs`.", highlight=False)
            raise typer.Exit(EXIT_FAILED)
        console.print(f"{target} is up to date", highlight=False)
        return
    console.print(f"wrote {schema.write_markdown(target)}", highlight=False)


@app.command("list")
def list_command(
    what: Annotated[
        Optional[str],
        typer.Argument(help="Only one section: algorithms, friction-algorithms, penalties, obstacles, "
                            "problems or examples."),
    ] = None,
) -> None:
    """List the registered algorithms, penalties, obstacles, built-in problems and example files."""
    from .app import list_components

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
