/*
 * The dense linear algebra both iLQR examples share (ilqr_puma560.c, ilqr_solo12.c): the
 * Cholesky factorization of Quu and the feedback gains of one step.  Include it after defining
 * NX (the state's tangent dimension) and NU (the controls).
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

#endif
