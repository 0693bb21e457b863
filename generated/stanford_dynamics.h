/*
 * stanford_dynamics — equations of motion of robot 'stanford' (6 joints, standard DH).
 *
 * GENERATED FILE — DO NOT EDIT. Regenerate it with symdyn instead.
 *   generator : symdyn 0.1.0 (newton-euler; forward dynamics by LDL^T of D, double precision)
 *   input     : stanford.yaml
 *   sha256    : 83739e3c36743844ddeaa3d6c49c1412572c7af9c9d2ec94ea6649a3a2b8c2b4
 */
#ifndef STANFORD_DYNAMICS_H
#define STANFORD_DYNAMICS_H

#ifdef __cplusplus
extern "C" {
#endif

/* Scalar type of every argument (double precision). */
typedef double stanford_real;

/* Number of joints N: q, qd, qdd, tau and vector outputs hold N numbers, matrices N*N (row-major). */
#define stanford_DOF 6

/* Number of runtime parameters NP (the array p, when present, is the last input). */
#define stanford_NP 0

/*
 * Model constants folded into the code:
 *   gravity [0, 0, -9.81] m/s^2 (world frame)
 *   link 1 (j1): mass 9.29 kg, com [0, 0.0175, -0.1105] m, inertia [xx yy zz xy xz yz] [0.276, 0.255, 0.071, 0, 0, 0] kg m^2
 *   link 2 (j2): mass 5.01 kg, com [0, -0.01054, 0] m, inertia [xx yy zz xy xz yz] [0.108, 0.018, 0.1, 0, 0, 0] kg m^2
 *   link 3 (j3): mass 4.25 kg, com [0, 0, -0.06447] m, inertia [xx yy zz xy xz yz] [2.51, 2.51, 0.006, 0, 0, 0] kg m^2
 *   link 4 (j4): mass 1.08 kg, com [0, 0.00092, -0.00054] m, inertia [xx yy zz xy xz yz] [0.002, 0.001, 0.001, 0, 0, 0] kg m^2
 *   link 5 (j5): mass 0.63 kg, com [0, 0.00566, 3e-05] m, inertia [xx yy zz xy xz yz] [0.003, 0.003, 0.0004, 0, 0, 0] kg m^2
 *   link 6 (j6): mass 0.51 kg, com [0, 0, 0.01554] m, inertia [xx yy zz xy xz yz] [0.013, 0.013, 0.0003, 0, 0, 0] kg m^2
 */

/*
 * Joints (index: name, type):
 *   1: j1, revolute
 *   2: j2, revolute
 *   3: j3, prismatic
 *   4: j4, revolute
 *   5: j5, revolute
 *   6: j6, revolute
 *
 * All functions are reentrant: no allocation, no global or static state, no recursion.
 * Output arrays must not overlap the inputs.
 *
 * Inputs are taken as given: a NaN or infinite input gives NaN or infinite outputs in every
 * function except stanford_forward_dynamics_checked, which then returns a
 * nonzero status and leaves qdd unchanged (as does stanford_forward_dynamics).
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
 * Cost: 227 multiplications, 171 additions/subtractions, 0 divisions, 8 sin/cos.
 */
void stanford_inverse_dynamics(const stanford_real *q, const stanford_real *qd, const stanford_real *qdd, stanford_real *tau);

/*
 * Mass (joint-space inertia) matrix D(q), without armature.
 *   q: joint positions, N (rad for revolute, m for prismatic joints)
 *   D (out): joint-space inertia matrix D(q), N*N row-major, symmetric (kg m^2, kg m or kg)
 * Cost: 62 multiplications, 62 additions/subtractions, 0 divisions, 6 sin/cos.
 */
void stanford_mass_matrix(const stanford_real *q, stanford_real *D);

/*
 * Coriolis and centrifugal torques h(q, qd).
 *   q: joint positions, N (rad for revolute, m for prismatic joints)
 *   qd: joint velocities, N (rad/s or m/s)
 *   h (out): Coriolis and centrifugal vector h(q, qd) = C(q, qd) qd, N (N m or N)
 * Cost: 203 multiplications, 141 additions/subtractions, 0 divisions, 8 sin/cos.
 */
void stanford_coriolis(const stanford_real *q, const stanford_real *qd, stanford_real *h);

/*
 * Coriolis matrix C(q, qd), C qd = h.
 *   q: joint positions, N (rad for revolute, m for prismatic joints)
 *   qd: joint velocities, N (rad/s or m/s)
 *   C (out): Coriolis matrix C(q, qd) from the Christoffel symbols of D, N*N row-major (dD/dt - 2C is skew-symmetric)
 * Cost: 734 multiplications, 481 additions/subtractions, 0 divisions, 8 sin/cos.
 */
void stanford_coriolis_matrix(const stanford_real *q, const stanford_real *qd, stanford_real *C);

/*
 * Gravity torques c(q).
 *   q: joint positions, N (rad for revolute, m for prismatic joints)
 *   c (out): gravity vector c(q), N (N m or N)
 * Cost: 68 multiplications, 39 additions/subtractions, 0 divisions, 8 sin/cos.
 */
void stanford_gravity(const stanford_real *q, stanford_real *c);

/*
 * Forward dynamics: accelerations for torques tau at state (q, qd), by an LDL^T factorization unrolled for this robot (no inverse, at most one division per joint).
 *   q: joint positions, N (rad for revolute, m for prismatic joints)
 *   qd: joint velocities, N (rad/s or m/s)
 *   tau: joint torques/forces, N (N m or N)
 *   qdd (out): joint accelerations solving (D + diag(armature)) qdd = tau - h - c - damping qd - coulomb sign(qd), N
 * Returns 0 on success; 1 when the mass matrix is singular at q (a pivot d_j of its LDL^T factorization is not above 1e-12 times its diagonal entry, or is not a number); 2 when an input is NaN or infinite, or a result is not finite (NaN or beyond the range of double). On a nonzero return qdd is not written.
 * Cost: 381 multiplications, 278 additions/subtractions, 6 divisions, 8 sin/cos.
 */
int stanford_forward_dynamics_checked(const stanford_real *q, const stanford_real *qd, const stanford_real *tau, stanford_real *qdd);

/*
 * Forward dynamics: accelerations for torques tau at state (q, qd), by an LDL^T factorization unrolled for this robot (no inverse, at most one division per joint). Same as stanford_forward_dynamics_checked, without the status: where that returns nonzero, qdd is left unchanged.
 *   q: joint positions, N (rad for revolute, m for prismatic joints)
 *   qd: joint velocities, N (rad/s or m/s)
 *   tau: joint torques/forces, N (N m or N)
 *   qdd (out): joint accelerations solving (D + diag(armature)) qdd = tau - h - c - damping qd - coulomb sign(qd), N
 * Cost: 381 multiplications, 278 additions/subtractions, 6 divisions, 8 sin/cos.
 */
void stanford_forward_dynamics(const stanford_real *q, const stanford_real *qd, const stanford_real *tau, stanford_real *qdd);

/*
 * Forward kinematics: pose of the tool frame in the world (base placement * chain * tool).
 *   q: joint positions, N (rad for revolute, m for prismatic joints)
 *   T (out): pose of the tool frame in the world, 4*4 row-major homogeneous transform [R p; 0 0 0 1] (p in m)
 * Cost: 46 multiplications, 22 additions/subtractions, 0 divisions, 10 sin/cos.
 */
void stanford_forward_kinematics(const stanford_real *q, stanford_real *T);

/*
 * Geometric Jacobian of the tool frame: [v; omega] = J qd, world axes.
 *   q: joint positions, N (rad for revolute, m for prismatic joints)
 *   J (out): tool Jacobian, 6*N row-major, world axes at the tool origin (Pinocchio's LOCAL_WORLD_ALIGNED): rows 0-2 map qd to the tool origin's linear velocity (m/s), rows 3-5 to the angular velocity (rad/s)
 * Cost: 70 multiplications, 43 additions/subtractions, 0 divisions, 8 sin/cos.
 */
void stanford_jacobian(const stanford_real *q, stanford_real *J);

/*
 * J-dot qd: the tool's acceleration bias, so that [a; alpha] = J qdd + J-dot qd (classical acceleration), world axes.
 *   q: joint positions, N (rad for revolute, m for prismatic joints)
 *   qd: joint velocities, N (rad/s or m/s)
 *   a (out): J-dot times qd, 6: the tool origin's classical linear acceleration (m/s^2, rows 0-2) and angular acceleration (rad/s^2, rows 3-5) at qdd = 0, world axes
 * Cost: 120 multiplications, 64 additions/subtractions, 0 divisions, 10 sin/cos.
 */
void stanford_jacobian_dot_qd(const stanford_real *q, const stanford_real *qd, stanford_real *a);

/*
 * Pose and Jacobian of the tool in one call: the same results as stanford_forward_kinematics and stanford_jacobian, sharing their sin/cos and link poses (about half the cost of the two calls).
 *   q: joint positions, N (rad for revolute, m for prismatic joints)
 *   T (out): pose of the tool frame in the world, 4*4 row-major homogeneous transform [R p; 0 0 0 1] (p in m)
 *   J (out): tool Jacobian, 6*N row-major, world axes at the tool origin (Pinocchio's LOCAL_WORLD_ALIGNED): rows 0-2 map qd to the tool origin's linear velocity (m/s), rows 3-5 to the angular velocity (rad/s)
 * Cost: 88 multiplications, 52 additions/subtractions, 0 divisions, 10 sin/cos.
 */
void stanford_kinematics(const stanford_real *q, stanford_real *T, stanford_real *J);

#ifdef __cplusplus
}
#endif

#endif /* STANFORD_DYNAMICS_H */
