/*
 * sru_platform_dynamics — dynamics of platform robot 'sru_platform' (6 legs, one actuated joint each; natural orthogonal complement).
 *
 * GENERATED FILE — DO NOT EDIT. Regenerate it with symdyn instead.
 *   generator : symdyn 0.1.0 (platform robot, double precision)
 *   input     : sru_platform.yaml
 *   sha256    : 103b28fafee2cf3b3b24eef8337b27429aa900c0565ae91f2d584cd51ff83ffd
 */
#ifndef SRU_PLATFORM_DYNAMICS_H
#define SRU_PLATFORM_DYNAMICS_H

#ifdef __cplusplus
extern "C" {
#endif

/* Scalar type of every argument (double precision). */
typedef double sru_platform_real;

/* Degrees of freedom of the platform = actuated joints (one per leg): q, qd, qdd and phi hold 6 numbers. */
#define SRU_PLATFORM_DOF 6

/* Status codes of the functions that return one (SRU_PLATFORM_OK: success; on any other code no output is written): */
#define SRU_PLATFORM_OK 0 /* success: every output written */
#define SRU_PLATFORM_UNREACHABLE 1 /* the pose is out of a leg's reach (its closed-form inverse kinematics has no real solution), or the quaternion is zero */
#define SRU_PLATFORM_LEG_SINGULAR 2 /* a leg is at a serial singularity at the pose (its Jacobian J_J is singular, or an angle of its inverse kinematics is not defined) */
#define SRU_PLATFORM_SINGULAR 3 /* the platform is at a parallel singularity: K (q_dot = K t, the inverse of the twist map T) is singular */
#define SRU_PLATFORM_NOT_FINITE 4 /* a result is not finite (NaN, or beyond the range of the scalar type: a twist or force so large that the dynamics overflow) */

/*
 * Relative pivot tolerance: a pivot at most SRU_PLATFORM_PIVOT_RTOL (1e-12 by default, for the
 * arithmetic the pivots are computed in) times its scale is reported as singular.  Checked in
 * the 6x6 LU factorizations (against the matrix's largest entry) and of the inverse
 * kinematics' denominators (PIVOT_RTOL^2 against the square of their length scale).
 * Define a larger value before including this header (in every file that includes it, the
 * generated source too) to stop further from a singularity.
 */
#ifndef SRU_PLATFORM_PIVOT_RTOL
#define SRU_PLATFORM_PIVOT_RTOL 1e-12
#endif

/*
 * State.  pose[7]: the position of the platform frame P's origin (m, world frame), then P's
 * orientation as a quaternion (x, y, z, w), Pinocchio's free-flyer order; any nonzero
 * quaternion (it is normalized).  twist[6]: t = [omega; c_dot], the platform's angular
 * velocity (rad/s) and the velocity of its mass centre (m/s), world axes (the twist of the natural orthogonal complement).
 * twist_rate[6]: t_dot = [omega_dot; c_ddot], the classical time derivative of t.
 *
 * Home pose (the robot file's home configuration): pose = {0, 0, 0.55, 0, 0, 0, 1}.
 * Joint limits and actuator strokes are not checked: a pose every leg reaches gives status 0.
 *
 * Legs, in the order of q, qd, qdd and phi (each leg's joint values follow from the pose in
 * closed form, on the branches of the robot file's home configuration):
 *   leg1: actuated joint 4 (knee, revolute); inverse-kinematics branches (joint 4, universal, spherical) (1, 1, 1)
 *   leg2: actuated joint 4 (knee, revolute); inverse-kinematics branches (joint 4, universal, spherical) (1, 1, 1)
 *   leg3: actuated joint 4 (knee, revolute); inverse-kinematics branches (joint 4, universal, spherical) (1, 1, 1)
 *   leg4: actuated joint 4 (knee, revolute); inverse-kinematics branches (joint 4, universal, spherical) (1, 1, 1)
 *   leg5: actuated joint 4 (knee, revolute); inverse-kinematics branches (joint 4, universal, spherical) (1, 1, 1)
 *   leg6: actuated joint 4 (knee, revolute); inverse-kinematics branches (joint 4, universal, spherical) (1, 1, 1)
 *
 * Model constants folded into the code, as symdyn read them from sru_platform.yaml, under the
 * robot file's field names (docs/parallel-format.md), so that they can be checked without it.
 * Each number is the shortest decimal that reads back as the double it stands for; an exact value
 * that is not such a decimal (pi/2, 1/3) is followed by " = " and that double. Units: lengths m,
 * angles rad (home: rad or m per joint), masses kg; gravity m/s^2 in the world frame; com in the
 * platform's or the link's frame; inertia (xx, yy, zz, xy, xz, yz) about the centre of mass in
 * that frame's axes, kg m^2; armature kg m^2 or kg, damping (viscous friction) N m s/rad or N s/m,
 * coulomb (Coulomb friction) N m or N (revolute or prismatic joint); limits are listed only.
 * base: a leg's frame 0 in the world; platform: its last link frame in the platform frame;
 * origin: a joint frame in the previous link's frame (xyz, then rpy: roll, pitch, yaw about the
 * fixed x, y, z axes), axis: the joint axis in it; Denavit-Hartenberg theta (revolute) and d
 * (prismatic) are offsets added to the joint variable.
 *
 *   gravity = [0.0, 0.0, -9.81]
 *   platform.mass = 7.634070148; platform.com = [0.0, 0.0, 0.0]
 *   platform.inertia = [0.1718301956, 0.1718301956, 0.3435331567, 0.0, 0.0, 0.0]
 *   leg leg1: actuated joint 4 (knee)
 *     base.xyz = [0.4829629131, -0.1294095226, 0.0]; base.rpy = [-26.14393763*pi/180 = -0.45629779107954305, 19.39950371*pi/180 = 0.3385852129923552, -116.167636*pi/180 = -2.0275077324582957]
 *     platform.xyz = [0.2121320344, -0.2121320344, 0.0]; platform.rpy = [-26.14393763*pi/180 = -0.45629779107954305, 19.39950371*pi/180 = 0.3385852129923552, -116.167636*pi/180 = -2.0275077324582957]
 *     home = [0.0, 0.0, 0.0, 0.0, 0.0, 0.0]
 *   leg leg2: actuated joint 4 (knee)
 *     base.xyz = [0.4829629131, 0.1294095226, 0.0]; base.rpy = [-26.14393763*pi/180 = -0.45629779107954305, -19.39950371*pi/180 = -0.3385852129923552, -63.83236399*pi/180 = -1.1140849209569648]
 *     platform.xyz = [0.2121320344, 0.2121320344, 0.0]; platform.rpy = [-26.14393763*pi/180 = -0.45629779107954305, -19.39950371*pi/180 = -0.3385852129923552, -63.83236399*pi/180 = -1.1140849209569648]
 *     home = [0.0, 0.0, 0.0, 0.0, 0.0, 0.0]
 *   leg leg3: actuated joint 4 (knee)
 *     base.xyz = [-0.1294095226, 0.4829629131, 0.0]; base.rpy = [-26.14393763*pi/180 = -0.45629779107954305, 19.39950371*pi/180 = 0.3385852129923552, 3.832363986*pi/180 = 0.06688736969055388]
 *     platform.xyz = [0.07764571353, 0.2897777479, 0.0]; platform.rpy = [-26.14393763*pi/180 = -0.45629779107954305, 19.39950371*pi/180 = 0.3385852129923552, 3.832363986*pi/180 = 0.06688736969055388]
 *     home = [0.0, 0.0, 0.0, 0.0, 0.0, 0.0]
 *   leg leg4: actuated joint 4 (knee)
 *     base.xyz = [-0.3535533906, 0.3535533906, 0.0]; base.rpy = [-26.14393763*pi/180 = -0.45629779107954305, -19.39950371*pi/180 = -0.3385852129923552, 56.16763601*pi/180 = 0.9803101814362307]
 *     platform.xyz = [-0.2897777479, 0.07764571353, 0.0]; platform.rpy = [-26.14393763*pi/180 = -0.45629779107954305, -19.39950371*pi/180 = -0.3385852129923552, 56.16763601*pi/180 = 0.9803101814362307]
 *     home = [0.0, 0.0, 0.0, 0.0, 0.0, 0.0]
 *   leg leg5: actuated joint 4 (knee)
 *     base.xyz = [-0.3535533906, -0.3535533906, 0.0]; base.rpy = [-26.14393763*pi/180 = -0.45629779107954305, 19.39950371*pi/180 = 0.3385852129923552, 123.832364*pi/180 = 2.1612824723280957]
 *     platform.xyz = [-0.2897777479, -0.07764571353, 0.0]; platform.rpy = [-26.14393763*pi/180 = -0.45629779107954305, 19.39950371*pi/180 = 0.3385852129923552, 123.832364*pi/180 = 2.1612824723280957]
 *     home = [0.0, 0.0, 0.0, 0.0, 0.0, 0.0]
 *   leg leg6: actuated joint 4 (knee)
 *     base.xyz = [-0.1294095226, -0.4829629131, 0.0]; base.rpy = [-26.14393763*pi/180 = -0.45629779107954305, -19.39950371*pi/180 = -0.3385852129923552, 176.167636*pi/180 = 3.074705283654893]
 *     platform.xyz = [0.07764571353, -0.2897777479, 0.0]; platform.rpy = [-26.14393763*pi/180 = -0.45629779107954305, -19.39950371*pi/180 = -0.3385852129923552, 176.167636*pi/180 = 3.074705283654893]
 *     home = [0.0, 0.0, 0.0, 0.0, 0.0, 0.0]
 *   links of every leg (one table for all 6):
 *     link 1 (s1): revolute joint, general placement
 *       origin.xyz = [0.0, 0.0, 0.0]; origin.rpy = [0.0, 0.0, 0.0]; axis = [1.0, 0.0, 0.0]
 *       mass = 0.0; com = [0.0, 0.0, 0.0]
 *       inertia = [0.0, 0.0, 0.0, 0.0, 0.0, 0.0]
 *       armature = 0.0; damping = 0.0; coulomb = 0.0
 *     link 2 (s2): revolute joint, general placement
 *       origin.xyz = [0.0, 0.0, 0.0]; origin.rpy = [0.0, 0.0, 0.0]; axis = [0.0, 1.0, 0.0]
 *       mass = 0.0; com = [0.0, 0.0, 0.0]
 *       inertia = [0.0, 0.0, 0.0, 0.0, 0.0, 0.0]
 *       armature = 0.0; damping = 0.0; coulomb = 0.0
 *     link 3 (thigh): revolute joint, general placement
 *       origin.xyz = [0.0, 0.0, 0.0]; origin.rpy = [0.0, 0.0, 0.0]; axis = [0.0, 0.0, 1.0]
 *       mass = 0.6; com = [0.0, 0.0, 0.175]
 *       inertia = [0.006125, 0.006125, 0.0003, 0.0, 0.0, 0.0]
 *       armature = 0.0; damping = 0.0; coulomb = 0.0
 *     link 4 (knee): revolute joint, general placement
 *       origin.xyz = [0.0, 0.0, 0.35]; origin.rpy = [0.0, 0.0, 0.0]; axis = [1.0, 0.0, 0.0]
 *       mass = 0.5; com = [0.0, -0.2211941033, 0.04120884205]
 *       inertia = [0.0084375, 0.000476319296, 0.008161180704, 0.0, 0.0, 0.001483181664]
 *       armature = 0.0; damping = 0.0; coulomb = 0.0
 *     link 5 (u1): revolute joint, general placement
 *       origin.xyz = [0.0, -0.4423882066, 0.08241768409]; origin.rpy = [0.0, 0.0, 0.0]; axis = [1.0, 0.0, 0.0]
 *       mass = 0.0; com = [0.0, 0.0, 0.0]
 *       inertia = [0.0, 0.0, 0.0, 0.0, 0.0, 0.0]
 *       armature = 0.0; damping = 0.0; coulomb = 0.0
 *     link 6 (u2): revolute joint, general placement
 *       origin.xyz = [0.0, 0.0, 0.0]; origin.rpy = [0.0, 0.0, 0.0]; axis = [0.0, 0.18315040909636277, 0.9830849035804766]
 *       mass = 0.0; com = [0.0, 0.0, 0.0]
 *       inertia = [0.0, 0.0, 0.0, 0.0, 0.0, 0.0]
 *       armature = 0.0; damping = 0.0; coulomb = 0.0
 *
 * Every function returns a status: 0, or one of the codes above, and then writes no output.
 * Near a singular configuration the 6x6 LU factorizations (partial pivoting) report it where a
 * pivot is at most SRU_PLATFORM_PIVOT_RTOL (above) times the matrix's largest entry.  The closed-form inverse kinematics checks each radicand
 * before taking its square root (negative: out of reach) and each denominator (a sum of squares)
 * before dividing by it (not above PIVOT_RTOL^2 times the square of its length scale: an angle
 * of a leg that is not defined, a serial singularity).  No NaN is written for a finite input.
 *
 * All functions are reentrant: no allocation, no global or static state, no recursion.
 * Output arrays must not overlap the inputs.  Costs count the LU factorizations (70
 * multiplications, 55 additions, 6 divisions each) and solves (36 multiplications, 30
 * additions per column) with the straight-line code.
 *
 * To keep only the functions a program calls: compile sru_platform_dynamics.c with
 * -ffunction-sections -fdata-sections and link with -Wl,--gc-sections (GCC, Clang), or generate
 * only those functions (symdyn generate --functions LIST).
 */

/*
 * Actuator forces phi (N or N m, leg by leg) that give the platform the twist rate t_dot at state (pose, t): inverse dynamics.
 *   pose[7]: platform pose: position of the platform frame P's origin (m, world frame), then P's orientation as a quaternion (x, y, z, w): any nonzero quaternion, it is normalized
 *   twist[6]: platform twist t = [omega; c_dot]: angular velocity (rad/s) and velocity of the platform's mass centre (m/s), world axes
 *   twist_rate[6]: t_dot = [omega_dot; c_ddot] (rad/s^2, m/s^2, world axes)
 *   phi[6] (out): actuator forces (N) or torques (N m), leg by leg
 * Returns SRU_PLATFORM_OK (0) on success; SRU_PLATFORM_UNREACHABLE (1) when the pose is out of a leg's reach (its closed-form inverse kinematics has no real solution), or the quaternion is zero; SRU_PLATFORM_LEG_SINGULAR (2) when a leg is at a serial singularity at the pose (its Jacobian J_J is singular, or an angle of its inverse kinematics is not defined); SRU_PLATFORM_SINGULAR (3) when the platform is at a parallel singularity: K (q_dot = K t, the inverse of the twist map T) is singular; SRU_PLATFORM_NOT_FINITE (4) when a result is not finite (NaN, or beyond the range of the scalar type: a twist or force so large that the dynamics overflow). On a nonzero return no output is written.
 * Cost: 6440 multiplications, 4748 additions/subtractions, 53 divisions, 0 sin/cos, 18 square roots, 4 other (sign, pow).
 */
int sru_platform_inverse_dynamics(const sru_platform_real pose[7], const sru_platform_real twist[6], const sru_platform_real twist_rate[6], sru_platform_real phi[6]);

/*
 * The platform's twist rate t_dot = [omega_dot; c_ddot] and the actuated joints' accelerations qdd under actuator forces phi at state (pose, t): forward dynamics.
 *   pose[7]: platform pose: position of the platform frame P's origin (m, world frame), then P's orientation as a quaternion (x, y, z, w): any nonzero quaternion, it is normalized
 *   twist[6]: platform twist t = [omega; c_dot]: angular velocity (rad/s) and velocity of the platform's mass centre (m/s), world axes
 *   phi[6]: actuator forces (N) or torques (N m), leg by leg
 *   twist_rate[6] (out): t_dot = [omega_dot; c_ddot] (rad/s^2, m/s^2, world axes)
 *   qdd[6] (out): actuated joint accelerations (rad/s^2 or m/s^2), leg by leg
 * Returns SRU_PLATFORM_OK (0) on success; SRU_PLATFORM_UNREACHABLE (1) when the pose is out of a leg's reach (its closed-form inverse kinematics has no real solution), or the quaternion is zero; SRU_PLATFORM_LEG_SINGULAR (2) when a leg is at a serial singularity at the pose (its Jacobian J_J is singular, or an angle of its inverse kinematics is not defined); SRU_PLATFORM_SINGULAR (3) when the platform's generalized inertia A (twist coordinates) is singular; forward dynamics is defined at a parallel singularity and returns 0 there; SRU_PLATFORM_NOT_FINITE (4) when a result is not finite (NaN, or beyond the range of the scalar type: a twist or force so large that the dynamics overflow). On a nonzero return no output is written.
 * Cost: 7640 multiplications, 5666 additions/subtractions, 53 divisions, 0 sin/cos, 18 square roots, 4 other (sign, pow).
 */
int sru_platform_forward_dynamics(const sru_platform_real pose[7], const sru_platform_real twist[6], const sru_platform_real phi[6], sru_platform_real twist_rate[6], sru_platform_real qdd[6]);

/*
 * The mass matrix M (6x6, row-major) in actuated coordinates: the kinetic energy is qd^T M qd / 2 (M = T^T M_M T + sum_J L_J^T I_J L_J, natural orthogonal complement).
 *   pose[7]: platform pose: position of the platform frame P's origin (m, world frame), then P's orientation as a quaternion (x, y, z, w): any nonzero quaternion, it is normalized
 *   M[36] (out): mass matrix in actuated coordinates, 6x6 row-major (kg m^2, kg m, kg as the joints are)
 * Returns SRU_PLATFORM_OK (0) on success; SRU_PLATFORM_UNREACHABLE (1) when the pose is out of a leg's reach (its closed-form inverse kinematics has no real solution), or the quaternion is zero; SRU_PLATFORM_LEG_SINGULAR (2) when a leg is at a serial singularity at the pose (its Jacobian J_J is singular, or an angle of its inverse kinematics is not defined); SRU_PLATFORM_SINGULAR (3) when the platform is at a parallel singularity: K (q_dot = K t, the inverse of the twist map T) is singular; SRU_PLATFORM_NOT_FINITE (4) when a result is not finite (NaN, or beyond the range of the scalar type: a twist or force so large that the dynamics overflow). On a nonzero return no output is written.
 * Cost: 5279 multiplications, 3955 additions/subtractions, 53 divisions, 0 sin/cos, 18 square roots, 4 other (sign, pow).
 */
int sru_platform_mass_matrix(const sru_platform_real pose[7], sru_platform_real M[36]);

/*
 * The twist map T (6x6, row-major): the platform's twist t = T qd for actuated joint rates qd (T = K^-1).
 *   pose[7]: platform pose: position of the platform frame P's origin (m, world frame), then P's orientation as a quaternion (x, y, z, w): any nonzero quaternion, it is normalized
 *   T[36] (out): the notes' T, 6x6 row-major: t = T qd
 * Returns SRU_PLATFORM_OK (0) on success; SRU_PLATFORM_UNREACHABLE (1) when the pose is out of a leg's reach (its closed-form inverse kinematics has no real solution), or the quaternion is zero; SRU_PLATFORM_LEG_SINGULAR (2) when a leg is at a serial singularity at the pose (its Jacobian J_J is singular, or an angle of its inverse kinematics is not defined); SRU_PLATFORM_SINGULAR (3) when the platform is at a parallel singularity: K (q_dot = K t, the inverse of the twist map T) is singular; SRU_PLATFORM_NOT_FINITE (4) when a result is not finite (NaN, or beyond the range of the scalar type: a twist or force so large that the dynamics overflow). On a nonzero return no output is written.
 * Cost: 2363 multiplications, 1759 additions/subtractions, 35 divisions, 0 sin/cos, 18 square roots, 4 other (sign, pow).
 */
int sru_platform_twist_map(const sru_platform_real pose[7], sru_platform_real T[36]);

/*
 * The leg rate maps L_J for the six legs (6 blocks of 6x6, row-major, leg by leg): leg J's joint rates are L_J qd.
 *   pose[7]: platform pose: position of the platform frame P's origin (m, world frame), then P's orientation as a quaternion (x, y, z, w): any nonzero quaternion, it is normalized
 *   L[216] (out): the notes' L_J, leg by leg: 6 blocks of 6x6 row-major (leg J's joint rates = L_J qd)
 * Returns SRU_PLATFORM_OK (0) on success; SRU_PLATFORM_UNREACHABLE (1) when the pose is out of a leg's reach (its closed-form inverse kinematics has no real solution), or the quaternion is zero; SRU_PLATFORM_LEG_SINGULAR (2) when a leg is at a serial singularity at the pose (its Jacobian J_J is singular, or an angle of its inverse kinematics is not defined); SRU_PLATFORM_SINGULAR (3) when the platform is at a parallel singularity: K (q_dot = K t, the inverse of the twist map T) is singular; SRU_PLATFORM_NOT_FINITE (4) when a result is not finite (NaN, or beyond the range of the scalar type: a twist or force so large that the dynamics overflow). On a nonzero return no output is written.
 * Cost: 5297 multiplications, 3805 additions/subtractions, 53 divisions, 0 sin/cos, 18 square roots, 4 other (sign, pow).
 */
int sru_platform_leg_rate_maps(const sru_platform_real pose[7], sru_platform_real L[216]);

/*
 * The actuated joints' positions q (rad or m) and rates qd at state (pose, t): inverse kinematics (the closed form of each leg, on the branch of the robot file's home configuration).
 *   pose[7]: platform pose: position of the platform frame P's origin (m, world frame), then P's orientation as a quaternion (x, y, z, w): any nonzero quaternion, it is normalized
 *   twist[6]: platform twist t = [omega; c_dot]: angular velocity (rad/s) and velocity of the platform's mass centre (m/s), world axes
 *   q[6] (out): actuated joint positions (rad or m), leg by leg
 *   qd[6] (out): actuated joint rates (rad/s or m/s), leg by leg
 * Returns SRU_PLATFORM_OK (0) on success; SRU_PLATFORM_UNREACHABLE (1) when the pose is out of a leg's reach (its closed-form inverse kinematics has no real solution), or the quaternion is zero; SRU_PLATFORM_LEG_SINGULAR (2) when a leg is at a serial singularity at the pose (its Jacobian J_J is singular, or an angle of its inverse kinematics is not defined); SRU_PLATFORM_NOT_FINITE (4) when a result is not finite (NaN, or beyond the range of the scalar type: a twist or force so large that the dynamics overflow). On a nonzero return no output is written.
 * Cost: 2095 multiplications, 1554 additions/subtractions, 29 divisions, 0 sin/cos, 18 square roots, 10 other (sign, pow).
 */
int sru_platform_inverse_kinematics(const sru_platform_real pose[7], const sru_platform_real twist[6], sru_platform_real q[6], sru_platform_real qd[6]);

#ifdef __cplusplus
}
#endif

#endif /* SRU_PLATFORM_DYNAMICS_H */
