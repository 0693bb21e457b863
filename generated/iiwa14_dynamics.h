/*
 * iiwa14_dynamics — equations of motion of robot 'iiwa14' (7 joints, standard DH).
 *
 * GENERATED FILE — DO NOT EDIT. Regenerate it with symdyn instead.
 *   generator : symdyn 0.1.0 (newton-euler; forward dynamics by LDL^T of D, double precision)
 *   input     : iiwa14.yaml
 *   sha256    : bb9ae76121f1b45419cf55df0f149ed01242e97474437572271d40165e92d74a
 */
#ifndef IIWA14_DYNAMICS_H
#define IIWA14_DYNAMICS_H

#ifdef __cplusplus
extern "C" {
#endif

/* Scalar type of every argument (double precision). */
typedef double iiwa14_real;

/* Number of joints N: q, qd, qdd, tau and vector outputs hold N numbers, matrices N*N (row-major). */
#define IIWA14_DOF 7

/* Number of runtime parameters NP (the array p, when present, is the last input). */
#define IIWA14_NP 0

/* Status codes of the functions that return one (IIWA14_OK: success; on any other code no output is written): */
#define IIWA14_OK 0 /* success: every output written */
#define IIWA14_SINGULAR 1 /* the mass matrix M = D + diag(armature) is singular at q: a pivot of its factorization is not above IIWA14_PIVOT_RTOL times its diagonal entry (the articulated-body algorithm: an articulated inertia is not positive) */
#define IIWA14_NOT_FINITE 2 /* an input is NaN or infinite, or a result is not finite (NaN, or beyond the range of the scalar type) */

/*
 * Relative pivot tolerance: a pivot at most IIWA14_PIVOT_RTOL (1e-12 by default, for the
 * arithmetic the pivots are computed in) times its scale is reported as singular.  Checked in
 * the factorizations of the mass matrix (each LDL^T pivot against its diagonal entry).
 * Define a larger value before including this header (in every file that includes it, the
 * generated source too) to stop further from a singularity.
 */
#ifndef IIWA14_PIVOT_RTOL
#define IIWA14_PIVOT_RTOL 1e-12
#endif

/*
 * Model constants folded into the code, as symdyn read them from iiwa14.yaml, under the
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
 *     a = 0.0; alpha = -pi/2 = -1.5707963267948966; d = 0.36; theta = 0.0
 *     mass = 4.0; com = [0.0, 0.08, -0.03]
 *     inertia = [0.1, 0.02, 0.09, 0.0, 0.0, 0.0]
 *     armature = 0.0; damping = 0.0; coulomb = 0.0
 *   link 2 (j2): revolute joint, standard DH
 *     a = 0.0; alpha = pi/2 = 1.5707963267948966; d = 0.0; theta = 0.0
 *     mass = 4.0; com = [0.0003, 0.042, 0.059]
 *     inertia = [0.05, 0.044, 0.018, 0.0, 0.0, 0.0]
 *     armature = 0.0; damping = 0.0; coulomb = 0.0
 *   link 3 (j3): revolute joint, standard DH
 *     a = 0.0; alpha = pi/2 = 1.5707963267948966; d = 0.42; theta = 0.0
 *     mass = 3.0; com = [0.0, -0.03, -0.07]
 *     inertia = [0.08, 0.075, 0.01, 0.0, 0.0, 0.0]
 *     armature = 0.0; damping = 0.0; coulomb = 0.0
 *   link 4 (j4): revolute joint, standard DH
 *     a = 0.0; alpha = -pi/2 = -1.5707963267948966; d = 0.0; theta = 0.0
 *     mass = 2.7; com = [0.0, 0.034, 0.067]
 *     inertia = [0.03, 0.029, 0.01, 0.0, 0.0, 0.0]
 *     armature = 0.0; damping = 0.0; coulomb = 0.0
 *   link 5 (j5): revolute joint, standard DH
 *     a = 0.0; alpha = -pi/2 = -1.5707963267948966; d = 0.4; theta = 0.0
 *     mass = 1.7; com = [0.0001, -0.021, -0.124]
 *     inertia = [0.02, 0.018, 0.005, 0.0, 0.0, 0.0]
 *     armature = 0.0; damping = 0.0; coulomb = 0.0
 *   link 6 (j6): revolute joint, standard DH
 *     a = 0.0; alpha = pi/2 = 1.5707963267948966; d = 0.0; theta = 0.0
 *     mass = 1.8; com = [0.0, 0.0004, 0.0006]
 *     inertia = [0.005, 0.0047, 0.0036, 0.0, 0.0, 0.0]
 *     armature = 0.0; damping = 0.0; coulomb = 0.0
 *   link 7 (j7): revolute joint, standard DH
 *     a = 0.0; alpha = 0.0; d = 0.126; theta = 0.0
 *     mass = 0.3; com = [0.0, 0.0, -0.106]
 *     inertia = [0.001, 0.001, 0.001, 0.0, 0.0, 0.0]
 *     armature = 0.0; damping = 0.0; coulomb = 0.0
 */

/*
 * Joints (index: name, type):
 *   1: j1, revolute
 *   2: j2, revolute
 *   3: j3, revolute
 *   4: j4, revolute
 *   5: j5, revolute
 *   6: j6, revolute
 *   7: j7, revolute
 *
 * All functions are reentrant: no allocation, no global or static state, no recursion.
 * Output arrays must not overlap the inputs.
 *
 * To keep only the functions a program calls: compile iiwa14_dynamics.c with
 * -ffunction-sections -fdata-sections and link with -Wl,--gc-sections (GCC, Clang), or generate
 * only those functions (symdyn generate --functions LIST).
 *
 * Inputs are taken as given: a NaN or infinite input gives NaN or infinite outputs in every
 * function except iiwa14_forward_dynamics_checked, which then returns a
 * nonzero status and leaves qdd unchanged (as does iiwa14_forward_dynamics).
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
 * Cost: 313 multiplications, 243 additions/subtractions, 0 divisions, 12 sin/cos.
 */
void iiwa14_inverse_dynamics(const iiwa14_real *q, const iiwa14_real *qd, const iiwa14_real *qdd, iiwa14_real *tau);

/*
 * Mass (joint-space inertia) matrix D(q), without armature.
 *   q: joint positions, N (rad for revolute, m for prismatic joints)
 *   D (out): joint-space inertia matrix D(q), N*N row-major, symmetric (kg m^2, kg m or kg)
 * Cost: 118 multiplications, 112 additions/subtractions, 0 divisions, 10 sin/cos.
 */
void iiwa14_mass_matrix(const iiwa14_real *q, iiwa14_real *D);

/*
 * Coriolis and centrifugal torques h(q, qd).
 *   q: joint positions, N (rad for revolute, m for prismatic joints)
 *   qd: joint velocities, N (rad/s or m/s)
 *   h (out): Coriolis and centrifugal vector h(q, qd) = C(q, qd) qd, N (N m or N)
 * Cost: 300 multiplications, 215 additions/subtractions, 0 divisions, 12 sin/cos.
 */
void iiwa14_coriolis(const iiwa14_real *q, const iiwa14_real *qd, iiwa14_real *h);

/*
 * Coriolis matrix C(q, qd), C qd = h.
 *   q: joint positions, N (rad for revolute, m for prismatic joints)
 *   qd: joint velocities, N (rad/s or m/s)
 *   C (out): Coriolis matrix C(q, qd) from the Christoffel symbols of D, N*N row-major (dD/dt - 2C is skew-symmetric)
 * Cost: 1289 multiplications, 1083 additions/subtractions, 0 divisions, 12 sin/cos.
 */
void iiwa14_coriolis_matrix(const iiwa14_real *q, const iiwa14_real *qd, iiwa14_real *C);

/*
 * Gravity torques c(q).
 *   q: joint positions, N (rad for revolute, m for prismatic joints)
 *   c (out): gravity vector c(q), N (N m or N)
 * Cost: 101 multiplications, 60 additions/subtractions, 0 divisions, 12 sin/cos.
 */
void iiwa14_gravity(const iiwa14_real *q, iiwa14_real *c);

/*
 * Forward dynamics: accelerations for torques tau at state (q, qd), by an LDL^T factorization unrolled for this robot (no inverse, at most one division per joint).
 *   q: joint positions, N (rad for revolute, m for prismatic joints)
 *   qd: joint velocities, N (rad/s or m/s)
 *   tau: joint torques/forces, N (N m or N)
 *   qdd (out): joint accelerations solving (D + diag(armature)) qdd = tau - h - c - damping qd - coulomb sign(qd), N
 * Returns IIWA14_OK (0) on success; IIWA14_SINGULAR (1) when the mass matrix is singular at q (a pivot d_j of its LDL^T factorization is not above IIWA14_PIVOT_RTOL, 1e-12 unless defined, times its diagonal entry, or is not a number); IIWA14_NOT_FINITE (2) when an input is NaN or infinite, or a result is not finite (NaN or beyond the range of double). On a nonzero return qdd is not written.
 * Cost: 584 multiplications, 439 additions/subtractions, 7 divisions, 12 sin/cos.
 */
int iiwa14_forward_dynamics_checked(const iiwa14_real *q, const iiwa14_real *qd, const iiwa14_real *tau, iiwa14_real *qdd);

/*
 * Forward dynamics: accelerations for torques tau at state (q, qd), by an LDL^T factorization unrolled for this robot (no inverse, at most one division per joint). Same as iiwa14_forward_dynamics_checked, without the status: where that returns nonzero, qdd is left unchanged.
 *   q: joint positions, N (rad for revolute, m for prismatic joints)
 *   qd: joint velocities, N (rad/s or m/s)
 *   tau: joint torques/forces, N (N m or N)
 *   qdd (out): joint accelerations solving (D + diag(armature)) qdd = tau - h - c - damping qd - coulomb sign(qd), N
 * Cost: 584 multiplications, 439 additions/subtractions, 7 divisions, 12 sin/cos.
 */
void iiwa14_forward_dynamics(const iiwa14_real *q, const iiwa14_real *qd, const iiwa14_real *tau, iiwa14_real *qdd);

/*
 * Forward kinematics: pose of the tool frame in the world (base placement * chain * tool).
 *   q: joint positions, N (rad for revolute, m for prismatic joints)
 *   T (out): pose of the tool frame in the world, 4*4 row-major homogeneous transform [R p; 0 0 0 1] (p in m)
 * Cost: 71 multiplications, 35 additions/subtractions, 0 divisions, 14 sin/cos.
 */
void iiwa14_forward_kinematics(const iiwa14_real *q, iiwa14_real *T);

/*
 * Geometric Jacobian of the tool frame: [v; omega] = J qd, world axes.
 *   q: joint positions, N (rad for revolute, m for prismatic joints)
 *   J (out): tool Jacobian, 6*N row-major, world axes at the tool origin (Pinocchio's LOCAL_WORLD_ALIGNED): rows 0-2 map qd to the tool origin's linear velocity (m/s), rows 3-5 to the angular velocity (rad/s)
 * Cost: 115 multiplications, 70 additions/subtractions, 0 divisions, 12 sin/cos.
 */
void iiwa14_jacobian(const iiwa14_real *q, iiwa14_real *J);

/*
 * J-dot qd: the tool's acceleration bias, so that [a; alpha] = J qdd + J-dot qd (classical acceleration), world axes.
 *   q: joint positions, N (rad for revolute, m for prismatic joints)
 *   qd: joint velocities, N (rad/s or m/s)
 *   a (out): J-dot times qd, 6: the tool origin's classical linear acceleration (m/s^2, rows 0-2) and angular acceleration (rad/s^2, rows 3-5) at qdd = 0, world axes
 * Cost: 169 multiplications, 96 additions/subtractions, 0 divisions, 14 sin/cos.
 */
void iiwa14_jacobian_dot_qd(const iiwa14_real *q, const iiwa14_real *qd, iiwa14_real *a);

/*
 * Pose and Jacobian of the tool in one call: the same results as iiwa14_forward_kinematics and iiwa14_jacobian, sharing their sin/cos and link poses (about half the cost of the two calls).
 *   q: joint positions, N (rad for revolute, m for prismatic joints)
 *   T (out): pose of the tool frame in the world, 4*4 row-major homogeneous transform [R p; 0 0 0 1] (p in m)
 *   J (out): tool Jacobian, 6*N row-major, world axes at the tool origin (Pinocchio's LOCAL_WORLD_ALIGNED): rows 0-2 map qd to the tool origin's linear velocity (m/s), rows 3-5 to the angular velocity (rad/s)
 * Cost: 133 multiplications, 79 additions/subtractions, 0 divisions, 14 sin/cos.
 */
void iiwa14_kinematics(const iiwa14_real *q, iiwa14_real *T, iiwa14_real *J);

#ifdef __cplusplus
}
#endif

#endif /* IIWA14_DYNAMICS_H */
