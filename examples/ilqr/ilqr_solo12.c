/*
 * iLQR of Solo-12 on its floating base, in the air (no contacts): a squat while falling, with
 * symdyn's generated C only: forward dynamics to simulate, its derivatives in the tangent space
 * (dqdd/dq, dqdd/dv and M^-1 from one call of solo_forward_dynamics_derivatives), integrate to
 * step the configuration (the base on SE(3)), integrate's Jacobians to carry the derivatives
 * through a step, and difference for the feedback on the configuration.  No finite
 * differences, no other library.  The same solver links against Pinocchio instead
 * (ilqr_solo12_pinocchio.cpp gives the same five functions from aba, computeABADerivatives,
 * integrate, dIntegrate and difference): see README.md.
 *
 * The task: from the standing posture at rest, crouch (hips and knees bent half as much again)
 * at T/2 and stand again at rest at T = 1 s, while the robot falls freely.
 *   state x = (q, v): q NQ = 19 numbers (base position, quaternion x y z w, 12 joints), v NV = 18
 *   (base linear and angular velocity in its frame, joint rates); its tangent dx (36) =
 *   (q (-) q_ref, v - v_ref); control u = the 12 joint torques (the base gets none);
 *   step dt = 0.02 s (50 steps), semi-implicit Euler on the manifold:
 *     v' = v + dt qdd(q, v, [0; u]),  q' = q (+) dt v'
 *   cost = sum_k 1/2 u_k^T R u_k + 1/2 w |joints(q_{N/2}) - crouch|^2
 *          + 1/2 w |joints(q_N) - stand|^2 + 1/2 w_v |joint rates(v_N)|^2
 * The base's pose and velocity are free (a falling robot cannot change its momentum).
 * Iterative LQR with a Levenberg-Marquardt term on Quu and a backtracking line search, stopped
 * when an iteration lowers the cost by less than 1e-6 of it.  Prints the cost per iteration,
 * the time per iteration (linearization, backward and forward passes), then the final errors;
 * exits 0 when the joints end within 1e-3 rad of the targets and 1e-2 rad/s of rest.
 *
 * Built with -DON_FEET (and a library generated with Solo-12's four feet as contacts): the same
 * squat standing on its four feet, the feet held by the ground (point contacts): the contact
 * dynamics to simulate, their derivatives (dqdd/dq, dqdd/dv and dqdd/dtau of the constrained
 * system from solo_contact_forward_dynamics_derivatives) to linearize, and the first guess the
 * torques that hold it at rest (solo_contact_inverse_dynamics at qdd = 0).
 */
#define _POSIX_C_SOURCE 199309L
#include <math.h>
#include <stdio.h>
#include <string.h>
#include <time.h>

#include "solo_dynamics.h"

#define NQ SOLO_NQ
#define NV SOLO_NV
#define NJ (NV - 6)
#define NX (2 * NV)
#define NU NJ
#define STEPS 50
#define DT 0.02
#define MAX_ITERATIONS 100

#include "ilqr_common.h"

static const double stand[NJ] = {0.0, 0.8, -1.6, 0.0, 0.8, -1.6, 0.0, -0.8, 1.6, 0.0, -0.8, 1.6};
static const double crouch[NJ] = {0.0, 1.2, -2.4, 0.0, 1.2, -2.4, 0.0, -1.2, 2.4, 0.0, -1.2, 2.4};
static const double control_weight = 1e-2;  /* R = 1e-2 I, per (N m)^2 */
static const double position_weight = 1e4;  /* on the joints at T/2 and T, per rad^2 */
static const double velocity_weight = 1e2;  /* on the joint rates at T, per (rad/s)^2 */

/* trajectories (each state q then v: NQ + NV numbers) and gains; A, B the linearization */
static double xs[STEPS + 1][NQ + NV], us[STEPS][NU], xs_new[STEPS + 1][NQ + NV], us_new[STEPS][NU];
static double A[STEPS][NX][NX], B[STEPS][NX][NU], k_ff[STEPS][NU], K_fb[STEPS][NU][NX];

static double now(void)
{
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return t.tv_sec + 1e-9 * t.tv_nsec;
}

/* One step of the semi-implicit Euler on the manifold; returns the forward dynamics' status. */
static int step(const double *x, const double *u, double *next)
{
    double tau[NV] = {0.0}, qdd[NV], displacement[NV];
    memcpy(tau + 6, u, sizeof(double) * NU);
#ifdef ON_FEET
    double lambda[SOLO_CONTACT_ROWS];
    int status = solo_contact_forward_dynamics(x, x + NQ, tau, qdd, lambda);
#else
    int status = solo_forward_dynamics_checked(x, x + NQ, tau, qdd);
#endif
    for (int i = 0; i < NV; ++i) {
        next[NQ + i] = x[NQ + i] + DT * qdd[i];
        displacement[i] = DT * next[NQ + i];
    }
    solo_integrate(x, displacement, next);
    return status;
}

/* The step's Jacobians in the tangent space, from the generated derivatives:
 *   d v'/d q = dt Fq,  d v'/d v = I + dt Fv,  d v'/d u = dt Minv[:, 6:]
 *   d q'/d q = J_q + J_v dt (d v'/d q),  d q'/d v = J_v dt (d v'/d v),  d q'/d u = J_v dt (d v'/d u)
 * with J_q, J_v integrate's Jacobians at dt v'. */
static int linearize(const double *x, const double *u, double a[NX][NX], double b[NX][NU])
{
    static double fq[NV * NV], fv[NV * NV], minv[NV * NV], jq[NV * NV], jv[NV * NV];
    double tau[NV] = {0.0}, next[NQ + NV], displacement[NV];
    memcpy(tau + 6, u, sizeof(double) * NU);
#ifdef ON_FEET  /* minv: dqdd/dtau of the constrained system; the forces' derivatives unused */
    static double qdd[NV], lambda[SOLO_CONTACT_ROWS], lq[SOLO_CONTACT_ROWS * NV], lv[SOLO_CONTACT_ROWS * NV], lt[SOLO_CONTACT_ROWS * NV];
    int status = solo_contact_forward_dynamics_derivatives(x, x + NQ, tau, qdd, lambda, fq, fv, minv, lq, lv, lt);
#else
    int status = solo_forward_dynamics_derivatives(x, x + NQ, tau, fq, fv, minv);
#endif
    if (status != 0 || (status = step(x, u, next)) != 0) {
        return status;
    }
    for (int i = 0; i < NV; ++i) displacement[i] = DT * next[NQ + i];
    solo_integrate_jacobians(displacement, jq, jv);
    for (int i = 0; i < NV; ++i) {
        for (int j = 0; j < NV; ++j) {
            a[NV + i][j] = DT * fq[i * NV + j];
            a[NV + i][NV + j] = (i == j ? 1.0 : 0.0) + DT * fv[i * NV + j];
        }
        for (int j = 0; j < NU; ++j) b[NV + i][j] = DT * minv[i * NV + 6 + j];
    }
    for (int i = 0; i < NV; ++i) {
        for (int j = 0; j < NV; ++j) {
            double by_q = jq[i * NV + j], by_v = 0.0;
            for (int l = 0; l < NV; ++l) {
                by_q += jv[i * NV + l] * DT * a[NV + l][j];
                by_v += jv[i * NV + l] * DT * a[NV + l][NV + j];
            }
            a[i][j] = by_q;
            a[i][NV + j] = by_v;
        }
        for (int j = 0; j < NU; ++j) {
            double by_u = 0.0;
            for (int l = 0; l < NV; ++l) by_u += jv[i * NV + l] * DT * b[NV + l][j];
            b[i][j] = by_u;
        }
    }
    return 0;
}

/* The state cost at step k: its gradient lx and (diagonal) Hessian lxx over the tangent dx,
 * and its value; zero but at T/2 and T. */
static double state_cost(int k, const double *x, double *lx, double *lxx)
{
    const double *target = k == STEPS ? stand : crouch;
    double value = 0.0;
    for (int i = 0; i < NX; ++i) lx[i] = lxx[i] = 0.0;
    if (k != STEPS && k != STEPS / 2) {
        return 0.0;
    }
    for (int j = 0; j < NJ; ++j) {
        double e = x[7 + j] - target[j];
        lx[6 + j] = position_weight * e;
        lxx[6 + j] = position_weight;
        value += 0.5 * position_weight * e * e;
        if (k == STEPS) {
            double r = x[NQ + 6 + j];
            lx[NV + 6 + j] = velocity_weight * r;
            lxx[NV + 6 + j] = velocity_weight;
            value += 0.5 * velocity_weight * r * r;
        }
    }
    return value;
}

static double cost(double x[STEPS + 1][NQ + NV], double u[STEPS][NU])
{
    double total = 0.0, lx[NX], lxx[NX];
    for (int k = 0; k <= STEPS; ++k) {
        total += state_cost(k, x[k], lx, lxx);
        for (int i = 0; k < STEPS && i < NU; ++i) total += 0.5 * control_weight * u[k][i] * u[k][i];
    }
    return total;
}

/* The backward pass at regularization mu; 0 when a Quu is not positive definite.  The products
 * run along rows (row-major arrays: the inner loops contiguous); the gains and the value
 * function's update are ilqr_common.h's. */
static int backward(double mu, double *expected)
{
    static double vx[NX], vxx[NX][NX], qxx[NX][NX], va[NX][NX], qux[NU][NX];
    double qx[NX], qu[NU], quu[NU][NU], vb[NX][NU], lx[NX], lxx[NX];
    *expected = 0.0;
    state_cost(STEPS, xs[STEPS], lx, lxx);
    for (int i = 0; i < NX; ++i) {
        vx[i] = lx[i];
        for (int j = 0; j < NX; ++j) vxx[i][j] = i == j ? lxx[i] : 0.0;
    }
    for (int k = STEPS - 1; k >= 0; --k) {
        double (*a)[NX] = A[k], (*b)[NU] = B[k];
        state_cost(k, xs[k], lx, lxx);
        memset(va, 0, sizeof va);
        memset(vb, 0, sizeof vb);
        for (int i = 0; i < NX; ++i) {  /* Vxx A and Vxx B */
            for (int l = 0; l < NX; ++l) {
                const double v = vxx[i][l];
                for (int j = 0; j < NX; ++j) va[i][j] += v * a[l][j];
                for (int j = 0; j < NU; ++j) vb[i][j] += v * b[l][j];
            }
        }
        memset(qxx, 0, sizeof qxx);
        memset(qux, 0, sizeof qux);
        memset(quu, 0, sizeof quu);
        for (int i = 0; i < NX; ++i) qx[i] = lx[i];
        for (int i = 0; i < NU; ++i) qu[i] = control_weight * us[k][i];
        for (int l = 0; l < NX; ++l) {  /* Qx = lx + A^T Vx, Qxx = A^T Vxx A, Qu = R u + B^T Vx, Qux, Quu */
            for (int i = 0; i < NX; ++i) {
                const double al = a[l][i];
                qx[i] += al * vx[l];
                for (int j = 0; j < NX; ++j) qxx[i][j] += al * va[l][j];
            }
            for (int i = 0; i < NU; ++i) {
                const double bl = b[l][i];
                qu[i] += bl * vx[l];
                for (int j = 0; j < NX; ++j) qux[i][j] += bl * va[l][j];
                for (int j = 0; j < NU; ++j) quu[i][j] += bl * vb[l][j];
            }
        }
        for (int i = 0; i < NX; ++i) qxx[i][i] += lxx[i];
        for (int i = 0; i < NU; ++i) quu[i][i] += control_weight + mu;
        if (!solve_gains(quu, qu, qux, k_ff[k], K_fb[k])) {
            return 0;
        }
        *expected += value_update(qx, qxx, qu, quu, qux, k_ff[k], K_fb[k], vx, vxx);
    }
    return 1;
}

/* Roll the controls out from x0 with step size alpha and the feedback gains, the deviation of
 * the configuration taken by difference (in the tangent space); 0 on a status. */
static int forward(double alpha)
{
    memcpy(xs_new[0], xs[0], sizeof xs_new[0]);
    for (int k = 0; k < STEPS; ++k) {
        double dx[NX];
        solo_difference(xs[k], xs_new[k], dx);
        for (int i = 0; i < NV; ++i) dx[NV + i] = xs_new[k][NQ + i] - xs[k][NQ + i];
        for (int i = 0; i < NU; ++i) {
            double u = us[k][i] + alpha * k_ff[k][i];
            for (int j = 0; j < NX; ++j) u += K_fb[k][i][j] * dx[j];
            us_new[k][i] = u;
        }
        if (step(xs_new[k], us_new[k], xs_new[k + 1]) != 0) {
            return 0;
        }
    }
    return 1;
}

int main(void)
{
    memset(xs, 0, sizeof xs);
    memset(us, 0, sizeof us);
    xs[0][6] = 1.0;  /* the base at the origin, upright (quaternion w = 1), at rest */
    memcpy(&xs[0][7], stand, sizeof stand);
    for (int k = 0; k < STEPS; ++k) {  /* the first guess: no torque (the robot falls as it stands) */
#ifdef ON_FEET  /* standing: the torques that hold it at rest on its feet (contact inverse dynamics) */
        double rest[NV] = {0.0}, tau[NV], lambda[SOLO_CONTACT_ROWS];
        if (solo_contact_inverse_dynamics(xs[k], rest, rest, tau, lambda) != 0) {
            fprintf(stderr, "contact inverse dynamics failed in the first rollout\n");
            return 1;
        }
        memcpy(us[k], tau + 6, sizeof us[k]);
#endif
        if (step(xs[k], us[k], xs[k + 1]) != 0) {
            fprintf(stderr, "forward dynamics failed in the first rollout\n");
            return 1;
        }
    }
    double current = cost(xs, us), mu = 1e-6, seconds[3] = {0.0, 0.0, 0.0};
    printf("iteration 0: cost %.9g\n", current);
    int iteration = 1, done = 0;
    for (; iteration <= MAX_ITERATIONS && !done; ++iteration) {
        double t0 = now();
        for (int k = 0; k < STEPS; ++k) {
            if (linearize(xs[k], us[k], A[k], B[k]) != 0) {
                fprintf(stderr, "the mass matrix is singular at step %d\n", k);
                return 1;
            }
        }
        double t1 = now(), expected;
        while (!backward(mu, &expected)) {
            mu *= 10.0;
            if (mu > 1e10) {
                fprintf(stderr, "Quu is not positive definite\n");
                return 1;
            }
        }
        double t2 = now(), alpha = 1.0, trial = current;
        int accepted = 0;
        for (int tries = 0; tries < 12; ++tries, alpha *= 0.5) {
            if (forward(alpha) && (trial = cost(xs_new, us_new)) < current) {
                accepted = 1;
                break;
            }
        }
        double t3 = now();
        seconds[0] += t1 - t0;
        seconds[1] += t2 - t1;
        seconds[2] += t3 - t2;
        if (!accepted) {
            mu *= 10.0;
            done = mu > 1e10;
            continue;
        }
        double decrease = current - trial;
        memcpy(xs, xs_new, sizeof xs);
        memcpy(us, us_new, sizeof us);
        current = trial;
        mu = mu > 1e-6 ? mu / 10.0 : mu;
        printf("iteration %d: cost %.9g (step %g, expected decrease %.3g)\n", iteration, current, alpha, -expected);
        done = decrease < 1e-6 * current;
    }
    --iteration;
    double position = 0.0, middle = 0.0, velocity = 0.0;
    for (int j = 0; j < NJ; ++j) {
        position = fmax(position, fabs(xs[STEPS][7 + j] - stand[j]));
        middle = fmax(middle, fabs(xs[STEPS / 2][7 + j] - crouch[j]));
        velocity = fmax(velocity, fabs(xs[STEPS][NQ + 6 + j]));
    }
    printf("time per iteration: %.3f ms (linearization %.3f ms, backward pass %.3f ms, forward passes %.3f ms)\n",
           1e3 * (seconds[0] + seconds[1] + seconds[2]) / iteration, 1e3 * seconds[0] / iteration,
           1e3 * seconds[1] / iteration, 1e3 * seconds[2] / iteration);
#ifdef ON_FEET  /* how far the feet moved: the contacts hold their accelerations, not their positions */
    double start[16 * SOLO_NFRAMES], end[16 * SOLO_NFRAMES], drift = 0.0, sink = xs[0][2] - xs[STEPS / 2][2];
    solo_frame_poses(xs[0], start);
    for (int k = 0; k <= STEPS; ++k) {
        solo_frame_poses(xs[k], end);
        for (int f = 0; f < SOLO_NFRAMES; ++f) {
            double d = 0.0;
            for (int i = 0; i < 3; ++i) d += pow(end[16 * f + 4 * i + 3] - start[16 * f + 4 * i + 3], 2);
            drift = fmax(drift, sqrt(d));
        }
    }
    printf("on four feet: the base sinks %.4f m at the crouch; the feet move at most %.3g m\n", sink, drift);
#endif
    int converged = position < 1e-3 && middle < 1e-3 && velocity < 1e-2;
    printf("final: cost %.9g after %d iterations; crouch %.3g rad, stand %.3g rad, joint rates %.3g rad/s: %s\n",
           current, iteration, middle, position, velocity, converged ? "converged" : "NOT converged");
    return converged ? 0 : 1;
}
