r"""Curved (isoparametric) P2 against straight-sided P2 on the neo-Hookean half-cylinder and hemisphere (issue 25).

Problem: :func:`alcontact.problems.half_cylinder.half_cylinder` (plane strain, P2, pressed to
:math:`\delta/R = 0.4` in 8 load steps, ``ssn``), on the second-order mesh whose edge nodes
follow the circle (``curved=True``, the default for P2) and on the straight-sided P2 mesh on
the same vertices (``curved=False``).

Reference: a fine-mesh Richardson-style reference, the curved P2 force at ``n = 64``
(66,306 DOFs; F = 366.5788 at the last step). Measured errors of the final force (the
straight P2 at ``n = 64`` is 366.5580, 0.021 below the reference):

======  =============  =============  =======
``n``   curved P2      straight P2    ratio
======  =============  =============  =======
4       0.651          3.94           6.0
8       0.347          1.55           4.5
16      0.0701         0.288          4.1
32      0.0156         0.0660         4.2
======  =============  =============  =======

Observed rates (16 -> 32) against that reference: curved 2.17, straight 2.13 (a fine-mesh
reference biases the rate of the next-finer pair). **The rate 3 of issue 25 is not reached**:
the curved geometry removes the geometric error (the error is 4x smaller at every level), but
what remains converges at about 2.3 (reference-free, consecutive-mesh differences along the
force-approach curve: 2.31, 2.33 up to n = 64; ``docs/benchmarks/curved_p2.md``). Neither the
reference, the (plane) obstacle nor the shape regularity of the mesh sets it (a shape-regular fan
mesh converges no faster: 1.90, 1.14); about half of the error is the jump of the nodal contact
edge across nodes. The nodal contact discretization itself is the suspect left (not tested).

Nodal pressure (nominal, at the last step; interior of the contact zone, the 4 active nodes
nearest the contact edge left out): the deviation of the mid-node values from the cubic
spline through the vertex values, relative to the peak pressure, measures the vertex/mid-node
alternation. Measured (n = 8, 16, 32): curved 5.3e-3, 2.0e-3, 8.3e-4; straight 6.6e-2,
4.1e-2, 2.4e-2. Peak nodal pressure (n = 8, 16, 32): curved 573.33, 571.23, 570.60 (rate
1.74); straight 600.08, 585.86, 578.26 (rate 0.90).
"""

from __future__ import annotations

import numpy as np
import pytest
from scipy.interpolate import CubicSpline

from alcontact.contact import solve_finite
from alcontact.problems.half_cylinder import half_cylinder

STEPS = 8
#: curved P2 force at n = 64, last step (module doc)
F_REF = 366.5788


def _solve(n: int, curved: bool):
    pb = half_cylinder(n, order=2, curved=curved)
    fs = solve_finite(pb, "ssn", steps=STEPS)
    assert fs.success, fs.message
    return pb, fs


@pytest.fixture(scope="module")
def runs():
    return {(n, c): _solve(n, c) for n in (8, 16, 32) for c in (True, False)}


def test_curved_option_took_effect(runs):
    (pb, _), (ps, _) = runs[8, True], runs[8, False]
    assert pb.meta["curved"] and not ps.meta["curved"]
    for p, err in ((pb, 1e-12), (ps, None)):
        pts, _ = p.model.node_dofs("curved")
        r = np.abs(np.linalg.norm(pts - [0.0, 1.0], axis=1) - 1.0)
        if err is None:
            assert r.max() > 1e-3  # straight: the edge midpoints lie inside the circle
        else:
            assert r.max() <= err


def test_curved_force_is_more_accurate_and_converges(runs):
    """Errors against the n = 64 reference: curved <= 1/3 of straight at n = 16, 32; rate >= 1.9 (module doc)."""
    err = {k: abs(fs.forces[-1, 1] - F_REF) for k, (_, fs) in runs.items()}
    for n in (16, 32):
        assert err[n, True] <= err[n, False] / 3.0, err
    assert np.log2(err[16, True] / err[32, True]) >= 1.9, err


@pytest.mark.slow
def test_reference_force():
    """The reference itself: the curved P2 force at n = 64 (module doc), to 1e-4."""
    _, fs = _solve(64, True)
    assert abs(fs.forces[-1, 1] - F_REF) <= 1e-4


def _alternation(pb, fs) -> tuple[float, float]:
    """(mid-node deviation from the vertex spline / peak, peak) of the nodal pressure (module doc)."""
    model = pb.model
    pts, _ = model.node_dofs("curved")
    mid = model._boundary_scalar_dofs("curved") >= model.mesh.nvertices
    p = np.asarray(fs.solution.pressure)
    o = np.argsort(pts[:, 0])
    xs, ps, ms = pts[o, 0], p[o], mid[o]
    active = np.flatnonzero(ps > 0)
    inner = active[(active > active.min() + 4) & (active < len(xs) - 1)]
    v, m = inner[~ms[inner]], inner[ms[inner]]
    dev = np.abs(ps[m] - CubicSpline(xs[v], ps[v])(xs[m])) / ps.max()
    return float(dev.max()), float(ps.max())


def test_nodal_pressure_has_no_vertex_midnode_alternation(runs):
    """Curved at n = 32: below 0.1 % of the peak; straight: above 1 % (the metric sees it) (module doc)."""
    curved, _ = _alternation(*runs[32, True])
    straight, _ = _alternation(*runs[32, False])
    assert curved <= 1e-3 and straight >= 1e-2, (curved, straight)


def test_peak_pressure_rate_improves(runs):
    """Peak nodal pressure: curved rate >= 1.5, at least 0.5 above the straight-sided rate (module doc)."""
    rates = {}
    for c in (True, False):
        peaks = [_alternation(*runs[n, c])[1] for n in (8, 16, 32)]
        rates[c] = np.log2(abs(peaks[0] - peaks[1]) / abs(peaks[1] - peaks[2]))
    assert rates[True] >= 1.5 and rates[True] >= rates[False] + 0.5, rates


#: 3D: curved P2 quarter hemisphere, delta/R = 0.1, 4 load steps, n = 4, 6, 8 (2187, 6591, 14739 DOFs)
#: measured forces curved 13.9012, 13.8262, 13.8054 (observed rate 2.65, Richardson limit 13.787);
#: straight 12.7310, 13.2856, 13.4890 (rate 1.87, limit 13.774): the two limits agree to 1e-3.
@pytest.mark.slow
def test_hemisphere_curved_force_rate():
    """3D hemisphere: observed rate of the curved P2 force over n = 4, 6, 8 >= 2.3 and its n = 8 value
    within 0.3 % of the straight-sided Richardson limit 13.774 (the straight n = 8 value is 2.1 % off)."""
    from scipy.optimize import brentq

    from alcontact.problems.hemisphere import hemisphere

    F = {}
    for n in (4, 6, 8):
        fs = solve_finite(hemisphere(n, order=2, delta=0.1), "ssn", steps=4)
        assert fs.success, fs.message
        F[n] = fs.forces[-1, 1]
    r = (F[4] - F[6]) / (F[6] - F[8])
    rate = brentq(lambda p: (4.0**-p - 6.0**-p) / (6.0**-p - 8.0**-p) - r, 0.1, 8.0)
    assert rate >= 2.3, (F, rate)
    assert abs(F[8] - 13.774) <= 3e-3 * 13.774, F


@pytest.mark.parametrize("algorithm,penalty", [("simo-laursen", None), ("penalty", None), ("family-p", "exp-met1")])
def test_algorithms_agree_on_the_curved_mesh(runs, algorithm, penalty):
    """Every algorithm reproduces the ssn force of the curved P2 half-cylinder (n = 8) within 1e-6 relative."""
    pb, ref = runs[8, True]
    fs = solve_finite(pb, algorithm, penalty, steps=STEPS)
    assert fs.success, fs.message
    assert np.max(np.abs(fs.forces[:, 1] - ref.forces[:, 1]) / ref.forces[:, 1]) <= 1e-6
