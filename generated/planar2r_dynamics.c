/*
 * planar2r_dynamics — equations of motion of robot 'planar2r' (2 joints, modified DH).
 *
 * GENERATED FILE — DO NOT EDIT. Regenerate it with symdyn instead.
 *   generator : symdyn 0.1.0 (newton-euler; forward dynamics by LDL^T of D, double precision)
 *   input     : planar2r.yaml
 *   sha256    : 086b6c674f0dbe0543d869373cbd4427195ffc7be448fd3367a82a7213766de8
 */
#include <math.h>
#include <float.h>
#include <stdint.h>
#include <string.h>

#include "planar2r_dynamics.h"

/*
 * Sine and cosine of the joint angles, all of a function's at once.
 * |x| <= 1e5: Cody-Waite reduction by pi/2 with a three-part pi/2 and fdlibm's minimax
 * polynomials on [-pi/4, pi/4], no branch, no call and no integer conversion (the quadrant is
 * read from the bits of the rounded x 2/pi, and selects and signs the polynomials by bit
 * operations), so the same statements run on GCC/Clang vector types: within 1 ulp
 * of glibc's sin and cos (or 1e-29 absolute) for |x| <= 8, within 1.2e-16 absolute up to 1e5
 * (symdyn's tests/emit/test_batch.py), with identical results in every lane and in the scalar form.
 * Any other angle (huge, infinite or NaN) goes to libm.  Define SYMDYN_LIBM_TRIG to use libm's
 * sin and cos for every angle, SYMDYN_NO_VECTOR for the scalar form only.
 */
#define planar2r_SINCOS_KERNEL(REAL, BITS, x, s, c) do { \
    /* x 2/pi rounded to the integer k by adding 1.5 * 2^52: the sum's low bits are k mod 4 */ \
    union { REAL real; BITS bits; } kb_, ps_bits_, pc_bits_; \
    const REAL big_ = (x) * 6.36619772367581382433e-01 + 6755399441055744.0; \
    const REAL k_ = big_ - 6755399441055744.0; \
    const REAL r_ = (((x) - k_ * 1.57079632673412561417e+00) - k_ * 6.07710050630396597660e-11) \
        - k_ * 2.02226624871116645580e-21; \
    const REAL z_ = r_ * r_; \
    const REAL hz_ = 0.5 * z_; \
    const REAL w_ = 1.0 - hz_; \
    BITS m_, swap_; \
    ps_bits_.real = r_ + (z_ * r_) * (-1.66666666666666324348e-01 + z_ * (8.33333333332248946124e-03 \
        + z_ * (-1.98412698298579493134e-04 + z_ * (2.75573137070700676789e-06 \
        + z_ * (-2.50507602534068634195e-08 + z_ * 1.58969099521155010221e-10))))); \
    pc_bits_.real = w_ + (((1.0 - w_) - hz_) + (z_ * z_) * (4.16666666666666019037e-02 \
        + z_ * (-1.38888888888741095749e-03 + z_ * (2.48015872894767294178e-05 \
        + z_ * (-2.75573143513906633035e-07 + z_ * (2.08757232129817482790e-09 \
        + z_ * -1.13596475577881948265e-11)))))); \
    kb_.real = big_; \
    m_ = kb_.bits; \
    /* odd quadrant: sin and cos polynomials swapped; sign bit: quadrants 2, 3 (sin), 1, 2 (cos) */ \
    swap_ = -(m_ & 1); \
    kb_.bits = ((ps_bits_.bits & ~swap_) | (pc_bits_.bits & swap_)) ^ ((m_ & 2) << 62); \
    (s) = kb_.real; \
    kb_.bits = ((pc_bits_.bits & ~swap_) | (ps_bits_.bits & swap_)) ^ (((m_ + 1) & 2) << 62); \
    (c) = kb_.real; \
} while (0)
#if !defined(SYMDYN_NO_VECTOR) && !defined(SYMDYN_LIBM_TRIG) && (defined(__clang__) || (defined(__GNUC__) && __GNUC__ >= 9))
#if defined(__AVX__)
#define PLANAR2R_TRIG_WIDTH 4
#else
#define PLANAR2R_TRIG_WIDTH 2
#endif
typedef double planar2r_treal __attribute__((vector_size(PLANAR2R_TRIG_WIDTH * sizeof(double))));
typedef unsigned long long planar2r_tbits __attribute__((vector_size(PLANAR2R_TRIG_WIDTH * sizeof(double))));
#endif

static void planar2r_sincos(int count, const double *x, double *s, double *c)
{
    int i;
#ifndef SYMDYN_LIBM_TRIG
    int in_range = 1;
    for (i = 0; i < count; ++i) {
        in_range &= (x[i] <= 1.0e5) & (x[i] >= -1.0e5);
    }
    if (in_range) {
#ifdef PLANAR2R_TRIG_WIDTH
        /* PLANAR2R_TRIG_WIDTH angles at a time (the last group padded with zeros) */
        for (i = 0; i < count; i += PLANAR2R_TRIG_WIDTH) {
            planar2r_treal angle = {0.0}, sine, cosine;
            int lane;
            for (lane = 0; lane < PLANAR2R_TRIG_WIDTH && i + lane < count; ++lane) {
                angle[lane] = x[i + lane];
            }
            planar2r_SINCOS_KERNEL(planar2r_treal, planar2r_tbits, angle, sine, cosine);
            for (lane = 0; lane < PLANAR2R_TRIG_WIDTH && i + lane < count; ++lane) {
                s[i + lane] = sine[lane];
                c[i + lane] = cosine[lane];
            }
        }
#else
        for (i = 0; i < count; ++i) {
            planar2r_SINCOS_KERNEL(double, unsigned long long, x[i], s[i], c[i]);
        }
#endif
        return;
    }
#endif
    for (i = 0; i < count; ++i) {
#ifndef SYMDYN_LIBM_TRIG
        if (x[i] <= 1.0e5 && x[i] >= -1.0e5) {
            planar2r_SINCOS_KERNEL(double, unsigned long long, x[i], s[i], c[i]);
            continue;
        }
#endif
        s[i] = sin(x[i]);
        c[i] = cos(x[i]);
    }
}

void planar2r_inverse_dynamics(const planar2r_real *q, const planar2r_real *qd, const planar2r_real *qdd, const planar2r_real *p, planar2r_real *tau)
{
    planar2r_real trig_sin[2], trig_cos[2];
    {
        const planar2r_real trig_angle[2] = {q[0], q[1]};
        planar2r_sincos(2, trig_angle, trig_sin, trig_cos);
    }
    const planar2r_real c1 = trig_cos[0];
    const planar2r_real s1 = trig_sin[0];
    const planar2r_real c2 = trig_cos[1];
    const planar2r_real s2 = trig_sin[1];
    const planar2r_real vd1g_0 = s1*p[0];
    const planar2r_real vd1g_1 = c1*p[0];
    const planar2r_real U1h_zz = qd[0]*qd[0];
    const planar2r_real w2h_2 = qd[0] + qd[1];
    const planar2r_real U2h_zz = w2h_2*w2h_2;
    const planar2r_real a1_1 = vd1g_1 + p[2]*qdd[0];
    const planar2r_real F1_1 = a1_1*p[1];
    const planar2r_real N1_2 = p[3]*qdd[0];
    const planar2r_real wd2_2 = qdd[0] + qdd[1];
    const planar2r_real aJ2_0 = vd1g_0 - U1h_zz*p[4];
    const planar2r_real aJ2_1 = vd1g_1 + p[4]*qdd[0];
    const planar2r_real vd2_0 = aJ2_0*c2 + aJ2_1*s2;
    const planar2r_real vd2_1 = aJ2_1*c2 - aJ2_0*s2;
    const planar2r_real a2_0 = vd2_0 - U2h_zz*p[6];
    const planar2r_real a2_1 = vd2_1 + wd2_2*p[6];
    const planar2r_real F2_0 = a2_0*p[5];
    const planar2r_real F2_1 = a2_1*p[5];
    const planar2r_real N2_2 = p[7]*wd2_2;
    const planar2r_real n2_2 = N2_2 + F2_1*p[6];
    const planar2r_real Rf1_1 = F2_0*s2 + F2_1*c2;
    const planar2r_real n1_2 = N1_2 + n2_2 + F1_1*p[2] + Rf1_1*p[4];
    tau[0] = n1_2;
    tau[1] = n2_2;
}

void planar2r_mass_matrix(const planar2r_real *q, const planar2r_real *p, planar2r_real *D)
{
    planar2r_real trig_sin[1], trig_cos[1];
    {
        const planar2r_real trig_angle[1] = {q[1]};
        planar2r_sincos(1, trig_angle, trig_sin, trig_cos);
    }
    const planar2r_real c2 = trig_cos[0];
    const planar2r_real Ic2h_0 = p[6]*p[5];
    const planar2r_real Ic2J_22 = p[7] + p[5]*p[6]*p[6];
    const planar2r_real Iq2h_0 = Ic2h_0*c2;
    const planar2r_real cse0 = Iq2h_0*p[4];
    const planar2r_real Ib2J_22 = Ic2J_22 + 2.0*cse0 + p[5]*p[4]*p[4];
    const planar2r_real Ic1J_22 = p[3] + Ib2J_22 + p[1]*p[2]*p[2];
    const planar2r_real F2b2n_2 = Ic2J_22 + cse0;
    D[0] = Ic1J_22;
    D[1] = F2b2n_2;
    D[3] = Ic2J_22;
    D[2] = D[1];
}

void planar2r_coriolis(const planar2r_real *q, const planar2r_real *qd, const planar2r_real *p, planar2r_real *h)
{
    planar2r_real trig_sin[1], trig_cos[1];
    {
        const planar2r_real trig_angle[1] = {q[1]};
        planar2r_sincos(1, trig_angle, trig_sin, trig_cos);
    }
    const planar2r_real c2 = trig_cos[0];
    const planar2r_real s2 = trig_sin[0];
    const planar2r_real U1h_zz = qd[0]*qd[0];
    const planar2r_real w2h_2 = qd[0] + qd[1];
    const planar2r_real aJ2h_0 = -U1h_zz*p[4];
    const planar2r_real U2h_zz = w2h_2*w2h_2;
    const planar2r_real vd2h_0 = aJ2h_0*c2;
    const planar2r_real vd2h_1 = -aJ2h_0*s2;
    const planar2r_real a2h_0 = vd2h_0 - U2h_zz*p[6];
    const planar2r_real F2h_0 = a2h_0*p[5];
    const planar2r_real F2h_1 = vd2h_1*p[5];
    const planar2r_real n2h_2 = F2h_1*p[6];
    const planar2r_real Rf1h_1 = F2h_0*s2 + F2h_1*c2;
    const planar2r_real n1h_2 = n2h_2 + Rf1h_1*p[4];
    h[0] = n1h_2;
    h[1] = n2h_2;
}

void planar2r_coriolis_matrix(const planar2r_real *q, const planar2r_real *qd, const planar2r_real *p, planar2r_real *C)
{
    planar2r_real trig_sin[1], trig_cos[1];
    {
        const planar2r_real trig_angle[1] = {q[1]};
        planar2r_sincos(1, trig_angle, trig_sin, trig_cos);
    }
    const planar2r_real c2 = trig_cos[0];
    const planar2r_real s2 = trig_sin[0];
    const planar2r_real w2h_2 = qd[0] + qd[1];
    const planar2r_real cse0 = -w2h_2*p[6];
    const planar2r_real dhaJ2h_0_dqd1 = -p[4]*qd[0];
    const planar2r_real dhvd2h_0_dqd1 = c2*dhaJ2h_0_dqd1;
    const planar2r_real dhvd2h_1_dqd1 = -dhaJ2h_0_dqd1*s2;
    const planar2r_real dha2h_0_dqd1 = dhvd2h_0_dqd1 + cse0;
    const planar2r_real dhF2h_0_dqd1 = dha2h_0_dqd1*p[5];
    const planar2r_real dhF2h_1_dqd1 = dhvd2h_1_dqd1*p[5];
    const planar2r_real dhn2h_2_dqd1 = dhF2h_1_dqd1*p[6];
    const planar2r_real dhRf1h_1_dqd1 = c2*dhF2h_1_dqd1 + dhF2h_0_dqd1*s2;
    const planar2r_real dhn1h_2_dqd1 = dhn2h_2_dqd1 + dhRf1h_1_dqd1*p[4];
    const planar2r_real dha2h_0_dqd2 = cse0;
    const planar2r_real dhF2h_0_dqd2 = dha2h_0_dqd2*p[5];
    const planar2r_real dhRf1h_1_dqd2 = dhF2h_0_dqd2*s2;
    const planar2r_real dhn1h_2_dqd2 = dhRf1h_1_dqd2*p[4];
    C[0] = dhn1h_2_dqd1;
    C[1] = dhn1h_2_dqd2;
    C[2] = dhn2h_2_dqd1;
    C[3] = 0.0;
}

void planar2r_gravity(const planar2r_real *q, const planar2r_real *p, planar2r_real *c)
{
    planar2r_real trig_sin[2], trig_cos[2];
    {
        const planar2r_real trig_angle[2] = {q[0], q[1]};
        planar2r_sincos(2, trig_angle, trig_sin, trig_cos);
    }
    const planar2r_real c1 = trig_cos[0];
    const planar2r_real s1 = trig_sin[0];
    const planar2r_real c2 = trig_cos[1];
    const planar2r_real s2 = trig_sin[1];
    const planar2r_real vd1g_0 = s1*p[0];
    const planar2r_real vd1g_1 = c1*p[0];
    const planar2r_real F1g_1 = vd1g_1*p[1];
    const planar2r_real vd2g_0 = c2*vd1g_0 + s2*vd1g_1;
    const planar2r_real vd2g_1 = c2*vd1g_1 - s2*vd1g_0;
    const planar2r_real F2g_0 = vd2g_0*p[5];
    const planar2r_real F2g_1 = vd2g_1*p[5];
    const planar2r_real n2g_2 = F2g_1*p[6];
    const planar2r_real Rf1g_1 = F2g_0*s2 + F2g_1*c2;
    const planar2r_real n1g_2 = n2g_2 + F1g_1*p[2] + Rf1g_1*p[4];
    c[0] = n1g_2;
    c[1] = n2g_2;
}

int planar2r_forward_dynamics_checked(const planar2r_real *q, const planar2r_real *qd, const planar2r_real *tau, const planar2r_real *p, planar2r_real *qdd)
{
    for (int i = 0; i < 2; ++i) {
        if (!(fabs(q[i]) <= DBL_MAX)
            || !(fabs(qd[i]) <= DBL_MAX)
            || !(fabs(tau[i]) <= DBL_MAX)) {
            return PLANAR2R_NOT_FINITE;
        }
    }
    planar2r_real trig_sin[2], trig_cos[2];
    {
        const planar2r_real trig_angle[2] = {q[0], q[1]};
        planar2r_sincos(2, trig_angle, trig_sin, trig_cos);
    }
    const planar2r_real c1 = trig_cos[0];
    const planar2r_real s1 = trig_sin[0];
    const planar2r_real c2 = trig_cos[1];
    const planar2r_real s2 = trig_sin[1];
    const planar2r_real vd1g_0 = s1*p[0];
    const planar2r_real vd1g_1 = c1*p[0];
    const planar2r_real F1g_1 = vd1g_1*p[1];
    const planar2r_real U1h_zz = qd[0]*qd[0];
    const planar2r_real w2h_2 = qd[0] + qd[1];
    const planar2r_real U2h_zz = w2h_2*w2h_2;
    const planar2r_real Ic2h_0 = p[6]*p[5];
    const planar2r_real Ic2J_22 = p[7] + p[5]*p[6]*p[6];
    const planar2r_real Iq2h_0 = Ic2h_0*c2;
    const planar2r_real cse0 = Iq2h_0*p[4];
    const planar2r_real Ib2J_22 = Ic2J_22 + 2.0*cse0 + p[5]*p[4]*p[4];
    const planar2r_real Ic1J_22 = p[3] + Ib2J_22 + p[1]*p[2]*p[2];
    if (!(Ic1J_22 > 0)) {
        return PLANAR2R_SINGULAR;
    }
    const planar2r_real F2b2n_2 = Ic2J_22 + cse0;
    const planar2r_real aJ2_0 = vd1g_0 - U1h_zz*p[4];
    const planar2r_real vd2b_0 = aJ2_0*c2 + s2*vd1g_1;
    const planar2r_real vd2b_1 = c2*vd1g_1 - aJ2_0*s2;
    const planar2r_real a2b_0 = vd2b_0 - U2h_zz*p[6];
    const planar2r_real F2b_0 = a2b_0*p[5];
    const planar2r_real F2b_1 = vd2b_1*p[5];
    const planar2r_real n2b_2 = F2b_1*p[6];
    const planar2r_real Rf1b_1 = F2b_0*s2 + F2b_1*c2;
    const planar2r_real n1b_2 = n2b_2 + F1g_1*p[2] + Rf1b_1*p[4];
    const planar2r_real rhs1 = tau[0] - n1b_2;
    const planar2r_real rhs2 = tau[1] - n2b_2;
    const planar2r_real ldl_inv1 = 1.0/Ic1J_22;
    const planar2r_real ldl_L21 = F2b2n_2*ldl_inv1;
    const planar2r_real ldl_d2 = Ic2J_22 - Ic1J_22*ldl_L21*ldl_L21;
    if (!(ldl_d2 > (double)PLANAR2R_PIVOT_RTOL*(Ic2J_22))) {
        return PLANAR2R_SINGULAR;
    }
    const planar2r_real ldl_inv2 = 1.0/ldl_d2;
    const planar2r_real ldl_y2 = rhs2 - ldl_L21*rhs1;
    const planar2r_real qdd2_fd = ldl_inv2*ldl_y2;
    const planar2r_real qdd1_fd = ldl_inv1*rhs1 - ldl_L21*qdd2_fd;
    if (!(fabs(qdd1_fd) <= DBL_MAX)
        || !(fabs(qdd2_fd) <= DBL_MAX)) {
        return PLANAR2R_NOT_FINITE;
    }
    qdd[0] = qdd1_fd;
    qdd[1] = qdd2_fd;
    return 0;
}

void planar2r_forward_dynamics(const planar2r_real *q, const planar2r_real *qd, const planar2r_real *tau, const planar2r_real *p, planar2r_real *qdd)
{
    (void)planar2r_forward_dynamics_checked(q, qd, tau, p, qdd);
}

void planar2r_forward_kinematics(const planar2r_real *q, const planar2r_real *p, planar2r_real *T)
{
    planar2r_real trig_sin[2], trig_cos[2];
    {
        const planar2r_real trig_angle[2] = {q[0], q[1]};
        planar2r_sincos(2, trig_angle, trig_sin, trig_cos);
    }
    const planar2r_real c1 = trig_cos[0];
    const planar2r_real s1 = trig_sin[0];
    const planar2r_real c2 = trig_cos[1];
    const planar2r_real s2 = trig_sin[1];
    const planar2r_real o2_0 = c1*p[4];
    const planar2r_real o2_1 = s1*p[4];
    const planar2r_real T02_00 = c1*c2 - s1*s2;
    const planar2r_real T02_01 = -c1*s2 - c2*s1;
    T[0] = T02_00;
    T[1] = T02_01;
    T[2] = 0.0;
    T[3] = o2_0;
    T[4] = -T02_01;
    T[5] = T02_00;
    T[6] = 0.0;
    T[7] = o2_1;
    T[8] = 0.0;
    T[9] = 0.0;
    T[10] = 1.0;
    T[11] = 0.0;
    T[12] = 0.0;
    T[13] = 0.0;
    T[14] = 0.0;
    T[15] = 1.0;
}

void planar2r_jacobian(const planar2r_real *q, const planar2r_real *p, planar2r_real *J)
{
    planar2r_real trig_sin[1], trig_cos[1];
    {
        const planar2r_real trig_angle[1] = {q[0]};
        planar2r_sincos(1, trig_angle, trig_sin, trig_cos);
    }
    const planar2r_real c1 = trig_cos[0];
    const planar2r_real s1 = trig_sin[0];
    const planar2r_real o2_0 = c1*p[4];
    const planar2r_real o2_1 = s1*p[4];
    J[0] = -o2_1;
    J[1] = 0.0;
    J[2] = o2_0;
    J[3] = 0.0;
    J[4] = 0.0;
    J[5] = 0.0;
    J[6] = 0.0;
    J[7] = 0.0;
    J[8] = 0.0;
    J[9] = 0.0;
    J[10] = 1.0;
    J[11] = 1.0;
}

void planar2r_jacobian_dot_qd(const planar2r_real *q, const planar2r_real *qd, const planar2r_real *p, planar2r_real *a)
{
    planar2r_real trig_sin[2], trig_cos[2];
    {
        const planar2r_real trig_angle[2] = {q[0], q[1]};
        planar2r_sincos(2, trig_angle, trig_sin, trig_cos);
    }
    const planar2r_real c1 = trig_cos[0];
    const planar2r_real s1 = trig_sin[0];
    const planar2r_real c2 = trig_cos[1];
    const planar2r_real s2 = trig_sin[1];
    const planar2r_real U1h_zz = qd[0]*qd[0];
    const planar2r_real aJ2h_0 = -U1h_zz*p[4];
    const planar2r_real vd2h_0 = aJ2h_0*c2;
    const planar2r_real vd2h_1 = -aJ2h_0*s2;
    const planar2r_real T02_00 = c1*c2 - s1*s2;
    const planar2r_real T02_01 = -c1*s2 - c2*s1;
    a[0] = T02_00*vd2h_0 + T02_01*vd2h_1;
    a[1] = T02_00*vd2h_1 - T02_01*vd2h_0;
    a[2] = 0.0;
    a[3] = 0.0;
    a[4] = 0.0;
    a[5] = 0.0;
}

void planar2r_kinematics(const planar2r_real *q, const planar2r_real *p, planar2r_real *T, planar2r_real *J)
{
    planar2r_real trig_sin[2], trig_cos[2];
    {
        const planar2r_real trig_angle[2] = {q[0], q[1]};
        planar2r_sincos(2, trig_angle, trig_sin, trig_cos);
    }
    const planar2r_real c1 = trig_cos[0];
    const planar2r_real s1 = trig_sin[0];
    const planar2r_real c2 = trig_cos[1];
    const planar2r_real s2 = trig_sin[1];
    const planar2r_real o2_0 = c1*p[4];
    const planar2r_real o2_1 = s1*p[4];
    const planar2r_real T02_00 = c1*c2 - s1*s2;
    const planar2r_real T02_01 = -c1*s2 - c2*s1;
    T[0] = T02_00;
    T[1] = T02_01;
    T[2] = 0.0;
    T[3] = o2_0;
    T[4] = -T02_01;
    T[5] = T02_00;
    T[6] = 0.0;
    T[7] = o2_1;
    T[8] = 0.0;
    T[9] = 0.0;
    T[10] = 1.0;
    T[11] = 0.0;
    T[12] = 0.0;
    T[13] = 0.0;
    T[14] = 0.0;
    T[15] = 1.0;
    J[0] = -o2_1;
    J[1] = 0.0;
    J[2] = o2_0;
    J[3] = 0.0;
    J[4] = 0.0;
    J[5] = 0.0;
    J[6] = 0.0;
    J[7] = 0.0;
    J[8] = 0.0;
    J[9] = 0.0;
    J[10] = 1.0;
    J[11] = 1.0;
}
