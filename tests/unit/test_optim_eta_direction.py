"""Which way should eta move? (Algorithm 5.4 prints eta <- 2 eta; section 6.3.1 the opposite.)

eta divides g in (5.28), so growing it weakens the penalty. Measured here on a
small QP (multiplier 3, mu0 = 1): tightening (eta <- eta/2) converges in a few outer iterations for every
AL penalty; the printed weakening (eta <- 2 eta) does not converge within 200.
The Newton-KKT polish is switched off: it would finish either run once the active
set is known, and the question is about the AL iteration itself.
"""

import logging

import numpy as np
import pytest
from scipy.optimize import NonlinearConstraint

from alcontact.optim import minimize

CON = NonlinearConstraint(lambda x: x[0] + x[1], -np.inf, -3.0,
                          jac=lambda x: np.array([[1.0, 1.0]]))


def _run(penalty, factor):
    logging.getLogger("alcontact.optim").disabled = True
    try:
        return minimize(lambda x: x @ x, [1.0, 2.0], jac=lambda x: 2 * x,
                        hess=lambda x: 2 * np.eye(2), constraints=CON, penalty=penalty,
                        options={"strategy": "always", "strategy_options": {"factor": factor},
                                 "maxiter": 200, "polish": False, "stall_iter": 200})
    finally:
        logging.getLogger("alcontact.optim").disabled = False


@pytest.mark.parametrize("penalty", ["exp-met1", "log-met1", "log-met2", "rockafellar",
                                     "quad-met2"])
def test_tightening_beats_printed_weakening(penalty):
    tighten = _run(penalty, 2.0)   # eta <- eta / 2 (stronger)
    weaken = _run(penalty, 0.5)    # eta <- 2 eta   (as printed in Algorithm 5.4)
    assert tighten.success and tighten.nit <= 12
    assert not weaken.success
