"""Pieces shared by the C timing benchmarks: the C timing loop and its output parser."""

import re

#: C prelude: includes, a monotonic clock, S seeded random states of N joints (q, qd, qdd) and
#: TIME(label, call): median of 7 repeats of 20000 calls, printed as "label ns".  The includes
#: of the code under test go in %(includes)s; N is %(dof)d.  Follow it with the body of main
#: and "return 0; }".
PRELUDE = r"""#define _POSIX_C_SOURCE 199309L
#include <stdio.h>
#include <stdlib.h>
#include <time.h>
%(includes)s
#define N %(dof)d
#define S 64
static double now(void) { struct timespec t; clock_gettime(CLOCK_MONOTONIC, &t); return t.tv_sec * 1e9 + t.tv_nsec; }
static int cmp(const void *a, const void *b) { double x = *(const double *)a, y = *(const double *)b; return (x > y) - (x < y); }
static double q[S][N], qd[S][N], qdd[S][N], out[N * N];
static volatile double sink;
#define TIME(label, call) do { double runs[7]; int r, i; for (r = 0; r < 7; ++r) { double t0 = now(); \
    for (i = 0; i < 20000; ++i) { int k = i %% S; call; sink += out[0]; } runs[r] = (now() - t0) / 20000; } \
    qsort(runs, 7, sizeof(double), cmp); printf("%%s %%.1f\n", label, runs[3]); } while (0)
int main(void) {
    int k, j;
    srand(1);
    for (k = 0; k < S; ++k) for (j = 0; j < N; ++j) {
        q[k][j] = 6.0 * rand() / RAND_MAX - 3; qd[k][j] = 2.0 * rand() / RAND_MAX - 1; qdd[k][j] = 2.0 * rand() / RAND_MAX - 1; }
"""


def parse(text):
    """{label: ns} from the harness's output."""
    return {m.group(1): float(m.group(2)) for m in re.finditer(r"^(\w+) ([\d.]+)$", text, re.M)}
