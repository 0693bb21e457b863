/*
 * panda_dynamics — equations of motion of robot 'panda' (7 joints, modified DH).
 *
 * GENERATED FILE — DO NOT EDIT. Regenerate it with symdyn instead.
 *   generator : symdyn 0.1.0 (newton-euler; forward dynamics by LDL^T of D, double precision)
 *   input     : panda.yaml
 *   sha256    : 38e63329690612d56672ffeea325710a3822b8c02df9caf43f43f81f72b92e43
 */
#ifndef PANDA_DYNAMICS_H
#define PANDA_DYNAMICS_H

#ifdef __cplusplus
extern "C" {
#endif

/* Scalar type of every argument (double precision). */
typedef double panda_real;

/* Number of joints N: q, qd, qdd, tau and vector outputs hold N numbers, matrices N*N (row-major). */
#define PANDA_DOF 7

/* Number of runtime parameters NP (the array p, when present, is the last input). */
#define PANDA_NP 0

/* Status codes of the functions that return one (PANDA_OK: success; on any other code no output is written): */
#define PANDA_OK 0 /* success: every output written */
#define PANDA_SINGULAR 1 /* the mass matrix M = D + diag(armature) is singular at q: a pivot of its factorization is not above PANDA_PIVOT_RTOL times its diagonal entry (the articulated-body algorithm: an articulated inertia is not positive) */
#define PANDA_NOT_FINITE 2 /* an input is NaN or infinite, or a result is not finite (NaN, or beyond the range of the scalar type) */

/*
 * Relative pivot tolerance: a pivot at most PANDA_PIVOT_RTOL (1e-12 by default, for the
 * arithmetic the pivots are computed in) times its scale is reported as singular.  Checked in
 * the factorizations of the mass matrix (each LDL^T pivot against its diagonal entry).
 * Define a larger value before including this header (in every file that includes it, the
 * generated source too) to stop further from a singularity.
 */
#ifndef PANDA_PIVOT_RTOL
#define PANDA_PIVOT_RTOL 1e-12
#endif

/*
 * Model constants folded into the code, as symdyn read them from panda.yaml, under the
 * robot file's field names (docs/robot-format.md), so that they can be checked without it. Each
 * number is the shortest decimal that reads back as the double it stands for; an exact value that
 * is not such a decimal (pi/2, 1/3) is followed by " = " and that double. A name is a runtime
 * parameter (an input in p, not folded). Units: lengths m, angles rad, masses kg; gravity m/s^2
 * in the world frame; com in the link frame; inertia (xx, yy, zz, xy, xz, yz) about the centre of
 * mass, link-frame axes, kg m^2; armature kg m^2, damping (viscous friction) N m s/rad and coulomb
 * (Coulomb friction) N m of a revolute joint, kg, N s/m and N of a prismatic one; limits rad or m,
 * rad/s or m/s, N m or N (listed only: no function checks them).
 * Modified Denavit-Hartenberg parameters; theta of a revolute joint and d of a
 * prismatic one are offsets added to q.
 * base: frame 0 of the chain in the world; tool: the tool frame in the last link's frame.
 *
 *   gravity = [0.0, 0.0, -9.81]
 *   base.xyz = [0.0, 0.0, 0.0]; base.rpy = [0.0, 0.0, 0.0]
 *   tool.xyz = [0.0, 0.0, 0.0]; tool.rpy = [0.0, 0.0, 0.0]
 *   link 1 (j1): revolute joint, modified DH
 *     a = 0.0; alpha = 0.0; d = 0.333; theta = 0.0
 *     mass = 4.970684; com = [0.003875, 0.002081, -0.04762]
 *     inertia = [0.70337, 0.70661, 0.009117, -0.000139, 0.006772, 0.019169]
 *     armature = 0.0; damping = 0.0; coulomb = 0.0
 *   link 2 (j2): revolute joint, modified DH
 *     a = 0.0; alpha = -pi/2 = -1.5707963267948966; d = 0.0; theta = 0.0
 *     mass = 0.646926; com = [-0.003141, -0.02872, 0.003495]
 *     inertia = [0.007962, 0.02811, 0.025995, -0.003925, 0.010254, 0.000704]
 *     armature = 0.0; damping = 0.0; coulomb = 0.0
 *   link 3 (j3): revolute joint, modified DH
 *     a = 0.0; alpha = pi/2 = 1.5707963267948966; d = 0.316; theta = 0.0
 *     mass = 3.228604; com = [0.027518, 0.039252, -0.066502]
 *     inertia = [0.037242, 0.036155, 0.01083, -0.004761, -0.011396, -0.012805]
 *     armature = 0.0; damping = 0.0; coulomb = 0.0
 *   link 4 (j4): revolute joint, modified DH
 *     a = 0.0825; alpha = pi/2 = 1.5707963267948966; d = 0.0; theta = 0.0
 *     mass = 3.587895; com = [-0.05317, 0.104419, 0.027454]
 *     inertia = [0.025853, 0.019552, 0.028323, 0.007796, -0.001332, 0.008641]
 *     armature = 0.0; damping = 0.0; coulomb = 0.0
 *   link 5 (j5): revolute joint, modified DH
 *     a = -0.0825; alpha = -pi/2 = -1.5707963267948966; d = 0.384; theta = 0.0
 *     mass = 1.225946; com = [-0.011953, 0.041065, -0.038437]
 *     inertia = [0.035549, 0.029474, 0.008627, -0.002117, -0.004037, 0.000229]
 *     armature = 0.0; damping = 0.0; coulomb = 0.0
 *   link 6 (j6): revolute joint, modified DH
 *     a = 0.0; alpha = pi/2 = 1.5707963267948966; d = 0.0; theta = 0.0
 *     mass = 1.666555; com = [0.060149, -0.014117, -0.010517]
 *     inertia = [0.001964, 0.004354, 0.005433, 0.000109, -0.001158, 0.000341]
 *     armature = 0.0; damping = 0.0; coulomb = 0.0
 *   link 7 (j7): revolute joint, modified DH
 *     a = 0.088; alpha = pi/2 = 1.5707963267948966; d = 0.0; theta = 0.0
 *     mass = 0.735522; com = [0.010517, -0.004252, 0.061597]
 *     inertia = [0.012516, 0.010027, 0.004815, -0.000428, -0.001196, -0.000741]
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
 * To keep only the functions a program calls: compile panda_dynamics.c with
 * -ffunction-sections -fdata-sections and link with -Wl,--gc-sections (GCC, Clang), or generate
 * only those functions (symdyn generate --functions LIST).
 *
 * Inputs are taken as given: a NaN or infinite input gives NaN or infinite outputs in every
 * function except panda_forward_dynamics_checked, which then returns a
 * nonzero status and leaves qdd unchanged (as does panda_forward_dynamics).
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
 * Cost: 441 multiplications, 379 additions/subtractions, 0 divisions, 12 sin/cos.
 */
void panda_inverse_dynamics(const panda_real *q, const panda_real *qd, const panda_real *qdd, panda_real *tau);

/*
 * Mass (joint-space inertia) matrix D(q), without armature.
 *   q: joint positions, N (rad for revolute, m for prismatic joints)
 *   D (out): joint-space inertia matrix D(q), N*N row-major, symmetric (kg m^2, kg m or kg)
 * Cost: 199 multiplications, 205 additions/subtractions, 0 divisions, 12 sin/cos.
 */
void panda_mass_matrix(const panda_real *q, panda_real *D);

/*
 * Coriolis and centrifugal torques h(q, qd).
 *   q: joint positions, N (rad for revolute, m for prismatic joints)
 *   qd: joint velocities, N (rad/s or m/s)
 *   h (out): Coriolis and centrifugal vector h(q, qd) = C(q, qd) qd, N (N m or N)
 * Cost: 429 multiplications, 352 additions/subtractions, 0 divisions, 12 sin/cos.
 */
void panda_coriolis(const panda_real *q, const panda_real *qd, panda_real *h);

/*
 * Coriolis matrix C(q, qd), C qd = h.
 *   q: joint positions, N (rad for revolute, m for prismatic joints)
 *   qd: joint velocities, N (rad/s or m/s)
 *   C (out): Coriolis matrix C(q, qd) from the Christoffel symbols of D, N*N row-major (dD/dt - 2C is skew-symmetric)
 * Cost: 1445 multiplications, 1242 additions/subtractions, 0 divisions, 12 sin/cos.
 */
void panda_coriolis_matrix(const panda_real *q, const panda_real *qd, panda_real *C);

/*
 * Gravity torques c(q).
 *   q: joint positions, N (rad for revolute, m for prismatic joints)
 *   c (out): gravity vector c(q), N (N m or N)
 * Cost: 123 multiplications, 81 additions/subtractions, 0 divisions, 12 sin/cos.
 */
void panda_gravity(const panda_real *q, panda_real *c);

/*
 * Forward dynamics: accelerations for torques tau at state (q, qd), by an LDL^T factorization unrolled for this robot (no inverse, at most one division per joint).
 *   q: joint positions, N (rad for revolute, m for prismatic joints)
 *   qd: joint velocities, N (rad/s or m/s)
 *   tau: joint torques/forces, N (N m or N)
 *   qdd (out): joint accelerations solving (D + diag(armature)) qdd = tau - h - c - damping qd - coulomb sign(qd), N
 * Returns PANDA_OK (0) on success; PANDA_SINGULAR (1) when the mass matrix is singular at q (a pivot d_j of its LDL^T factorization is not above PANDA_PIVOT_RTOL, 1e-12 unless defined, times its diagonal entry, or is not a number); PANDA_NOT_FINITE (2) when an input is NaN or infinite, or a result is not finite (NaN or beyond the range of double). On a nonzero return qdd is not written.
 * Cost: 792 multiplications, 666 additions/subtractions, 7 divisions, 12 sin/cos.
 */
int panda_forward_dynamics_checked(const panda_real *q, const panda_real *qd, const panda_real *tau, panda_real *qdd);

/*
 * Forward dynamics: accelerations for torques tau at state (q, qd), by an LDL^T factorization unrolled for this robot (no inverse, at most one division per joint). Same as panda_forward_dynamics_checked, without the status: where that returns nonzero, qdd is left unchanged.
 *   q: joint positions, N (rad for revolute, m for prismatic joints)
 *   qd: joint velocities, N (rad/s or m/s)
 *   tau: joint torques/forces, N (N m or N)
 *   qdd (out): joint accelerations solving (D + diag(armature)) qdd = tau - h - c - damping qd - coulomb sign(qd), N
 * Cost: 792 multiplications, 666 additions/subtractions, 7 divisions, 12 sin/cos.
 */
void panda_forward_dynamics(const panda_real *q, const panda_real *qd, const panda_real *tau, panda_real *qdd);

/*
 * Forward kinematics: pose of the tool frame in the world (base placement * chain * tool).
 *   q: joint positions, N (rad for revolute, m for prismatic joints)
 *   T (out): pose of the tool frame in the world, 4*4 row-major homogeneous transform [R p; 0 0 0 1] (p in m)
 * Cost: 77 multiplications, 41 additions/subtractions, 0 divisions, 14 sin/cos.
 */
void panda_forward_kinematics(const panda_real *q, panda_real *T);

/*
 * Geometric Jacobian of the tool frame: [v; omega] = J qd, world axes.
 *   q: joint positions, N (rad for revolute, m for prismatic joints)
 *   J (out): tool Jacobian, 6*N row-major, world axes at the tool origin (Pinocchio's LOCAL_WORLD_ALIGNED): rows 0-2 map qd to the tool origin's linear velocity (m/s), rows 3-5 to the angular velocity (rad/s)
 * Cost: 119 multiplications, 74 additions/subtractions, 0 divisions, 12 sin/cos.
 */
void panda_jacobian(const panda_real *q, panda_real *J);

/*
 * J-dot qd: the tool's acceleration bias, so that [a; alpha] = J qdd + J-dot qd (classical acceleration), world axes.
 *   q: joint positions, N (rad for revolute, m for prismatic joints)
 *   qd: joint velocities, N (rad/s or m/s)
 *   a (out): J-dot times qd, 6: the tool origin's classical linear acceleration (m/s^2, rows 0-2) and angular acceleration (rad/s^2, rows 3-5) at qdd = 0, world axes
 * Cost: 185 multiplications, 107 additions/subtractions, 0 divisions, 14 sin/cos.
 */
void panda_jacobian_dot_qd(const panda_real *q, const panda_real *qd, panda_real *a);

/*
 * Pose and Jacobian of the tool in one call: the same results as panda_forward_kinematics and panda_jacobian, sharing their sin/cos and link poses (about half the cost of the two calls).
 *   q: joint positions, N (rad for revolute, m for prismatic joints)
 *   T (out): pose of the tool frame in the world, 4*4 row-major homogeneous transform [R p; 0 0 0 1] (p in m)
 *   J (out): tool Jacobian, 6*N row-major, world axes at the tool origin (Pinocchio's LOCAL_WORLD_ALIGNED): rows 0-2 map qd to the tool origin's linear velocity (m/s), rows 3-5 to the angular velocity (rad/s)
 * Cost: 131 multiplications, 80 additions/subtractions, 0 divisions, 14 sin/cos.
 */
void panda_kinematics(const panda_real *q, panda_real *T, panda_real *J);

#ifdef __cplusplus
}
#endif

#endif /* PANDA_DYNAMICS_H */
