// Pinocchio's side of benchmarks/harness.py for the derivatives of the dynamics (symdyn's
// inverse_dynamics_derivatives, gravity_derivative, forward_dynamics_derivatives and
// mass_matrix_inverse): compiled as the part DERIV of the
// harness's cached objects, beside benchmarks/harness_pinocchio.cpp (whose Model and Data it
// uses).  Entry points, declared in harness_cases.h:
//   pin_rneaDerivatives(q, v, a, out)         computeRNEADerivatives: dtau/dq, dtau/dv (and dtau/da = M)
//   pin_gravityDerivatives(q, out)            computeGeneralizedGravityDerivatives
//   pin_abaDerivatives(q, v, tau, out)        computeABADerivatives: dqdd/dq, dqdd/dv and M^-1
//   pin_computeMinverse(q, out)               computeMinverse (its upper triangle, as Pinocchio fills it)
#include <pinocchio/multibody.hpp>
#include <pinocchio/algorithm/aba.hpp>
#include <pinocchio/algorithm/aba-derivatives.hpp>
#include <pinocchio/algorithm/rnea-derivatives.hpp>

extern pinocchio::Model *harness_model;
extern pinocchio::Data *harness_data;
typedef Eigen::Map<const Eigen::VectorXd> In;

extern "C" {
void pin_rneaDerivatives(const double *q, const double *v, const double *a, double *out);
void pin_gravityDerivatives(const double *q, double *out);
void pin_abaDerivatives(const double *q, const double *v, const double *tau, double *out);
void pin_computeMinverse(const double *q, double *out);
}

void pin_rneaDerivatives(const double *q, const double *v, const double *a, double *out) {
  const pinocchio::Model &model = *harness_model;
  pinocchio::computeRNEADerivatives(model, *harness_data, In(q, model.nq), In(v, model.nv), In(a, model.nv));
  out[0] = harness_data->dtau_dq(0, 0) + harness_data->dtau_dv(0, 0);
}

void pin_gravityDerivatives(const double *q, double *out) {
  static Eigen::MatrixXd partial = Eigen::MatrixXd::Zero(harness_model->nv, harness_model->nv);
  pinocchio::computeGeneralizedGravityDerivatives(*harness_model, *harness_data, In(q, harness_model->nq), partial);
  out[0] = partial(0, 0);
}

void pin_abaDerivatives(const double *q, const double *v, const double *tau, double *out) {
  const pinocchio::Model &model = *harness_model;
  pinocchio::computeABADerivatives(model, *harness_data, In(q, model.nq), In(v, model.nv), In(tau, model.nv));
  out[0] = harness_data->ddq_dq(0, 0) + harness_data->ddq_dv(0, 0) + harness_data->Minv(0, 0);
}

void pin_computeMinverse(const double *q, double *out) {
  pinocchio::computeMinverse(*harness_model, *harness_data, In(q, harness_model->nq));
  out[0] = harness_data->Minv(0, 0);
}
