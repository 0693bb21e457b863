// Pinocchio's side of benchmarks/harness.py for the tool kinematics (symdyn's forward_kinematics,
// jacobian, jacobian_dot_qd and kinematics): compiled as the part KIN of the harness's cached
// objects, beside benchmarks/harness_pinocchio.cpp (whose Model and Data it uses), the frame
// "tool" in Pinocchio's LOCAL_WORLD_ALIGNED convention (symdyn's).  Entry points, declared in
// harness_cases.h:
//   pin_framePlacement(q, out)                forwardKinematics + updateFramePlacement
//   pin_frameJacobian(q, out)                 computeFrameJacobian
//   pin_frameClassicalAcceleration(q, v, out) forwardKinematics(q, v, 0) + getFrameClassicalAcceleration
//   pin_framePlacementJacobian(q, out)        computeFrameJacobian, which leaves the frame's
//                                             placement in data.oMf too (symdyn's kinematics: T and J)
#include <pinocchio/multibody.hpp>
#include <pinocchio/algorithm/frames.hpp>
#include <pinocchio/algorithm/kinematics.hpp>

extern pinocchio::Model *harness_model;
extern pinocchio::Data *harness_data;
typedef Eigen::Map<const Eigen::VectorXd> In;

extern "C" {
void pin_framePlacement(const double *q, double *out);
void pin_frameJacobian(const double *q, double *out);
void pin_frameClassicalAcceleration(const double *q, const double *v, double *out);
void pin_framePlacementJacobian(const double *q, double *out);
}

static pinocchio::FrameIndex tool_frame() {
  static const pinocchio::FrameIndex tool = harness_model->getFrameId("tool");
  return tool;
}

static Eigen::Matrix<double, 6, Eigen::Dynamic> &jacobian() {
  static Eigen::Matrix<double, 6, Eigen::Dynamic> J = Eigen::Matrix<double, 6, Eigen::Dynamic>::Zero(6, harness_model->nv);
  return J;
}

void pin_framePlacement(const double *q, double *out) {
  pinocchio::forwardKinematics(*harness_model, *harness_data, In(q, harness_model->nq));
  out[0] = pinocchio::updateFramePlacement(*harness_model, *harness_data, tool_frame()).translation()[0];
}

void pin_frameJacobian(const double *q, double *out) {
  Eigen::Matrix<double, 6, Eigen::Dynamic> &J = jacobian();
  pinocchio::computeFrameJacobian(*harness_model, *harness_data, In(q, harness_model->nq), tool_frame(),
                                  pinocchio::LOCAL_WORLD_ALIGNED, J);
  out[0] = J(0, 0);
}

void pin_frameClassicalAcceleration(const double *q, const double *v, double *out) {
  static const Eigen::VectorXd zero = Eigen::VectorXd::Zero(harness_model->nv);
  pinocchio::forwardKinematics(*harness_model, *harness_data, In(q, harness_model->nq), In(v, harness_model->nv), zero);
  out[0] = pinocchio::getFrameClassicalAcceleration(*harness_model, *harness_data, tool_frame(),
                                                    pinocchio::LOCAL_WORLD_ALIGNED).linear()[0];
}

void pin_framePlacementJacobian(const double *q, double *out) {
  Eigen::Matrix<double, 6, Eigen::Dynamic> &J = jacobian();
  pinocchio::computeFrameJacobian(*harness_model, *harness_data, In(q, harness_model->nq), tool_frame(),
                                  pinocchio::LOCAL_WORLD_ALIGNED, J);
  out[0] = J(0, 0) + harness_data->oMf[tool_frame()].translation()[0];
}
