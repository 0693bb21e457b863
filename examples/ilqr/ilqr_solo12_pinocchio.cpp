// The five functions ilqr_solo12.c calls, from Pinocchio instead of symdyn's generated C, with
// the same names and layouts (solo_dynamics.h): the same solver, linked against either.
//   solo_forward_dynamics_checked      aba
//   solo_forward_dynamics_derivatives  computeABADerivatives (ddq_dq, ddq_dv, Minv: its upper
//                                      triangle mirrored), row-major
//   solo_integrate                     integrate
//   solo_integrate_jacobians           dIntegrate, ARG0 and ARG1 (independent of q: at neutral)
//   solo_difference                    difference
// The model is Pinocchio's reading of solo12.urdf on its free-flyer (buildModelFromUrdf with
// JointModelFreeFlyer, in Python: solo12_ddp.py), saved with saveToText to the file the
// environment variable SOLO12_MODEL names, loaded once.
#include <cstdio>
#include <cstdlib>

#include <pinocchio/algorithm/aba-derivatives.hpp>
#include <pinocchio/algorithm/aba.hpp>
#include <pinocchio/algorithm/joint-configuration.hpp>
#include <pinocchio/serialization.hpp>

#include "solo_dynamics.h"

namespace {

using RowMajor = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;

struct Solo {
  pinocchio::Model model;
  pinocchio::Data data;
  Eigen::MatrixXd jq, jv;
  Eigen::VectorXd q0;
  Solo() {
    const char *path = std::getenv("SOLO12_MODEL");
    if (path == nullptr) {
      std::fprintf(stderr, "set SOLO12_MODEL to Solo-12's model saved by pinocchio.Model.saveToText\n");
      std::exit(2);
    }
    model.loadFromText(path);
    if (model.nq != SOLO_NQ || model.nv != SOLO_NV) {
      std::fprintf(stderr, "%s: nq %d, nv %d: not Solo-12's\n", path, model.nq, model.nv);
      std::exit(2);
    }
    data = pinocchio::Data(model);
    jq = Eigen::MatrixXd::Zero(model.nv, model.nv);
    jv = Eigen::MatrixXd::Zero(model.nv, model.nv);
    q0 = pinocchio::neutral(model);
  }
};

Solo &solo() {
  static Solo instance;
  return instance;
}

Eigen::Map<const Eigen::VectorXd> in(const double *x, int n) { return Eigen::Map<const Eigen::VectorXd>(x, n); }

}  // namespace

extern "C" int solo_forward_dynamics_checked(const double *q, const double *qd, const double *tau, double *qdd) {
  Solo &s = solo();
  pinocchio::aba(s.model, s.data, in(q, s.model.nq), in(qd, s.model.nv), in(tau, s.model.nv));
  Eigen::Map<Eigen::VectorXd>(qdd, s.model.nv) = s.data.ddq;
  return 0;
}

extern "C" int solo_forward_dynamics_derivatives(const double *q, const double *qd, const double *tau,
                                                 double *dqdd_dq, double *dqdd_dqd, double *Minv) {
  Solo &s = solo();
  const int n = s.model.nv;
  pinocchio::computeABADerivatives(s.model, s.data, in(q, s.model.nq), in(qd, n), in(tau, n));
  s.data.Minv.triangularView<Eigen::StrictlyLower>() = s.data.Minv.transpose().triangularView<Eigen::StrictlyLower>();
  Eigen::Map<RowMajor>(dqdd_dq, n, n) = s.data.ddq_dq;
  Eigen::Map<RowMajor>(dqdd_dqd, n, n) = s.data.ddq_dv;
  Eigen::Map<RowMajor>(Minv, n, n) = s.data.Minv;
  return 0;
}

extern "C" void solo_integrate(const double *q, const double *v, double *q_out) {
  Solo &s = solo();
  Eigen::Map<Eigen::VectorXd> out(q_out, s.model.nq);
  pinocchio::integrate(s.model, in(q, s.model.nq), in(v, s.model.nv), out);
}

extern "C" void solo_integrate_jacobians(const double *v, double *J_q, double *J_v) {
  Solo &s = solo();
  const int n = s.model.nv;
  pinocchio::dIntegrate(s.model, s.q0, in(v, n), s.jq, pinocchio::ARG0);
  pinocchio::dIntegrate(s.model, s.q0, in(v, n), s.jv, pinocchio::ARG1);
  Eigen::Map<RowMajor>(J_q, n, n) = s.jq;
  Eigen::Map<RowMajor>(J_v, n, n) = s.jv;
}

extern "C" void solo_difference(const double *q, const double *q1, double *v_out) {
  Solo &s = solo();
  Eigen::Map<Eigen::VectorXd> out(v_out, s.model.nv);
  pinocchio::difference(s.model, in(q, s.model.nq), in(q1, s.model.nq), out);
}
