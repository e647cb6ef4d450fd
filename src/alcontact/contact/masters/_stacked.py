r"""The master of the stacked contact points of several contact pairs on one body.

A :class:`~alcontact.contact.ContactProblem` with several pairs (a block squeezed between
two plates, a seal pressed by a cover into a groove) stacks the contact points of its
pairs: the points of pair 0's slave boundary, then those of pair 1, ... (one constraint
per slave point and pair: a node on two slave boundaries appears once per pair). Each
pair's points are measured against that pair's own master, so the gap (6.15) of point
:math:`i` of pair :math:`k` is :math:`g_i = g^{(k)}(x_i)`. :class:`StackedMaster` presents
the pairs' masters as one :class:`~alcontact.contact.Master` over the stacked points: every
evaluation takes the points of *all* pairs, in the stacked order, and evaluates each block
with its own master.
"""

from __future__ import annotations

from typing import Any

import numpy as np
from numpy.typing import ArrayLike

from ...errors import InputError
from .obstacles import FloatArray, _ObstacleBase, _points, _previous, surface_slip


class StackedMaster(_ObstacleBase):
    """Rigid masters of several contact pairs, each evaluated on its own block of stacked points.

    Parameters
    ----------
    masters : sequence of Master
        The rigid master of each pair, in the order of the pairs.
    sizes : sequence of int
        Number of contact points of each pair's slave boundary (same order).

    Notes
    -----
    Point arguments must hold the points of every pair (``sum(sizes)`` rows, stacked in the
    pairs' order): a block of rows is evaluated by its pair's master, the rows are never
    reassigned by position. :attr:`owner` gives the pair of each stacked point.

    Examples
    --------
    >>> from alcontact.contact import obstacles
    >>> lo = obstacles.make("half-space", point=[0.0, 0.0], normal=[0.0, 1.0])
    >>> hi = obstacles.make("half-space", point=[0.0, 1.0], normal=[0.0, -1.0])
    >>> StackedMaster([lo, hi], [1, 1]).gap([[0.0, 0.1], [0.0, 0.8]])
    array([-0.1, -0.2])
    """

    def __init__(self, masters: Any, sizes: Any, *, owner: Any = None) -> None:
        self.masters = tuple(masters)
        self.sizes = tuple(int(s) for s in sizes)
        if len(self.masters) != len(self.sizes) or not self.masters:
            raise InputError(f"StackedMaster: {len(self.masters)} masters for {len(self.sizes)} point blocks; give "
                             "one master per pair and one size per pair.")
        self.bounds = np.concatenate([[0], np.cumsum(self.sizes)]).astype(np.int64)
        self.owner = (np.repeat(np.arange(len(self.sizes)), self.sizes) if owner is None
                      else np.asarray(owner, dtype=np.int64))
        dims = {m.dim for m in self.masters if m.dim is not None}
        self._dim = dims.pop() if len(dims) == 1 else None

    def take(self, idx: Any) -> "StackedMaster":
        """The master of the stacked points ``idx`` only (e.g. the contact candidates): point ``j`` of an
        evaluation is measured against the master of the pair of stacked point ``idx[j]``."""
        owner = self.owner[np.asarray(idx, dtype=np.int64)]
        return StackedMaster(self.masters, np.bincount(owner, minlength=len(self.masters)), owner=owner)

    @property
    def dim(self) -> int | None:
        return self._dim

    @property
    def name(self) -> str:
        return "stacked"

    @property
    def rigid(self) -> bool:
        return all(bool(getattr(m, "rigid", True)) for m in self.masters)

    def describe(self) -> str:
        parts = "; ".join(f"pair {k}: {m.describe()}" for k, m in enumerate(self.masters))
        return f"{len(self.masters)} masters ({parts})"

    def check_dim(self, d: int) -> None:
        for m in self.masters:
            m.check_dim(d)

    def _blocks(self, x: FloatArray, what: str):
        if x.shape[0] != self.owner.size:
            raise InputError(f"{what}: {x.shape[0]} points given to the master of {len(self.masters)} contact "
                             f"pairs, which needs the {self.owner.size} stacked points of all pairs "
                             "(in the pairs' order), or take(idx) for some of them.")
        return [np.flatnonzero(self.owner == k) for k in range(len(self.masters))]

    def _gap_normal(self, x: FloatArray) -> tuple[FloatArray, FloatArray]:
        g = np.empty(x.shape[0])
        n = np.empty_like(x)
        for m, s in zip(self.masters, self._blocks(x, "evaluate")):
            if s.size:
                g[s], n[s] = m.evaluate(x[s])
        return g, n

    def project(self, x: ArrayLike) -> FloatArray:
        pts = _points(x, self.dim)
        out = np.empty_like(pts)
        for m, s in zip(self.masters, self._blocks(pts, "project")):
            if s.size:
                out[s] = m.project(pts[s])
        return out

    def _hessian(self, x: FloatArray) -> FloatArray:
        d = x.shape[1]
        out = np.zeros((x.shape[0], d, d))
        for m, s in zip(self.masters, self._blocks(x, "gap_hessian")):
            if s.size:
                out[s] = m.gap_hessian(x[s])
        return out

    def _extent(self, d: int) -> tuple[FloatArray, FloatArray]:
        boxes = [m.bounding_box(d) for m in self.masters]
        return np.min([b[0] for b in boxes], axis=0), np.max([b[1] for b in boxes], axis=0)

    def surface_slip(self, x: ArrayLike, y_prev: ArrayLike, *,
                     jacobian: bool = True) -> tuple[FloatArray, FloatArray | None]:
        pts = _points(x, self.dim)
        prev = _previous(y_prev, pts)
        d = pts.shape[1]
        slip = np.zeros_like(pts)
        jac = np.zeros((pts.shape[0], d, d)) if jacobian else None
        for m, s in zip(self.masters, self._blocks(pts, "surface_slip")):
            if s.size:
                ds, dj = surface_slip(m, pts[s], prev[s], jacobian=jacobian)
                slip[s] = ds
                if jacobian:
                    jac[s] = dj
        return slip, jac
