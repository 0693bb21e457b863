/*
 * The dense linear algebra both iLQR examples share (ilqr_puma560.c, ilqr_solo12.c): the
 * Cholesky factorization of Quu, the feedback gains of one step and the value function's update.
 * Include it after defining NX (the state's tangent dimension) and NU (the controls).
 */
#ifndef ILQR_COMMON_H
#define ILQR_COMMON_H

/* Cholesky of the symmetric positive definite m (NU x NU, in place, lower triangle); 0 if it is
 * not positive definite. */
static int cholesky(double m[NU][NU])
{
    for (int j = 0; j < NU; ++j) {
        double d = m[j][j];
        for (int k = 0; k < j; ++k) d -= m[j][k] * m[j][k];
        if (!(d > 0.0)) {
            return 0;
        }
        m[j][j] = sqrt(d);
        for (int i = j + 1; i < NU; ++i) {
            double s = m[i][j];
            for (int k = 0; k < j; ++k) s -= m[i][k] * m[j][k];
            m[i][j] = s / m[j][j];
        }
    }
    return 1;
}

/* x = m^-1 b with m's Cholesky factor l (b overwritten). */
static void cholesky_solve(double l[NU][NU], double *b)
{
    for (int i = 0; i < NU; ++i) {
        for (int k = 0; k < i; ++k) b[i] -= l[i][k] * b[k];
        b[i] /= l[i][i];
    }
    for (int i = NU - 1; i >= 0; --i) {
        for (int k = i + 1; k < NU; ++k) b[i] -= l[k][i] * b[k];
        b[i] /= l[i][i];
    }
}

/* The gains of one step, k = -Quu^-1 Qu (NU) and K = -Quu^-1 Qux (NU x NX), by the Cholesky
 * factor of Quu (quu is left as it is); 0 if Quu is not positive definite. */
static int solve_gains(double quu[NU][NU], const double *qu, double qux[NU][NX], double *k, double K[NU][NX])
{
    double factor[NU][NU];
    memcpy(factor, quu, sizeof factor);
    if (!cholesky(factor)) {
        return 0;
    }
    for (int i = 0; i < NU; ++i) k[i] = -qu[i];
    cholesky_solve(factor, k);
    for (int j = 0; j < NX; ++j) {
        double column[NU];
        for (int i = 0; i < NU; ++i) column[i] = -qux[i][j];
        cholesky_solve(factor, column);
        for (int i = 0; i < NU; ++i) K[i][j] = column[i];
    }
    return 1;
}

/* The value function one step earlier from the step's Q terms and its gains k, K:
 *   Vx = Qx + K^T (Quu k + Qu) + Qux^T k,   Vxx = Qxx + K^T (Quu K + Qux) + Qux^T K
 * (W = Quu K + Qux formed once, NU x NX; Vxx kept symmetric against rounding).  Returns
 * k^T Qu, the step's share of the expected decrease. */
static double value_update(const double *qx, double qxx[NX][NX], const double *qu, double quu[NU][NU],
                           double qux[NU][NX], const double *k, double K[NU][NX], double *vx, double vxx[NX][NX])
{
    static double w[NU][NX];
    double wk[NU], expected = 0.0;
    for (int r = 0; r < NU; ++r) {
        expected += k[r] * qu[r];
        wk[r] = qu[r];
        for (int j = 0; j < NX; ++j) w[r][j] = qux[r][j];
        for (int c = 0; c < NU; ++c) {
            wk[r] += quu[r][c] * k[c];
            for (int j = 0; j < NX; ++j) w[r][j] += quu[r][c] * K[c][j];
        }
    }
    for (int i = 0; i < NX; ++i) {
        double s = qx[i];
        for (int r = 0; r < NU; ++r) s += K[r][i] * wk[r] + qux[r][i] * k[r];
        vx[i] = s;
        for (int j = 0; j < NX; ++j) vxx[i][j] = qxx[i][j];
    }
    for (int r = 0; r < NU; ++r) {
        for (int i = 0; i < NX; ++i) {
            const double ki = K[r][i], qi = qux[r][i];
            for (int j = 0; j < NX; ++j) vxx[i][j] += ki * w[r][j] + qi * K[r][j];
        }
    }
    for (int i = 0; i < NX; ++i) {
        for (int j = 0; j < i; ++j) vxx[i][j] = vxx[j][i] = 0.5 * (vxx[i][j] + vxx[j][i]);
    }
    return expected;
}

#endif
