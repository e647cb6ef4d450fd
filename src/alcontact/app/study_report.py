"""``report.md`` and the heat maps of a study folder, generated from its ``results.csv`` only.

Every number in the report is read from the CSV of the same folder (:func:`tables` builds the
tables from the rows; :func:`write_report` renders them), so a re-run of the report on the same
CSV gives the same text. Tables:

- per problem and mesh: method x :math:`\\varepsilon` scale -> Newton iterations with the base rule
  (``fixed``; friction solvers: none), a failure shown as its status in brackets;
- per method: converged cells of the :math:`\\varepsilon` sweep over all problems and meshes, as
  ``converged/cells`` and a percentage ("which method needs no tuning");
- per method and update rule (frictionless problems): converged cells per eps scale and over the sweep,
  and the mean outer and Newton iterations of the converged cells ("which rule makes which method
  robust to eps").

An "Answers" section states the findings in sentences, each figure computed from the same rows: the
convergence of the sweep per eps scale (:func:`scale_totals`), MET 1 against MET 2
(:func:`met_pairs`), the update rules over all methods and scales (:func:`rule_totals`, Algorithm
5.4 as printed and as corrected) and the most robust rule of each method (:func:`robust_rules`),
the barrier anchor against the family-P methods, without and with friction (:func:`barrier_vs_al`).
"""

from __future__ import annotations

import csv
import math
import os
from collections import OrderedDict
from pathlib import Path

__all__ = ["CSV_NAME", "read_rows", "tables", "render", "write_report", "heat_maps", "met_pairs", "rule_totals",
           "barrier_vs_al", "scale_totals", "robust_rules", "rules_heat_map",
           "frictional_problems", "publish_report", "check_publish_target", "PUBLISHED_MARKER"]

#: The CSV of a study folder.
CSV_NAME = "results.csv"


def read_rows(path: str | os.PathLike) -> list[dict]:
    """The rows of a study CSV (strings, as written); ``[]`` when there is none."""
    p = Path(path)
    if not p.is_file():
        return []
    with p.open(newline="", encoding="utf-8") as fh:
        return list(csv.DictReader(fh))


def _num(x: str) -> float:
    try:
        return float(x)
    except (TypeError, ValueError):
        return math.nan


def _scale_key(s: str) -> float:
    return _num(s) if s != "-" else 0.0


def _mesh_key(m: str):
    v = _num(m)
    return (0, v, "") if not math.isnan(v) else (1, 0.0, m)


def _median(values) -> float:
    v = sorted(x for x in values if not math.isnan(x))
    if not v:
        return math.nan
    k = len(v) // 2
    return v[k] if len(v) % 2 else 0.5 * (v[k - 1] + v[k])


def _order(values):
    return list(OrderedDict.fromkeys(values))


def tables(rows: list[dict]) -> dict:
    """The report's tables from the CSV rows (strings as in the CSV).

    Returns ``{"sweep": {(problem, mesh): {"dofs", "scales", "methods", "cells": {(method, scale): text}}},
    "robustness": [(method, converged, cells, median Newton, median time / linear solve)],
    "rules": [(method, rule, [(scale, cells, converged)], cells, converged, outer, newton)]}``.
    """
    method_order = _order(r["method"] for r in rows)
    return {"sweep": _sweep_table(rows, method_order), "robustness": _robustness_table(rows, method_order),
            "rules": _rules_table(rows, method_order)}


def _sweep_table(rows: list[dict], method_order: list[str]) -> dict:
    """Per (problem, mesh) of the eps sweep (rule ``fixed`` or none): the Newton count or status of each cell."""
    sweep: dict = OrderedDict()
    for p in _order(r["problem"] for r in rows):
        prow = [r for r in rows if r["problem"] == p]
        for mesh in sorted(_order(r["mesh"] for r in prow), key=_mesh_key):
            mrows = [r for r in prow if r["mesh"] == mesh and r["rule"] in ("fixed", "-")]
            if not mrows:
                continue
            scales = sorted(_order(r["eps_scale"] for r in mrows if r["eps_scale"] != "-"), key=_scale_key)
            cells = {(r["method"], r["eps_scale"]): r["newton"] if r["status"] == "converged" else f"[{r['status']}]"
                     for r in mrows}
            sweep[(p, mesh)] = {"dofs": mrows[0]["dofs"] or "-", "scales": scales,
                                "methods": [m for m in method_order if any(r["method"] == m for r in mrows)],
                                "cells": cells}
    return sweep


def _robustness_table(rows: list[dict], method_order: list[str]) -> list[tuple]:
    """Per method over the eps sweep: converged cells, cells, median Newton and time / linear solve."""
    robustness = []
    for m in method_order:
        mrows = [r for r in rows if r["method"] == m and r["rule"] in ("fixed", "-")]
        ok = [r for r in mrows if r["status"] == "converged"]
        robustness.append((m, len(ok), len(mrows), _median([_num(r["newton"]) for r in ok]),
                           _median([_num(r["time_per_linear_solve"]) for r in ok])))
    return robustness


def _per_scale(sel: list[dict], scales: list[str]) -> list[tuple[str, int, int]]:
    """``(scale, cells, converged)`` of ``sel`` at each of ``scales``."""
    out = []
    for sc in scales:
        at = [r for r in sel if r["eps_scale"] == sc]
        out.append((sc, len(at), sum(r["status"] == "converged" for r in at)))
    return out


def _rule_scales(rows: list[dict]) -> list[str]:
    """The eps scales of the rows with an update rule, ascending."""
    return sorted(_order(r["eps_scale"] for r in rows if r["rule"] != "-" and r["eps_scale"] != "-"), key=_scale_key)


def _rules_table(rows: list[dict], method_order: list[str]) -> list[tuple]:
    """Per method and update rule over the eps sweep (every problem and mesh with a rule): ``(method, rule,
    [(scale, cells, converged)], cells, converged, mean outer, mean Newton)``, means over the converged cells."""
    scales = _rule_scales(rows)
    rules = []
    for m in method_order:
        for rule in _order(r["rule"] for r in rows if r["method"] == m and r["rule"] != "-"):
            rr = [r for r in rows if r["method"] == m and r["rule"] == rule]
            ok = [r for r in rr if r["status"] == "converged"]
            rules.append((m, rule, _per_scale(rr, scales), len(rr), len(ok), _mean([_num(r["outer"]) for r in ok]),
                          _mean([_num(r["newton"]) for r in ok])))
    return rules


def identical_methods(rows: list[dict]) -> list[list[str]]:
    """Groups of methods whose status, outer and Newton counts agree in every cell they share."""
    per: dict = OrderedDict()
    for r in rows:
        cell = (r["problem"], r["mesh"], r["eps_scale"], r["rule"])
        per.setdefault(r["method"], {})[cell] = (r["status"], r["outer"], r["newton"])
    groups: list[list[str]] = []
    for m, cells in per.items():
        for g in groups:
            ref = per[g[0]]
            if cells.keys() == ref.keys() and all(cells[c] == ref[c] for c in cells):
                g.append(m)
                break
        else:
            groups.append([m])
    return [g for g in groups if len(g) > 1]


def met_pairs(rows: list[dict]) -> list[tuple[str, int, int, list[tuple]]]:
    """Per generator ``theta`` with both ``theta-met1`` and ``theta-met2`` in ``rows``: ``(theta, identical, shared,
    differing cells)``, a cell identical when status, outer and Newton iterations agree."""
    by = {(r["problem"], r["mesh"], r["method"], r["eps_scale"], r["rule"]): r for r in rows}
    out = []
    for theta in _order(r["method"].removesuffix("-met1") for r in rows if r["method"].endswith("-met1")):
        shared, same, differ = 0, 0, []
        for (p, mesh, m, s, rule), r1 in by.items():
            r2 = by.get((p, mesh, f"{theta}-met2", s, rule))
            if m != f"{theta}-met1" or r2 is None:
                continue
            shared += 1
            a, b = (r1["status"], r1["outer"], r1["newton"]), (r2["status"], r2["outer"], r2["newton"])
            if a == b:
                same += 1
            else:
                differ.append((p, mesh, s, rule, a, b))
        if shared:
            out.append((theta, same, shared, differ))
    return out


def scale_totals(rows: list[dict]) -> list[tuple[str, int, int]]:
    """Per eps scale of the sweep (rule ``fixed`` or none, methods with a penalty parameter): ``(scale, cells,
    converged)``."""
    sweep = [r for r in rows if r["rule"] in ("fixed", "-") and r["eps_scale"] != "-"]
    out = []
    for s in sorted(_order(r["eps_scale"] for r in sweep), key=_scale_key):
        sel = [r for r in sweep if r["eps_scale"] == s]
        out.append((s, len(sel), sum(r["status"] == "converged" for r in sel)))
    return out


def rule_totals(rows: list[dict]) -> list[tuple[str, list[tuple[str, int, int]], int, int, float, float]]:
    """Per update rule, over every method with a rule and the whole eps sweep: ``(rule, [(scale, cells,
    converged)], cells, converged, mean outer, mean Newton)`` (means over the converged cells)."""
    scales = _rule_scales(rows)
    out = []
    for rule in _order(r["rule"] for r in rows if r["rule"] != "-"):
        sel = [r for r in rows if r["rule"] == rule]
        ok = [r for r in sel if r["status"] == "converged"]
        out.append((rule, _per_scale(sel, scales), len(sel), len(ok), _mean([_num(r["outer"]) for r in ok]),
                    _mean([_num(r["newton"]) for r in ok])))
    return out


def robust_rules(rows: list[dict], base: str = "fixed") -> list[tuple[str, list[str], int, int, int]]:
    """Per method with update rules: ``(method, rules, converged, cells, base converged)``: the rules that
    converge in the most cells of the eps sweep (ties: all of them, fewest mean Newton first), their count,
    and the count of the ``base`` rule on the same cells (``-1`` without it)."""
    t = _rules_table(rows, _order(r["method"] for r in rows))
    out = []
    for m in _order(x[0] for x in t):
        mine = [x for x in t if x[0] == m]
        top = max(x[4] for x in mine)
        best = sorted((x for x in mine if x[4] == top), key=lambda x: (math.isnan(x[6]), x[6]))
        fixed = next((x[4] for x in mine if x[1] == base), -1)
        out.append((m, [x[1] for x in best], top, best[0][3], fixed))
    return out


def frictional_problems(rows: list[dict]) -> set[str]:
    """The problems solved with friction: those whose family-P cells have no update rule (``-``)."""
    return {r["problem"] for r in rows if r["family_p"] == "1" and r["rule"] == "-"}


def barrier_vs_al(rows: list[dict], barrier: str = "log-barrier", friction: bool | None = None) -> dict | None:
    """The barrier anchor against the family-P AL methods on the same sweep cells (problem, mesh, eps scale).

    ``{"cells", "converged", "outer", "newton"}`` for the barrier and ``{"al_cells", "al_converged",
    "al_outer", "al_newton"}`` for the family-P methods (medians over the converged cells); ``None`` without
    barrier rows. ``friction``: only the frictional (``True``) or frictionless (``False``) problems
    (:func:`frictional_problems`).
    """
    if friction is not None:
        fr = frictional_problems(rows)
        rows = [r for r in rows if (r["problem"] in fr) == friction]
    bar = [r for r in rows if r["method"] == barrier]
    if not bar:
        return None
    where = {(r["problem"], r["mesh"], r["eps_scale"]) for r in bar}
    al = [r for r in rows if r["family_p"] == "1" and r["rule"] in ("fixed", "-")
          and (r["problem"], r["mesh"], r["eps_scale"]) in where]
    ok, al_ok = [r for r in bar if r["status"] == "converged"], [r for r in al if r["status"] == "converged"]
    return {"cells": len(bar), "converged": len(ok), "outer": _median([_num(r["outer"]) for r in ok]),
            "newton": _median([_num(r["newton"]) for r in ok]), "al_cells": len(al), "al_converged": len(al_ok),
            "al_outer": _median([_num(r["outer"]) for r in al_ok]),
            "al_newton": _median([_num(r["newton"]) for r in al_ok])}


def _mean(values) -> float:
    v = [x for x in values if not math.isnan(x)]
    return sum(v) / len(v) if v else math.nan


def _answers(rows: list[dict]) -> list[str]:
    """The "Answers" section: plain sentences whose every figure is computed here from ``rows``."""
    lines = ["## Answers", ""]
    by_scale = scale_totals(rows)
    if by_scale:
        lines += ["- **Where the penalty sweep fails** (rule `fixed`, every method with a penalty parameter): "
                  + ", ".join(f"eps x{s} converged {ok} of {n}" for s, n, ok in by_scale) + ". Per method: "
                  "the table below.", ""]
    pairs = met_pairs(rows)
    if pairs:
        lines += ["- **MET 1 vs MET 2.** Cells with the same status, outer and Newton iterations: "
                  + ", ".join(f"{t}-met1 / {t}-met2 {same} of {n}" for t, same, n, _ in pairs) + ". This is "
                  "not a switch that fails to take effect: the study scales every family-P law to the "
                  "stiffness eps_N at zero gap from the current multipliers (`eta_scaling = \"adaptive\"`, "
                  "eta = p''(0, lambda)/eps_N), and then MET 1, lambda theta'(g/eta_1) with eta_1 = lambda "
                  "theta''(0)/eps_N, and MET 2, lambda theta'(lambda g/eta_2) with eta_2 = lambda^2 "
                  "theta''(0)/eps_N, are the same function lambda theta'(g eps_N/(lambda theta''(0))) of the gap: "
                  "one traction law, one sequence of iterates. They can differ only where eta is not recomputed "
                  "from the multiplier it is used with (`eta_scaling = \"fixed\"`; the frictional solvers' eta "
                  "floor at tiny multipliers) and by rounding near a stopping test (`tests/unit/test_met_variants.py`"
                  " shows both).", ""]
        differ = [(t, *d) for t, _, _, ds in pairs for d in ds]
        if differ:
            lines[-2] += " Cells that differ (problem, mesh, eps scale, rule: MET 1 / MET 2 status, outer, Newton): " + \
                "; ".join(f"{t} {p} {mesh} x{sc} {rule}: {'/'.join(a)} vs {'/'.join(b)}"
                          for t, p, mesh, sc, rule, a, b in differ[:8]) + ("" if len(differ) <= 8 else
                                                                           f"; and {len(differ) - 8} more") + "."
    rules = rule_totals(rows)
    if rules:
        lines += ["- **Penalty update rules across the eps sweep** (every method with a rule, every problem and mesh "
                  "with one; converged of cells per eps scale): "
                  + "; ".join(f"`{rule}` " + ", ".join(f"x{sc} {ok} of {n}" for sc, n, ok in per)
                              + f" (all: {ok} of {n}, mean {_fmt_mean(outer)} outer / {_fmt_mean(newton)} Newton)"
                              for rule, per, n, ok, outer, newton in rules) + "."]
        named = {rule: (n, ok) for rule, _, n, ok, _, _ in rules}
        if "alg54-printed" in named and "alg54-corrected" in named:
            (n1, ok1), (n2, ok2) = named["alg54-printed"], named["alg54-corrected"]
            lines += ["  Algorithm 5.4 as printed (eta <- 2 eta, i.e. eps_N halved every outer iteration) "
                      f"converged in {ok1} of {n1} cells, as corrected (eps_N doubled) in {ok2} of {n2}: a larger "
                      "eta weakens the penalty, since eta divides g in (5.28)."]
        robust = robust_rules(rows)
        if robust:
            lines += ["  Which rule makes which method robust to eps (the rules converging in the most cells of the "
                      "sweep, fewest Newton iterations first; in brackets the rule `fixed`): "
                      + "; ".join(f"{m}: " + ", ".join(f"`{r}`" for r in best) + f" {ok} of {n}"
                                  + (f" (fixed {fx})" if fx >= 0 else "") for m, best, ok, n, fx in robust) + "."]
        lines.append("")
    for friction, what in ((False, "frictionless problems: modified log barrier with fixed multipliers, eta -> 0, "
                                   "no multiplier update"),
                           (True, "frictional problems: the same barrier on the normal part per load step, the "
                                  "tangential part of Algorithm 6.2")):
        bar = barrier_vs_al(rows, friction=friction)
        if bar:
            lines += [f"- **Barrier anchor, {what.split(':')[0]}** (`log-barrier`, {what.split(': ')[1]}): converged "
                      f"in {bar['converged']} of {bar['cells']} cells of the eps sweep, median "
                      f"{_fmt_mean(bar['outer'])} outer / {_fmt_mean(bar['newton'])} Newton iterations; on the same "
                      f"cells the family-P augmented Lagrangian methods converged in {bar['al_converged']} of "
                      f"{bar['al_cells']}, median {_fmt_mean(bar['al_outer'])} outer / {_fmt_mean(bar['al_newton'])} "
                      "Newton.", ""]
    return lines if len(lines) > 2 else []


def _fmt_mean(x: float) -> str:
    return "-" if math.isnan(x) else f"{x:.1f}"


def render(rows: list[dict], *, title: str = "alcontact study", images: dict | None = None) -> str:
    """The markdown report of ``rows`` (see the module doc)."""
    t = tables(rows)
    status = OrderedDict()
    for r in rows:
        status[r["status"]] = status.get(r["status"], 0) + 1
    lines = [f"# {title}", "",
             f"{len(rows)} cells; status: " + ", ".join(f"{k} {v}" for k, v in status.items()) + ".", "",
             "Every number below is read from `results.csv` of this folder. Newton (outer): Newton (outer) "
             "iterations of the whole solve, summed over the accepted load steps (the work of a step that was "
             "cut back is in the CPU time; `cutbacks` column); `[status]`: the cell did not converge. eps scale: "
             "the cell's `penalty_scale`, eps_N = scale x E'/h at the start (the solvers' own default is a "
             "scale of 100). Tables per problem: update rule `fixed` (friction solvers: none). `converged` is the "
             "solver's status: every invariant it checks holds at the returned state (the pure penalty and the "
             "barrier stop on their penetration tolerance, see the `eps_final` column).", ""]
    lines += _answers(rows)
    lines += _robustness_section(t["robustness"], rows)
    lines += _rules_section(t["rules"], (images or {}).get("rules"))
    lines += _sweep_section(t["sweep"], images)
    return "\n".join(lines)


def _robustness_section(robustness: list[tuple], rows: list[dict]) -> list[str]:
    """"Which method needs no tuning": converged cells of the eps sweep per method, and what they say."""
    lines = ["## Which method needs no tuning", "",
             "Converged cells of the eps sweep, over every problem and mesh; the cost across the sweep as "
             "medians over the converged cells (time / linear solve: CPU time of the solve over one sparse "
             "factorization + solve of the same mesh's stiffness, measured once per mesh in the same run).", "",
             "| method | converged | cells | fraction | median Newton | median time / linear solve |",
             "|---|---:|---:|---:|---:|---:|"]
    for m, ok, n, newton, ratio in robustness:
        frac = f"{100.0 * ok / n:.0f}%" if n else "-"
        lines.append(f"| {m} | {ok} | {n} | {frac} | {_fmt_mean(newton)} | {_fmt_mean(ratio)} |")
    lines.append("")
    best = [m for m, ok, n, _, _ in robustness if n and ok == n]
    if best:
        lines += ["Converged in every cell of the sweep: " + ", ".join(best) + ".", ""]
    tuned = [(ok / n, m, ok, n) for m, ok, n, _, _ in robustness if n and m not in best]
    if tuned:
        top = max(f for f, *_ in tuned)
        names = [f"{m} ({ok}/{n})" for f, m, ok, n in tuned if f == top]
        lines += ["Of the methods that failed somewhere, the most robust to the penalty parameter: "
                  + ", ".join(names) + ".", ""]
    same = identical_methods(rows)
    if same:
        lines += ["Methods with the same status, outer and Newton iterations in every cell they share: "
                  + "; ".join(" = ".join(g) for g in same) + ".", ""]
    return lines


def _rules_section(rules: list[tuple], image: str | None = None) -> list[str]:
    """"Penalty update rules": converged cells per method, rule and eps scale, and the mean cost."""
    scales = [sc for sc, _, _ in rules[0][2]] if rules else []
    lines = ["## Penalty update rules", ""] + ([f"![update rules]({image})", ""] if image else []) + [
             "Frictionless problems (the friction solvers have no rule), every problem and mesh; per eps scale "
             "converged / cells; outer and Newton: means over the converged cells of the whole sweep. "
             "`alg54-printed`: Algorithm 5.4 as printed, eta <- 2 eta (eps_N halved) after every outer "
             "iteration; `alg54-corrected`: eta <- eta / 2 (eps_N doubled); `infeasibility`: eps_N times 10 "
             "when the penetration did not fall below 1/4 of its previous value.", "",
             "| method | rule | " + " | ".join(f"eps x{sc}" for sc in scales) + " | converged | cells | outer | Newton |",
             "|---|---|" + "---:|" * (len(scales) + 4)]
    for m, rule, per, n, ok, outer, newton in rules:
        lines.append(f"| {m} | {rule} | " + " | ".join(f"{k}/{c}" for _, c, k in per)
                     + f" | {ok} | {n} | {_fmt_mean(outer)} | {_fmt_mean(newton)} |")
    lines.append("")
    fewest = OrderedDict()
    for m, rule, per, n, ok, outer, newton in rules:
        if n and ok == n and not math.isnan(newton) and (m not in fewest or newton < fewest[m][1]):
            fewest[m] = (rule, newton)
    if fewest:
        lines += ["Rule with the fewest Newton iterations among those converging in every cell of the sweep: "
                  + ", ".join(f"{m}: {r}" for m, (r, _) in fewest.items()) + ".", ""]
    return lines


def _sweep_section(sweep: dict, images: dict | None) -> list[str]:
    """"Newton iterations per method and eps scale": one table per problem and mesh."""
    lines = ["## Newton iterations per method and eps scale", ""]
    for (p, mesh), tab in sweep.items():
        lines += [f"### {p}, mesh {mesh} ({tab['dofs']} DOFs)", ""]
        if images and (p, mesh) in images:
            lines += [f"![{p}]({images[(p, mesh)]})", ""]
        scales = tab["scales"] or ["-"]
        lines.append("| method | " + " | ".join(f"eps x{s}" for s in scales) + " |")
        lines.append("|---|" + "---:|" * len(scales))
        for m in tab["methods"]:
            # ssn: no penalty parameter, the same value in every column
            vals = [tab["cells"].get((m, s), tab["cells"].get((m, "-"), "")) for s in scales]
            lines.append(f"| {m} | " + " | ".join(vals) + " |")
        lines.append("")
    return lines


def heat_maps(rows: list[dict], out: Path) -> dict:
    """One PNG per problem (its largest mesh): method x eps scale -> Newton, failures marked ``x``.

    Returns ``{(problem, mesh): file name}``.
    """
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    import numpy as np

    t = tables(rows)
    last: dict = OrderedDict()
    for (p, mesh), tab in t["sweep"].items():
        last[p] = (mesh, tab)  # meshes are sorted: the last is the largest
    images = {}
    for p, (mesh, tab) in last.items():
        scales, meths = tab["scales"] or ["-"], tab["methods"]
        z = np.full((len(meths), len(scales)), np.nan)
        fail = []
        for i, m in enumerate(meths):
            for j, s in enumerate(scales):
                v = tab["cells"].get((m, s), tab["cells"].get((m, "-")))
                if v is None:
                    continue
                if v.startswith("["):
                    fail.append((i, j))
                else:
                    z[i, j] = float(v)
        fig, ax = plt.subplots(figsize=(1.2 + 0.9 * len(scales), 0.9 + 0.4 * len(meths)))
        im = ax.imshow(z, aspect="auto", cmap="viridis")
        for i, j in fail:
            ax.text(j, i, "x", ha="center", va="center", color="red", fontsize=12, fontweight="bold")
        for i in range(len(meths)):
            for j in range(len(scales)):
                if not math.isnan(z[i, j]):
                    ax.text(j, i, f"{z[i, j]:.0f}", ha="center", va="center", color="w", fontsize=7)
        ax.set_xticks(range(len(scales)), [f"x{s}" for s in scales])
        ax.set_yticks(range(len(meths)), meths)
        ax.set_xlabel("eps scale")
        ax.set_title(f"{p}, mesh {mesh}: Newton iterations (x = failed)", fontsize=9)
        fig.colorbar(im, ax=ax)
        fig.tight_layout()
        name = f"heatmap-{p}.png"
        fig.savefig(out / name, dpi=90)
        plt.close(fig)
        images[(p, mesh)] = name
    return images


def rules_heat_map(rows: list[dict], out: Path) -> str | None:
    """One PNG: update rule x eps scale -> fraction of the cells converged (every method with a rule), annotated
    ``converged/cells``; ``None`` without rows with a rule."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    import numpy as np

    totals = rule_totals(rows)
    if not totals:
        return None
    scales = [sc for sc, _, _ in totals[0][1]]
    z = np.array([[ok / n if n else np.nan for _, n, ok in per] for _, per, *_ in totals])
    fig, ax = plt.subplots(figsize=(1.6 + 0.9 * len(scales), 0.9 + 0.4 * len(totals)))
    im = ax.imshow(z, aspect="auto", cmap="RdYlGn", vmin=0.0, vmax=1.0)
    for i, (_, per, *_) in enumerate(totals):
        for j, (_, n, ok) in enumerate(per):
            ax.text(j, i, f"{ok}/{n}", ha="center", va="center", fontsize=7)
    ax.set_xticks(range(len(scales)), [f"x{s}" for s in scales])
    ax.set_yticks(range(len(totals)), [t[0] for t in totals])
    ax.set_xlabel("eps scale")
    ax.set_title("update rules: converged cells / cells (every method with a rule)", fontsize=9)
    fig.colorbar(im, ax=ax)
    fig.tight_layout()
    name = "heatmap-rules.png"
    fig.savefig(out / name, dpi=90)
    plt.close(fig)
    return name


def write_report(out: str | os.PathLike, *, title: str = "alcontact study") -> Path:
    """Write ``report.md`` and the heat maps of the study folder ``out`` from its ``results.csv``."""
    from ..io import write_text_atomic

    out = Path(out)
    rows = read_rows(out / CSV_NAME)
    images = heat_maps(rows, out) if rows else {}
    rules_png = rules_heat_map(rows, out) if rows else None
    if rules_png:
        images["rules"] = rules_png
    path = out / "report.md"
    write_text_atomic(path, render(rows, title=title, images=images) + "\n")
    return path


#: First characters of a published report (:func:`publish_report` overwrites only a file that starts with them).
PUBLISHED_MARKER = "<!-- generated by `alcontact study"


def check_publish_target(target: str | os.PathLike) -> Path:
    """``target`` as a path, if :func:`publish_report` may write it (new, or published before).

    Raises
    ------
    InputError
        It exists and is not a published study report (its first line is not :data:`PUBLISHED_MARKER`'s).
    """
    from ..errors import InputError

    target = Path(target)
    if target.exists() and not (target.is_file() and _first_line(target).startswith(PUBLISHED_MARKER)):
        raise InputError(f"--publish {str(target)!r} exists and is not a report published by `alcontact study`; "
                         "pass another path (or delete that file).")
    return target


def _first_line(path: Path) -> str:
    try:
        with path.open(encoding="utf-8") as fh:
            return fh.readline()
    except (OSError, UnicodeDecodeError):
        return ""


def publish_report(out: str | os.PathLike, target: str | os.PathLike, *, title: str = "alcontact study",
                   command: str = "alcontact study") -> Path:
    """Publish the study folder ``out`` as ``target`` (e.g. ``docs/study.md``) with its data beside it.

    ``target``'s folder of the same stem (``docs/study/``) receives ``results.csv``, ``study.json`` and the
    heat maps; ``target`` is the report of that CSV with the images linked there, after a first line that
    names ``command`` and the CSV. Nothing but a file published before (it starts with
    :data:`PUBLISHED_MARKER`) is overwritten.

    Raises
    ------
    InputError
        ``target`` exists and is not a published study report, or ``out`` holds no results.
    """
    import shutil

    from ..errors import InputError
    from ..io import write_text_atomic

    out, target = Path(out), check_publish_target(target)
    rows = read_rows(out / CSV_NAME)
    if not rows:
        raise InputError(f"--publish: {str(out / CSV_NAME)!r} holds no cells to publish.")
    assets = target.with_suffix("")
    assets.mkdir(parents=True, exist_ok=True)
    images = heat_maps(rows, assets)
    rules_png = rules_heat_map(rows, assets)
    if rules_png:
        images["rules"] = rules_png
    for name in (CSV_NAME, "study.json"):
        if (out / name).is_file():
            shutil.copyfile(out / name, assets / name)
    linked = {k: f"{assets.name}/{v}" for k, v in images.items()}
    if not command.startswith("alcontact study"):
        raise ValueError(f"publish_report: command {command!r} must start with 'alcontact study'")
    head = (f"<!-- generated by `{command} --out DIR --publish {target.name}` from `{assets.name}/{CSV_NAME}`, the "
            "CSV of the same run; regenerate it with that command, never edit it by hand -->")
    assert head.startswith(PUBLISHED_MARKER)
    write_text_atomic(target, head + "\n\n" + render(rows, title=title, images=linked) + "\n")
    return target
