/* The timing driver of benchmarks/harness.py.
 *
 * Usage: harness STATES.bin MODEL.txt PASSES
 *   STATES.bin: S states as doubles, four blocks: S x NQ (q), then S x N (qd, qdd, tau), the same
 *   arrays for every side (NQ = N unless the robot has a floating base: N + 1); MODEL.txt: the
 *   Pinocchio model (pinocchio::Model::saveToText).
 *
 * harness_cases.h (written by harness.py for one robot) includes the code under test and lists
 * the cases as X(function, side, call, result, whole), the call reading the state through Q, QD,
 * QDD, TAU (float copies QF, QDF, QDDF, TAUF when SYMDYN_FLOAT is defined, for symdyn's float C)
 * and runtime parameters through P (PF) and writing through OUT (OUTF), result the number it adds
 * to a checksum (so no call can be dropped).  Each case gets a pass function that calls it once
 * per state (whole = 0) or, for a batch function (whole = 1), once for all states, reading the
 * whole arrays q, qd, qdd, tau (qf, ...) and writing OUTB (OUTBF); either way it returns the
 * thread CPU time of the pass (CLOCK_THREAD_CPUTIME_ID) per state in ns.  After one untimed warm-up pass
 * of every case, the sides of one function take turns, pass after pass (their order rotated each
 * pass, so that no side always follows the same neighbour), so that drift in clock speed or
 * cache state reaches all sides alike.  Prints "time FUNCTION SIDE ns ns ..." (one number per
 * pass), "check NAME max_abs_difference max_abs_value" (Pinocchio's result against the CasADi
 * peer's on the first state; a batch function's results against the scalar function's on the
 * first states, HARNESS_BATCH_CHECKS) and "checksum X". */
#define _POSIX_C_SOURCE 199309L
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <math.h>

#include "harness_pinocchio.h"
#include "harness_cases.h"

static long S;
static double *q, *qd, *qdd, *tau, *OUT, *other;
static volatile double sink;
#ifdef HARNESS_PARAMETERS
static const double P[] = HARNESS_PARAMETERS;
#ifdef SYMDYN_FLOAT
static const float PF[] = HARNESS_PARAMETERS;
#endif
#endif
#ifdef HARNESS_BATCH_SIZE
static double *OUTB;  /* S x HARNESS_BATCH_SIZE: a batch function's results, state after state */
#ifdef SYMDYN_FLOAT
static float *OUTBF;
#endif
#endif
#ifdef SYMDYN_FLOAT
static float *qf, *qdf, *qddf, *tauf, *OUTF;
#define FLOAT_STATE const float *QF = qf + k * NQ, *QDF = qdf + k * N, *QDDF = qddf + k * N, *TAUF = tauf + k * N; \
    (void)QF; (void)QDF; (void)QDDF; (void)TAUF;

static void float_states(void) {
    long i;
    qf = malloc(sizeof(float) * S * (NQ + 3 * N));
    for (i = 0; i < S * (NQ + 3 * N); ++i) qf[i] = (float)q[i];
    qdf = qf + S * NQ;
    qddf = qdf + S * N;
    tauf = qddf + S * N;
    OUTF = calloc(HARNESS_OUT_SIZE, sizeof(float));
#ifdef HARNESS_BATCH_SIZE
    OUTBF = calloc((size_t)S * HARNESS_BATCH_SIZE, sizeof(float));
#endif
}
#else
#define FLOAT_STATE
#endif

static double cpu_ns(void) {
    struct timespec t;
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
    return t.tv_sec * 1e9 + t.tv_nsec;
}

#ifdef HARNESS_PEER
static const casadi_real *peer_arg[4];
static casadi_real *peer_res[1];
static casadi_int *peer_iw;
static casadi_real *peer_w;
#define PEER(f, a0, a1, a2) do { peer_arg[0] = a0; peer_arg[1] = a1; peer_arg[2] = a2; peer_res[0] = OUT; \
    f(peer_arg, peer_res, peer_iw, peer_w, 0); } while (0)

static void peer_workspace(void) {
    casadi_int n_arg, n_res, n_iw, n_w, max_iw = 1, max_w = 1;
#define X(f) f##_work(&n_arg, &n_res, &n_iw, &n_w); if (n_iw > max_iw) max_iw = n_iw; if (n_w > max_w) max_w = n_w;
    HARNESS_PEER_FUNCTIONS(X)
#undef X
    peer_iw = malloc(sizeof(casadi_int) * max_iw);
    peer_w = malloc(sizeof(casadi_real) * max_w);
}
#endif

#ifdef HARNESS_CASADI
/* symdyn's CasADi functions compiled from CasADi's C (symdyn generate --target casadi-c): the
 * calls in harness_cases.h fill casadi_arg and casadi_res, then call with these work vectors */
static const casadi_real *casadi_arg[8];
static casadi_real *casadi_res[8];
static casadi_int *casadi_iw;
static casadi_real *casadi_w;

static void casadi_workspace(void) {
    casadi_int n_arg, n_res, n_iw, n_w, max_iw = 1, max_w = 1;
#define X(f) f##_work(&n_arg, &n_res, &n_iw, &n_w); if (n_iw > max_iw) max_iw = n_iw; if (n_w > max_w) max_w = n_w; \
    if (n_arg > 8 || n_res > 8) { fprintf(stderr, #f ": more than 8 arguments\n"); exit(2); }
    HARNESS_CASADI_FUNCTIONS(X)
#undef X
    casadi_iw = malloc(sizeof(casadi_int) * max_iw);
    casadi_w = malloc(sizeof(casadi_real) * max_w);
}
#endif

#define X(fn, side, call, result, whole) static double pass_##fn##_##side(void) { \
    double acc = 0.0, t0 = cpu_ns(), t1; long k; \
    for (k = 0; k < (whole ? 1 : S); ++k) { \
        const double *Q = q + k * NQ, *QD = qd + k * N, *QDD = qdd + k * N, *TAU = tau + k * N; \
        FLOAT_STATE (void)Q; (void)QD; (void)QDD; (void)TAU; call; acc += result; } \
    t1 = cpu_ns(); sink += acc; return (t1 - t0) / S; }
HARNESS_CASES(X)
#undef X

struct timed_case { const char *function, *side; double (*pass)(void); };
static const struct timed_case cases[] = {
#define X(fn, side, call, result, whole) {#fn, #side, pass_##fn##_##side},
    HARNESS_CASES(X)
#undef X
};
#define NCASES ((int)(sizeof(cases) / sizeof(cases[0])))

static void cross_check(void) {
#ifdef HARNESS_PEER
    const double *Q = q, *QD = qd, *QDD = qdd, *TAU = tau;
    int n, i;
    double diff, scale;
    (void)Q; (void)QD; (void)QDD; (void)TAU;
#define X(name, pin_call, peer_call) pin_call; n = pin_result(#name, other); peer_call; \
    for (diff = 0, scale = 0, i = 0; i < n; ++i) { diff = fmax(diff, fabs(OUT[i] - other[i])); \
        scale = fmax(scale, fabs(other[i])); } \
    printf("check %s %.3g %.3g\n", #name, diff, scale);
    HARNESS_CHECKS(X)
#undef X
#endif
#ifdef HARNESS_BATCH_SIZE
    {  /* each batch function against the scalar function, on the first states */
        long k;
        int i;
        double diff, scale;
#define X(name, call, size, batch_call, batch_result) batch_call; \
        for (diff = 0, scale = 0, k = 0; k < S && k < 4; ++k) { \
        const double *Q = q + k * NQ, *QD = qd + k * N, *QDD = qdd + k * N, *TAU = tau + k * N; \
        FLOAT_STATE (void)Q; (void)QD; (void)QDD; (void)TAU; call; \
        for (i = 0; i < (size); ++i) { diff = fmax(diff, fabs((double)(batch_result)[k * (size) + i] - (double)SCALAR_RESULT[i])); \
            scale = fmax(scale, fabs((double)SCALAR_RESULT[i])); } } \
        printf("check batch_%s %.3g %.3g\n", #name, diff, scale);
        HARNESS_BATCH_CHECKS(X)
#undef X
    }
#endif
}

static int read_states(const char *path) {
    FILE *f = fopen(path, "rb");
    long bytes;
    if (!f) return 0;
    fseek(f, 0, SEEK_END);
    bytes = ftell(f);
    fseek(f, 0, SEEK_SET);
    S = bytes / (long)((NQ + 3 * N) * sizeof(double));
    if (S < 1 || bytes != S * (NQ + 3 * N) * (long)sizeof(double)) { fclose(f); return 0; }
    q = malloc(bytes);
    if (fread(q, 1, bytes, f) != (size_t)bytes) { fclose(f); return 0; }
    fclose(f);
    qd = q + S * NQ;
    qdd = qd + S * N;
    tau = qdd + S * N;
    return 1;
}

int main(int argc, char **argv) {
    int passes, r, g, end, j, i;
    double *times;
    if (argc != 4) { fprintf(stderr, "usage: %s STATES.bin MODEL.txt PASSES\n", argv[0]); return 2; }
    if (!read_states(argv[1])) { fprintf(stderr, "cannot read %d-joint states from %s\n", N, argv[1]); return 2; }
    /* pin_load gives nv when nq = nv, else -1 (a floating base: NQ = N + 1 here) */
    if (pin_load(argv[2]) != (NQ == N ? N : -1)) {
        fprintf(stderr, "%s is not a model with nq = %d, nv = %d\n", argv[2], NQ, N);
        return 2;
    }
    passes = atoi(argv[3]);
    OUT = calloc(HARNESS_OUT_SIZE, sizeof(double));
#ifdef SYMDYN_FLOAT
    float_states();
#endif
    other = calloc(HARNESS_OUT_SIZE, sizeof(double));
#ifdef HARNESS_BATCH_SIZE
    OUTB = calloc((size_t)S * HARNESS_BATCH_SIZE, sizeof(double));
#endif
#ifdef HARNESS_PEER
    peer_workspace();
#endif
#ifdef HARNESS_CASADI
    casadi_workspace();
#endif
    cross_check();
    for (i = 0; i < NCASES; ++i) cases[i].pass();  /* warm-up */
    times = malloc(sizeof(double) * passes * NCASES);
    for (r = 0; r < passes; ++r)
        for (g = 0; g < NCASES; g = end) {  /* the cases of one function: g .. end - 1 */
            for (end = g; end < NCASES && !strcmp(cases[end].function, cases[g].function); ++end) {}
            for (j = 0; j < end - g; ++j) {
                i = g + (j + r) % (end - g);
                times[r * NCASES + i] = cases[i].pass();
            }
        }
    for (i = 0; i < NCASES; ++i) {
        printf("time %s %s", cases[i].function, cases[i].side);
        for (r = 0; r < passes; ++r) printf(" %.2f", times[r * NCASES + i]);
        printf("\n");
    }
    printf("states %ld\nchecksum %.17g\n", S, (double)sink);
    return 0;
}
