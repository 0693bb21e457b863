/* Pinocchio's side of benchmarks/harness.py: C entry points around Pinocchio's C++ algorithms
 * (benchmarks/harness_pinocchio.cpp).  pin_load reads a model saved by
 * pinocchio::Model::saveToText and returns its nv (or -1 when nq != nv).  Each algorithm call
 * leaves its result where Pinocchio leaves it (in its Data) and copies the first number to
 * out[0], for the harness's checksum.  pin_result(name, out) copies the whole result of the
 * last call of pin_<name> to out, column-major (CasADi's order; crba's upper triangle mirrored),
 * and returns how many numbers it wrote: the harness's cross-check against the CasADi peer. */
#ifndef HARNESS_PINOCCHIO_H
#define HARNESS_PINOCCHIO_H
#ifdef __cplusplus
extern "C" {
#endif
int pin_load(const char *path);
void pin_rnea(const double *q, const double *v, const double *a, double *out);
void pin_computeGeneralizedGravity(const double *q, double *out);
void pin_nonLinearEffects(const double *q, const double *v, double *out);
void pin_computeCoriolisMatrix(const double *q, const double *v, double *out);
void pin_crba_local(const double *q, double *out);
void pin_crba_world(const double *q, double *out);
void pin_aba_local(const double *q, const double *v, const double *tau, double *out);
void pin_aba_world(const double *q, const double *v, const double *tau, double *out);
int pin_result(const char *name, double *out);
#ifdef __cplusplus
}
#endif
#endif
