r"""Differential test of the contact algorithms on random small problems (issue 19).

Random 2D problems (block size, mesh, P1/P2, E, nu, push depth; a tilted rigid plane or a
rigid cylinder pressed into the bottom face) are solved with every registered frictionless
algorithm (:func:`alcontact.contact.available_algorithms`). Asserted:

* **agreement**: whenever two algorithms both converge, their displacements agree to
  ``1e-5`` relative to the largest displacement, and their total contact forces to
  ``1e-5`` relative to the force's norm. Reference: the solutions of one discrete problem
  (the KKT point of (6.15)); the algorithms' own tolerances (``1e-8``) are far below.
  Observed on 8 seeded problems: AL algorithms and semi-smooth Newton to 1e-10, the
  penalty method to 1.3e-7.
* **equilibrium on every converged result**, from public data only:
  :math:`r = K u - f - f_c` (stiffness ``model.stiffness()``, loads
  ``problem.load_vector()``, contact nodal forces ``solution.contact_point_forces()`` on the
  DOFs of ``model.node_dofs(contact_boundary)``) vanishes on the free DOFs to ``1e-8``
  relative to :math:`\|K u\|`, and the reactions :math:`r` on the supported DOFs balance the
  contact force and the loads per direction (:math:`\sum (f + f_c + r_{fixed}) = 0`, global
  force balance) to ``1e-8`` of the contact force. (Observed: 1e-15.)

``make fuzz`` (``ALCONTACT_FUZZ=1``) draws 200 problems (about 0.1 s each); the default suite 40.
"""

from __future__ import annotations

import math
import os

import numpy as np
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from alcontact.contact import ContactProblem, Support, available_algorithms, solve
from alcontact.contact.obstacles import Circle, HalfSpace
from alcontact.fem import LinearElasticity, Material, meshes

FUZZ = bool(os.environ.get("ALCONTACT_FUZZ"))
AGREE = 1e-5
EQUILIBRIUM = 1e-8


@st.composite
def problems(draw) -> ContactProblem:
    W, H = draw(st.floats(0.5, 2.0)), draw(st.floats(0.3, 1.0))
    nx, ny, order = draw(st.integers(3, 6)), draw(st.integers(2, 3)), draw(st.integers(1, 2))
    E, nu = 10.0 ** draw(st.floats(1.0, 5.0)), draw(st.floats(0.0, 0.45))
    model = LinearElasticity(meshes.rectangle(0.0, W, 0.0, H, nx, ny), Material(E=E, nu=nu), order=order)
    d = draw(st.floats(0.002, 0.03)) * H
    if draw(st.booleans()):
        a = draw(st.floats(-0.1, 0.1))
        obstacle = HalfSpace(point=(W * draw(st.floats(0.3, 0.7)), 0.0), normal=(math.sin(a), math.cos(a)))
    else:
        R = W * draw(st.floats(1.0, 10.0))  # its top d/2 into the body, under a node: contact whatever the mesh
        cx = W * draw(st.integers(1, nx - 1)) / nx
        obstacle = Circle(center=(cx, 0.5 * d - R), radius=R)
    return ContactProblem(model=model, obstacle=obstacle, contact_boundary="bottom",
                          supports=[Support("top", (1,), -d), Support("left", (0,))])


def equilibrium_residuals(problem: ContactProblem, solution) -> tuple[float, float]:
    """``(free, balance)``: relative residual on the free DOFs and of the global force balance (public data only)."""
    model = problem.model
    Ku = model.stiffness() @ solution.u
    f = problem.load_vector()
    _, dofs = model.node_dofs(problem.contact_boundary)
    fc = np.zeros(model.ndofs)
    np.add.at(fc, dofs.ravel(), np.asarray(solution.contact_point_forces(), dtype=float).ravel())
    fixed, _ = problem.dirichlet()
    r = Ku - f - fc
    free = np.ones(model.ndofs, dtype=bool)
    free[fixed] = False
    free_res = float(np.linalg.norm(r[free]) / max(np.linalg.norm(Ku), 1e-300))
    reaction = np.where(free, 0.0, r)  # K u = f + f_c + R: the supports' forces R are r on the fixed DOFs
    comp = model.dof_map  # (n_scalar, dim): the DOF of each direction at each node
    balance = np.array([np.sum((f + fc + reaction)[comp[:, c]]) for c in range(model.dim)])
    scale = max(float(np.linalg.norm([np.sum(fc[comp[:, c]]) for c in range(model.dim)])), 1e-300)
    return free_res, float(np.linalg.norm(balance) / scale)


@settings(max_examples=200 if FUZZ else 40, deadline=None,
          suppress_health_check=[HealthCheck.too_slow, HealthCheck.data_too_large])
@given(problem=problems())
def test_every_algorithm_agrees_and_every_converged_result_is_in_equilibrium(problem):
    sols = {alg: solve(problem, algorithm=alg) for alg in available_algorithms()}
    done = {alg: s for alg, s in sols.items() if s.result.status > 0}
    assert "ssn" in done, sols["ssn"].result.message  # the reference converges on these small problems
    for alg, s in done.items():
        free_res, balance = equilibrium_residuals(problem, s)
        assert free_res <= EQUILIBRIUM and balance <= EQUILIBRIUM, (alg, free_res, balance)
    umax = max(float(np.max(np.abs(s.u))) for s in done.values())
    names = sorted(done)
    for i, a in enumerate(names):
        for b in names[i + 1:]:
            du = float(np.max(np.abs(done[a].u - done[b].u))) / umax
            fa, fb = (np.asarray(done[x].total_contact_force, dtype=float) for x in (a, b))
            df = float(np.linalg.norm(fa - fb) / max(np.linalg.norm(fa), 1e-300))
            assert du <= AGREE and df <= AGREE, (a, b, du, df)
