/*
 * flight_simulator_dynamics — dynamics of platform robot 'flight_simulator' (6 legs, one actuated joint each; natural orthogonal complement).
 *
 * GENERATED FILE — DO NOT EDIT. Regenerate it with symdyn instead.
 *   generator : symdyn 0.1.0 (platform robot, double precision)
 *   input     : flight_simulator.yaml
 *   sha256    : 93fc825b95bcb7b117ed3ed5fed22ce4e11455629ee80e2bf373783789f7e29a
 */
#ifndef FLIGHT_SIMULATOR_DYNAMICS_H
#define FLIGHT_SIMULATOR_DYNAMICS_H

#ifdef __cplusplus
extern "C" {
#endif

/* Scalar type of every argument (double precision). */
typedef double flight_simulator_real;

/* Degrees of freedom of the platform = actuated joints (one per leg): q, qd, qdd and phi hold 6 numbers. */
#define FLIGHT_SIMULATOR_DOF 6

/* Status codes (0: success): */
#define FLIGHT_SIMULATOR_UNREACHABLE 1 /* the pose is out of a leg's reach (its closed-form inverse kinematics has no real solution), or the quaternion is zero */
#define FLIGHT_SIMULATOR_LEG_SINGULAR 2 /* a leg is at a serial singularity at the pose (its Jacobian J_J is singular, or an angle of its inverse kinematics is not defined) */
#define FLIGHT_SIMULATOR_SINGULAR 3 /* the platform is at a parallel singularity: K (q_dot = K t, the inverse of the twist map T) is singular */
#define FLIGHT_SIMULATOR_NOT_FINITE 4 /* a result is not finite (NaN, or beyond the range of the scalar type: a twist or force so large that the dynamics overflow) */

/*
 * State.  pose[7]: the position of the platform frame P's origin (m, world frame), then P's
 * orientation as a quaternion (x, y, z, w), Pinocchio's free-flyer order; any nonzero
 * quaternion (it is normalized).  twist[6]: t = [omega; c_dot], the platform's angular
 * velocity (rad/s) and the velocity of its mass centre (m/s), world axes (the twist of the natural orthogonal complement).
 * twist_rate[6]: t_dot = [omega_dot; c_ddot], the classical time derivative of t.
 *
 * Home pose (the robot file's home configuration): pose = {0, 0, 2, 0, 0, 0, 1}.
 * Joint limits and actuator strokes are not checked: a pose every leg reaches gives status 0.
 *
 * Legs, in the order of q, qd, qdd and phi (each leg's joint values follow from the pose in
 * closed form, on the branches of the robot file's home configuration):
 *   leg1: actuated joint 4 (rod, prismatic); inverse-kinematics branches (joint 4, universal, spherical) (1, 1, 1)
 *   leg2: actuated joint 4 (rod, prismatic); inverse-kinematics branches (joint 4, universal, spherical) (1, 1, 1)
 *   leg3: actuated joint 4 (rod, prismatic); inverse-kinematics branches (joint 4, universal, spherical) (1, 1, 1)
 *   leg4: actuated joint 4 (rod, prismatic); inverse-kinematics branches (joint 4, universal, spherical) (1, 1, 1)
 *   leg5: actuated joint 4 (rod, prismatic); inverse-kinematics branches (joint 4, universal, spherical) (1, 1, 1)
 *   leg6: actuated joint 4 (rod, prismatic); inverse-kinematics branches (joint 4, universal, spherical) (1, 1, 1)
 *
 * Model constants folded into the code:
 *   platform mass 1216.926818 kg, centre of mass [0.0, 0.0, 0.0] m (platform frame), inertia about it (xx, yy, zz, xy, xz, yz) [304.4852309, 304.4852309, 608.463409, 0.0, 0.0, 0.0] kg m^2
 *   gravity [0.0, 0.0, -9.81] m/s^2 (world frame)
 *
 * Every function returns a status: 0, or one of the codes above, and then writes no output.
 * Near a singular configuration the 6x6 LU factorizations (partial pivoting) report it where a
 * pivot is at most FLIGHT_SIMULATOR_PIVOT_RTOL (1e-12 unless defined when compiling the source)
 * times the matrix's largest entry.  The closed-form inverse kinematics checks each radicand
 * before taking its square root (negative: out of reach) and each denominator (a sum of squares)
 * before dividing by it (not above PIVOT_RTOL^2 times the square of its length scale: an angle
 * of a leg that is not defined, a serial singularity).  No NaN is written for a finite input.
 *
 * All functions are reentrant: no allocation, no global or static state, no recursion.
 * Output arrays must not overlap the inputs.  Costs count the LU factorizations (70
 * multiplications, 55 additions, 6 divisions each) and solves (36 multiplications, 30
 * additions per column) with the straight-line code.
 */

/*
 * Actuator forces phi (N or N m, leg by leg) that give the platform the twist rate t_dot at state (pose, t): inverse dynamics.
 *   pose[7]: platform pose: position of the platform frame P's origin (m, world frame), then P's orientation as a quaternion (x, y, z, w): any nonzero quaternion, it is normalized
 *   twist[6]: platform twist t = [omega; c_dot]: angular velocity (rad/s) and velocity of the platform's mass centre (m/s), world axes
 *   twist_rate[6]: t_dot = [omega_dot; c_ddot] (rad/s^2, m/s^2, world axes)
 *   phi[6] (out): actuator forces (N) or torques (N m), leg by leg
 * Returns 0 on success; FLIGHT_SIMULATOR_UNREACHABLE (1) when the pose is out of a leg's reach (its closed-form inverse kinematics has no real solution), or the quaternion is zero; FLIGHT_SIMULATOR_LEG_SINGULAR (2) when a leg is at a serial singularity at the pose (its Jacobian J_J is singular, or an angle of its inverse kinematics is not defined); FLIGHT_SIMULATOR_SINGULAR (3) when the platform is at a parallel singularity: K (q_dot = K t, the inverse of the twist map T) is singular; FLIGHT_SIMULATOR_NOT_FINITE (4) when a result is not finite (NaN, or beyond the range of the scalar type: a twist or force so large that the dynamics overflow). On a nonzero return no output is written.
 * Cost: 4716 multiplications, 3452 additions/subtractions, 50 divisions, 0 sin/cos, 18 square roots, 4 other (sign, pow).
 */
int flight_simulator_inverse_dynamics(const flight_simulator_real pose[7], const flight_simulator_real twist[6], const flight_simulator_real twist_rate[6], flight_simulator_real phi[6]);

/*
 * The platform's twist rate t_dot = [omega_dot; c_ddot] and the actuated joints' accelerations qdd under actuator forces phi at state (pose, t): forward dynamics.
 *   pose[7]: platform pose: position of the platform frame P's origin (m, world frame), then P's orientation as a quaternion (x, y, z, w): any nonzero quaternion, it is normalized
 *   twist[6]: platform twist t = [omega; c_dot]: angular velocity (rad/s) and velocity of the platform's mass centre (m/s), world axes
 *   phi[6]: actuator forces (N) or torques (N m), leg by leg
 *   twist_rate[6] (out): t_dot = [omega_dot; c_ddot] (rad/s^2, m/s^2, world axes)
 *   qdd[6] (out): actuated joint accelerations (rad/s^2 or m/s^2), leg by leg
 * Returns 0 on success; FLIGHT_SIMULATOR_UNREACHABLE (1) when the pose is out of a leg's reach (its closed-form inverse kinematics has no real solution), or the quaternion is zero; FLIGHT_SIMULATOR_LEG_SINGULAR (2) when a leg is at a serial singularity at the pose (its Jacobian J_J is singular, or an angle of its inverse kinematics is not defined); FLIGHT_SIMULATOR_SINGULAR (3) when the platform's generalized inertia A (twist coordinates) is singular; forward dynamics is defined at a parallel singularity and returns 0 there; FLIGHT_SIMULATOR_NOT_FINITE (4) when a result is not finite (NaN, or beyond the range of the scalar type: a twist or force so large that the dynamics overflow). On a nonzero return no output is written.
 * Cost: 5478 multiplications, 3944 additions/subtractions, 50 divisions, 0 sin/cos, 18 square roots, 4 other (sign, pow).
 */
int flight_simulator_forward_dynamics(const flight_simulator_real pose[7], const flight_simulator_real twist[6], const flight_simulator_real phi[6], flight_simulator_real twist_rate[6], flight_simulator_real qdd[6]);

/*
 * The mass matrix M (6x6, row-major) in actuated coordinates: the kinetic energy is qd^T M qd / 2 (M = T^T M_M T + sum_J L_J^T I_J L_J, natural orthogonal complement).
 *   pose[7]: platform pose: position of the platform frame P's origin (m, world frame), then P's orientation as a quaternion (x, y, z, w): any nonzero quaternion, it is normalized
 *   M[36] (out): mass matrix in actuated coordinates, 6x6 row-major (kg m^2, kg m, kg as the joints are)
 * Returns 0 on success; FLIGHT_SIMULATOR_UNREACHABLE (1) when the pose is out of a leg's reach (its closed-form inverse kinematics has no real solution), or the quaternion is zero; FLIGHT_SIMULATOR_LEG_SINGULAR (2) when a leg is at a serial singularity at the pose (its Jacobian J_J is singular, or an angle of its inverse kinematics is not defined); FLIGHT_SIMULATOR_SINGULAR (3) when the platform is at a parallel singularity: K (q_dot = K t, the inverse of the twist map T) is singular; FLIGHT_SIMULATOR_NOT_FINITE (4) when a result is not finite (NaN, or beyond the range of the scalar type: a twist or force so large that the dynamics overflow). On a nonzero return no output is written.
 * Cost: 3753 multiplications, 2725 additions/subtractions, 50 divisions, 0 sin/cos, 18 square roots, 4 other (sign, pow).
 */
int flight_simulator_mass_matrix(const flight_simulator_real pose[7], flight_simulator_real M[36]);

/*
 * The twist map T (6x6, row-major): the platform's twist t = T qd for actuated joint rates qd (T = K^-1).
 *   pose[7]: platform pose: position of the platform frame P's origin (m, world frame), then P's orientation as a quaternion (x, y, z, w): any nonzero quaternion, it is normalized
 *   T[36] (out): the notes' T, 6x6 row-major: t = T qd
 * Returns 0 on success; FLIGHT_SIMULATOR_UNREACHABLE (1) when the pose is out of a leg's reach (its closed-form inverse kinematics has no real solution), or the quaternion is zero; FLIGHT_SIMULATOR_LEG_SINGULAR (2) when a leg is at a serial singularity at the pose (its Jacobian J_J is singular, or an angle of its inverse kinematics is not defined); FLIGHT_SIMULATOR_SINGULAR (3) when the platform is at a parallel singularity: K (q_dot = K t, the inverse of the twist map T) is singular; FLIGHT_SIMULATOR_NOT_FINITE (4) when a result is not finite (NaN, or beyond the range of the scalar type: a twist or force so large that the dynamics overflow). On a nonzero return no output is written.
 * Cost: 1233 multiplications, 979 additions/subtractions, 32 divisions, 0 sin/cos, 18 square roots, 4 other (sign, pow).
 */
int flight_simulator_twist_map(const flight_simulator_real pose[7], flight_simulator_real T[36]);

/*
 * The leg rate maps L_J for the six legs (6 blocks of 6x6, row-major, leg by leg): leg J's joint rates are L_J qd.
 *   pose[7]: platform pose: position of the platform frame P's origin (m, world frame), then P's orientation as a quaternion (x, y, z, w): any nonzero quaternion, it is normalized
 *   L[216] (out): the notes' L_J, leg by leg: 6 blocks of 6x6 row-major (leg J's joint rates = L_J qd)
 * Returns 0 on success; FLIGHT_SIMULATOR_UNREACHABLE (1) when the pose is out of a leg's reach (its closed-form inverse kinematics has no real solution), or the quaternion is zero; FLIGHT_SIMULATOR_LEG_SINGULAR (2) when a leg is at a serial singularity at the pose (its Jacobian J_J is singular, or an angle of its inverse kinematics is not defined); FLIGHT_SIMULATOR_SINGULAR (3) when the platform is at a parallel singularity: K (q_dot = K t, the inverse of the twist map T) is singular; FLIGHT_SIMULATOR_NOT_FINITE (4) when a result is not finite (NaN, or beyond the range of the scalar type: a twist or force so large that the dynamics overflow). On a nonzero return no output is written.
 * Cost: 4209 multiplications, 3001 additions/subtractions, 50 divisions, 0 sin/cos, 18 square roots, 4 other (sign, pow).
 */
int flight_simulator_leg_rate_maps(const flight_simulator_real pose[7], flight_simulator_real L[216]);

/*
 * The actuated joints' positions q (rad or m) and rates qd at state (pose, t): inverse kinematics (the closed form of each leg, on the branch of the robot file's home configuration).
 *   pose[7]: platform pose: position of the platform frame P's origin (m, world frame), then P's orientation as a quaternion (x, y, z, w): any nonzero quaternion, it is normalized
 *   twist[6]: platform twist t = [omega; c_dot]: angular velocity (rad/s) and velocity of the platform's mass centre (m/s), world axes
 *   q[6] (out): actuated joint positions (rad or m), leg by leg
 *   qd[6] (out): actuated joint rates (rad/s or m/s), leg by leg
 * Returns 0 on success; FLIGHT_SIMULATOR_UNREACHABLE (1) when the pose is out of a leg's reach (its closed-form inverse kinematics has no real solution), or the quaternion is zero; FLIGHT_SIMULATOR_LEG_SINGULAR (2) when a leg is at a serial singularity at the pose (its Jacobian J_J is singular, or an angle of its inverse kinematics is not defined); FLIGHT_SIMULATOR_NOT_FINITE (4) when a result is not finite (NaN, or beyond the range of the scalar type: a twist or force so large that the dynamics overflow). On a nonzero return no output is written.
 * Cost: 965 multiplications, 774 additions/subtractions, 26 divisions, 0 sin/cos, 18 square roots, 4 other (sign, pow).
 */
int flight_simulator_inverse_kinematics(const flight_simulator_real pose[7], const flight_simulator_real twist[6], flight_simulator_real q[6], flight_simulator_real qd[6]);

#ifdef __cplusplus
}
#endif

#endif /* FLIGHT_SIMULATOR_DYNAMICS_H */
