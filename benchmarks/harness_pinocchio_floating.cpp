// Pinocchio's side of benchmarks/harness.py for a floating base (q has nq = nv + 1 entries: the
// free-flyer's position and quaternion, then the joints): rnea, nonLinearEffects,
// computeCoriolisMatrix and aba with q
// read as nq numbers.  Compiled as the part FLOAT of the harness's cached objects, beside
// benchmarks/harness_pinocchio.cpp (whose Model and Data it uses, and whose crba and
// computeGeneralizedGravity already read nq numbers).  Entry points, called from harness_cases.h:
//   void pin_rneaFF(const double *q, const double *v, const double *a, double *out);
//   void pin_nonLinearEffectsFF(const double *q, const double *v, double *out);
//   void pin_computeCoriolisMatrixFF(const double *q, const double *v, double *out);
//   void pin_abaFF_local(const double *q, const double *v, const double *tau, double *out);
//   void pin_abaFF_world(const double *q, const double *v, const double *tau, double *out);
#include <pinocchio/multibody.hpp>
#include <pinocchio/algorithm/aba.hpp>
#include <pinocchio/algorithm/rnea.hpp>

extern pinocchio::Model *harness_model;
extern pinocchio::Data *harness_data;
typedef Eigen::Map<const Eigen::VectorXd> In;

extern "C" {
void pin_rneaFF(const double *q, const double *v, const double *a, double *out);
void pin_nonLinearEffectsFF(const double *q, const double *v, double *out);
void pin_computeCoriolisMatrixFF(const double *q, const double *v, double *out);
void pin_abaFF_local(const double *q, const double *v, const double *tau, double *out);
void pin_abaFF_world(const double *q, const double *v, const double *tau, double *out);
}

void pin_rneaFF(const double *q, const double *v, const double *a, double *out) {
  const pinocchio::Model &model = *harness_model;
  out[0] = pinocchio::rnea(model, *harness_data, In(q, model.nq), In(v, model.nv), In(a, model.nv))[0];
}

void pin_nonLinearEffectsFF(const double *q, const double *v, double *out) {
  const pinocchio::Model &model = *harness_model;
  out[0] = pinocchio::nonLinearEffects(model, *harness_data, In(q, model.nq), In(v, model.nv))[0];
}

void pin_computeCoriolisMatrixFF(const double *q, const double *v, double *out) {
  const pinocchio::Model &model = *harness_model;
  out[0] = pinocchio::computeCoriolisMatrix(model, *harness_data, In(q, model.nq), In(v, model.nv))(0, 0);
}

void pin_abaFF_local(const double *q, const double *v, const double *tau, double *out) {
  const pinocchio::Model &model = *harness_model;
  out[0] = pinocchio::aba(model, *harness_data, In(q, model.nq), In(v, model.nv), In(tau, model.nv),
                          pinocchio::Convention::LOCAL)[0];
}

void pin_abaFF_world(const double *q, const double *v, const double *tau, double *out) {
  const pinocchio::Model &model = *harness_model;
  out[0] = pinocchio::aba(model, *harness_data, In(q, model.nq), In(v, model.nv), In(tau, model.nv),
                          pinocchio::Convention::WORLD)[0];
}
