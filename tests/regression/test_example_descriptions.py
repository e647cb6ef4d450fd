"""The examples' descriptions say what the files do (README: "Start from one of examples/")."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from alcontact.io import load_problem

EXAMPLES = Path(__file__).resolve().parents[2] / "examples"


def test_hertz_2d_example_is_the_builtin_problem_at_level_1():
    """Same mesh (node coordinates to 1e-12 mm) and obstacle (centre and radius to 1e-6 mm) as hertz_2d(level=1)."""
    from alcontact.problems import hertz

    setup = load_problem(EXAMPLES / "hertz_2d.toml")
    assert "level 1" in setup.data["problem"]["description"]
    built = hertz.hertz_2d(level=1)
    a, b = setup.problem.model.mesh.p, built.model.mesh.p
    assert a.shape == b.shape and setup.problem.model.ndofs == built.model.ndofs
    np.testing.assert_allclose(a[:, np.lexsort(a)], b[:, np.lexsort(b)], atol=1e-12)
    ob_a, ob_b = setup.problem.obstacle, built.obstacle
    np.testing.assert_allclose(np.asarray(ob_a.center), np.asarray(ob_b.center), atol=1e-6)
    assert abs(ob_a.radius - ob_b.radius) <= 1e-6


def test_signorini_example_touches_from_about_x_1_5_to_the_free_end():
    """Described contact zone: x in [1.5 +- 0.25, 4]; the bottom near the clamp (x < 1) is lifted off."""
    from alcontact.runner import run_setup

    setup = load_problem(EXAMPLES / "signorini_liftoff.toml")
    assert "x = 1.5" in setup.data["problem"]["description"]
    frame = run_setup(setup).frames[-1]
    assert frame.result.success
    x = frame.points[frame.active, 0]
    assert abs(x.min() - 1.5) <= 0.25 and x.max() == 4.0
    assert not np.any(frame.active & (frame.points[:, 0] < 1.0))
