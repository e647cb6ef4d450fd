r"""Frictionless ironing: a rigid cylinder pressed into a neo-Hookean block, then slid sideways.

The cylinder (radius 0.5) starts touching the top of a 4 x 1 block (bottom clamped,
plane strain), is pressed down by 0.1 over the first fifth of the pseudo-time and then
moved 1.0 to the right in 10 steps (a moving obstacle, ``obstacle_path``; the slide
increment is 1.5 node spacings, so contact points enter and leave the contact zone at
every step).

References (frictionless, hyperelastic, quasi-static: no dissipation, so the steady
sliding state is symmetric about the cylinder axis): in the steady phase the horizontal
reaction is below 1 % of the vertical one, and the vertical reaction shows no jumps as
points enter and leave contact: it changes by less than 2 % between consecutive steps
(at this resolution, about 4 nodes per contact half-width, the nodal collocation moves
it by about 1 % between a node and a half-spacing offset; a lost or spurious contact
point would move it by 10-30 %).
"""

from __future__ import annotations

import numpy as np

from alcontact.contact import ContactProblem, Ramp, Support, obstacles, solve_finite
from alcontact.fem import Material, meshes
from alcontact.fem.hyperelastic import Hyperelastic


def test_ironing_steady_sliding():
    """Steady phase: |H| <= 1e-2 |V| and |V_k+1 - V_k| <= 2e-2 |V_k| (module doc)."""
    mesh = meshes.rectangle(0.0, 4.0, 0.0, 1.0, 60, 6)
    body = Hyperelastic(mesh, Material(E=1000.0, nu=0.3, plane="strain"))
    radius = 0.5
    problem = ContactProblem(body, obstacles.Circle(center=(1.0, 1.0 + radius), radius=radius), "top",
                             supports=(Support("bottom"),), kinematics="finite")
    press = Ramp((0.0, 0.2), (0.0, -0.1), hold_after=True)
    slide = Ramp((0.2, 1.0), (0.0, 1.0))
    times = list(np.linspace(0.0, 0.2, 5)[1:]) + list(np.linspace(0.2, 1.0, 11)[1:])
    fs = solve_finite(problem, "ssn", steps=times, obstacle_path=lambda t: np.array([slide(t), press(t)]))
    assert fs.success, fs.message
    t = fs.times
    F = fs.forces
    steady = t > 0.3  # the sliding has started and the contact zone has moved on by > 1 element
    assert np.sum(steady) >= 8
    H, V = F[steady, 0], F[steady, 1]
    assert np.all(V < 0)  # the cylinder pushes the block down
    assert np.max(np.abs(H) / np.abs(V)) <= 1e-2
    assert np.max(np.abs(np.diff(V)) / np.abs(V[:-1])) <= 2e-2
