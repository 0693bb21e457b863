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
#define STANFORD_DOF 6

/* Number of runtime parameters NP (the array p, when present, is the last input). */
#define STANFORD_NP 0

/* Status codes of the functions that return one (STANFORD_OK: success; on any other code no output is written): */
#define STANFORD_OK 0 /* success: every output written */
#define STANFORD_SINGULAR 1 /* the mass matrix M = D + diag(armature) is singular at q: a pivot of its factorization is not above STANFORD_PIVOT_RTOL times its diagonal entry (the articulated-body algorithm: an articulated inertia is not positive) */
#define STANFORD_NOT_FINITE 2 /* an input is NaN or infinite, or a result is not finite (NaN, or beyond the range of the scalar type) */

/*
 * Relative pivot tolerance: a pivot at most STANFORD_PIVOT_RTOL (1e-12 by default, for the
 * arithmetic the pivots are computed in) times its scale is reported as singular.  Checked in
 * the factorizations of the mass matrix (each LDL^T pivot against its diagonal entry).
 * Define a larger value before including this header (in every file that includes it, the
 * generated source too) to stop further from a singularity.
 */
#ifndef STANFORD_PIVOT_RTOL
#define STANFORD_PIVOT_RTOL 1e-12
#endif

/*
 * Model constants folded into the code, as symdyn read them from stanford.yaml, under the
 * robot file's field names (docs/robot-format.md), so that they can be checked without it. Each
 * number is the shortest decimal that reads back as the double it stands for; an exact value that
 * is not such a decimal (pi/2, 1/3) is followed by " = " and that double. A name is a runtime
 * parameter (an input in p, not folded). Units: lengths m, angles rad, masses kg; gravity m/s^2
 * in the world frame; com in the link frame; inertia (xx, yy, zz, xy, xz, yz) about the centre of
 * mass, link-frame axes, kg m^2; armature kg m^2, damping (viscous friction) N m s/rad and coulomb
 * (Coulomb friction) N m of a revolute joint, kg, N s/m and N of a prismatic one; limits rad or m,
 * rad/s or m/s, N m or N (listed only: no function checks them).
 * Standard Denavit-Hartenberg parameters; theta of a revolute joint and d of a
 * prismatic one are offsets added to q.
 * base: frame 0 of the chain in the world; tool: the tool frame in the last link's frame.
 *
 *   gravity = [0.0, 0.0, -9.81]
 *   base.xyz = [0.0, 0.0, 0.0]; base.rpy = [0.0, 0.0, 0.0]
 *   tool.xyz = [0.0, 0.0, 0.0]; tool.rpy = [0.0, 0.0, 0.0]
 *   link 1 (j1): revolute joint, standard DH
 *     a = 0.0; alpha = -pi/2 = -1.5707963267948966; d = 0.412; theta = 0.0
 *     mass = 9.29; com = [0.0, 0.0175, -0.1105]
 *     inertia = [0.276, 0.255, 0.071, 0.0, 0.0, 0.0]
 *     armature = 0.953; damping = 0.0; coulomb = 0.0
 *   link 2 (j2): revolute joint, standard DH
 *     a = 0.0; alpha = pi/2 = 1.5707963267948966; d = 0.154; theta = 0.0
 *     mass = 5.01; com = [0.0, -0.01054, 0.0]
 *     inertia = [0.108, 0.018, 0.1, 0.0, 0.0, 0.0]
 *     armature = 2.193; damping = 0.0; coulomb = 0.0
 *   link 3 (j3): prismatic joint, standard DH
 *     a = 0.0; alpha = 0.0; d = 0.0; theta = -pi/2 = -1.5707963267948966
 *     mass = 4.25; com = [0.0, 0.0, -0.06447]
 *     inertia = [2.51, 2.51, 0.006, 0.0, 0.0, 0.0]
 *     armature = 0.782; damping = 0.0; coulomb = 0.0
 *   link 4 (j4): revolute joint, standard DH
 *     a = 0.0; alpha = -pi/2 = -1.5707963267948966; d = 0.0; theta = 0.0
 *     mass = 1.08; com = [0.0, 0.00092, -0.00054]
 *     inertia = [0.002, 0.001, 0.001, 0.0, 0.0, 0.0]
 *     armature = 0.106; damping = 0.0; coulomb = 0.0
 *   link 5 (j5): revolute joint, standard DH
 *     a = 0.0; alpha = pi/2 = 1.5707963267948966; d = 0.0; theta = 0.0
 *     mass = 0.63; com = [0.0, 0.00566, 3e-05]
 *     inertia = [0.003, 0.003, 0.0004, 0.0, 0.0, 0.0]
 *     armature = 0.097; damping = 0.0; coulomb = 0.0
 *   link 6 (j6): revolute joint, standard DH
 *     a = 0.0; alpha = 0.0; d = 0.263; theta = 0.0
 *     mass = 0.51; com = [0.0, 0.0, 0.01554]
 *     inertia = [0.013, 0.013, 0.0003, 0.0, 0.0, 0.0]
 *     armature = 0.02; damping = 0.0; coulomb = 0.0
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
 * To keep only the functions a program calls: compile stanford_dynamics.c with
 * -ffunction-sections -fdata-sections and link with -Wl,--gc-sections (GCC, Clang), or generate
 * only those functions (symdyn generate --functions LIST).
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
 * Returns STANFORD_OK (0) on success; STANFORD_SINGULAR (1) when the mass matrix is singular at q (a pivot d_j of its LDL^T factorization is not above STANFORD_PIVOT_RTOL, 1e-12 unless defined, times its diagonal entry, or is not a number); STANFORD_NOT_FINITE (2) when an input is NaN or infinite, or a result is not finite (NaN or beyond the range of double). On a nonzero return qdd is not written.
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
