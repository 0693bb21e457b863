"""Platform robots in the tests: random states about the home pose of each bundled platform
(Pinocchio's side of the closed loop: symdyn.check.pinocchio_model)."""

import numpy as np
import pinocchio as pin

from symdyn.check.closed_loop import platform_states
from symdyn.check.pinocchio_model import (actuation_matrix, closure_accelerations, closure_mismatch,  # noqa: F401
                                          free_flyer_twist_rate, pinocchio_forward_dynamics,
                                          pinocchio_inverse_dynamics, pinocchio_state)

#: bundled platform -> (home height of P (m), range of the positions (m) and angles (rad) of the
#: random states about the home pose)
PLATFORMS = {"flight_simulator": (2.0, 0.2, 0.17), "sru_platform": (0.55, 0.03, 0.08)}


def states(name, count, seed):
    """Platform states about the home pose (level, P at the home height), twists and twist rates
    of order 1 (symdyn.check.closed_loop.platform_states, which symdyn verify and bench draw from)."""
    height, reach, tilt = PLATFORMS[name]
    yield from platform_states(np.array([0.0, 0.0, height]), reach, tilt, count, seed)


def _skew(w):
    """[w x] (3 x 3)."""
    return np.array([[0.0, -w[2], w[1]], [w[2], 0.0, -w[0]], [-w[1], w[0], 0.0]])


def energy_balance(robot, ref, model, info, forward, steps=150, step=0.002):
    """Simulate from rest at the home pose under actuator forces that vary about those holding
    it there (``forward(p, R, twist, phi) -> twist rate``, RK4): returns (the change of the whole
    mechanism's kinetic plus potential energy, which Pinocchio computes from the legs' and the
    platform's states; the work of phi, Simpson over phi . q_dot)."""
    data = model.createData()
    height = PLATFORMS[robot.name][0]
    hold = ref.inverse_dynamics(np.array([0, 0, height]), np.eye(3), np.zeros(6), np.zeros(6))

    def forces(t):
        return hold * (1.0 + 0.05 * np.sin(2 * np.pi * t / 0.4 + np.arange(6)))

    def derivative(t, p, R, twist):
        rate = forward(p, R, twist, forces(t))
        return twist[3:] - np.cross(twist[:3], R @ ref.com), _skew(twist[:3]) @ R, rate

    def energy_and_power(t, p, R, twist):
        legs = ref.leg_states(p, R, twist)
        q, v, _ = pinocchio_state(model, info, ref, p, R, twist, None, legs)
        energy = pin.computeKineticEnergy(model, data, q, v) + pin.computePotentialEnergy(model, data, q)
        q_dot = np.array([leg.theta_dot[a] for leg, a in zip(legs, ref.actuated)])
        return energy, forces(t) @ q_dot

    p, R, twist = np.array([0, 0, height], dtype=float), np.eye(3), np.zeros(6)
    energies, powers = [], []
    for k in range(steps + 1):
        t = k * step
        energy, power = energy_and_power(t, p, R, twist)
        energies.append(energy)
        powers.append(power)
        if k == steps:
            break
        k1 = derivative(t, p, R, twist)
        k2 = derivative(t + step / 2, *(x + step / 2 * dx for x, dx in zip((p, R, twist), k1)))
        k3 = derivative(t + step / 2, *(x + step / 2 * dx for x, dx in zip((p, R, twist), k2)))
        k4 = derivative(t + step, *(x + step * dx for x, dx in zip((p, R, twist), k3)))
        p, R, twist = (x + step / 6 * (a + 2 * b + 2 * c + d) for x, a, b, c, d in zip((p, R, twist), k1, k2, k3, k4))
        u, _, vt = np.linalg.svd(R)
        R = u @ vt  # back onto the rotations
    work = step / 3 * (powers[0] + powers[-1] + 4 * sum(powers[1:-1:2]) + 2 * sum(powers[2:-1:2]))
    change = energies[-1] - energies[0]
    assert abs(work) > 1e-6 * abs(energies[0]), "the platform hardly moved"
    return change, work
