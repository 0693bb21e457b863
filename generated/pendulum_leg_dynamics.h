/*
 * pendulum_leg_dynamics — equations of motion of robot 'pendulum_leg' (6 joints, general joint placements).
 *
 * GENERATED FILE — DO NOT EDIT. Regenerate it with symdyn instead.
 *   generator : symdyn 0.1.0 (newton-euler; forward dynamics by LDL^T of D, double precision)
 *   input     : pendulum_leg.yaml
 *   sha256    : d45f10268fea15f488c0a529bab52cbe575efb88a0af35320dd5cd3f89d80022
 */
#ifndef PENDULUM_LEG_DYNAMICS_H
#define PENDULUM_LEG_DYNAMICS_H

#ifdef __cplusplus
extern "C" {
#endif

/* Scalar type of every argument (double precision). */
typedef double pendulum_leg_real;

/* Number of joints N: q, qd, qdd, tau and vector outputs hold N numbers, matrices N*N (row-major). */
#define PENDULUM_LEG_DOF 6

/* Number of runtime parameters NP (the array p, when present, is the last input). */
#define PENDULUM_LEG_NP 0

/* Status codes of the functions that return one (PENDULUM_LEG_OK: success; on any other code no output is written): */
#define PENDULUM_LEG_OK 0 /* success: every output written */
#define PENDULUM_LEG_SINGULAR 1 /* the mass matrix M = D + diag(armature) is singular at q: a pivot of its factorization is not above PENDULUM_LEG_PIVOT_RTOL times its diagonal entry (the articulated-body algorithm: an articulated inertia is not positive) */
#define PENDULUM_LEG_NOT_FINITE 2 /* an input is NaN or infinite, or a result is not finite (NaN, or beyond the range of the scalar type) */

/*
 * Relative pivot tolerance: a pivot at most PENDULUM_LEG_PIVOT_RTOL (1e-12 by default, for the
 * arithmetic the pivots are computed in) times its scale is reported as singular.  Checked in
 * the factorizations of the mass matrix (each LDL^T pivot against its diagonal entry).
 * Define a larger value before including this header (in every file that includes it, the
 * generated source too) to stop further from a singularity.
 */
#ifndef PENDULUM_LEG_PIVOT_RTOL
#define PENDULUM_LEG_PIVOT_RTOL 1e-12
#endif

/*
 * Model constants folded into the code, as symdyn read them from pendulum_leg.yaml, under the
 * robot file's field names (docs/robot-format.md), so that they can be checked without it. Each
 * number is the shortest decimal that reads back as the double it stands for; an exact value that
 * is not such a decimal (pi/2, 1/3) is followed by " = " and that double. A name is a runtime
 * parameter (an input in p, not folded). Units: lengths m, angles rad, masses kg; gravity m/s^2
 * in the world frame; com in the link frame; inertia (xx, yy, zz, xy, xz, yz) about the centre of
 * mass, link-frame axes, kg m^2; armature kg m^2, damping (viscous friction) N m s/rad and coulomb
 * (Coulomb friction) N m of a revolute joint, kg, N s/m and N of a prismatic one; limits rad or m,
 * rad/s or m/s, N m or N (listed only: no function checks them).
 * origin: the joint frame in the previous link's frame (xyz, then rpy: roll, pitch, yaw about the
 * fixed x, y, z axes); axis: the joint axis in the joint frame (unit).
 * base: frame 0 of the chain in the world; tool: the tool frame in the last link's frame.
 *
 *   gravity = [0.0, 0.0, -9.81]
 *   base.xyz = [0.0, 0.0, 0.0]; base.rpy = [0.0, 0.0, 0.0]
 *   tool.xyz = [0.0, 0.0, 0.0]; tool.rpy = [0.0, 0.0, 0.0]
 *   passive joints (tau 0, not actuated): 1 (foot_roll), 2 (foot_pitch), 3 (foot_yaw)
 *   link 1 (foot_roll): revolute joint, general placement, passive (not actuated)
 *     origin.xyz = [0.0, 0.0, 0.0]; origin.rpy = [0.0, 0.0, 0.0]; axis = [1.0, 0.0, 0.0]
 *     mass = 0.0; com = [0.0, 0.0, 0.0]
 *     inertia = [0.0, 0.0, 0.0, 0.0, 0.0, 0.0]
 *     armature = 0.0; damping = 0.0; coulomb = 0.0
 *   link 2 (foot_pitch): revolute joint, general placement, passive (not actuated)
 *     origin.xyz = [0.0, 0.0, 0.0]; origin.rpy = [0.0, 0.0, 0.0]; axis = [0.0, 1.0, 0.0]
 *     mass = 0.0; com = [0.0, 0.0, 0.0]
 *     inertia = [0.0, 0.0, 0.0, 0.0, 0.0, 0.0]
 *     armature = 0.0; damping = 0.0; coulomb = 0.0
 *   link 3 (foot_yaw): revolute joint, general placement, passive (not actuated)
 *     origin.xyz = [0.0, 0.0, 0.0]; origin.rpy = [0.0, 0.0, 0.0]; axis = [0.0, 0.0, 1.0]
 *     mass = 8.8; com = [0.0, 0.0, 0.5]
 *     inertia = [0.62, 0.6, 0.035, 0.0, 0.004, 0.0]
 *     armature = 0.0; damping = 0.0; coulomb = 0.0
 *   link 4 (hip_roll): revolute joint, general placement
 *     origin.xyz = [0.0, 0.0, 0.88]; origin.rpy = [0.0, 0.0, 0.0]; axis = [1.0, 0.0, 0.0]
 *     mass = 0.0; com = [0.0, 0.0, 0.0]
 *     inertia = [0.0, 0.0, 0.0, 0.0, 0.0, 0.0]
 *     armature = 0.0; damping = 0.4; coulomb = 0.0
 *   link 5 (hip_pitch): revolute joint, general placement
 *     origin.xyz = [0.0, 0.0, 0.0]; origin.rpy = [0.0, 0.0, 0.0]; axis = [0.0, 1.0, 0.0]
 *     mass = 1.2; com = [0.0, 0.02, 0.0]
 *     inertia = [0.0015, 0.0012, 0.0015, 0.0, 0.0, 0.0]
 *     armature = 0.0; damping = 0.4; coulomb = 0.0
 *   link 6 (hip_yaw): revolute joint, general placement
 *     origin.xyz = [0.0, 0.0, 0.0]; origin.rpy = [0.0, 0.0, 0.0]; axis = [0.0, 0.0, 1.0]
 *     mass = 40.7; com = [0.02, 0.0, 0.3]
 *     inertia = [1.65, 1.38, 0.42, 0.0, -0.05, 0.0]
 *     armature = 0.0; damping = 0.4; coulomb = 0.0
 */

/* Number of actuated joints NA (columns of the reaction map's D; the others are passive, tau = 0). */
#define PENDULUM_LEG_NA 3

/*
 * Joints (index: name, type):
 *   1: foot_roll, revolute, passive (tau = 0)
 *   2: foot_pitch, revolute, passive (tau = 0)
 *   3: foot_yaw, revolute, passive (tau = 0)
 *   4: hip_roll, revolute
 *   5: hip_pitch, revolute
 *   6: hip_yaw, revolute
 * Actuated joints, in the order of the reaction map's columns: 4 (hip_roll), 5 (hip_pitch), 6 (hip_yaw).
 *
 * All functions are reentrant: no allocation, no global or static state, no recursion.
 * Output arrays must not overlap the inputs.
 *
 * To keep only the functions a program calls: compile pendulum_leg_dynamics.c with
 * -ffunction-sections -fdata-sections and link with -Wl,--gc-sections (GCC, Clang), or generate
 * only those functions (symdyn generate --functions LIST).
 *
 * Inputs are taken as given: a NaN or infinite input gives NaN or infinite outputs in every
 * function except pendulum_leg_forward_dynamics_checked, which then returns a
 * nonzero status and leaves qdd unchanged (as does pendulum_leg_forward_dynamics).
 *
 * Sines and cosines of the joint angles are computed in one block at the top of each function,
 * by a branch-free polynomial within 1 ulp of libm for |q| <= 1e5 rad (libm's sin and cos
 * beyond, and for every angle when SYMDYN_LIBM_TRIG is defined).
 *
 * Floating-point contraction: compile with -ffp-contract=off (the default of -std=c99) for the
 * results documented here, identical across compilers and optimization levels.  GCC's
 * vectorizer (-O3, or -O2 from GCC 12, on FMA hardware such as -march=native) may still fuse
 * pairs a*b - c, a*b + c of neighbouring statements into one vfmaddsub despite the flag; add
 * -fno-tree-slp-vectorize (or -mno-fma) when you need those identical results.  Contraction into
 * fused multiply-adds (-ffp-contract=fast with FMA hardware) made these functions 1-36% faster
 * with errors of the same order against a 50-digit reference; results then change by rounding,
 * and batch functions may differ from the scalar ones in the last bits (symdyn's
 * docs/benchmarks.md, "FMA").
 */

/*
 * Inverse dynamics: torques that produce accelerations qdd at state (q, qd) (recursive Newton-Euler when derived by it).
 *   q: joint positions, N (rad for revolute, m for prismatic joints)
 *   qd: joint velocities, N (rad/s or m/s)
 *   qdd: joint accelerations, N (rad/s^2 or m/s^2)
 *   tau (out): joint torques/forces tau = D qdd + h + c + armature qdd + damping qd + coulomb sign(qd), N (N m or N)
 * Cost: 187 multiplications, 130 additions/subtractions, 0 divisions, 12 sin/cos.
 */
void pendulum_leg_inverse_dynamics(const pendulum_leg_real *q, const pendulum_leg_real *qd, const pendulum_leg_real *qdd, pendulum_leg_real *tau);

/*
 * Mass (joint-space inertia) matrix D(q), without armature.
 *   q: joint positions, N (rad for revolute, m for prismatic joints)
 *   D (out): joint-space inertia matrix D(q), N*N row-major, symmetric (kg m^2, kg m or kg)
 * Cost: 101 multiplications, 78 additions/subtractions, 0 divisions, 10 sin/cos.
 */
void pendulum_leg_mass_matrix(const pendulum_leg_real *q, pendulum_leg_real *D);

/*
 * Coriolis and centrifugal torques h(q, qd).
 *   q: joint positions, N (rad for revolute, m for prismatic joints)
 *   qd: joint velocities, N (rad/s or m/s)
 *   h (out): Coriolis and centrifugal vector h(q, qd) = C(q, qd) qd, N (N m or N)
 * Cost: 172 multiplications, 112 additions/subtractions, 0 divisions, 10 sin/cos.
 */
void pendulum_leg_coriolis(const pendulum_leg_real *q, const pendulum_leg_real *qd, pendulum_leg_real *h);

/*
 * Coriolis matrix C(q, qd), C qd = h.
 *   q: joint positions, N (rad for revolute, m for prismatic joints)
 *   qd: joint velocities, N (rad/s or m/s)
 *   C (out): Coriolis matrix C(q, qd) from the Christoffel symbols of D, N*N row-major (dD/dt - 2C is skew-symmetric)
 * Cost: 764 multiplications, 603 additions/subtractions, 0 divisions, 10 sin/cos.
 */
void pendulum_leg_coriolis_matrix(const pendulum_leg_real *q, const pendulum_leg_real *qd, pendulum_leg_real *C);

/*
 * Gravity torques c(q).
 *   q: joint positions, N (rad for revolute, m for prismatic joints)
 *   c (out): gravity vector c(q), N (N m or N)
 * Cost: 66 multiplications, 32 additions/subtractions, 0 divisions, 12 sin/cos.
 */
void pendulum_leg_gravity(const pendulum_leg_real *q, pendulum_leg_real *c);

/*
 * Forward dynamics: accelerations for torques tau at state (q, qd), by an LDL^T factorization unrolled for this robot (no inverse, at most one division per joint).
 *   q: joint positions, N (rad for revolute, m for prismatic joints)
 *   qd: joint velocities, N (rad/s or m/s)
 *   tau: joint torques/forces, N (N m or N)
 *   qdd (out): joint accelerations solving (D + diag(armature)) qdd = tau - h - c - damping qd - coulomb sign(qd), N
 * Returns PENDULUM_LEG_OK (0) on success; PENDULUM_LEG_SINGULAR (1) when the mass matrix is singular at q (a pivot d_j of its LDL^T factorization is not above PENDULUM_LEG_PIVOT_RTOL, 1e-12 unless defined, times its diagonal entry, or is not a number); PENDULUM_LEG_NOT_FINITE (2) when an input is NaN or infinite, or a result is not finite (NaN or beyond the range of double). On a nonzero return qdd is not written.
 * Cost: 395 multiplications, 271 additions/subtractions, 6 divisions, 12 sin/cos.
 */
int pendulum_leg_forward_dynamics_checked(const pendulum_leg_real *q, const pendulum_leg_real *qd, const pendulum_leg_real *tau, pendulum_leg_real *qdd);

/*
 * Forward dynamics: accelerations for torques tau at state (q, qd), by an LDL^T factorization unrolled for this robot (no inverse, at most one division per joint). Same as pendulum_leg_forward_dynamics_checked, without the status: where that returns nonzero, qdd is left unchanged.
 *   q: joint positions, N (rad for revolute, m for prismatic joints)
 *   qd: joint velocities, N (rad/s or m/s)
 *   tau: joint torques/forces, N (N m or N)
 *   qdd (out): joint accelerations solving (D + diag(armature)) qdd = tau - h - c - damping qd - coulomb sign(qd), N
 * Cost: 395 multiplications, 271 additions/subtractions, 6 divisions, 12 sin/cos.
 */
void pendulum_leg_forward_dynamics(const pendulum_leg_real *q, const pendulum_leg_real *qd, const pendulum_leg_real *tau, pendulum_leg_real *qdd);

/*
 * Forward kinematics: pose of the tool frame in the world (base placement * chain * tool).
 *   q: joint positions, N (rad for revolute, m for prismatic joints)
 *   T (out): pose of the tool frame in the world, 4*4 row-major homogeneous transform [R p; 0 0 0 1] (p in m)
 * Cost: 53 multiplications, 22 additions/subtractions, 0 divisions, 12 sin/cos.
 */
void pendulum_leg_forward_kinematics(const pendulum_leg_real *q, pendulum_leg_real *T);

/*
 * Geometric Jacobian of the tool frame: [v; omega] = J qd, world axes.
 *   q: joint positions, N (rad for revolute, m for prismatic joints)
 *   J (out): tool Jacobian, 6*N row-major, world axes at the tool origin (Pinocchio's LOCAL_WORLD_ALIGNED): rows 0-2 map qd to the tool origin's linear velocity (m/s), rows 3-5 to the angular velocity (rad/s)
 * Cost: 45 multiplications, 17 additions/subtractions, 0 divisions, 10 sin/cos.
 */
void pendulum_leg_jacobian(const pendulum_leg_real *q, pendulum_leg_real *J);

/*
 * J-dot qd: the tool's acceleration bias, so that [a; alpha] = J qdd + J-dot qd (classical acceleration), world axes.
 *   q: joint positions, N (rad for revolute, m for prismatic joints)
 *   qd: joint velocities, N (rad/s or m/s)
 *   a (out): J-dot times qd, 6: the tool origin's classical linear acceleration (m/s^2, rows 0-2) and angular acceleration (rad/s^2, rows 3-5) at qdd = 0, world axes
 * Cost: 129 multiplications, 68 additions/subtractions, 0 divisions, 12 sin/cos.
 */
void pendulum_leg_jacobian_dot_qd(const pendulum_leg_real *q, const pendulum_leg_real *qd, pendulum_leg_real *a);

/*
 * Force-to-torque map (the note 'Force to Torque - Articulated Body Mapping Analysis', eqs. 5-14): the wrench the base exerts on body 1 through joint 1 is [n; f] = k0 + D tau_H, affine in the actuated joints' torques tau_H with the passive joints' torques zero; derived from the articulated-body recursion (k0 at tau = 0, D's columns X_1^T A_1 ... X_j^T b_j).
 *   q: joint positions, N (rad for revolute, m for prismatic joints)
 *   qd: joint velocities, N (rad/s or m/s)
 *   k0 (out): base wrench at zero actuated torques, 6: [n; f], the moment (N m, about the base origin) and force (N) the base exerts on body 1 through joint 1, base-frame axes
 *   D (out): wrench per unit actuated torque, 6*NA row-major (column j: actuated joint j in the order listed above): [n; f] = k0 + D tau_H
 * Cost: 817 multiplications, 515 additions/subtractions, 5 divisions, 12 sin/cos.
 */
void pendulum_leg_reaction_map(const pendulum_leg_real *q, const pendulum_leg_real *qd, pendulum_leg_real *k0, pendulum_leg_real *D);

/*
 * Pose and Jacobian of the tool in one call: the same results as pendulum_leg_forward_kinematics and pendulum_leg_jacobian, sharing their sin/cos and link poses (about half the cost of the two calls).
 *   q: joint positions, N (rad for revolute, m for prismatic joints)
 *   T (out): pose of the tool frame in the world, 4*4 row-major homogeneous transform [R p; 0 0 0 1] (p in m)
 *   J (out): tool Jacobian, 6*N row-major, world axes at the tool origin (Pinocchio's LOCAL_WORLD_ALIGNED): rows 0-2 map qd to the tool origin's linear velocity (m/s), rows 3-5 to the angular velocity (rad/s)
 * Cost: 63 multiplications, 26 additions/subtractions, 0 divisions, 12 sin/cos.
 */
void pendulum_leg_kinematics(const pendulum_leg_real *q, pendulum_leg_real *T, pendulum_leg_real *J);

#ifdef __cplusplus
}
#endif

#endif /* PENDULUM_LEG_DYNAMICS_H */
