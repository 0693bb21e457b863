/*
 * iLQR on puma560 with symdyn's generated C only: forward dynamics to simulate, its derivatives
 * (dqdd/dq, dqdd/dqd and dqdd/dtau = M^-1, all from one call of
 * puma560_forward_dynamics_derivatives) to linearize, and the gravity torques to start from.
 * No finite differences, no other library.
 *
 * The task: move the arm from rest at q = 0 to rest at a target pose in T = 1.5 s.
 *   state x = [q; qd] (12), control u = tau (6), step dt = 0.01 s (150 steps), semi-implicit Euler:
 *     qd' = qd + dt qdd(q, qd, u),  q' = q + dt qd'
 *   cost  = sum_k 1/2 u_k^T R u_k + 1/2 (x_N - x*)^T Qf (x_N - x*)
 * Iterative LQR (Li and Todorov, 2004) with a Levenberg-Marquardt term on Quu and a
 * backtracking line search, stopped when an iteration lowers the cost by less than 1e-5 of it.
 * The arm's Coulomb friction makes the dynamics non-smooth where a joint's velocity changes
 * sign (its derivative there is zero, as the generated header says), so the last iterations
 * take short steps.  Prints the cost per iteration, then the final errors; exits 0 when the arm
 * ends within 1e-3 rad of the target and 1e-2 rad/s of rest, 1 otherwise.
 *
 * Build (see README.md):
 *   symdyn generate robots/puma560.yaml --out build --functions forward_dynamics,forward_dynamics_derivatives,gravity
 *   cc -std=c99 -O2 -I build examples/ilqr/ilqr_puma560.c build/puma560_dynamics.c -lm -o ilqr
 */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "puma560_dynamics.h"

#define NQ PUMA560_DOF
#define NX (2 * NQ)
#define NU NQ
#define STEPS 150
#define DT 0.01
#define MAX_ITERATIONS 50

#include "ilqr_common.h"

static const double target[NQ] = {0.6, -0.5, 0.4, 0.3, -0.6, 0.9};
static const double control_weight = 1e-4;  /* R = 1e-4 I, per (N m)^2 */
static const double position_weight = 1e6;  /* Qf on q - q*, per rad^2 */
static const double velocity_weight = 1e4;  /* Qf on qd, per (rad/s)^2 */

/* trajectories and gains: x[k] and u[k] the current ones, A, B the linearization at them */
static double xs[STEPS + 1][NX], us[STEPS][NU], xs_new[STEPS + 1][NX], us_new[STEPS][NU];
static double A[STEPS][NX][NX], B[STEPS][NX][NU], k_ff[STEPS][NU], K_fb[STEPS][NU][NX];

/* One step of the semi-implicit Euler; returns the forward dynamics' status. */
static int step(const double *x, const double *u, double *next)
{
    double qdd[NQ];
    int status = puma560_forward_dynamics_checked(x, x + NQ, u, qdd);
    for (int i = 0; i < NQ; ++i) {
        next[NQ + i] = x[NQ + i] + DT * qdd[i];
        next[i] = x[i] + DT * next[NQ + i];
    }
    return status;
}

/* The step's Jacobians from the generated derivatives:
 *   d qd'/d q = dt Fq,        d qd'/d qd = I + dt Fv,        d qd'/d u = dt Minv
 *   d q'/d q  = I + dt^2 Fq,  d q'/d qd  = dt I + dt^2 Fv,   d q'/d u  = dt^2 Minv */
static int linearize(const double *x, const double *u, double a[NX][NX], double b[NX][NU])
{
    double fq[NQ * NQ], fv[NQ * NQ], minv[NQ * NQ];
    int status = puma560_forward_dynamics_derivatives(x, x + NQ, u, fq, fv, minv);
    if (status != 0) {
        return status;
    }
    for (int i = 0; i < NQ; ++i) {
        for (int j = 0; j < NQ; ++j) {
            double eye = i == j ? 1.0 : 0.0;
            a[NQ + i][j] = DT * fq[i * NQ + j];
            a[NQ + i][NQ + j] = eye + DT * fv[i * NQ + j];
            a[i][j] = eye + DT * DT * fq[i * NQ + j];
            a[i][NQ + j] = DT * eye + DT * DT * fv[i * NQ + j];
            b[NQ + i][j] = DT * minv[i * NQ + j];
            b[i][j] = DT * DT * minv[i * NQ + j];
        }
    }
    return 0;
}

static double terminal_error(const double *x, int i)
{
    return i < NQ ? x[i] - target[i] : x[i];
}

static double terminal_weight(int i)
{
    return i < NQ ? position_weight : velocity_weight;
}

static double cost(double x[STEPS + 1][NX], double u[STEPS][NU])
{
    double total = 0.0;
    for (int k = 0; k < STEPS; ++k) {
        for (int i = 0; i < NU; ++i) {
            total += 0.5 * control_weight * u[k][i] * u[k][i];
        }
    }
    for (int i = 0; i < NX; ++i) {
        double e = terminal_error(x[STEPS], i);
        total += 0.5 * terminal_weight(i) * e * e;
    }
    return total;
}

/* sum over l of x[l][i] y[l][j], for row-major arrays of NX rows with x_cols and y_cols columns
 * (entry (i, j) of x^T y; a vector is an array of one column) */
static double column_dot(const double *x, int x_cols, int i, const double *y, int y_cols, int j)
{
    double s = 0.0;
    for (int l = 0; l < NX; ++l) s += x[l * x_cols + i] * y[l * y_cols + j];
    return s;
}

/* The backward pass at regularization mu; 0 when a Quu is not positive definite. */
static int backward(double mu, double *expected)
{
    static double vx[NX], vxx[NX][NX];
    double qx[NX], qu[NU], qxx[NX][NX], quu[NU][NU], qux[NU][NX], vb[NX][NU], va[NX][NX];
    *expected = 0.0;
    for (int i = 0; i < NX; ++i) {
        vx[i] = terminal_weight(i) * terminal_error(xs[STEPS], i);
        for (int j = 0; j < NX; ++j) {
            vxx[i][j] = i == j ? terminal_weight(i) : 0.0;
        }
    }
    for (int k = STEPS - 1; k >= 0; --k) {
        double (*a)[NX] = A[k], (*b)[NU] = B[k];
        for (int i = 0; i < NX; ++i) {  /* Vxx A and Vxx B (Vxx is symmetric: row i = column i) */
            for (int j = 0; j < NX; ++j) va[i][j] = column_dot(&vxx[0][0], NX, i, &a[0][0], NX, j);
            for (int j = 0; j < NU; ++j) vb[i][j] = column_dot(&vxx[0][0], NX, i, &b[0][0], NU, j);
        }
        for (int i = 0; i < NX; ++i) {  /* Qx = A^T Vx, Qxx = A^T Vxx A */
            qx[i] = column_dot(&a[0][0], NX, i, vx, 1, 0);
            for (int j = 0; j < NX; ++j) qxx[i][j] = column_dot(&a[0][0], NX, i, &va[0][0], NX, j);
        }
        for (int i = 0; i < NU; ++i) {  /* Qu = R u + B^T Vx, Quu = R + mu + B^T Vxx B, Qux = B^T Vxx A */
            qu[i] = control_weight * us[k][i] + column_dot(&b[0][0], NU, i, vx, 1, 0);
            for (int j = 0; j < NU; ++j)
                quu[i][j] = (i == j ? control_weight + mu : 0.0) + column_dot(&b[0][0], NU, i, &vb[0][0], NU, j);
            for (int j = 0; j < NX; ++j) qux[i][j] = column_dot(&b[0][0], NU, i, &va[0][0], NX, j);
        }
        if (!solve_gains(quu, qu, qux, k_ff[k], K_fb[k])) {
            return 0;
        }
        *expected += value_update(qx, qxx, qu, quu, qux, k_ff[k], K_fb[k], vx, vxx);
    }
    return 1;
}

/* Roll the controls out from x0 with step size alpha and the feedback gains; 0 on a status. */
static int forward(double alpha)
{
    memcpy(xs_new[0], xs[0], sizeof xs_new[0]);
    for (int k = 0; k < STEPS; ++k) {
        for (int i = 0; i < NU; ++i) {
            double u = us[k][i] + alpha * k_ff[k][i];
            for (int j = 0; j < NX; ++j) u += K_fb[k][i][j] * (xs_new[k][j] - xs[k][j]);
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
    double gravity[NQ];
    memset(xs, 0, sizeof xs);  /* at rest at q = 0 */
    puma560_gravity(xs[0], gravity);
    for (int k = 0; k < STEPS; ++k) {  /* start by holding the arm against gravity */
        memcpy(us[k], gravity, sizeof gravity);
        if (step(xs[k], us[k], xs[k + 1]) != 0) {
            fprintf(stderr, "forward dynamics failed in the first rollout\n");
            return 1;
        }
    }
    double current = cost(xs, us), mu = 1e-6;
    printf("iteration 0: cost %.9g\n", current);
    int iteration = 1;
    for (; iteration <= MAX_ITERATIONS; ++iteration) {
        for (int k = 0; k < STEPS; ++k) {
            if (linearize(xs[k], us[k], A[k], B[k]) != 0) {
                fprintf(stderr, "the mass matrix is singular at step %d\n", k);
                return 1;
            }
        }
        double expected;
        while (!backward(mu, &expected)) {
            mu *= 10.0;
            if (mu > 1e10) {
                fprintf(stderr, "Quu is not positive definite\n");
                return 1;
            }
        }
        double alpha = 1.0, trial = current;
        int accepted = 0;
        for (int tries = 0; tries < 12; ++tries, alpha *= 0.5) {
            if (forward(alpha) && (trial = cost(xs_new, us_new)) < current) {
                accepted = 1;
                break;
            }
        }
        if (!accepted) {
            mu *= 10.0;
            if (mu > 1e10) break;
            continue;
        }
        double decrease = current - trial;
        memcpy(xs, xs_new, sizeof xs);
        memcpy(us, us_new, sizeof us);
        current = trial;
        mu = mu > 1e-6 ? mu / 10.0 : mu;
        printf("iteration %d: cost %.9g (step %g, expected decrease %.3g)\n", iteration, current, alpha, -expected);
        if (decrease < 1e-5 * current) {
            break;
        }
    }
    double position = 0.0, velocity = 0.0;
    for (int i = 0; i < NQ; ++i) {
        position = fmax(position, fabs(xs[STEPS][i] - target[i]));
        velocity = fmax(velocity, fabs(xs[STEPS][NQ + i]));
    }
    int converged = position < 1e-3 && velocity < 1e-2;
    printf("final: cost %.9g after %d iterations; |q - q*| %.3g rad, |qd| %.3g rad/s: %s\n", current,
           iteration, position, velocity, converged ? "converged" : "NOT converged");
    return converged ? 0 : 1;
}
