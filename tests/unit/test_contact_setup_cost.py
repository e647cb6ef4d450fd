"""Fixed costs of a frictionless contact solve: the penalty lookup and the element size are computed once."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

import alcontact.penalties as penalties
from alcontact.contact import contact_element_size
from alcontact.contact.algorithms import contact_penalties, find_algorithm
from alcontact.contact.systems import DiscreteContact
from alcontact.errors import UnknownNameError
from alcontact.problems import hertz


def test_penalty_for_makes_only_the_named_penalty(monkeypatch):
    """``penalty_for`` checks the named penalty only (making every registered one cost ~1 ms per solve)."""
    made = []
    real = penalties.make
    monkeypatch.setattr(penalties, "make", lambda name, *a, **k: made.append(name) or real(name, *a, **k))
    assert find_algorithm("family-p").penalty_for("log-met2") == "log-met2"
    assert made == ["log-met2"]


@pytest.mark.parametrize("name", ["nope", "log-barrier", "hestenes-powell"])
def test_penalty_for_refuses_names_that_are_no_contact_penalty(name):
    """Unknown names and registered penalties that are not usable for contact are refused, listing the usable ones."""
    assert name not in contact_penalties()
    with pytest.raises(UnknownNameError, match="contact penalty") as info:
        find_algorithm("family-p").penalty_for(name)
    for known in contact_penalties():
        assert known in str(info.value)


def test_element_size_is_kept_and_follows_the_obstacle():
    """The element size of the contact zone is computed once per model, obstacle and boundary.

    Reference: the public function :func:`alcontact.contact.contact_element_size` on the same arguments (exact equality).
    """
    prob = hertz.hertz_2d(n_per_a=4, growth=1.3)
    dc = DiscreteContact(prob)
    ref = contact_element_size(prob.model, prob.contact_boundary, prob.obstacle)
    assert dc.h == ref
    assert dc._element_size() is dc._element_size()  # kept, not recomputed
    # an obstacle moved over the coarse part of the boundary: another (larger) element size
    obstacle = dataclasses.replace(prob.obstacle, center=prob.obstacle.center + np.array([5.0, 0.0]))
    moved = dataclasses.replace(prob, obstacle=obstacle)
    expected = contact_element_size(moved.model, moved.contact_boundary, moved.obstacle)
    assert expected > 2 * ref
    dc.problem = moved
    assert dc._element_size() == expected
