// Pinocchio's side of benchmarks/harness.py for the task-space functions (symdyn's task_space):
// compiled as the part TASK of the harness's cached objects, beside benchmarks/harness_pinocchio.cpp
// (whose Model and Data it uses).  Entry point, called from harness_cases.h:
//   void pin_taskSpace(const double *q, const double *v, double *out);
#include <pinocchio/multibody.hpp>
#include <pinocchio/algorithm/aba.hpp>
#include <pinocchio/algorithm/frames.hpp>
#include <pinocchio/algorithm/jacobian.hpp>
#include <pinocchio/algorithm/kinematics.hpp>
#include <pinocchio/algorithm/rnea.hpp>
#include <Eigen/Cholesky>

extern pinocchio::Model *harness_model;
extern pinocchio::Data *harness_data;
typedef Eigen::Map<const Eigen::VectorXd> In;

extern "C" void pin_taskSpace(const double *q, const double *v, double *out);

// Task-space dynamics of the frame "tool" (symdyn's task_space, whole pose): M^-1 by
// computeMinverse, J and Jdot qd from one forwardKinematics pass (LOCAL_WORLD_ALIGNED),
// h + c and c by nonLinearEffects and computeGeneralizedGravity, then Lambda = (J M^-1 J^T)^-1 by
// a Cholesky factorization, mu = Lambda (J M^-1 h - Jdot qd), Gx = Lambda J M^-1 c and
// Jbar = M^-1 J^T Lambda with Eigen.
static Eigen::MatrixXd task_Lambda, task_Jbar;
static Eigen::VectorXd task_mu, task_Gx;

void pin_taskSpace(const double *q, const double *v, double *out) {
  const pinocchio::Model &model = *harness_model;
  pinocchio::Data &data = *harness_data;
  const int n = model.nv;
  static const pinocchio::FrameIndex tool = model.getFrameId("tool");
  const In qv(q, n), vv(v, n);
  static const Eigen::VectorXd zero = Eigen::VectorXd::Zero(n);
  pinocchio::forwardKinematics(model, data, qv, vv, zero);
  pinocchio::computeJointJacobians(model, data);
  pinocchio::updateFramePlacement(model, data, tool);
  Eigen::Matrix<double, 6, Eigen::Dynamic> J(6, n);
  J.setZero();
  pinocchio::getFrameJacobian(model, data, tool, pinocchio::LOCAL_WORLD_ALIGNED, J);
  const pinocchio::Motion a = pinocchio::getFrameClassicalAcceleration(model, data, tool, pinocchio::LOCAL_WORLD_ALIGNED);
  Eigen::Matrix<double, 6, 1> jdot_qd;
  jdot_qd << a.linear(), a.angular();
  pinocchio::computeMinverse(model, data, qv);
  data.Minv.triangularView<Eigen::StrictlyLower>() = data.Minv.transpose().triangularView<Eigen::StrictlyLower>();
  const Eigen::VectorXd c = pinocchio::computeGeneralizedGravity(model, data, qv);
  const Eigen::VectorXd h = pinocchio::nonLinearEffects(model, data, qv, vv) - c;
  const Eigen::MatrixXd MinvJt = data.Minv * J.transpose();
  const Eigen::Matrix<double, 6, 6> A = J * MinvJt;
  const Eigen::LLT<Eigen::Matrix<double, 6, 6>> llt(A);
  task_Lambda = llt.solve(Eigen::Matrix<double, 6, 6>::Identity());
  task_mu = task_Lambda * (J * (data.Minv * h) - jdot_qd);
  task_Gx = task_Lambda * (J * (data.Minv * c));
  task_Jbar = MinvJt * task_Lambda;
  out[0] = task_Lambda(0, 0);
}
