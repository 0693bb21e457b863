// Pinocchio's side of benchmarks/harness.py for the whole robot's centre of mass and centroidal
// momentum (symdyn's center_of_mass, center_of_mass_jacobian, center_of_mass_bias,
// centroidal_momentum_matrix and centroidal_bias): compiled as the part CENT of the harness's
// cached objects, beside benchmarks/harness_pinocchio.cpp (whose Model and Data it uses); q is
// read as nq numbers (a floating base's too).  Entry points, declared in harness_cases.h:
//   pin_centerOfMass_subtrees(q, out)     centerOfMass(q) (every subtree's too: the default)
//   pin_centerOfMass_whole(q, out)        centerOfMass(q, computeSubtreeComs = false)
//   pin_jacobianCenterOfMass_subtrees(q, out)  jacobianCenterOfMass(q) (the default)
//   pin_jacobianCenterOfMass_whole(q, out)     jacobianCenterOfMass(q, computeSubtreeComs = false)
//   pin_centerOfMassBias(q, v, out)       centerOfMass(q, v, 0): data.acom[0]
//   pin_ccrba_ccrba(q, v, out)            ccrba(q, v): data.Ag (and hg)
//   pin_ccrba_map(q, v, out)              computeCentroidalMap(q): data.Ag only
// (the harness reports the faster of each pair: Pinocchio's fastest call for the quantity)
//   pin_centroidalBias(q, v, out)         computeCentroidalMomentumTimeVariation(q, v, 0): data.dhg
#include <pinocchio/multibody.hpp>
#include <pinocchio/algorithm/center-of-mass.hpp>
#include <pinocchio/algorithm/centroidal.hpp>

extern pinocchio::Model *harness_model;
extern pinocchio::Data *harness_data;
typedef Eigen::Map<const Eigen::VectorXd> In;

extern "C" {
void pin_centerOfMass_subtrees(const double *q, double *out);
void pin_centerOfMass_whole(const double *q, double *out);
void pin_jacobianCenterOfMass_subtrees(const double *q, double *out);
void pin_jacobianCenterOfMass_whole(const double *q, double *out);
void pin_centerOfMassBias(const double *q, const double *v, double *out);
void pin_ccrba_ccrba(const double *q, const double *v, double *out);
void pin_ccrba_map(const double *q, const double *v, double *out);
void pin_centroidalBias(const double *q, const double *v, double *out);
}

static const Eigen::VectorXd &zero() {
  static const Eigen::VectorXd z = Eigen::VectorXd::Zero(harness_model->nv);
  return z;
}

void pin_centerOfMass_subtrees(const double *q, double *out) {
  out[0] = pinocchio::centerOfMass(*harness_model, *harness_data, In(q, harness_model->nq))[0];
}

void pin_centerOfMass_whole(const double *q, double *out) {
  out[0] = pinocchio::centerOfMass(*harness_model, *harness_data, In(q, harness_model->nq), false)[0];
}

void pin_jacobianCenterOfMass_subtrees(const double *q, double *out) {
  out[0] = pinocchio::jacobianCenterOfMass(*harness_model, *harness_data, In(q, harness_model->nq))(0, 0);
}

void pin_jacobianCenterOfMass_whole(const double *q, double *out) {
  out[0] = pinocchio::jacobianCenterOfMass(*harness_model, *harness_data, In(q, harness_model->nq), false)(0, 0);
}

void pin_centerOfMassBias(const double *q, const double *v, double *out) {
  pinocchio::centerOfMass(*harness_model, *harness_data, In(q, harness_model->nq), In(v, harness_model->nv), zero());
  out[0] = harness_data->acom[0][0];
}

void pin_ccrba_ccrba(const double *q, const double *v, double *out) {
  out[0] = pinocchio::ccrba(*harness_model, *harness_data, In(q, harness_model->nq), In(v, harness_model->nv))(0, 0);
}

void pin_ccrba_map(const double *q, const double *v, double *out) {
  (void)v;
  out[0] = pinocchio::computeCentroidalMap(*harness_model, *harness_data, In(q, harness_model->nq))(0, 0);
}

void pin_centroidalBias(const double *q, const double *v, double *out) {
  out[0] = pinocchio::computeCentroidalMomentumTimeVariation(*harness_model, *harness_data, In(q, harness_model->nq),
                                                             In(v, harness_model->nv), zero()).linear()[0];
}
