/*
 * chain12_dynamics — equations of motion of robot 'chain12' (12 joints, modified DH).
 *
 * GENERATED FILE — DO NOT EDIT. Regenerate it with symdyn instead.
 *   generator : symdyn 0.1.0 (newton-euler; forward dynamics by the articulated-body algorithm, double precision)
 *   input     : chain12.yaml
 *   sha256    : 1aa9009c929e2fd0d86ff36cae8f4e88189c8724cd2d728ecf32e27db1c90d31
 *   note      : forward dynamics by the articulated-body algorithm, chosen by operation count: 3896 (articulated-body) against 4002 (LDL^T)
 */
#ifndef CHAIN12_DYNAMICS_H
#define CHAIN12_DYNAMICS_H

#ifdef __cplusplus
extern "C" {
#endif

/* Scalar type of every argument (double precision). */
typedef double chain12_real;

/* Number of joints N: q, qd, qdd, tau and vector outputs hold N numbers, matrices N*N (row-major). */
#define CHAIN12_DOF 12

/* Number of runtime parameters NP (the array p, when present, is the last input). */
#define CHAIN12_NP 0

/* Status codes of the functions that return one (CHAIN12_OK: success; on any other code no output is written): */
#define CHAIN12_OK 0 /* success: every output written */
#define CHAIN12_SINGULAR 1 /* the mass matrix M = D + diag(armature) is singular at q: a pivot of its factorization is not above CHAIN12_PIVOT_RTOL times its diagonal entry (the articulated-body algorithm: an articulated inertia is not positive) */
#define CHAIN12_NOT_FINITE 2 /* an input is NaN or infinite, or a result is not finite (NaN, or beyond the range of the scalar type) */

/*
 * Relative pivot tolerance: a pivot at most CHAIN12_PIVOT_RTOL (1e-12 by default, for the
 * arithmetic the pivots are computed in) times its scale is reported as singular.  Checked in
 * the factorizations of the mass matrix (each LDL^T pivot against its diagonal entry).
 * Define a larger value before including this header (in every file that includes it, the
 * generated source too) to stop further from a singularity.
 */
#ifndef CHAIN12_PIVOT_RTOL
#define CHAIN12_PIVOT_RTOL 1e-12
#endif

/*
 * Model constants folded into the code, as symdyn read them from chain12.yaml, under the
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
 *     a = 0.142; alpha = pi/2 = 1.5707963267948966; d = 0.164; theta = 0.0
 *     mass = 2.832; com = [-0.071, -0.098, -0.025]
 *     inertia = [0.021, 0.0424, 0.0418, 0.0004, 0.0, 0.0]
 *     armature = 0.202; damping = 1.16; coulomb = 0.0
 *   link 2 (j2): revolute joint, modified DH
 *     a = 0.044; alpha = -pi/2 = -1.5707963267948966; d = 0.11; theta = 0.0
 *     mass = 1.068; com = [0.081, -0.088, 0.064]
 *     inertia = [0.013, 0.0375, 0.0344, -0.0004, 0.0, 0.0]
 *     armature = 0.0; damping = 0.0; coulomb = 0.0
 *   link 3 (j3): prismatic joint, modified DH
 *     a = 0.253; alpha = 0.0; d = 0.005; theta = -pi/2 = -1.5707963267948966
 *     mass = 0.713; com = [0.083, 0.002, -0.082]
 *     inertia = [0.0495, 0.0479, 0.0088, -0.0003, 0.0, 0.0]
 *     armature = 0.0; damping = 0.0; coulomb = 0.0
 *   link 4 (j4): revolute joint, modified DH
 *     a = 0.041; alpha = pi/2 = 1.5707963267948966; d = 0.078; theta = 0.0
 *     mass = 2.675; com = [-0.067, 0.039, -0.09]
 *     inertia = [0.0168, 0.0426, 0.0367, -0.0003, 0.0, 0.0]
 *     armature = 0.148; damping = 1.23; coulomb = 0.0
 *   link 5 (j5): revolute joint, modified DH
 *     a = 0.115; alpha = pi/3 = 1.0471975511965979; d = 0.008; theta = pi/6 = 0.5235987755982989
 *     mass = 3.042; com = [0.093, 0.095, 0.033]
 *     inertia = [0.0243, 0.0245, 0.0352, 0.0007, 0.0, 0.0]
 *     armature = 0.0; damping = 0.0; coulomb = 0.0
 *   link 6 (j6): prismatic joint, modified DH
 *     a = 0.034; alpha = -pi/2 = -1.5707963267948966; d = 0.059; theta = -pi/2 = -1.5707963267948966
 *     mass = 1.772; com = [0.002, 0.062, 0.0]
 *     inertia = [0.0111, 0.0429, 0.0408, 0.0001, 0.0, 0.0]
 *     armature = 0.0; damping = 0.0; coulomb = 0.0
 *   link 7 (j7): revolute joint, modified DH
 *     a = 0.067; alpha = pi/2 = 1.5707963267948966; d = 0.107; theta = 0.0
 *     mass = 1.859; com = [0.054, -0.079, 0.01]
 *     inertia = [0.0171, 0.0378, 0.0237, -0.0009, 0.0, 0.0]
 *     armature = 0.195; damping = 0.75; coulomb = 0.0
 *   link 8 (j8): revolute joint, modified DH
 *     a = 0.016; alpha = 0.0; d = 0.115; theta = 0.0
 *     mass = 1.231; com = [-0.044, -0.005, 0.092]
 *     inertia = [0.0292, 0.0482, 0.0259, 0.0017, 0.0, 0.0]
 *     armature = 0.0; damping = 0.0; coulomb = 0.0
 *   link 9 (j9): revolute joint, modified DH
 *     a = 0.109; alpha = -pi/4 = -0.7853981633974483; d = 0.047; theta = 0.0
 *     mass = 3.12; com = [0.082, -0.099, -0.046]
 *     inertia = [0.0408, 0.0237, 0.0266, -0.002, 0.0, 0.0]
 *     armature = 0.0; damping = 0.0; coulomb = 0.0
 *   link 10 (j10): prismatic joint, modified DH
 *     a = 0.012; alpha = pi/2 = 1.5707963267948966; d = 0.155; theta = -pi/2 = -1.5707963267948966
 *     mass = 3.943; com = [0.1, 0.001, -0.095]
 *     inertia = [0.0229, 0.0415, 0.0451, 0.0006, 0.0, 0.0]
 *     armature = 0.163; damping = 0.54; coulomb = 0.0
 *   link 11 (j11): revolute joint, modified DH
 *     a = 0.143; alpha = -pi/2 = -1.5707963267948966; d = 0.157; theta = 0.0
 *     mass = 1.419; com = [0.089, 0.079, -0.068]
 *     inertia = [0.0217, 0.0449, 0.0321, 0.0018, 0.0, 0.0]
 *     armature = 0.0; damping = 0.0; coulomb = 0.0
 *   link 12 (j12): revolute joint, modified DH
 *     a = 0.155; alpha = 0.0; d = 0.174; theta = 0.0
 *     mass = 2.966; com = [-0.057, -0.043, -0.049]
 *     inertia = [0.0373, 0.0378, 0.0088, 0.0015, 0.0, 0.0]
 *     armature = 0.0; damping = 0.0; coulomb = 0.0
 */

/*
 * Joints (index: name, type):
 *   1: j1, revolute
 *   2: j2, revolute
 *   3: j3, prismatic
 *   4: j4, revolute
 *   5: j5, revolute
 *   6: j6, prismatic
 *   7: j7, revolute
 *   8: j8, revolute
 *   9: j9, revolute
 *   10: j10, prismatic
 *   11: j11, revolute
 *   12: j12, revolute
 *
 * All functions are reentrant: no allocation, no global or static state, no recursion.
 * Output arrays must not overlap the inputs.
 *
 * To keep only the functions a program calls: compile chain12_dynamics.c with
 * -ffunction-sections -fdata-sections and link with -Wl,--gc-sections (GCC, Clang), or generate
 * only those functions (symdyn generate --functions LIST).
 *
 * Inputs are taken as given: a NaN or infinite input gives NaN or infinite outputs in every
 * function except chain12_forward_dynamics_checked, which then returns a
 * nonzero status and leaves qdd unchanged (as does chain12_forward_dynamics).
 *
 * Sines and cosines of the joint angles are computed in one block at the top of each function,
 * by a branch-free polynomial within 1 ulp of libm for |q| <= 1e5 rad (libm's sin and cos
 * beyond, and for every angle when SYMDYN_LIBM_TRIG is defined).
 *
 * The loops over arrays of 6-vectors in this long chain's functions (the mass matrix's
 * off-diagonal entries D_ij = S_i . F_j, the Coriolis matrix's C_ik = S_i . F_k above the
 * diagonal and g_i . dS_k + e_i . S_k below) run over GCC/Clang vector types where the target
 * has 16- or 32-byte vector registers (SSE2, AVX, NEON), each entry summed in the plain loop's
 * order; define SYMDYN_NO_VECTOR for the plain loop.
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
 * The functions whose note says "fused multiply-adds" (the forward-dynamics derivatives, and
 * any function of 1500 statements or more, whose code fused is shorter) fuse their
 * multiply-adds (the derivatives' loops; chain12_forward_dynamics_derivatives and the long
 * functions every sum of products) explicitly, by fma()
 * wherever the target has a fast one (FP_FAST_FMA or __FP_FAST_FMA defined), whatever the
 * contraction flag: their results then differ by rounding from those of a target without one
 * (their batch forms loop over them: the same bits).  Define SYMDYN_NO_FMA for c + a*b there too.
 */

/*
 * Inverse dynamics: torques that produce accelerations qdd at state (q, qd) (recursive Newton-Euler when derived by it).
 *   q: joint positions, N (rad for revolute, m for prismatic joints)
 *   qd: joint velocities, N (rad/s or m/s)
 *   qdd: joint accelerations, N (rad/s^2 or m/s^2)
 *   tau (out): joint torques/forces tau = D qdd + h + c + armature qdd + damping qd + coulomb sign(qd), N (N m or N)
 * Cost: 774 multiplications, 678 additions/subtractions, 0 divisions, 18 sin/cos.
 */
void chain12_inverse_dynamics(const chain12_real *q, const chain12_real *qd, const chain12_real *qdd, chain12_real *tau);

/*
 * Mass (joint-space inertia) matrix D(q), without armature.
 *   q: joint positions, N (rad for revolute, m for prismatic joints)
 *   D (out): joint-space inertia matrix D(q), N*N row-major, symmetric (kg m^2, kg m or kg)
 * Cost: 783 multiplications, 768 additions/subtractions, 0 divisions, 16 sin/cos.
 */
void chain12_mass_matrix(const chain12_real *q, chain12_real *D);

/*
 * Coriolis and centrifugal torques h(q, qd).
 *   q: joint positions, N (rad for revolute, m for prismatic joints)
 *   qd: joint velocities, N (rad/s or m/s)
 *   h (out): Coriolis and centrifugal vector h(q, qd) = C(q, qd) qd, N (N m or N)
 * Cost: 749 multiplications, 633 additions/subtractions, 0 divisions, 16 sin/cos.
 */
void chain12_coriolis(const chain12_real *q, const chain12_real *qd, chain12_real *h);

/*
 * Coriolis matrix C(q, qd), C qd = h. Fused multiply-adds where the target has a fast fma (see the top of this file).
 *   q: joint positions, N (rad for revolute, m for prismatic joints)
 *   qd: joint velocities, N (rad/s or m/s)
 *   C (out): Coriolis matrix C(q, qd) from the Christoffel symbols of D, N*N row-major (dD/dt - 2C is skew-symmetric)
 * Cost: 3341 multiplications, 2934 additions/subtractions, 0 divisions, 16 sin/cos.
 */
void chain12_coriolis_matrix(const chain12_real *q, const chain12_real *qd, chain12_real *C);

/*
 * Gravity torques c(q).
 *   q: joint positions, N (rad for revolute, m for prismatic joints)
 *   c (out): gravity vector c(q), N (N m or N)
 * Cost: 267 multiplications, 203 additions/subtractions, 0 divisions, 18 sin/cos.
 */
void chain12_gravity(const chain12_real *q, chain12_real *c);

/*
 * Forward dynamics: accelerations for torques tau at state (q, qd), by the articulated-body algorithm written out for this robot (three sweeps, at most one division per joint, no mass matrix).
 *   q: joint positions, N (rad for revolute, m for prismatic joints)
 *   qd: joint velocities, N (rad/s or m/s)
 *   tau: joint torques/forces, N (N m or N)
 *   qdd (out): joint accelerations solving (D + diag(armature)) qdd = tau - h - c - damping qd - coulomb sign(qd), N
 * Returns CHAIN12_OK (0) on success; CHAIN12_SINGULAR (1) when the mass matrix is singular at q (an articulated inertia d_j about joint j's axis, by which the algorithm divides, is not positive, or is not a number); CHAIN12_NOT_FINITE (2) when an input is NaN or infinite, or a result is not finite (NaN or beyond the range of double). On a nonzero return qdd is not written.
 * Cost: 2055 multiplications, 1830 additions/subtractions, 11 divisions, 18 sin/cos.
 */
int chain12_forward_dynamics_checked(const chain12_real *q, const chain12_real *qd, const chain12_real *tau, chain12_real *qdd);

/*
 * Forward dynamics: accelerations for torques tau at state (q, qd), by the articulated-body algorithm written out for this robot (three sweeps, at most one division per joint, no mass matrix). Same as chain12_forward_dynamics_checked, without the status: where that returns nonzero, qdd is left unchanged.
 *   q: joint positions, N (rad for revolute, m for prismatic joints)
 *   qd: joint velocities, N (rad/s or m/s)
 *   tau: joint torques/forces, N (N m or N)
 *   qdd (out): joint accelerations solving (D + diag(armature)) qdd = tau - h - c - damping qd - coulomb sign(qd), N
 * Cost: 2055 multiplications, 1830 additions/subtractions, 11 divisions, 18 sin/cos.
 */
void chain12_forward_dynamics(const chain12_real *q, const chain12_real *qd, const chain12_real *tau, chain12_real *qdd);

/*
 * Forward kinematics: pose of the tool frame in the world (base placement * chain * tool).
 *   q: joint positions, N (rad for revolute, m for prismatic joints)
 *   T (out): pose of the tool frame in the world, 4*4 row-major homogeneous transform [R p; 0 0 0 1] (p in m)
 * Cost: 199 multiplications, 136 additions/subtractions, 0 divisions, 18 sin/cos.
 */
void chain12_forward_kinematics(const chain12_real *q, chain12_real *T);

/*
 * Geometric Jacobian of the tool frame: [v; omega] = J qd, world axes.
 *   q: joint positions, N (rad for revolute, m for prismatic joints)
 *   J (out): tool Jacobian, 6*N row-major, world axes at the tool origin (Pinocchio's LOCAL_WORLD_ALIGNED): rows 0-2 map qd to the tool origin's linear velocity (m/s), rows 3-5 to the angular velocity (rad/s)
 * Cost: 255 multiplications, 184 additions/subtractions, 0 divisions, 16 sin/cos.
 */
void chain12_jacobian(const chain12_real *q, chain12_real *J);

/*
 * J-dot qd: the tool's acceleration bias, so that [a; alpha] = J qdd + J-dot qd (classical acceleration), world axes.
 *   q: joint positions, N (rad for revolute, m for prismatic joints)
 *   qd: joint velocities, N (rad/s or m/s)
 *   a (out): J-dot times qd, 6: the tool origin's classical linear acceleration (m/s^2, rows 0-2) and angular acceleration (rad/s^2, rows 3-5) at qdd = 0, world axes
 * Cost: 396 multiplications, 274 additions/subtractions, 0 divisions, 18 sin/cos.
 */
void chain12_jacobian_dot_qd(const chain12_real *q, const chain12_real *qd, chain12_real *a);

/*
 * Pose and Jacobian of the tool in one call: the same results as chain12_forward_kinematics and chain12_jacobian, sharing their sin/cos and link poses (about half the cost of the two calls).
 *   q: joint positions, N (rad for revolute, m for prismatic joints)
 *   T (out): pose of the tool frame in the world, 4*4 row-major homogeneous transform [R p; 0 0 0 1] (p in m)
 *   J (out): tool Jacobian, 6*N row-major, world axes at the tool origin (Pinocchio's LOCAL_WORLD_ALIGNED): rows 0-2 map qd to the tool origin's linear velocity (m/s), rows 3-5 to the angular velocity (rad/s)
 * Cost: 273 multiplications, 193 additions/subtractions, 0 divisions, 18 sin/cos.
 */
void chain12_kinematics(const chain12_real *q, chain12_real *T, chain12_real *J);

#ifdef __cplusplus
}
#endif

#endif /* CHAIN12_DYNAMICS_H */
