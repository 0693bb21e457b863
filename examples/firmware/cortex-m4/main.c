/*
 * A generated float header on a Cortex-M4: inverse dynamics, forward dynamics with its status,
 * the mass matrix and the kinematics at a few fixed states, every number printed exactly (its
 * bits) and as a decimal; then the instructions each function takes, measured with SysTick.
 *
 * Build: make (puma560) or make ROBOT=panda; run: make run (QEMU's mps2-an386 board).
 * ROBOT_HEADER, ROBOT (the generated files' prefix) and ROBOT_MACROS (the prefix of the header's
 * macros, in capitals) come from the Makefile, and what the header has: ROBOT_FLOATING (a
 * floating base: q holds NQ numbers, the base's position and quaternion first), ROBOT_TOOL (the
 * tool's pose and Jacobian of a chain) and ROBOT_FRAMES (the frames' poses, Jacobians and J-dot v
 * of a tree or a floating base, given with --frames).
 */

#include <math.h>
#include <stdint.h>

#include ROBOT_HEADER
#include "report.h"

#define CAT2(a, b) a##_##b
#define CAT(a, b) CAT2(a, b)
#define FN(name) CAT(ROBOT, name)
#define MACRO(name) CAT(ROBOT_MACROS, name)
#define N MACRO(DOF)
#ifdef ROBOT_FLOATING
#define NQ MACRO(NQ)
#define BASE_Q 7 /* the base's position and quaternion come first in q */
#else
#define NQ N
#define BASE_Q 0
#endif
#if defined(ROBOT_TOOL)
#define NPOSES 16
#define NJ (6 * N)
#define NA 6
#elif defined(ROBOT_FRAMES)
#define NPOSES (16 * MACRO(NFRAMES))
#define NJ (6 * MACRO(NFRAMES) * N)
#define NA (6 * MACRO(NFRAMES))
#else
#define NPOSES 1
#define NJ 1
#define NA 1
#endif
#define TEXT2(x) #x
#define TEXT(x) TEXT2(x)

typedef FN(real) real;

#if MACRO(NP) != 0
#error "this example calls robots without runtime parameters: pass your values of p (the header lists them) and remove this line"
#endif

/* The states: the same formulas on every machine (float arithmetic, no libm), so that a host
 * can recompute them; state 3 has an infinite velocity (forward dynamics: status 2). */
#define STATES 4

static void make_state(int k, real *q, real *qd, real *qdd, real *tau)
{
    int i;
    for (i = 0; i < NQ; ++i) {
        q[i] = 0.25F * (real)(i + 1 - BASE_Q) - 0.4F * (real)k + 0.1F;
    }
    if (BASE_Q) { /* a quaternion of any nonzero length (the functions divide by it) */
        q[3] = 0.1F * (real)k;
        q[4] = -0.2F;
        q[5] = 0.3F;
        q[6] = 0.9F - 0.1F * (real)k;
    }
    for (i = 0; i < N; ++i) {
        const real x = (real)(i + 1);
        qd[i] = 0.3F - 0.15F * x + 0.2F * (real)k;
        qdd[i] = 0.5F * x - 1.0F + 0.25F * (real)k;
        tau[i] = 2.0F - 1.5F * x + (real)k;
    }
    if (k == 3) {
        qd[0] = INFINITY;
    }
}

static void report_vector(const char *tag, const real *values, int count)
{
    int i;
    for (i = 0; i < count; ++i) {
        report_float(tag, i, values[i]);
    }
}

/* SysTick counts down at the core clock (QEMU: the board's 25 MHz in virtual time, which with
 * -icount shift=0 advances 1 ns per instruction) */
#define SYST_CSR (*(volatile uint32_t *)0xE000E010u)
#define SYST_RVR (*(volatile uint32_t *)0xE000E014u)
#define SYST_CVR (*(volatile uint32_t *)0xE000E018u)
#define REPEATS 16

static uint32_t ticks_since(uint32_t start)
{
    return (start - SYST_CVR) & 0x00FFFFFFu;
}

/* ticks of a loop of 2 * count instructions (subs, bne), to turn ticks into instructions */
static uint32_t calibration_ticks(uint32_t count)
{
    const uint32_t start = SYST_CVR;
    __asm__ volatile ("1: subs %0, %0, #1\n\tbne 1b" : "+r"(count) : : "cc");
    return ticks_since(start);
}

static void report_cost(const char *name, uint32_t ticks, uint64_t instructions_per_tick_x1000)
{
    const uint64_t instructions = (uint64_t)ticks * instructions_per_tick_x1000 / (1000u * REPEATS);
    report_text("instructions ");
    report_text(name);
    report_text(" ");
    report_int((int)instructions);
    report_text("\n");
}

static void measure(void)
{
    static real q[NQ], qd[N], qdd[N], tau[N], out[N], D[N * N], T[NPOSES], J[NJ], a[NA];
    const uint32_t loop = 200000u;
    uint64_t per_tick_x1000;
    uint32_t start, ticks;
    int r, status = 0;
    SYST_RVR = 0x00FFFFFFu;
    SYST_CVR = 0u;
    SYST_CSR = 5u; /* enabled, core clock, no interrupt */
    ticks = calibration_ticks(loop);
    per_tick_x1000 = ticks ? (uint64_t)2u * loop * 1000u / ticks : 0u;
    make_state(1, q, qd, qdd, tau);
#define TIME(name, call) \
    start = SYST_CVR; \
    for (r = 0; r < REPEATS; ++r) { call; } \
    report_cost(name, ticks_since(start), per_tick_x1000)
    TIME("inverse_dynamics", FN(inverse_dynamics)(q, qd, qdd, out));
    TIME("mass_matrix", FN(mass_matrix)(q, D));
    TIME("gravity", FN(gravity)(q, out));
    TIME("forward_dynamics_checked", status |= FN(forward_dynamics_checked)(q, qd, tau, out));
#if defined(ROBOT_TOOL)
    TIME("forward_kinematics", FN(forward_kinematics)(q, T));
    TIME("jacobian", FN(jacobian)(q, J));
    TIME("kinematics", FN(kinematics)(q, T, J));
    (void)a;
#elif defined(ROBOT_FRAMES)
    TIME("frame_poses", FN(frame_poses)(q, T));
    TIME("frame_jacobians", FN(frame_jacobians)(q, J));
    TIME("frame_kinematics", FN(frame_kinematics)(q, qd, T, J, a));
#else
    (void)T, (void)J, (void)a;
#endif
#undef TIME
    if (status != 0) {
        report_text("timing state: unexpected forward dynamics status\n");
    }
}

int main(void)
{
    static real q[NQ], qd[N], qdd[N], tau[N], out[N], D[N * N], T[NPOSES], J[NJ], a[NA];
    int k, status;
    report_text("robot " TEXT(ROBOT) "\n");
    for (k = 0; k < STATES; ++k) {
        report_text("state ");
        report_int(k);
        report_text("\n");
        make_state(k, q, qd, qdd, tau);
        report_vector("in q", q, NQ);
        report_vector("in qd", qd, N);
        report_vector("in qdd", qdd, N);
        report_vector("in tau", tau, N);
        if (k < 3) {
            FN(inverse_dynamics)(q, qd, qdd, out);
            report_vector("out inverse_dynamics", out, N);
            FN(mass_matrix)(q, D);
            report_vector("out mass_matrix", D, N * N);
#if defined(ROBOT_TOOL)
            FN(forward_kinematics)(q, T);
            report_vector("out forward_kinematics", T, 16);
            FN(jacobian)(q, J);
            report_vector("out jacobian", J, 6 * N);
            (void)a;
#elif defined(ROBOT_FRAMES)
            FN(frame_kinematics)(q, qd, T, J, a);
            report_vector("out frame_poses", T, NPOSES);
            report_vector("out frame_jacobians", J, NJ);
            report_vector("out frame_jacobian_dot_v", a, NA);
#else
            (void)T, (void)J, (void)a;
#endif
        }
        /* forward dynamics: 0 solved; 1 the mass matrix is singular at q; 2 an input or a result
           is not finite. On a nonzero status qdd is left as it was. */
        status = FN(forward_dynamics_checked)(q, qd, tau, out);
        report_text("status forward_dynamics ");
        report_int(status);
        report_text("\n");
        if (status == 0) {
            report_vector("out forward_dynamics", out, N);
        }
    }
    measure();
    report_text("done\n");
    return 0;
}
