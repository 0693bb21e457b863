/*
 * planar2r_dynamics — equations of motion of robot 'planar2r' (2 joints, modified DH).
 *
 * GENERATED FILE — DO NOT EDIT. Regenerate it with symdyn instead.
 *   generator : symdyn 0.1.0 (newton-euler; forward dynamics by LDL^T of D, double precision)
 *   input     : planar2r.yaml
 *   sha256    : 086b6c674f0dbe0543d869373cbd4427195ffc7be448fd3367a82a7213766de8
 */
#ifndef PLANAR2R_DYNAMICS_H
#define PLANAR2R_DYNAMICS_H

#ifdef __cplusplus
extern "C" {
#endif

/* Scalar type of every argument (double precision). */
typedef double planar2r_real;

/* Number of joints N: q, qd, qdd, tau and vector outputs hold N numbers, matrices N*N (row-major). */
#define PLANAR2R_DOF 2

/* Number of runtime parameters NP (the array p, when present, is the last input). */
#define PLANAR2R_NP 8
/*
 * Runtime parameters, in the order of p (where each enters the model, with its unit):
 *   p[0] = g  (runtime parameter, no nominal value)
 *          gravity (m/s^2)
 *   p[1] = m1  (runtime parameter, no nominal value)
 *          link 1 (shoulder): mass (kg)
 *   p[2] = lc1  (runtime parameter, no nominal value)
 *          link 1 (shoulder): com (m)
 *   p[3] = I1  (runtime parameter, no nominal value)
 *          link 1 (shoulder): inertia (kg m^2)
 *   p[4] = l1  (runtime parameter, no nominal value)
 *          link 2 (elbow): a (m)
 *   p[5] = m2  (runtime parameter, no nominal value)
 *          link 2 (elbow): mass (kg)
 *   p[6] = lc2  (runtime parameter, no nominal value)
 *          link 2 (elbow): com (m)
 *   p[7] = I2  (runtime parameter, no nominal value)
 *          link 2 (elbow): inertia (kg m^2)
 */

/* Status codes of the functions that return one (PLANAR2R_OK: success; on any other code no output is written): */
#define PLANAR2R_OK 0 /* success: every output written */
#define PLANAR2R_SINGULAR 1 /* the mass matrix M = D + diag(armature) is singular at q: a pivot of its factorization is not above PLANAR2R_PIVOT_RTOL times its diagonal entry (the articulated-body algorithm: an articulated inertia is not positive) */
#define PLANAR2R_NOT_FINITE 2 /* an input is NaN or infinite, or a result is not finite (NaN, or beyond the range of the scalar type) */

/*
 * Relative pivot tolerance: a pivot at most PLANAR2R_PIVOT_RTOL (1e-12 by default, for the
 * arithmetic the pivots are computed in) times its scale is reported as singular.  Checked in
 * the factorizations of the mass matrix (each LDL^T pivot against its diagonal entry).
 * Define a larger value before including this header (in every file that includes it, the
 * generated source too) to stop further from a singularity.
 */
#ifndef PLANAR2R_PIVOT_RTOL
#define PLANAR2R_PIVOT_RTOL 1e-12
#endif

/*
 * Model constants folded into the code, as symdyn read them from planar2r.yaml, under the
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
 *   gravity = [0.0, -g, 0.0]
 *   base.xyz = [0.0, 0.0, 0.0]; base.rpy = [0.0, 0.0, 0.0]
 *   tool.xyz = [0.0, 0.0, 0.0]; tool.rpy = [0.0, 0.0, 0.0]
 *   runtime parameters (inputs in p, not folded): p[0] = g; p[1] = m1; p[2] = lc1; p[3] = I1; p[4] = l1; p[5] = m2; p[6] = lc2; p[7] = I2
 *   link 1 (shoulder): revolute joint, modified DH
 *     a = 0.0; alpha = 0.0; d = 0.0; theta = 0.0
 *     mass = m1; com = [lc1, 0.0, 0.0]
 *     inertia = [0.0, 0.0, I1, 0.0, 0.0, 0.0]
 *     armature = 0.0; damping = 0.0; coulomb = 0.0
 *   link 2 (elbow): revolute joint, modified DH
 *     a = l1; alpha = 0.0; d = 0.0; theta = 0.0
 *     mass = m2; com = [lc2, 0.0, 0.0]
 *     inertia = [0.0, 0.0, I2, 0.0, 0.0, 0.0]
 *     armature = 0.0; damping = 0.0; coulomb = 0.0
 */

/*
 * Joints (index: name, type):
 *   1: shoulder, revolute
 *   2: elbow, revolute
 *
 * All functions are reentrant: no allocation, no global or static state, no recursion.
 * Output arrays must not overlap the inputs.
 *
 * To keep only the functions a program calls: compile planar2r_dynamics.c with
 * -ffunction-sections -fdata-sections and link with -Wl,--gc-sections (GCC, Clang), or generate
 * only those functions (symdyn generate --functions LIST).
 *
 * Inputs are taken as given: a NaN or infinite input gives NaN or infinite outputs in every
 * function except planar2r_forward_dynamics_checked, which then returns a
 * nonzero status and leaves qdd unchanged (as does planar2r_forward_dynamics).
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
 *   p: runtime parameters, NP, in the order listed above
 *   tau (out): joint torques/forces tau = D qdd + h + c + armature qdd + damping qd + coulomb sign(qd), N (N m or N)
 * Cost: 23 multiplications, 14 additions/subtractions, 0 divisions, 4 sin/cos.
 */
void planar2r_inverse_dynamics(const planar2r_real *q, const planar2r_real *qd, const planar2r_real *qdd, const planar2r_real *p, planar2r_real *tau);

/*
 * Mass (joint-space inertia) matrix D(q), without armature.
 *   q: joint positions, N (rad for revolute, m for prismatic joints)
 *   p: runtime parameters, NP, in the order listed above
 *   D (out): joint-space inertia matrix D(q), N*N row-major, symmetric (kg m^2, kg m or kg)
 * Cost: 10 multiplications, 6 additions/subtractions, 0 divisions, 1 sin/cos.
 */
void planar2r_mass_matrix(const planar2r_real *q, const planar2r_real *p, planar2r_real *D);

/*
 * Coriolis and centrifugal torques h(q, qd).
 *   q: joint positions, N (rad for revolute, m for prismatic joints)
 *   qd: joint velocities, N (rad/s or m/s)
 *   p: runtime parameters, NP, in the order listed above
 *   h (out): Coriolis and centrifugal vector h(q, qd) = C(q, qd) qd, N (N m or N)
 * Cost: 12 multiplications, 4 additions/subtractions, 0 divisions, 2 sin/cos.
 */
void planar2r_coriolis(const planar2r_real *q, const planar2r_real *qd, const planar2r_real *p, planar2r_real *h);

/*
 * Coriolis matrix C(q, qd), C qd = h.
 *   q: joint positions, N (rad for revolute, m for prismatic joints)
 *   qd: joint velocities, N (rad/s or m/s)
 *   p: runtime parameters, NP, in the order listed above
 *   C (out): Coriolis matrix C(q, qd) from the Christoffel symbols of D, N*N row-major (dD/dt - 2C is skew-symmetric)
 * Cost: 13 multiplications, 4 additions/subtractions, 0 divisions, 2 sin/cos.
 */
void planar2r_coriolis_matrix(const planar2r_real *q, const planar2r_real *qd, const planar2r_real *p, planar2r_real *C);

/*
 * Gravity torques c(q).
 *   q: joint positions, N (rad for revolute, m for prismatic joints)
 *   p: runtime parameters, NP, in the order listed above
 *   c (out): gravity vector c(q), N (N m or N)
 * Cost: 14 multiplications, 5 additions/subtractions, 0 divisions, 4 sin/cos.
 */
void planar2r_gravity(const planar2r_real *q, const planar2r_real *p, planar2r_real *c);

/*
 * Forward dynamics: accelerations for torques tau at state (q, qd), by an LDL^T factorization unrolled for this robot (no inverse, at most one division per joint).
 *   q: joint positions, N (rad for revolute, m for prismatic joints)
 *   qd: joint velocities, N (rad/s or m/s)
 *   tau: joint torques/forces, N (N m or N)
 *   p: runtime parameters, NP, in the order listed above
 *   qdd (out): joint accelerations solving (D + diag(armature)) qdd = tau - h - c - damping qd - coulomb sign(qd), N
 * Returns PLANAR2R_OK (0) on success; PLANAR2R_SINGULAR (1) when the mass matrix is singular at q (a pivot d_j of its LDL^T factorization is not above PLANAR2R_PIVOT_RTOL, 1e-12 unless defined, times its diagonal entry, or is not a number); PLANAR2R_NOT_FINITE (2) when an input is NaN or infinite, or a result is not finite (NaN or beyond the range of double). On a nonzero return qdd is not written.
 * Cost: 35 multiplications, 19 additions/subtractions, 2 divisions, 4 sin/cos.
 */
int planar2r_forward_dynamics_checked(const planar2r_real *q, const planar2r_real *qd, const planar2r_real *tau, const planar2r_real *p, planar2r_real *qdd);

/*
 * Forward dynamics: accelerations for torques tau at state (q, qd), by an LDL^T factorization unrolled for this robot (no inverse, at most one division per joint). Same as planar2r_forward_dynamics_checked, without the status: where that returns nonzero, qdd is left unchanged.
 *   q: joint positions, N (rad for revolute, m for prismatic joints)
 *   qd: joint velocities, N (rad/s or m/s)
 *   tau: joint torques/forces, N (N m or N)
 *   p: runtime parameters, NP, in the order listed above
 *   qdd (out): joint accelerations solving (D + diag(armature)) qdd = tau - h - c - damping qd - coulomb sign(qd), N
 * Cost: 35 multiplications, 19 additions/subtractions, 2 divisions, 4 sin/cos.
 */
void planar2r_forward_dynamics(const planar2r_real *q, const planar2r_real *qd, const planar2r_real *tau, const planar2r_real *p, planar2r_real *qdd);

/*
 * Forward kinematics: pose of the tool frame in the world (base placement * chain * tool).
 *   q: joint positions, N (rad for revolute, m for prismatic joints)
 *   p: runtime parameters, NP, in the order listed above
 *   T (out): pose of the tool frame in the world, 4*4 row-major homogeneous transform [R p; 0 0 0 1] (p in m)
 * Cost: 6 multiplications, 2 additions/subtractions, 0 divisions, 4 sin/cos.
 */
void planar2r_forward_kinematics(const planar2r_real *q, const planar2r_real *p, planar2r_real *T);

/*
 * Geometric Jacobian of the tool frame: [v; omega] = J qd, world axes.
 *   q: joint positions, N (rad for revolute, m for prismatic joints)
 *   p: runtime parameters, NP, in the order listed above
 *   J (out): tool Jacobian, 6*N row-major, world axes at the tool origin (Pinocchio's LOCAL_WORLD_ALIGNED): rows 0-2 map qd to the tool origin's linear velocity (m/s), rows 3-5 to the angular velocity (rad/s)
 * Cost: 2 multiplications, 0 additions/subtractions, 0 divisions, 2 sin/cos.
 */
void planar2r_jacobian(const planar2r_real *q, const planar2r_real *p, planar2r_real *J);

/*
 * J-dot qd: the tool's acceleration bias, so that [a; alpha] = J qdd + J-dot qd (classical acceleration), world axes.
 *   q: joint positions, N (rad for revolute, m for prismatic joints)
 *   qd: joint velocities, N (rad/s or m/s)
 *   p: runtime parameters, NP, in the order listed above
 *   a (out): J-dot times qd, 6: the tool origin's classical linear acceleration (m/s^2, rows 0-2) and angular acceleration (rad/s^2, rows 3-5) at qdd = 0, world axes
 * Cost: 12 multiplications, 4 additions/subtractions, 0 divisions, 4 sin/cos.
 */
void planar2r_jacobian_dot_qd(const planar2r_real *q, const planar2r_real *qd, const planar2r_real *p, planar2r_real *a);

/*
 * Pose and Jacobian of the tool in one call: the same results as planar2r_forward_kinematics and planar2r_jacobian, sharing their sin/cos and link poses (about half the cost of the two calls).
 *   q: joint positions, N (rad for revolute, m for prismatic joints)
 *   p: runtime parameters, NP, in the order listed above
 *   T (out): pose of the tool frame in the world, 4*4 row-major homogeneous transform [R p; 0 0 0 1] (p in m)
 *   J (out): tool Jacobian, 6*N row-major, world axes at the tool origin (Pinocchio's LOCAL_WORLD_ALIGNED): rows 0-2 map qd to the tool origin's linear velocity (m/s), rows 3-5 to the angular velocity (rad/s)
 * Cost: 6 multiplications, 2 additions/subtractions, 0 divisions, 4 sin/cos.
 */
void planar2r_kinematics(const planar2r_real *q, const planar2r_real *p, planar2r_real *T, planar2r_real *J);

#ifdef __cplusplus
}
#endif

#endif /* PLANAR2R_DYNAMICS_H */
