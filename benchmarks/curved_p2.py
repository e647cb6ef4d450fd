"""Curved P2 convergence: what limits the force rate of the neo-Hookean half-cylinder, and the Hertz P2 peak pressure.

Part 1, half-cylinder (:func:`alcontact.problems.half_cylinder.half_cylinder`, plane strain, neo-Hookean,
E = 1000, nu = 0.3, ``ssn``), curved and straight-sided P2 on the ``n x n`` mapped mesh, pressed to
``delta/R = 0.4`` in ``STEPS`` equal load steps: the force ``F_n(delta)`` at every step (frictionless contact is
path independent, so the steps sample the force-approach curve). Per ``n``:

* the error of the final force against the finest curved mesh and the reference-free observed rate of
  three consecutive meshes, ``log2((F_n - F_2n) / (F_2n - F_4n))`` (a fine-mesh reference biases the rate of
  the next-finer pair: with a true rate p, ``(e_n - e_ref) / (e_2n - e_ref)`` overstates ``2^p``);
* the **contact-edge signature**: the error ``e_n(delta) = F_n(delta) - F_ref(delta)`` along the curve, split
  into a smooth part (a quadratic least-squares fit in delta over the second half of the curve) and the
  residual. The smooth part is the error of a fixed contact zone; the residual jumps as the discrete
  contact edge crosses a node (nodal contact), and its amplitude (RMS) and rate say whether the edge sets
  the rate;
* the vertex / mid-node alternation of the nodal pressure at the last step (the metric of
  ``tests/verification/test_curved_p2.py``: mid-node deviation from the cubic spline through the vertex
  values, over the peak, away from the contact edge).

Part 1b, the same problem on a shape-regular nested mesh (:func:`fan_mesh`): the elliptical-grid mesh of
:func:`half_cylinder` flattens its elements near the image of the square's corner (smallest angle 13.4, 6.9,
3.5, 1.8 deg at n = 8 ... 64), inside the contact zone at delta/R = 0.4; the fan mesh says whether that limits
the rate. Reference-free rates from the differences of consecutive meshes.

Part 2, small-deformation Hertz P2 (:func:`alcontact.problems.hertz.hertz_2d` and ``hertz_axisym``, order 2,
``n_per_a`` elements per contact half-width, a/R = 0.1, the block of 20 a): the peak nodal pressure and the
contact half-width against Johnson's closed forms (at the model's own load), and the self-convergence of the
peak pressure (differences of consecutive meshes). The closed forms are those of a half-space at a/R -> 0; the
finite block and a/R = 0.1 make a model error that the discretization error falls below.

Writes ``<out>/curved_p2.json`` and ``curved_p2.md``.

Usage::

    python benchmarks/curved_p2.py [--out docs/benchmarks] [--n 8 16 32 64] [--hertz 2 4 8 16 32] [--fan 3 4 5 6]
"""

from __future__ import annotations

import argparse
import json
import os
import platform
import time
from pathlib import Path

import numpy as np
from scipy.interpolate import CubicSpline

from alcontact.contact import solve
from alcontact.problems import hertz
from alcontact.problems.half_cylinder import half_cylinder

STEPS = 20


def _alternation(pb, sol) -> float:
    model = pb.model
    pts, _ = model.node_dofs("curved")
    mid = model._boundary_scalar_dofs("curved") >= model.mesh.nvertices
    p = np.asarray(sol.pressure)
    o = np.argsort(pts[:, 0])
    xs, ps, ms = pts[o, 0], p[o], mid[o]
    active = np.flatnonzero(ps > 0)
    inner = active[(active > active.min() + 4) & (active < len(xs) - 1)]
    v, m = inner[~ms[inner]], inner[ms[inner]]
    if v.size < 3 or m.size < 1:  # too few nodes inside the contact zone
        return float("nan")
    return float((np.abs(ps[m] - CubicSpline(xs[v], ps[v])(xs[m])) / ps.max()).max())


def half_cylinder_runs(ns, curved_flags=(True, False)) -> list[dict]:
    rows = []
    for curved in curved_flags:
        for n in ns:
            pb = half_cylinder(n, order=2, curved=curved, delta=0.4)
            c0 = time.process_time()
            sol = solve(pb, "ssn", steps=STEPS)
            cpu = time.process_time() - c0
            assert sol.result.success, sol.result.message
            rows.append({"curved": curved, "n": n, "ndofs": int(pb.model.ndofs), "cpu_s": cpu,
                         "delta": [float(0.4 * f.t) for f in sol.frames],
                         "force": [float(f.contact_force[1]) for f in sol.frames],
                         "alternation": _alternation(pb, sol)})
            print(json.dumps({k: v for k, v in rows[-1].items() if k not in ("delta", "force")}), flush=True)
    return rows


def fan_mesh(levels: int, sectors: int = 3, radius: float = 1.0):
    """A shape-regular curved P2 mesh of the half-cylinder's quarter disc: a fan of ``sectors`` triangles about
    ``(0, R)`` refined ``levels`` times (each triangle into 4, new arc vertices moved onto the circle), then
    second order with the arc's edge nodes on the circle. Nested, every angle bounded away from 0 and 180 deg
    (unlike the elliptical-grid map of :func:`half_cylinder`, whose elements near the image of the square's
    corner, on the arc at 45 deg, flatten under refinement)."""
    import dataclasses

    import skfem

    c = np.array([0.0, radius])
    th = np.linspace(-np.pi / 2, -np.pi, sectors + 1)  # from the bottom (0, 0) to (-R, R)
    pts = np.vstack([c] + [c + radius * np.array([np.cos(t), np.sin(t)]) for t in th]).T
    m = skfem.MeshTri(pts, np.array([[0, k + 1, k + 2] for k in range(sectors)]).T)
    tol = 1e-9 * radius

    def on_arc(x):
        return (x[0] < -tol) & (x[1] < radius - tol)

    for _ in range(levels):
        m = m.refined()
        p = m.p.copy()
        bnd = m.boundary_nodes()
        arc = bnd[on_arc(p[:, bnd])]
        d = p[:, arc] - c[:, None]
        p[:, arc] = c[:, None] + radius * d / np.linalg.norm(d, axis=0)
        m = skfem.MeshTri(p, m.t)
    m2 = skfem.MeshTri2.from_mesh(m)
    x = np.array(m2.doflocs, dtype=float)
    bf = m.boundary_facets()
    arc = bf[on_arc(m.p[:, m.facets[:, bf]].mean(axis=1))]
    d = x[:, m.nvertices + arc] - c[:, None]
    x[:, m.nvertices + arc] = c[:, None] + radius * d / np.linalg.norm(d, axis=0)
    m2 = dataclasses.replace(m2, doflocs=x)
    return m2.with_boundaries({"top": lambda x: x[1] > radius - tol, "symmetry": lambda x: x[0] > -tol,
                               "curved": on_arc})


def min_angle(mesh) -> float:
    """Smallest angle (degrees) of the triangles of ``mesh``'s vertices."""
    p, t = mesh.p, mesh.t
    out = []
    for i in range(3):
        a, b, c = p[:, t[i]], p[:, t[(i + 1) % 3]], p[:, t[(i + 2) % 3]]
        u, v = b - a, c - a
        out.append(np.degrees(np.arccos(np.sum(u * v, 0) / np.linalg.norm(u, axis=0) / np.linalg.norm(v, axis=0))))
    return float(np.min(out))


def fan_runs(levels) -> list[dict]:
    from alcontact.contact import ContactProblem, Support
    from alcontact.contact.obstacles import HalfSpace
    from alcontact.fem import Hyperelastic, Material

    rows = []
    for L in levels:
        mesh = fan_mesh(L)
        body = Hyperelastic(mesh, Material(E=1000.0, nu=0.3, plane="strain"), order=2, model="neo-hookean")
        pb = ContactProblem(model=body, obstacle=HalfSpace([0.0, 0.0], [0.0, 1.0]), contact_boundary="curved",
                            supports=(Support("symmetry", components=(0,)), Support("top", components=(1,), value=-0.4)),
                            kinematics="finite")
        sol = solve(pb, "ssn", steps=STEPS)
        assert sol.result.success, sol.result.message
        rows.append({"mesh": "fan", "level": L, "ndofs": int(body.ndofs), "min_angle": min_angle(mesh),
                     "delta": [float(0.4 * f.t) for f in sol.frames], "force": [float(f.contact_force[1]) for f in sol.frames]})
        print(json.dumps({k: v for k, v in rows[-1].items() if k not in ("delta", "force")}), flush=True)
    return rows


def consecutive(curves) -> list[dict]:
    """Reference-free: differences of consecutive meshes, at the last step and RMS over delta in [0.2, 0.4]."""
    out = []
    for a, b in zip(curves, curves[1:]):
        d = np.array(a["delta"])
        e = np.array(a["force"]) - np.array(b["force"])
        half = d >= 0.5 * d[-1]
        out.append({"from": a.get("n", a.get("level")), "to": b.get("n", b.get("level")), "final": float(e[-1]),
                    "rms": float(np.sqrt(np.mean(e[half] ** 2)))})
    for x, y in zip(out, out[1:]):
        y["rate_final"] = float(np.log2(abs(x["final"]) / abs(y["final"])))
        y["rate_rms"] = float(np.log2(x["rms"] / y["rms"]))
    return out


def edge_signature(rows) -> list[dict]:
    """Per curved flag and n: final error vs the finest curved mesh, observed rates, smooth / residual split."""
    out = []
    ref = max((r for r in rows if r["curved"]), key=lambda r: r["n"])
    Fref = np.array(ref["force"])
    d = np.array(ref["delta"])
    half = d >= 0.5 * d[-1]
    for curved in (True, False):
        rs = sorted((r for r in rows if r["curved"] == curved), key=lambda r: r["n"])
        for i, r in enumerate(rs):
            e = np.array(r["force"]) - Fref
            coef = np.polyfit(d[half], e[half], 2)
            resid = e[half] - np.polyval(coef, d[half])
            rate3 = None
            if i + 2 < len(rs):
                a, b, c = (rs[i + k]["force"][-1] for k in range(3))
                rate3 = float(np.log2(abs(a - b) / abs(b - c))) if b != c else None
            out.append({"curved": curved, "n": r["n"], "ndofs": r["ndofs"], "final_error": float(e[-1]),
                        "final_rel_error": float(e[-1] / Fref[-1]), "rate3": rate3,
                        "smooth_rms": float(np.sqrt(np.mean(np.polyval(coef, d[half]) ** 2))),
                        "edge_rms": float(np.sqrt(np.mean(resid ** 2))), "alternation": r["alternation"],
                        "is_reference": curved and r["n"] == ref["n"]})
    return out


def hertz_runs(ns) -> list[dict]:
    rows = []
    for fn in (hertz.hertz_2d, hertz.hertz_axisym):
        for n in ns:
            prob = fn(order=2, n_per_a=n)
            sol = solve(prob)
            ref = prob.reference
            P = ref.load(sol.normal_force)
            rows.append({"problem": fn.__name__, "n_per_a": n, "ndofs": int(prob.model.ndofs),
                         "p0": float(sol.peak_pressure_nodal_max), "p0_rel_error": float(
                             sol.peak_pressure_nodal_max / ref.peak_pressure(P) - 1.0),
                         "a_rel_error": float(sol.contact_half_width(axis=0, center=(0.0, 0.0)) / ref.half_width(P) - 1.0)})
            print(json.dumps(rows[-1]), flush=True)
    return rows


def report(hc, sig, hz, load: str, fan=None) -> str:
    lines = ["# Curved P2: force convergence of the half-cylinder, contact-edge signature, Hertz P2 peak pressure", "",
             f"`python benchmarks/curved_p2.py` on {platform.processor() or platform.machine()}, {os.cpu_count()} cores "
             f"shared with other jobs ({load}).", "",
             f"## Half-cylinder, neo-Hookean, delta/R = 0.4 in {STEPS} steps, ssn", "",
             "Errors against the finest curved mesh (marked ref); `rate (3 meshes)`: log2((F_n - F_2n) / (F_2n - F_4n)), "
             "no reference; `smooth` / `edge`: RMS over delta in [0.2, 0.4] of the quadratic fit of the error curve and "
             "of its residual (the jumps as the discrete contact edge crosses nodes); `alternation`: mid-node pressure "
             "deviation from the vertex spline / peak.", "",
             "| P2 | n | DOFs | final force error | relative | rate (3 meshes) | smooth RMS | edge RMS | alternation |",
             "|---|---|---|---|---|---|---|---|---|"]
    for s in sig:
        rate = "-" if s["rate3"] is None else f"{s['rate3']:.2f}"
        tag = " (ref)" if s["is_reference"] else ""
        lines.append(f"| {'curved' if s['curved'] else 'straight'} | {s['n']}{tag} | {s['ndofs']:,} | "
                     f"{s['final_error']:+.3e} | {s['final_rel_error']:+.2e} | {rate} | {s['smooth_rms']:.2e} | "
                     f"{s['edge_rms']:.2e} | {s['alternation']:.1e} |")
    if fan:
        lines += ["", "## Reference-free: differences of consecutive meshes (curved P2)", "",
                  "`F_n - F_next` at the last step and its RMS over delta in [0.2, 0.4]; rates from successive "
                  "differences (each halving h). `elliptical`: the built-in mesh of `half_cylinder(n)` (its smallest "
                  "angle halves with n, near the arc at 45 deg, inside the contact zone at delta/R = 0.4); `fan`: "
                  "the shape-regular nested mesh of `fan_mesh(level)`.", "",
                  "| mesh | from | to | DOFs (to) | smallest angle (to) | difference, last step | rate | RMS over delta | rate |",
                  "|---|---|---|---|---|---|---|---|---|"]
        for label, curves, diffs in fan:
            for c in diffs:
                to = next(x for x in curves if x.get("n", x.get("level")) == c["to"])
                rf = f"{c['rate_final']:.2f}" if "rate_final" in c else "-"
                rr = f"{c['rate_rms']:.2f}" if "rate_rms" in c else "-"
                lines.append(f"| {label} | {c['from']} | {c['to']} | {to['ndofs']:,} | {to.get('min_angle', float('nan')):.2f} | "
                             f"{c['final']:+.3e} | {rf} | {c['rms']:.3e} | {rr} |")
    lines += ["", "## Hertz, small deformation, P2 (Johnson's closed forms at the model's load)", "",
              "| problem | elements per a | DOFs | p0 | p0 error | a error | p0 change from the previous mesh |",
              "|---|---|---|---|---|---|---|"]
    prev = {}
    for h in hz:
        d = "-" if h["problem"] not in prev else f"{abs(h['p0'] - prev[h['problem']]) / h['p0']:.1e}"
        prev[h["problem"]] = h["p0"]
        lines.append(f"| {h['problem']} | {h['n_per_a']} | {h['ndofs']:,} | {h['p0']:.6g} | {h['p0_rel_error']:+.2e} | "
                     f"{h['a_rel_error']:+.2e} | {d} |")
    return "\n".join(lines) + "\n"


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--out", type=Path, default=Path("docs/benchmarks"))
    ap.add_argument("--n", type=int, nargs="*", default=[8, 16, 32, 64])
    ap.add_argument("--hertz", type=int, nargs="*", default=[2, 4, 8, 16, 32])
    ap.add_argument("--fan", type=int, nargs="*", default=[3, 4, 5, 6])
    args = ap.parse_args()
    hc = half_cylinder_runs(args.n)
    sig = edge_signature(hc)
    for r in hc:
        r["min_angle"] = min_angle(half_cylinder(r["n"], order=1).model.mesh)
    fr = fan_runs(args.fan)
    ell = sorted((r for r in hc if r["curved"]), key=lambda r: r["n"])
    fan = [("elliptical", ell, consecutive(ell)), ("fan", fr, consecutive(fr))]
    hz = hertz_runs(args.hertz)
    load = "load average %.1f %.1f %.1f at the end" % os.getloadavg()
    args.out.mkdir(parents=True, exist_ok=True)
    (args.out / "curved_p2.json").write_text(json.dumps({"half_cylinder": hc, "signature": sig, "fan": fr,
                                                         "consecutive": {k: d for k, _, d in fan}, "hertz": hz,
                                                         "load": load}, indent=1))
    (args.out / "curved_p2.md").write_text(report(hc, sig, hz, load, fan))


if __name__ == "__main__":
    main()
