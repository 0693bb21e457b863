/*
 * ur5_dynamics — equations of motion of robot 'ur5' (6 joints, standard DH).
 *
 * GENERATED FILE — DO NOT EDIT. Regenerate it with symdyn instead.
 *   generator : symdyn 0.1.0 (newton-euler; forward dynamics by LDL^T of D, double precision)
 *   input     : ur5.yaml
 *   sha256    : 2aec31518849d593f4f52ec7fbf92a91dbb1d9835f5a8fa2761b363f4cc7a48d
 */
#ifndef UR5_DYNAMICS_H
#define UR5_DYNAMICS_H

#ifdef __cplusplus
extern "C" {
#endif

/* Scalar type of every argument (double precision). */
typedef double ur5_real;

/* Number of joints N: q, qd, qdd, tau and vector outputs hold N numbers, matrices N*N (row-major). */
#define UR5_DOF 6

/* Number of runtime parameters NP (the array p, when present, is the last input). */
#define UR5_NP 0

/* Status codes of the functions that return one (UR5_OK: success; on any other code no output is written): */
#define UR5_OK 0 /* success: every output written */
#define UR5_SINGULAR 1 /* the mass matrix M = D + diag(armature) is singular at q: a pivot of its factorization is not above UR5_PIVOT_RTOL times its diagonal entry (the articulated-body algorithm: an articulated inertia is not positive) */
#define UR5_NOT_FINITE 2 /* an input is NaN or infinite, or a result is not finite (NaN, or beyond the range of the scalar type) */

/*
 * Relative pivot tolerance: a pivot at most UR5_PIVOT_RTOL (1e-12 by default, for the
 * arithmetic the pivots are computed in) times its scale is reported as singular.  Checked in
 * the factorizations of the mass matrix (each LDL^T pivot against its diagonal entry).
 * Define a larger value before including this header (in every file that includes it, the
 * generated source too) to stop further from a singularity.
 */
#ifndef UR5_PIVOT_RTOL
#define UR5_PIVOT_RTOL 1e-12
#endif

/*
 * Model constants folded into the code, as symdyn read them from ur5.yaml, under the
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
 *   link 1 (shoulder_pan): revolute joint, standard DH
 *     a = 0.0; alpha = pi/2 = 1.5707963267948966; d = 0.089159; theta = 0.0
 *     mass = 3.7; com = [0.0, -0.02561, 0.00193]
 *     inertia = [0.0102675, 0.00666, 0.0102675, 0.0, 0.0, 0.0]
 *     armature = 0.0; damping = 0.0; coulomb = 0.0
 *   link 2 (shoulder_lift): revolute joint, standard DH
 *     a = -0.425; alpha = 0.0; d = 0.0; theta = 0.0
 *     mass = 8.393; com = [0.2125, 0.0, 0.11336]
 *     inertia = [0.0151074, 64265201/480000000 = 0.13388583541666665, 64265201/480000000 = 0.13388583541666665, 0.0, 0.0, 0.0]
 *     armature = 0.0; damping = 0.0; coulomb = 0.0
 *   link 3 (elbow): revolute joint, standard DH
 *     a = -0.39225; alpha = 0.0; d = 0.0; theta = 0.0
 *     mass = 2.33; com = [0.15, 0.0, 0.0265]
 *     inertia = [0.004194, 0.03197149546875, 0.03197149546875, 0.0, 0.0, 0.0]
 *     armature = 0.0; damping = 0.0; coulomb = 0.0
 *   link 4 (wrist_1): revolute joint, standard DH
 *     a = 0.0; alpha = pi/2 = 1.5707963267948966; d = 0.10915; theta = 0.0
 *     mass = 1.219; com = [0.0, -0.0018, 0.01634]
 *     inertia = [0.0025599, 0.0025599, 0.0021942, 0.0, 0.0, 0.0]
 *     armature = 0.0; damping = 0.0; coulomb = 0.0
 *   link 5 (wrist_2): revolute joint, standard DH
 *     a = 0.0; alpha = -pi/2 = -1.5707963267948966; d = 0.09465; theta = 0.0
 *     mass = 1.219; com = [0.0, 0.0018, 0.01634]
 *     inertia = [0.0025599, 0.0025599, 0.0021942, 0.0, 0.0, 0.0]
 *     armature = 0.0; damping = 0.0; coulomb = 0.0
 *   link 6 (wrist_3): revolute joint, standard DH
 *     a = 0.0; alpha = 0.0; d = 0.0823; theta = 0.0
 *     mass = 0.1879; com = [0.0, 0.0, -0.001159]
 *     inertia = [516351079/3000000000000 = 0.00017211702633333333, 516351079/3000000000000 = 0.00017211702633333333, 0.0001321171875, 0.0, 0.0, 0.0]
 *     armature = 0.0; damping = 0.0; coulomb = 0.0
 */

/*
 * Joints (index: name, type):
 *   1: shoulder_pan, revolute
 *   2: shoulder_lift, revolute
 *   3: elbow, revolute
 *   4: wrist_1, revolute
 *   5: wrist_2, revolute
 *   6: wrist_3, revolute
 *
 * All functions are reentrant: no allocation, no global or static state, no recursion.
 * Output arrays must not overlap the inputs.
 *
 * To keep only the functions a program calls: compile ur5_dynamics.c with
 * -ffunction-sections -fdata-sections and link with -Wl,--gc-sections (GCC, Clang), or generate
 * only those functions (symdyn generate --functions LIST).
 *
 * Inputs are taken as given: a NaN or infinite input gives NaN or infinite outputs in every
 * function except ur5_forward_dynamics_checked, which then returns a
 * nonzero status and leaves qdd unchanged (as does ur5_forward_dynamics).
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
 * Cost: 266 multiplications, 201 additions/subtractions, 0 divisions, 10 sin/cos.
 */
void ur5_inverse_dynamics(const ur5_real *q, const ur5_real *qd, const ur5_real *qdd, ur5_real *tau);

/*
 * Mass (joint-space inertia) matrix D(q), without armature.
 *   q: joint positions, N (rad for revolute, m for prismatic joints)
 *   D (out): joint-space inertia matrix D(q), N*N row-major, symmetric (kg m^2, kg m or kg)
 * Cost: 91 multiplications, 86 additions/subtractions, 0 divisions, 8 sin/cos.
 */
void ur5_mass_matrix(const ur5_real *q, ur5_real *D);

/*
 * Coriolis and centrifugal torques h(q, qd).
 *   q: joint positions, N (rad for revolute, m for prismatic joints)
 *   qd: joint velocities, N (rad/s or m/s)
 *   h (out): Coriolis and centrifugal vector h(q, qd) = C(q, qd) qd, N (N m or N)
 * Cost: 252 multiplications, 176 additions/subtractions, 0 divisions, 10 sin/cos.
 */
void ur5_coriolis(const ur5_real *q, const ur5_real *qd, ur5_real *h);

/*
 * Coriolis matrix C(q, qd), C qd = h.
 *   q: joint positions, N (rad for revolute, m for prismatic joints)
 *   qd: joint velocities, N (rad/s or m/s)
 *   C (out): Coriolis matrix C(q, qd) from the Christoffel symbols of D, N*N row-major (dD/dt - 2C is skew-symmetric)
 * Cost: 640 multiplications, 536 additions/subtractions, 0 divisions, 10 sin/cos.
 */
void ur5_coriolis_matrix(const ur5_real *q, const ur5_real *qd, ur5_real *C);

/*
 * Gravity torques c(q).
 *   q: joint positions, N (rad for revolute, m for prismatic joints)
 *   c (out): gravity vector c(q), N (N m or N)
 * Cost: 82 multiplications, 49 additions/subtractions, 0 divisions, 10 sin/cos.
 */
void ur5_gravity(const ur5_real *q, ur5_real *c);

/*
 * Forward dynamics: accelerations for torques tau at state (q, qd), by an LDL^T factorization unrolled for this robot (no inverse, at most one division per joint).
 *   q: joint positions, N (rad for revolute, m for prismatic joints)
 *   qd: joint velocities, N (rad/s or m/s)
 *   tau: joint torques/forces, N (N m or N)
 *   qdd (out): joint accelerations solving (D + diag(armature)) qdd = tau - h - c - damping qd - coulomb sign(qd), N
 * Returns UR5_OK (0) on success; UR5_SINGULAR (1) when the mass matrix is singular at q (a pivot d_j of its LDL^T factorization is not above UR5_PIVOT_RTOL, 1e-12 unless defined, times its diagonal entry, or is not a number); UR5_NOT_FINITE (2) when an input is NaN or infinite, or a result is not finite (NaN or beyond the range of double). On a nonzero return qdd is not written.
 * Cost: 456 multiplications, 336 additions/subtractions, 6 divisions, 10 sin/cos.
 */
int ur5_forward_dynamics_checked(const ur5_real *q, const ur5_real *qd, const ur5_real *tau, ur5_real *qdd);

/*
 * Forward dynamics: accelerations for torques tau at state (q, qd), by an LDL^T factorization unrolled for this robot (no inverse, at most one division per joint). Same as ur5_forward_dynamics_checked, without the status: where that returns nonzero, qdd is left unchanged.
 *   q: joint positions, N (rad for revolute, m for prismatic joints)
 *   qd: joint velocities, N (rad/s or m/s)
 *   tau: joint torques/forces, N (N m or N)
 *   qdd (out): joint accelerations solving (D + diag(armature)) qdd = tau - h - c - damping qd - coulomb sign(qd), N
 * Cost: 456 multiplications, 336 additions/subtractions, 6 divisions, 10 sin/cos.
 */
void ur5_forward_dynamics(const ur5_real *q, const ur5_real *qd, const ur5_real *tau, ur5_real *qdd);

/*
 * Forward kinematics: pose of the tool frame in the world (base placement * chain * tool).
 *   q: joint positions, N (rad for revolute, m for prismatic joints)
 *   T (out): pose of the tool frame in the world, 4*4 row-major homogeneous transform [R p; 0 0 0 1] (p in m)
 * Cost: 64 multiplications, 37 additions/subtractions, 0 divisions, 12 sin/cos.
 */
void ur5_forward_kinematics(const ur5_real *q, ur5_real *T);

/*
 * Geometric Jacobian of the tool frame: [v; omega] = J qd, world axes.
 *   q: joint positions, N (rad for revolute, m for prismatic joints)
 *   J (out): tool Jacobian, 6*N row-major, world axes at the tool origin (Pinocchio's LOCAL_WORLD_ALIGNED): rows 0-2 map qd to the tool origin's linear velocity (m/s), rows 3-5 to the angular velocity (rad/s)
 * Cost: 87 multiplications, 59 additions/subtractions, 0 divisions, 10 sin/cos.
 */
void ur5_jacobian(const ur5_real *q, ur5_real *J);

/*
 * J-dot qd: the tool's acceleration bias, so that [a; alpha] = J qdd + J-dot qd (classical acceleration), world axes.
 *   q: joint positions, N (rad for revolute, m for prismatic joints)
 *   qd: joint velocities, N (rad/s or m/s)
 *   a (out): J-dot times qd, 6: the tool origin's classical linear acceleration (m/s^2, rows 0-2) and angular acceleration (rad/s^2, rows 3-5) at qdd = 0, world axes
 * Cost: 161 multiplications, 92 additions/subtractions, 0 divisions, 12 sin/cos.
 */
void ur5_jacobian_dot_qd(const ur5_real *q, const ur5_real *qd, ur5_real *a);

/*
 * Pose and Jacobian of the tool in one call: the same results as ur5_forward_kinematics and ur5_jacobian, sharing their sin/cos and link poses (about half the cost of the two calls).
 *   q: joint positions, N (rad for revolute, m for prismatic joints)
 *   T (out): pose of the tool frame in the world, 4*4 row-major homogeneous transform [R p; 0 0 0 1] (p in m)
 *   J (out): tool Jacobian, 6*N row-major, world axes at the tool origin (Pinocchio's LOCAL_WORLD_ALIGNED): rows 0-2 map qd to the tool origin's linear velocity (m/s), rows 3-5 to the angular velocity (rad/s)
 * Cost: 104 multiplications, 67 additions/subtractions, 0 divisions, 12 sin/cos.
 */
void ur5_kinematics(const ur5_real *q, ur5_real *T, ur5_real *J);

#ifdef __cplusplus
}
#endif

#endif /* UR5_DYNAMICS_H */
