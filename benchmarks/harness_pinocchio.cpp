// Pinocchio's side of benchmarks/harness.py (entry points: harness_pinocchio.h).  Compiled in
// parts, one object per part and flag set, with the flags of the symdyn C it is timed against
// (the harness caches the objects: Pinocchio's templates take 20-50 s per part to compile):
//   -DPART_LOAD  the Model and Data (pin_load, pin_result)
//   -DPART_RNEA  rnea, computeGeneralizedGravity, nonLinearEffects, computeCoriolisMatrix
//   -DPART_CRBA  crba in both conventions
//   -DPART_ABA   aba in both conventions
// The algorithms are Pinocchio's header templates, instantiated here: the pin wheel's headers do
// not declare them as explicit instantiations of its library.
#include <pinocchio/multibody.hpp>
#ifdef PART_LOAD
#include <pinocchio/serialization.hpp>
#endif
#ifdef PART_RNEA
#include <pinocchio/algorithm/rnea.hpp>
#endif
#ifdef PART_CRBA
#include <pinocchio/algorithm/crba.hpp>
#endif
#ifdef PART_ABA
#include <pinocchio/algorithm/aba.hpp>
#endif
#include <cstring>

#include "harness_pinocchio.h"

extern pinocchio::Model *harness_model;
extern pinocchio::Data *harness_data;
typedef Eigen::Map<const Eigen::VectorXd> In;

#ifdef PART_LOAD
pinocchio::Model *harness_model;
pinocchio::Data *harness_data;

int pin_load(const char *path) {
  harness_model = new pinocchio::Model();
  harness_model->loadFromText(path);
  harness_data = new pinocchio::Data(*harness_model);
  return harness_model->nq == harness_model->nv ? harness_model->nv : -1;
}

template <typename Derived> static int copy(const Eigen::MatrixBase<Derived> &value, double *out) {
  Eigen::Map<Eigen::MatrixXd>(out, value.rows(), value.cols()) = value;  // column-major
  return (int)(value.rows() * value.cols());
}

int pin_result(const char *name, double *out) {
  pinocchio::Data &data = *harness_data;
  if (!std::strcmp(name, "rnea")) return copy(data.tau, out);
  if (!std::strcmp(name, "computeGeneralizedGravity")) return copy(data.g, out);
  if (!std::strcmp(name, "nonLinearEffects")) return copy(data.nle, out);
  if (!std::strcmp(name, "computeCoriolisMatrix")) return copy(data.C, out);
  if (!std::strcmp(name, "rneaDerivatives")) {  // [dtau/dq dtau/dv], as the peer's one output
    Eigen::MatrixXd both(data.dtau_dq.rows(), 2 * data.dtau_dq.cols());
    both << data.dtau_dq, data.dtau_dv;
    return copy(both, out);
  }
  if (!std::strcmp(name, "abaDerivatives") || !std::strcmp(name, "computeMinverse")) {
    Eigen::MatrixXd minv = data.Minv;  // the upper triangle is Pinocchio's
    minv.triangularView<Eigen::StrictlyLower>() = minv.transpose().triangularView<Eigen::StrictlyLower>();
    if (name[0] == 'c') return copy(minv, out);
    Eigen::MatrixXd all(minv.rows(), 3 * minv.cols());  // [dqdd/dq dqdd/dv dqdd/dtau]
    all << data.ddq_dq, data.ddq_dv, minv;
    return copy(all, out);
  }
  if (!std::strncmp(name, "aba_", 4)) return copy(data.ddq, out);
  if (!std::strncmp(name, "crba", 4)) {
    Eigen::MatrixXd full = data.M;
    full.triangularView<Eigen::StrictlyLower>() = full.transpose().triangularView<Eigen::StrictlyLower>();
    return copy(full, out);
  }
  return 0;
}
#endif

#ifdef PART_RNEA
void pin_rnea(const double *q, const double *v, const double *a, double *out) {
  const int n = harness_model->nv;
  out[0] = pinocchio::rnea(*harness_model, *harness_data, In(q, n), In(v, n), In(a, n))[0];
}

void pin_computeGeneralizedGravity(const double *q, double *out) {
  out[0] = pinocchio::computeGeneralizedGravity(*harness_model, *harness_data, In(q, harness_model->nq))[0];
}

void pin_nonLinearEffects(const double *q, const double *v, double *out) {
  const int n = harness_model->nv;
  out[0] = pinocchio::nonLinearEffects(*harness_model, *harness_data, In(q, n), In(v, n))[0];
}

void pin_computeCoriolisMatrix(const double *q, const double *v, double *out) {
  const int n = harness_model->nv;
  out[0] = pinocchio::computeCoriolisMatrix(*harness_model, *harness_data, In(q, n), In(v, n))(0, 0);
}
#endif

#ifdef PART_CRBA
void pin_crba_local(const double *q, double *out) {
  out[0] = pinocchio::crba(*harness_model, *harness_data, In(q, harness_model->nq), pinocchio::Convention::LOCAL)(0, 0);
}

void pin_crba_world(const double *q, double *out) {
  out[0] = pinocchio::crba(*harness_model, *harness_data, In(q, harness_model->nq), pinocchio::Convention::WORLD)(0, 0);
}
#endif

#ifdef PART_ABA
void pin_aba_local(const double *q, const double *v, const double *tau, double *out) {
  const int n = harness_model->nv;
  out[0] = pinocchio::aba(*harness_model, *harness_data, In(q, n), In(v, n), In(tau, n), pinocchio::Convention::LOCAL)[0];
}

void pin_aba_world(const double *q, const double *v, const double *tau, double *out) {
  const int n = harness_model->nv;
  out[0] = pinocchio::aba(*harness_model, *harness_data, In(q, n), In(v, n), In(tau, n), pinocchio::Convention::WORLD)[0];
}
#endif
