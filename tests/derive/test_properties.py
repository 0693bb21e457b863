"""Physical properties of the derived equations, at seeded random states."""

import numpy as np
import pytest

from helpers import ROBOTS, parameter_values, random_states


@pytest.mark.parametrize("name", ROBOTS)
def test_properties(derived, name):
    eqs = derived(name, "newton-euler")
    num = eqs.numeric
    values = parameter_values(eqs.robot)
    p = [values[s] for s in eqs.parameters]
    n = eqs.n
    zero = np.zeros(n)
    for q, qd, qdd, tau in random_states(n, 10, seed=11):
        D = num.mass_matrix(q, p)
        # D symmetric positive definite
        assert np.allclose(D, D.T, rtol=0, atol=1e-13 * np.abs(D).max())
        assert np.linalg.eigvalsh(D).min() > 0
        # dD/dt - 2C skew-symmetric (dD/dt by central differences along qd)
        step = 1e-6
        Ddot = (num.mass_matrix(q + step * qd, p) - num.mass_matrix(q - step * qd, p)) / (2 * step)
        C = num.coriolis_matrix(q, qd, p)
        N = Ddot - 2 * C
        assert np.allclose(N, -N.T, rtol=0, atol=1e-6 * max(1.0, np.abs(Ddot).max()))
        # C qd = h
        h = num.coriolis(q, qd, p)
        assert np.allclose(C @ qd, h, rtol=1e-11, atol=1e-11 * max(1.0, np.abs(h).max()))
        # tau(q, 0, 0) = c
        c = num.gravity(q, p)
        assert np.allclose(num.inverse_dynamics(q, zero, zero, p), c, rtol=1e-12, atol=1e-12 * max(1.0, np.abs(c).max()))
        # forward dynamics inverts inverse dynamics
        tau_id = num.inverse_dynamics(q, qd, qdd, p)
        assert np.allclose(num.forward_dynamics(q, qd, tau_id, p), qdd, rtol=1e-9, atol=1e-9)


def test_skew_check_would_fail_for_a_wrong_coriolis_matrix(derived):
    """C + (a skew matrix times |qd|) still gives C qd = h for symmetric tweaks? No: the property
    test is sharp; doubling C breaks dD/dt - 2C skew-symmetry."""
    eqs = derived("puma560")
    num = eqs.numeric
    q, qd = np.full(6, 0.3), np.linspace(-1, 1, 6)
    step = 1e-6
    Ddot = (num.mass_matrix(q + step * qd) - num.mass_matrix(q - step * qd)) / (2 * step)
    N = Ddot - 4 * num.coriolis_matrix(q, qd)
    assert not np.allclose(N, -N.T, atol=1e-6)
