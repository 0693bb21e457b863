"""The configuration space of a robot: integrate, difference and their Jacobians.

A fixed base's configuration is R^n (its joints' positions): ``q (+) v = q + v``.  A floating
base's is SE(3) x R^n, q = [p (3, m, world); quaternion x, y, z, w; joints] and a tangent vector
v = [v_lin (3); omega (3); joints] in the base frame, as Pinocchio's ``integrate`` and
``difference`` define them (its Lie-group conventions, ``SpecialEuclideanOperationTpl<3>``):

- ``q (+) v``: the base moves by SE(3)'s exponential in its own frame, ``M_out = M exp6(v)``:
  ``p_out = p + R V(omega) v_lin``, ``quat_out = quat * exp3(omega)`` (taken in the hemisphere
  of ``quat``: the sign is flipped when the rotation passes pi); the joints add;
- ``q1 (-) q0 = log6(M0^-1 M1)`` (the rotation's angle in [0, pi]), the joints subtract;
- their Jacobians in the tangent space, as Pinocchio's ``dIntegrate`` and ``dDifference``:
  ``d(q (+) v)/dq = Ad(exp6(v))^-1`` and ``d(q (+) v)/dv = Jr(v)`` (SE(3)'s right Jacobian),
  ``d(q1 (-) q0)/dq1 = Jr(log6 M)^-1`` and ``d(q1 (-) q0)/dq0 = -Jr(log6 M)^-1 Ad(M^-1)``,
  ``M = M0^-1 M1``.

The same log (:func:`relative_log`, from two rotation matrices) gives a corrected sole's
placement error, and SE(3)'s inverse left Jacobian its derivative.

A quaternion of any nonzero scale is taken as its unit quaternion (the emitters divide it by
its largest entry first).  The maps' coefficients are even functions of the rotation angle
theta with removable singularities at 0 (``(theta - sin theta) / theta^3``, ...): below
theta^2 = :data:`SERIES_BELOW` each is its Taylor series (:data:`SERIES_TERMS` terms, computed
by SymPy from the closed form), above it the closed form; the closed form divides by a guarded
angle that is 1 in the series' branch, so no branch divides by zero.  The series and the closed
form are the textbook ones (Barfoot, *State Estimation for Robotics*, sections 7.1.3-7.1.5, for
SE(3)'s Jacobians).
"""

from __future__ import annotations

import sympy as sp

from .spatial import cross, quaternion_rotation, skew

#: theta^2 (rad^2) below which the coefficients use their series
SERIES_BELOW = sp.Rational(1, 4)
#: terms of each series (in theta^2): at theta = 1/2 the first term left out is below 1e-18 of
#: the sum for every coefficient (the nearest singularity is at theta = 2 pi)
SERIES_TERMS = 8

_X = sp.Symbol("x", positive=True)

#: the coefficients' closed forms as functions of theta (for their series)
_CLOSED = {
    "half_sinc": sp.sin(_X / 2) / _X,  # sin(theta/2) / theta
    "c1": (_X - sp.sin(_X)) / _X ** 3,  # (theta - sin theta) / theta^3
    "c2": (_X ** 2 + 2 * sp.cos(_X) - 2) / (2 * _X ** 4),
    "c3": (2 * _X - 3 * sp.sin(_X) + _X * sp.cos(_X)) / (2 * _X ** 5),
    "e": (1 - (_X / 2) * sp.cos(_X / 2) / sp.sin(_X / 2)) / _X ** 2,  # Jr^-1's [w]x^2 coefficient
    "angle_per_sin": _X / sp.sin(_X / 2),  # theta / sin(theta/2)
}


def _series_coefficients(name: str) -> list[sp.Rational]:
    expansion = sp.series(_CLOSED[name], _X, 0, 2 * SERIES_TERMS).removeO()
    return [sp.nsimplify(expansion.coeff(_X, 2 * k)) for k in range(SERIES_TERMS)]


#: the coefficients shown in a printed derivation, in order
PRINTED_COEFFICIENTS = ("half_sinc", "c1", "c2", "c3", "e", "angle_per_sin")


def coefficient_series(theta: sp.Symbol) -> list[tuple[str, sp.Expr, sp.Expr]]:
    """``(name, closed form, series)`` of each coefficient of :data:`PRINTED_COEFFICIENTS` as a
    function of the angle ``theta``: the closed form and the Taylor series the functions use
    below theta^2 = :data:`SERIES_BELOW` (for a printed derivation)."""
    return [(name, _CLOSED[name].subs(_X, theta),
             sum(k * theta ** (2 * i) for i, k in enumerate(_series_coefficients(name))))
            for name in PRINTED_COEFFICIENTS]


class _Angle:
    """A rotation angle theta given by ``t2 = theta^2`` and by the sine and cosine of theta / 2:
    the even functions of theta the maps need, each a named Piecewise of its series and its
    closed form (in the guarded angle ``theta_g``, 1 where the series is used)."""

    def __init__(self, builder, hint: str, t2, theta, half_sin, half_cos):
        self.b, self.hint, self.t2 = builder, hint, t2
        self.small = sp.StrictLessThan(t2, SERIES_BELOW)
        self.theta_g = builder.define(f"{hint}_tg", sp.Piecewise((sp.S.One, self.small), (theta, True)), force=True)
        self.half_sin, self.half_cos = half_sin, half_cos
        #: sin(theta / 2), 1 where the series is used (the closed forms divide by it)
        self.half_sin_g = builder.define(f"{hint}_sg", sp.Piecewise((sp.S.One, self.small), (half_sin, True)),
                                         force=True)

    def coefficient(self, name: str) -> sp.Expr:
        t, s, c, s_g = self.theta_g, self.half_sin, self.half_cos, self.half_sin_g
        sin_t, cos_t = 2 * s * c, 1 - 2 * s * s
        closed = {  # (divided by t and s_g only: 1 in the series' branch)
            "half_sinc": s / t,
            "c1": (t - sin_t) / t ** 3,
            "c2": (t * t - 4 * s * s) / (2 * t ** 4),
            "c3": (2 * t - 3 * sin_t + t * cos_t) / (2 * t ** 5),
            "e": (1 - t * c / (2 * s_g)) / (t * t),
            "angle_per_sin": t / s_g,
        }[name]
        series = sp.horner(sum(k * self.t2 ** i for i, k in enumerate(_series_coefficients(name))))
        return self.b.define(f"{self.hint}_{name}", sp.Piecewise((series, self.small), (closed, True)), force=True)


def _named(builder, hint: str, values) -> sp.Matrix:
    values = list(values)
    return sp.Matrix([builder.define(f"{hint}{k + 1}", e) for k, e in enumerate(values)])


def _unit(builder, hint: str, quaternion) -> sp.Matrix:
    """The quaternion (x, y, z, w) divided by its norm (entries the emitters scaled to within
    [1, 2] in magnitude: the sum of squares neither overflows nor underflows)."""
    x, y, z, w = quaternion
    norm = builder.define(f"{hint}_n", 1 / sp.sqrt(x * x + y * y + z * z + w * w), force=True)
    return _named(builder, hint, [e * norm for e in quaternion])


def _product(a, b) -> list:
    """Hamilton product a * b of quaternions (x, y, z, w)."""
    ax, ay, az, aw = a
    bx, by, bz, bw = b
    return [aw * bx + ax * bw + ay * bz - az * by,
            aw * by - ax * bz + ay * bw + az * bx,
            aw * bz + ax * by - ay * bx + az * bw,
            aw * bw - ax * bx - ay * by - az * bz]


def _offdiagonal(angle: _Angle, rho, phi) -> sp.Matrix:
    """Barfoot's Q(rho, phi), the upper-right block of SE(3)'s left Jacobian Jl([rho; phi]) (3x3):
    the right Jacobian's is Q(-rho, -phi)."""
    P, R = skew(phi), skew(rho)
    c1, c2, c3 = (angle.coefficient(k) for k in ("c1", "c2", "c3"))
    return (R / 2 + c1 * (P * R + R * P + P * R * P) + c2 * (P * P * R + R * P * P - 3 * P * R * P)
            + c3 * (P * R * P * P + P * P * R * P))


def _block(top_left, top_right, bottom_right) -> sp.Matrix:
    return sp.Matrix(sp.BlockMatrix([[top_left, top_right], [sp.zeros(3, 3), bottom_right]]))


def _with_joints(base: sp.Matrix, joints: int, scale: int = 1) -> sp.Matrix:
    """The nv x nv Jacobian of a base block (6x6) and ``scale`` times the identity on the joints."""
    out = sp.zeros(6 + joints, 6 + joints)
    out[:6, :6] = base
    for j in range(joints):
        out[6 + j, 6 + j] = scale
    return out


def configuration_outputs(builder, floating: bool, q, v, q1, wanted) -> dict[str, sp.Matrix]:
    """The configuration-space outputs named in ``wanted`` (integrate, integrate_dq,
    integrate_dv, difference, difference_dq0, difference_dq1) for q, q1 (nq symbols each) and v
    (nv symbols), intermediate quantities defined in the program ``builder``."""
    nv = len(v)
    if not floating:
        identity = sp.eye(nv)
        found = {"integrate": sp.Matrix([a + b for a, b in zip(q, v)]), "integrate_dq": identity,
                 "integrate_dv": identity, "difference": sp.Matrix([b - a for a, b in zip(q, q1)]),
                 "difference_dq0": -identity, "difference_dq1": identity}
        return {name: found[name] for name in wanted}
    joints = nv - 6
    out: dict[str, sp.Matrix] = {}
    if {"integrate", "integrate_dq", "integrate_dv"} & set(wanted):
        out.update(_integrate(builder, q, v, joints, wanted))
    if {"difference", "difference_dq0", "difference_dq1"} & set(wanted):
        out.update(_difference(builder, q, q1, joints, wanted))
    return out


def _integrate(builder, q, v, joints: int, wanted) -> dict[str, sp.Matrix]:
    b = builder
    v_lin, omega = sp.Matrix(v[0:3]), sp.Matrix(v[3:6])
    t2 = b.define("xi_t2", omega.dot(omega), force=True)
    theta = b.define("xi_t", sp.sqrt(t2), force=True)
    half_sin, half_cos = sp.sin(theta / 2), sp.cos(theta / 2)
    angle = _Angle(b, "xi", t2, theta, half_sin, half_cos)
    k1 = angle.coefficient("half_sinc")  # sin(theta/2) / theta
    c1 = angle.coefficient("c1")
    b1 = b.define("xi_b", 2 * k1 * k1, force=True)  # (1 - cos theta) / theta^2
    wv = _named(b, "xi_wv", cross(omega, v_lin))
    translation = _named(b, "xi_p", v_lin + b1 * wv + c1 * cross(omega, wv))  # V(omega) v_lin
    out: dict[str, sp.Matrix] = {}
    if "integrate" in wanted:
        unit = _unit(b, "xi_u", q[3:7])
        rotation = quaternion_rotation(b, *q[3:7], hint="xi_k")
        step = [k1 * omega[0], k1 * omega[1], k1 * omega[2], half_cos]  # exp3(omega) as a quaternion
        sign = b.define("xi_sign", sp.Piecewise((-1, sp.StrictLessThan(half_cos, 0)), (1, True)), force=True)
        position = sp.Matrix(q[0:3]) + rotation * translation
        orientation = [sign * e for e in _product(unit, step)]
        out["integrate"] = sp.Matrix(list(position) + orientation + [a + d for a, d in zip(q[7:], v[6:])])
    if "integrate_dq" in wanted:  # Ad(exp6(v))^-1 = [R^T, -R^T [p]x; 0, R^T]
        W = skew(omega)
        step_rotation = sp.eye(3) + 2 * k1 * half_cos * W + b1 * W * W
        Rt = sp.Matrix(3, 3, lambda i, j: b.define(f"xi_R{j + 1}{i + 1}", step_rotation[j, i]))
        out["integrate_dq"] = _with_joints(_block(Rt, -Rt * skew(translation), Rt), joints)
    if "integrate_dv" in wanted:  # Jr(v) = [Jr3(omega), Q(-v_lin, -omega); 0, Jr3(omega)]
        W = skew(omega)
        right = sp.Matrix(3, 3, lambda i, j: b.define(f"xi_J{i + 1}{j + 1}", (sp.eye(3) - b1 * W + c1 * W * W)[i, j]))
        offdiagonal = _offdiagonal(angle, -v_lin, -omega)
        out["integrate_dv"] = _with_joints(_block(right, offdiagonal, right), joints)
    return out


def _difference(builder, q0, q1, joints: int, wanted) -> dict[str, sp.Matrix]:
    b = builder
    u0, u1 = _unit(b, "xd_u0_", q0[3:7]), _unit(b, "xd_u1_", q1[3:7])
    relative = _product([-u0[0], -u0[1], -u0[2], u0[3]], u1)  # u0^-1 u1: R0^T R1
    sign = b.define("xd_sign", sp.Piecewise((-1, sp.StrictLessThan(relative[3], 0)), (1, True)), force=True)
    d = _named(b, "xd_d", [sign * e for e in relative])  # in the hemisphere w >= 0: angle in [0, pi]
    s = b.define("xd_s", sp.sqrt(d[0] ** 2 + d[1] ** 2 + d[2] ** 2), force=True)  # sin(theta/2)
    theta = b.define("xd_t", 2 * sp.atan2(s, d[3]), force=True)
    t2 = b.define("xd_t2", theta * theta, force=True)
    angle = _Angle(b, "xd", t2, theta, s, d[3])
    per_sin = angle.coefficient("angle_per_sin")
    omega = _named(b, "xd_w", [per_sin * e for e in d[0:3]])
    R0 = quaternion_rotation(b, *q0[3:7], hint="xd_k")
    offset = _named(b, "xd_p", R0.T * (sp.Matrix(q1[0:3]) - sp.Matrix(q0[0:3])))  # M's translation
    e = angle.coefficient("e")
    W = skew(omega)
    inverse_right = sp.eye(3) + W / 2 + e * W * W  # Jr3(omega)^-1
    wp = _named(b, "xd_wp", cross(omega, offset))
    rho = _named(b, "xd_v", offset - wp / 2 + e * cross(omega, wp))  # V(omega)^-1 offset
    out: dict[str, sp.Matrix] = {}
    if "difference" in wanted:
        out["difference"] = sp.Matrix(list(rho) + list(omega) + [a1 - a0 for a0, a1 in zip(q0[7:], q1[7:])])
    if {"difference_dq0", "difference_dq1"} & set(wanted):
        A = sp.Matrix(3, 3, lambda i, j: b.define(f"xd_A{i + 1}{j + 1}", inverse_right[i, j]))
        corner = -A * _offdiagonal(angle, -rho, -omega) * A
        corner = sp.Matrix(3, 3, lambda i, j: b.define(f"xd_B{i + 1}{j + 1}", corner[i, j]))
        jlog = _block(A, corner, A)
        if "difference_dq1" in wanted:
            out["difference_dq1"] = _with_joints(jlog, joints)
        if "difference_dq0" in wanted:  # -Jlog6(M) Ad(M^-1), Ad(M^-1) = [R^T, -R^T [p]x; 0, R^T]
            R = quaternion_rotation(b, *d, hint="xd_kd")
            Rt = sp.Matrix(3, 3, lambda i, j: b.define(f"xd_R{j + 1}{i + 1}", R[j, i]))
            out["difference_dq0"] = _with_joints(-jlog * _block(Rt, -Rt * skew(offset), Rt), joints, -1)
    return out


class _Definer:
    """A builder's ``define`` from a plain ``define(name, expr)`` (a printout's: the identity)."""

    def __init__(self, define):
        self._define = define

    def define(self, name: str, expr, force: bool = False):
        return self._define(name, expr)


def relative_log(define, R1: sp.Matrix, p1: sp.Matrix, R2: sp.Matrix, p2: sp.Matrix, hint: str):
    """``(rho, phi, jacobian)``: ``log6(M1^-1 M2)`` of two placements (``R1``, ``p1``: the first's
    rotation and origin in the world; ``R2``, ``p2`` the second's) as Pinocchio's ``log6`` gives
    it (``phi = log3(R1^T R2)``, the angle in [0, pi]; ``rho = V(phi)^-1 R1^T (p2 - p1)``), and a
    function returning SE(3)'s inverse left Jacobian at it, ``Jl^-1([rho; phi])`` (6 x 6:
    ``log6(exp(eps) X) = log6(X) + Jl^-1 eps`` to first order).  The angle comes from
    ``atan2(|w|, (tr R - 1) / 2)``, w = vee(R - R^T) / 2; ``phi = (theta / sin theta) w``, its
    coefficient by its series near 0 (:class:`_Angle`): accurate for a rotation well away from pi
    (a sole turned half a turn from where it is held), where the axis of ``R - R^T`` vanishes.
    ``define(name, expr)`` names each intermediate."""
    b = _Definer(define)
    R = sp.Matrix(3, 3, lambda i, j: define(f"{hint}_R{i + 1}{j + 1}", (R1[:, i].T * R2[:, j])[0, 0]))
    offset = _named(b, f"{hint}_t", R1.T * (p2 - p1))
    w = _named(b, f"{hint}_w", [(R[2, 1] - R[1, 2]) / 2, (R[0, 2] - R[2, 0]) / 2, (R[1, 0] - R[0, 1]) / 2])
    s = define(f"{hint}_s", sp.sqrt(w[0] ** 2 + w[1] ** 2 + w[2] ** 2))  # sin(theta)
    cosine = define(f"{hint}_c", (R[0, 0] + R[1, 1] + R[2, 2] - 1) / 2)
    theta = define(f"{hint}_th", sp.atan2(s, cosine))
    t2 = define(f"{hint}_t2", theta * theta)
    angle = _Angle(b, hint, t2, theta, define(f"{hint}_hs", sp.sin(theta / 2)), define(f"{hint}_hc", sp.cos(theta / 2)))
    per_sin = angle.coefficient("angle_per_sin")  # theta / sin(theta/2): theta / sin(theta) = that / (2 cos(theta/2))
    phi = _named(b, f"{hint}_phi", [per_sin * e / (2 * angle.half_cos) for e in w])
    e = angle.coefficient("e")
    wt = _named(b, f"{hint}_wt", cross(phi, offset))
    rho = _named(b, f"{hint}_rho", offset - wt / 2 + e * cross(phi, wt))  # V(phi)^-1 offset

    def jacobian() -> sp.Matrix:
        W = skew(phi)
        A = sp.Matrix(3, 3, lambda i, j: define(f"{hint}_A{i + 1}{j + 1}", (sp.eye(3) - W / 2 + e * W * W)[i, j]))
        corner = -A * _offdiagonal(angle, rho, phi) * A
        corner = sp.Matrix(3, 3, lambda i, j: define(f"{hint}_B{i + 1}{j + 1}", corner[i, j]))
        return _block(A, corner, A)
    return rho, phi, jacobian
