/*
 * scara_dynamics — equations of motion of robot 'scara' (4 joints, standard DH).
 *
 * GENERATED FILE — DO NOT EDIT. Regenerate it with symdyn instead.
 *   generator : symdyn 0.1.0 (newton-euler; forward dynamics by LDL^T of D, double precision)
 *   input     : scara.yaml
 *   sha256    : 0a7a32e7314995d04c0f541c34ef4f611bb5ca2bc912f19f3ffb18e0c80931ee
 */
#include <math.h>
#include <float.h>
#include <stdint.h>
#include <string.h>

#include "scara_dynamics.h"

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
#define scara_SINCOS_KERNEL(REAL, BITS, x, s, c) do { \
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
#define SCARA_TRIG_WIDTH 4
#else
#define SCARA_TRIG_WIDTH 2
#endif
typedef double scara_treal __attribute__((vector_size(SCARA_TRIG_WIDTH * sizeof(double))));
typedef unsigned long long scara_tbits __attribute__((vector_size(SCARA_TRIG_WIDTH * sizeof(double))));
#endif

static void scara_sincos(int count, const double *x, double *s, double *c)
{
    int i;
#ifndef SYMDYN_LIBM_TRIG
    int in_range = 1;
    for (i = 0; i < count; ++i) {
        in_range &= (x[i] <= 1.0e5) & (x[i] >= -1.0e5);
    }
    if (in_range) {
#ifdef SCARA_TRIG_WIDTH
        /* SCARA_TRIG_WIDTH angles at a time (the last group padded with zeros) */
        for (i = 0; i < count; i += SCARA_TRIG_WIDTH) {
            scara_treal angle = {0.0}, sine, cosine;
            int lane;
            for (lane = 0; lane < SCARA_TRIG_WIDTH && i + lane < count; ++lane) {
                angle[lane] = x[i + lane];
            }
            scara_SINCOS_KERNEL(scara_treal, scara_tbits, angle, sine, cosine);
            for (lane = 0; lane < SCARA_TRIG_WIDTH && i + lane < count; ++lane) {
                s[i + lane] = sine[lane];
                c[i + lane] = cosine[lane];
            }
        }
#else
        for (i = 0; i < count; ++i) {
            scara_SINCOS_KERNEL(double, unsigned long long, x[i], s[i], c[i]);
        }
#endif
        return;
    }
#endif
    for (i = 0; i < count; ++i) {
#ifndef SYMDYN_LIBM_TRIG
        if (x[i] <= 1.0e5 && x[i] >= -1.0e5) {
            scara_SINCOS_KERNEL(double, unsigned long long, x[i], s[i], c[i]);
            continue;
        }
#endif
        s[i] = sin(x[i]);
        c[i] = cos(x[i]);
    }
}

void scara_inverse_dynamics(const scara_real *q, const scara_real *qd, const scara_real *qdd, scara_real *tau)
{
    scara_real trig_sin[2], trig_cos[2];
    {
        const scara_real trig_angle[2] = {q[1], q[3]};
        scara_sincos(2, trig_angle, trig_sin, trig_cos);
    }
    const scara_real c2 = trig_cos[0];
    const scara_real s2 = trig_sin[0];
    const scara_real c4 = trig_cos[1];
    const scara_real s4 = trig_sin[1];
    const scara_real U1h_zz = qd[0]*qd[0];
    const scara_real w2h_2 = qd[0] + qd[1];
    const scara_real aJ2h_0 = -(0.4)*U1h_zz;
    const scara_real U2h_zz = w2h_2*w2h_2;
    const scara_real a1_1 = (0.2)*qdd[0];
    const scara_real F1_1 = 6.0*a1_1;
    const scara_real N1_2 = (0.085)*qdd[0];
    const scara_real wd2_2 = qdd[0] + qdd[1];
    const scara_real aJ2_1 = (0.4)*qdd[0];
    const scara_real vd2_0 = aJ2_1*s2 + aJ2h_0*c2;
    const scara_real cse0 = -vd2_0;
    const scara_real vd2_1 = aJ2_1*c2 - aJ2h_0*s2;
    const scara_real a2_0 = -cse0 - (0.125)*U2h_zz;
    const scara_real a2_1 = vd2_1 + (0.125)*wd2_2;
    const scara_real F2_0 = (3.5)*a2_0;
    const scara_real F2_1 = (3.5)*a2_1;
    const scara_real N2_2 = (0.020229166666666666)*wd2_2;
    const scara_real vd3_0 = -cse0 - (0.25)*U2h_zz;
    const scara_real vd3_1 = -vd2_1 - (0.25)*wd2_2;
    const scara_real vd3_2 = -9.81 + qdd[2];
    const scara_real F3_0 = (1.2)*vd3_0;
    const scara_real F3_1 = (1.2)*vd3_1;
    const scara_real F3_2 = (1.2)*vd3_2;
    const scara_real N3_2 = -(0.0004)*wd2_2;
    const scara_real wd4_2 = qdd[3] - wd2_2;
    const scara_real vd4_0 = c4*vd3_0 + s4*vd3_1;
    const scara_real vd4_1 = c4*vd3_1 - s4*vd3_0;
    const scara_real F4_0 = (0.4)*vd4_0;
    const scara_real F4_1 = (0.4)*vd4_1;
    const scara_real F4_2 = (0.4)*vd3_2;
    const scara_real N4_2 = (0.0003)*wd4_2;
    const scara_real Rf3_0 = F4_0*c4 - F4_1*s4;
    const scara_real Rf3_1 = F4_0*s4 + F4_1*c4;
    const scara_real f3_0 = F3_0 + Rf3_0;
    const scara_real f3_1 = F3_1 + Rf3_1;
    const scara_real f3_2 = F3_2 + F4_2;
    const scara_real n3_2 = N3_2 + N4_2;
    const scara_real f2_0 = F2_0 + f3_0;
    const scara_real f2_1 = F2_1 - f3_1;
    const scara_real n2_2 = N2_2 - n3_2 - (0.25)*f3_1 + (0.125)*F2_1;
    const scara_real Rf1_1 = c2*f2_1 + f2_0*s2;
    const scara_real n1_2 = N1_2 + n2_2 + (0.2)*F1_1 + (0.4)*Rf1_1;
    tau[0] = n1_2 + 3.0*((double)((qd[0] > 0) - (qd[0] < 0))) + (0.8)*qdd[0] + (2.5)*qd[0];
    tau[1] = n2_2 + (1.5)*((double)((qd[1] > 0) - (qd[1] < 0))) + (0.3)*qdd[1] + (1.2)*qd[1];
    tau[2] = f3_2 + (0.5)*qdd[2] + 4.0*((double)((qd[2] > 0) - (qd[2] < 0))) + 10.0*qd[2];
    tau[3] = N4_2 + (0.2)*((double)((qd[3] > 0) - (qd[3] < 0))) + (0.1)*qd[3] + (0.05)*qdd[3];
}

void scara_mass_matrix(const scara_real *q, scara_real *D)
{
    scara_real trig_sin[1], trig_cos[1];
    {
        const scara_real trig_angle[1] = {q[1]};
        scara_sincos(1, trig_angle, trig_sin, trig_cos);
    }
    const scara_real c2 = trig_cos[0];
    const scara_real Iq2h_0 = (0.8375)*c2;
    const scara_real Ib2J_22 = 0.9916166666666667 + (0.8)*Iq2h_0;
    const scara_real Ic1J_22 = 0.325 + Ib2J_22;
    const scara_real F2b2n_2 = 0.17561666666666667 + (0.4)*Iq2h_0;
    D[0] = Ic1J_22;
    D[1] = F2b2n_2;
    D[2] = 0.0;
    D[3] = -0.0003;
    D[5] = 0.17561666666666667;
    D[6] = 0.0;
    D[7] = -0.0003;
    D[10] = 1.6;
    D[11] = 0.0;
    D[15] = 0.0003;
    D[4] = D[1];
    D[8] = D[2];
    D[9] = D[6];
    D[12] = D[3];
    D[13] = D[7];
    D[14] = D[11];
}

void scara_coriolis(const scara_real *q, const scara_real *qd, scara_real *h)
{
    scara_real trig_sin[2], trig_cos[2];
    {
        const scara_real trig_angle[2] = {q[1], q[3]};
        scara_sincos(2, trig_angle, trig_sin, trig_cos);
    }
    const scara_real c2 = trig_cos[0];
    const scara_real s2 = trig_sin[0];
    const scara_real c4 = trig_cos[1];
    const scara_real s4 = trig_sin[1];
    const scara_real U1h_zz = qd[0]*qd[0];
    const scara_real w2h_2 = qd[0] + qd[1];
    const scara_real aJ2h_0 = -(0.4)*U1h_zz;
    const scara_real U2h_zz = w2h_2*w2h_2;
    const scara_real vd2h_0 = aJ2h_0*c2;
    const scara_real cse0 = -vd2h_0;
    const scara_real vd2h_1 = -aJ2h_0*s2;
    const scara_real a2h_0 = -cse0 - (0.125)*U2h_zz;
    const scara_real F2h_0 = (3.5)*a2h_0;
    const scara_real F2h_1 = (3.5)*vd2h_1;
    const scara_real vd3h_0 = -cse0 - (0.25)*U2h_zz;
    const scara_real F3h_0 = (1.2)*vd3h_0;
    const scara_real F3h_1 = -(1.2)*vd2h_1;
    const scara_real vd4h_0 = c4*vd3h_0 - s4*vd2h_1;
    const scara_real vd4h_1 = -c4*vd2h_1 - s4*vd3h_0;
    const scara_real F4h_0 = (0.4)*vd4h_0;
    const scara_real F4h_1 = (0.4)*vd4h_1;
    const scara_real Rf3h_0 = F4h_0*c4 - F4h_1*s4;
    const scara_real Rf3h_1 = F4h_0*s4 + F4h_1*c4;
    const scara_real f3h_0 = F3h_0 + Rf3h_0;
    const scara_real f3h_1 = F3h_1 + Rf3h_1;
    const scara_real f2h_0 = F2h_0 + f3h_0;
    const scara_real f2h_1 = F2h_1 - f3h_1;
    const scara_real n2h_2 = -(0.25)*f3h_1 + (0.125)*F2h_1;
    const scara_real Rf1h_1 = c2*f2h_1 + f2h_0*s2;
    const scara_real n1h_2 = n2h_2 + (0.4)*Rf1h_1;
    h[0] = n1h_2;
    h[1] = n2h_2;
    h[2] = 0.0;
    h[3] = 0.0;
}

void scara_coriolis_matrix(const scara_real *q, const scara_real *qd, scara_real *C)
{
    scara_real trig_sin[2], trig_cos[2];
    {
        const scara_real trig_angle[2] = {q[1], q[3]};
        scara_sincos(2, trig_angle, trig_sin, trig_cos);
    }
    const scara_real c2 = trig_cos[0];
    const scara_real s2 = trig_sin[0];
    const scara_real c4 = trig_cos[1];
    const scara_real s4 = trig_sin[1];
    const scara_real w2h_2 = qd[0] + qd[1];
    const scara_real cse0 = -(0.125)*w2h_2;
    const scara_real cse1 = -(0.25)*w2h_2;
    const scara_real dhaJ2h_0_dqd1 = -(0.4)*qd[0];
    const scara_real dhvd2h_0_dqd1 = c2*dhaJ2h_0_dqd1;
    const scara_real dhvd2h_1_dqd1 = -dhaJ2h_0_dqd1*s2;
    const scara_real dha2h_0_dqd1 = dhvd2h_0_dqd1 + cse0;
    const scara_real dhF2h_0_dqd1 = (3.5)*dha2h_0_dqd1;
    const scara_real dhF2h_1_dqd1 = (3.5)*dhvd2h_1_dqd1;
    const scara_real dhvd3h_0_dqd1 = dhvd2h_0_dqd1 + cse1;
    const scara_real dhF3h_0_dqd1 = (1.2)*dhvd3h_0_dqd1;
    const scara_real dhF3h_1_dqd1 = -(1.2)*dhvd2h_1_dqd1;
    const scara_real dhvd4h_0_dqd1 = c4*dhvd3h_0_dqd1 - dhvd2h_1_dqd1*s4;
    const scara_real dhvd4h_1_dqd1 = -c4*dhvd2h_1_dqd1 - dhvd3h_0_dqd1*s4;
    const scara_real dhF4h_0_dqd1 = (0.4)*dhvd4h_0_dqd1;
    const scara_real dhF4h_1_dqd1 = (0.4)*dhvd4h_1_dqd1;
    const scara_real dhRf3h_0_dqd1 = c4*dhF4h_0_dqd1 - dhF4h_1_dqd1*s4;
    const scara_real dhRf3h_1_dqd1 = c4*dhF4h_1_dqd1 + dhF4h_0_dqd1*s4;
    const scara_real dhf3h_0_dqd1 = dhF3h_0_dqd1 + dhRf3h_0_dqd1;
    const scara_real dhf3h_1_dqd1 = dhF3h_1_dqd1 + dhRf3h_1_dqd1;
    const scara_real dhf2h_0_dqd1 = dhF2h_0_dqd1 + dhf3h_0_dqd1;
    const scara_real dhf2h_1_dqd1 = dhF2h_1_dqd1 - dhf3h_1_dqd1;
    const scara_real dhn2h_2_dqd1 = -(0.25)*dhf3h_1_dqd1 + (0.125)*dhF2h_1_dqd1;
    const scara_real dhRf1h_1_dqd1 = c2*dhf2h_1_dqd1 + dhf2h_0_dqd1*s2;
    const scara_real dhn1h_2_dqd1 = dhn2h_2_dqd1 + (0.4)*dhRf1h_1_dqd1;
    const scara_real dha2h_0_dqd2 = cse0;
    const scara_real dhF2h_0_dqd2 = (3.5)*dha2h_0_dqd2;
    const scara_real dhvd3h_0_dqd2 = cse1;
    const scara_real dhF3h_0_dqd2 = (1.2)*dhvd3h_0_dqd2;
    const scara_real dhvd4h_0_dqd2 = c4*dhvd3h_0_dqd2;
    const scara_real dhvd4h_1_dqd2 = -dhvd3h_0_dqd2*s4;
    const scara_real dhF4h_0_dqd2 = (0.4)*dhvd4h_0_dqd2;
    const scara_real dhF4h_1_dqd2 = (0.4)*dhvd4h_1_dqd2;
    const scara_real dhRf3h_0_dqd2 = c4*dhF4h_0_dqd2 - dhF4h_1_dqd2*s4;
    const scara_real dhRf3h_1_dqd2 = c4*dhF4h_1_dqd2 + dhF4h_0_dqd2*s4;
    const scara_real dhf3h_0_dqd2 = dhF3h_0_dqd2 + dhRf3h_0_dqd2;
    const scara_real dhf2h_0_dqd2 = dhF2h_0_dqd2 + dhf3h_0_dqd2;
    const scara_real dhn2h_2_dqd2 = -(0.25)*dhRf3h_1_dqd2;
    const scara_real dhRf1h_1_dqd2 = dhf2h_0_dqd2*s2 - c2*dhRf3h_1_dqd2;
    const scara_real dhn1h_2_dqd2 = dhn2h_2_dqd2 + (0.4)*dhRf1h_1_dqd2;
    C[0] = dhn1h_2_dqd1;
    C[1] = dhn1h_2_dqd2;
    C[2] = 0.0;
    C[3] = 0.0;
    C[4] = dhn2h_2_dqd1;
    C[5] = dhn2h_2_dqd2;
    C[6] = 0.0;
    C[7] = 0.0;
    C[8] = 0.0;
    C[9] = 0.0;
    C[10] = 0.0;
    C[11] = 0.0;
    C[12] = 0.0;
    C[13] = 0.0;
    C[14] = 0.0;
    C[15] = 0.0;
}

void scara_gravity(const scara_real *q, scara_real *c)
{
    (void)q;
    c[0] = 0.0;
    c[1] = 0.0;
    c[2] = -15.696;
    c[3] = 0.0;
}

int scara_forward_dynamics_checked(const scara_real *q, const scara_real *qd, const scara_real *tau, scara_real *qdd)
{
    for (int i = 0; i < 4; ++i) {
        if (!(fabs(q[i]) <= DBL_MAX)
            || !(fabs(qd[i]) <= DBL_MAX)
            || !(fabs(tau[i]) <= DBL_MAX)) {
            return SCARA_NOT_FINITE;
        }
    }
    scara_real trig_sin[2], trig_cos[2];
    {
        const scara_real trig_angle[2] = {q[1], q[3]};
        scara_sincos(2, trig_angle, trig_sin, trig_cos);
    }
    const scara_real c2 = trig_cos[0];
    const scara_real s2 = trig_sin[0];
    const scara_real c4 = trig_cos[1];
    const scara_real s4 = trig_sin[1];
    const scara_real U1h_zz = qd[0]*qd[0];
    const scara_real w2h_2 = qd[0] + qd[1];
    const scara_real aJ2h_0 = -(0.4)*U1h_zz;
    const scara_real U2h_zz = w2h_2*w2h_2;
    const scara_real vd2h_0 = aJ2h_0*c2;
    const scara_real cse0 = -vd2h_0;
    const scara_real vd2h_1 = -aJ2h_0*s2;
    const scara_real a2h_0 = -cse0 - (0.125)*U2h_zz;
    const scara_real F2h_0 = (3.5)*a2h_0;
    const scara_real F2h_1 = (3.5)*vd2h_1;
    const scara_real vd3h_0 = -cse0 - (0.25)*U2h_zz;
    const scara_real F3h_0 = (1.2)*vd3h_0;
    const scara_real F3h_1 = -(1.2)*vd2h_1;
    const scara_real vd4h_0 = c4*vd3h_0 - s4*vd2h_1;
    const scara_real vd4h_1 = -c4*vd2h_1 - s4*vd3h_0;
    const scara_real F4h_0 = (0.4)*vd4h_0;
    const scara_real F4h_1 = (0.4)*vd4h_1;
    const scara_real Rf3h_0 = F4h_0*c4 - F4h_1*s4;
    const scara_real Rf3h_1 = F4h_0*s4 + F4h_1*c4;
    const scara_real f3h_0 = F3h_0 + Rf3h_0;
    const scara_real f3h_1 = F3h_1 + Rf3h_1;
    const scara_real f2h_0 = F2h_0 + f3h_0;
    const scara_real f2h_1 = F2h_1 - f3h_1;
    const scara_real n2h_2 = -(0.25)*f3h_1 + (0.125)*F2h_1;
    const scara_real Rf1h_1 = c2*f2h_1 + f2h_0*s2;
    const scara_real n1h_2 = n2h_2 + (0.4)*Rf1h_1;
    const scara_real Iq2h_0 = (0.8375)*c2;
    const scara_real Ib2J_22 = 0.9916166666666667 + (0.8)*Iq2h_0;
    const scara_real Ic1J_22 = 0.325 + Ib2J_22;
    const scara_real cse1 = 0.8 + Ic1J_22;
    const scara_real F2b2n_2 = 0.17561666666666667 + (0.4)*Iq2h_0;
    const scara_real rhs1 = tau[0] - n1h_2 - 3.0*((double)((qd[0] > 0) - (qd[0] < 0))) - (2.5)*qd[0];
    const scara_real rhs2 = tau[1] - n2h_2 - (1.2)*qd[1] - (1.5)*((double)((qd[1] > 0) - (qd[1] < 0)));
    const scara_real rhs3 = 15.696 + tau[2] - 10.0*qd[2] - 4.0*((double)((qd[2] > 0) - (qd[2] < 0)));
    const scara_real rhs4 = tau[3] - (0.2)*((double)((qd[3] > 0) - (qd[3] < 0))) - (0.1)*qd[3];
    const scara_real ldl_d1 = cse1;
    if (!(ldl_d1 > (double)SCARA_PIVOT_RTOL*(cse1))) {
        return SCARA_SINGULAR;
    }
    const scara_real ldl_inv1 = 1.0/ldl_d1;
    const scara_real ldl_L21 = F2b2n_2*ldl_inv1;
    const scara_real ldl_L41 = -(0.0003)*ldl_inv1;
    const scara_real ldl_d2 = 0.4756166666666667 - ldl_d1*ldl_L21*ldl_L21;
    if (!(ldl_d2 > (double)SCARA_PIVOT_RTOL*(0.4756166666666667))) {
        return SCARA_SINGULAR;
    }
    const scara_real ldl_inv2 = 1.0/ldl_d2;
    const scara_real ldl_L42 = ldl_inv2*(-0.0003 - ldl_L21*ldl_L41*ldl_d1);
    const scara_real ldl_d4 = 0.0503 - ldl_d1*ldl_L41*ldl_L41 - ldl_d2*ldl_L42*ldl_L42;
    if (!(ldl_d4 > (double)SCARA_PIVOT_RTOL*(0.0503))) {
        return SCARA_SINGULAR;
    }
    const scara_real ldl_inv4 = 1.0/ldl_d4;
    const scara_real ldl_y2 = rhs2 - ldl_L21*rhs1;
    const scara_real ldl_y4 = rhs4 - ldl_L41*rhs1 - ldl_L42*ldl_y2;
    const scara_real qdd4_fd = ldl_inv4*ldl_y4;
    const scara_real qdd3_fd = (0.47619047619047616)*rhs3;
    const scara_real qdd2_fd = ldl_inv2*ldl_y2 - ldl_L42*qdd4_fd;
    const scara_real qdd1_fd = ldl_inv1*rhs1 - ldl_L21*qdd2_fd - ldl_L41*qdd4_fd;
    if (!(fabs(qdd1_fd) <= DBL_MAX)
        || !(fabs(qdd2_fd) <= DBL_MAX)
        || !(fabs(qdd3_fd) <= DBL_MAX)
        || !(fabs(qdd4_fd) <= DBL_MAX)) {
        return SCARA_NOT_FINITE;
    }
    qdd[0] = qdd1_fd;
    qdd[1] = qdd2_fd;
    qdd[2] = qdd3_fd;
    qdd[3] = qdd4_fd;
    return 0;
}

void scara_forward_dynamics(const scara_real *q, const scara_real *qd, const scara_real *tau, scara_real *qdd)
{
    (void)scara_forward_dynamics_checked(q, qd, tau, qdd);
}

void scara_forward_kinematics(const scara_real *q, scara_real *T)
{
    scara_real trig_sin[3], trig_cos[3];
    {
        const scara_real trig_angle[3] = {q[0], q[1], q[3]};
        scara_sincos(3, trig_angle, trig_sin, trig_cos);
    }
    const scara_real c1 = trig_cos[0];
    const scara_real s1 = trig_sin[0];
    const scara_real c2 = trig_cos[1];
    const scara_real cse0 = c1*c2;
    const scara_real cse3 = c2*s1;
    const scara_real s2 = trig_sin[1];
    const scara_real cse1 = s1*s2;
    const scara_real cse2 = c1*s2;
    const scara_real c4 = trig_cos[2];
    const scara_real s4 = trig_sin[2];
    const scara_real T01_03 = (0.4)*c1;
    const scara_real T01_13 = (0.4)*s1;
    const scara_real T02_00 = cse0 - cse1;
    const scara_real T02_01 = cse2 + cse3;
    const scara_real T02_03 = T01_03 + (0.25)*(cse0 - cse1);
    const scara_real T02_13 = T01_13 + (0.25)*(cse2 + cse3);
    const scara_real T03_23 = 0.3 - q[2];
    const scara_real T04_00 = T02_00*c4 + T02_01*s4;
    const scara_real T04_01 = T02_01*c4 - T02_00*s4;
    const scara_real T04_23 = -0.1 + T03_23;
    T[0] = T04_00;
    T[1] = T04_01;
    T[2] = 0.0;
    T[3] = T02_03;
    T[4] = T04_01;
    T[5] = -T04_00;
    T[6] = 0.0;
    T[7] = T02_13;
    T[8] = 0.0;
    T[9] = 0.0;
    T[10] = -1.0;
    T[11] = T04_23;
    T[12] = 0.0;
    T[13] = 0.0;
    T[14] = 0.0;
    T[15] = 1.0;
}

void scara_jacobian(const scara_real *q, scara_real *J)
{
    scara_real trig_sin[2], trig_cos[2];
    {
        const scara_real trig_angle[2] = {q[0], q[1]};
        scara_sincos(2, trig_angle, trig_sin, trig_cos);
    }
    const scara_real c1 = trig_cos[0];
    const scara_real s1 = trig_sin[0];
    const scara_real c2 = trig_cos[1];
    const scara_real cse1 = (0.25)*c2;
    const scara_real s2 = trig_sin[1];
    const scara_real cse0 = (0.25)*s2;
    const scara_real T01_03 = (0.4)*c1;
    const scara_real T01_13 = (0.4)*s1;
    const scara_real T02_03 = T01_03 + c1*cse1 - s1*cse0;
    const scara_real T02_13 = T01_13 + c1*cse0 + s1*cse1;
    const scara_real cse2 = -T02_13;
    J[0] = cse2;
    J[1] = T01_13 + cse2;
    J[2] = 0.0;
    J[3] = 0.0;
    J[4] = T02_03;
    J[5] = T02_03 - T01_03;
    J[6] = 0.0;
    J[7] = 0.0;
    J[8] = 0.0;
    J[9] = 0.0;
    J[10] = -1.0;
    J[11] = 0.0;
    J[12] = 0.0;
    J[13] = 0.0;
    J[14] = 0.0;
    J[15] = 0.0;
    J[16] = 0.0;
    J[17] = 0.0;
    J[18] = 0.0;
    J[19] = 0.0;
    J[20] = 1.0;
    J[21] = 1.0;
    J[22] = 0.0;
    J[23] = -1.0;
}

void scara_jacobian_dot_qd(const scara_real *q, const scara_real *qd, scara_real *a)
{
    scara_real trig_sin[3], trig_cos[3];
    {
        const scara_real trig_angle[3] = {q[0], q[1], q[3]};
        scara_sincos(3, trig_angle, trig_sin, trig_cos);
    }
    const scara_real c1 = trig_cos[0];
    const scara_real s1 = trig_sin[0];
    const scara_real c2 = trig_cos[1];
    const scara_real s2 = trig_sin[1];
    const scara_real c4 = trig_cos[2];
    const scara_real s4 = trig_sin[2];
    const scara_real U1h_zz = qd[0]*qd[0];
    const scara_real w2h_2 = qd[0] + qd[1];
    const scara_real aJ2h_0 = -(0.4)*U1h_zz;
    const scara_real U2h_zz = w2h_2*w2h_2;
    const scara_real vd2h_1 = -aJ2h_0*s2;
    const scara_real T02_00 = c1*c2 - s1*s2;
    const scara_real T02_01 = c1*s2 + c2*s1;
    const scara_real T04_00 = T02_00*c4 + T02_01*s4;
    const scara_real T04_01 = T02_01*c4 - T02_00*s4;
    const scara_real vd2h_0_2 = -(0.25)*U2h_zz + aJ2h_0*c2;
    const scara_real vd4h_0_2 = c4*vd2h_0_2 - s4*vd2h_1;
    const scara_real vd4h_1_2 = -c4*vd2h_1 - s4*vd2h_0_2;
    a[0] = T04_00*vd4h_0_2 + T04_01*vd4h_1_2;
    a[1] = T04_01*vd4h_0_2 - T04_00*vd4h_1_2;
    a[2] = 0.0;
    a[3] = 0.0;
    a[4] = 0.0;
    a[5] = 0.0;
}

void scara_kinematics(const scara_real *q, scara_real *T, scara_real *J)
{
    scara_real trig_sin[3], trig_cos[3];
    {
        const scara_real trig_angle[3] = {q[0], q[1], q[3]};
        scara_sincos(3, trig_angle, trig_sin, trig_cos);
    }
    const scara_real c1 = trig_cos[0];
    const scara_real s1 = trig_sin[0];
    const scara_real c2 = trig_cos[1];
    const scara_real cse0 = c1*c2;
    const scara_real cse3 = c2*s1;
    const scara_real s2 = trig_sin[1];
    const scara_real cse1 = s1*s2;
    const scara_real cse2 = c1*s2;
    const scara_real c4 = trig_cos[2];
    const scara_real s4 = trig_sin[2];
    const scara_real T01_03 = (0.4)*c1;
    const scara_real T01_13 = (0.4)*s1;
    const scara_real T02_00 = cse0 - cse1;
    const scara_real T02_01 = cse2 + cse3;
    const scara_real T02_03 = T01_03 + (0.25)*(cse0 - cse1);
    const scara_real T02_13 = T01_13 + (0.25)*(cse2 + cse3);
    const scara_real cse4 = -T02_13;
    const scara_real T03_23 = 0.3 - q[2];
    const scara_real T04_00 = T02_00*c4 + T02_01*s4;
    const scara_real T04_01 = T02_01*c4 - T02_00*s4;
    const scara_real T04_23 = -0.1 + T03_23;
    T[0] = T04_00;
    T[1] = T04_01;
    T[2] = 0.0;
    T[3] = T02_03;
    T[4] = T04_01;
    T[5] = -T04_00;
    T[6] = 0.0;
    T[7] = T02_13;
    T[8] = 0.0;
    T[9] = 0.0;
    T[10] = -1.0;
    T[11] = T04_23;
    T[12] = 0.0;
    T[13] = 0.0;
    T[14] = 0.0;
    T[15] = 1.0;
    J[0] = cse4;
    J[1] = T01_13 + cse4;
    J[2] = 0.0;
    J[3] = 0.0;
    J[4] = T02_03;
    J[5] = T02_03 - T01_03;
    J[6] = 0.0;
    J[7] = 0.0;
    J[8] = 0.0;
    J[9] = 0.0;
    J[10] = -1.0;
    J[11] = 0.0;
    J[12] = 0.0;
    J[13] = 0.0;
    J[14] = 0.0;
    J[15] = 0.0;
    J[16] = 0.0;
    J[17] = 0.0;
    J[18] = 0.0;
    J[19] = 0.0;
    J[20] = 1.0;
    J[21] = 1.0;
    J[22] = 0.0;
    J[23] = -1.0;
}
