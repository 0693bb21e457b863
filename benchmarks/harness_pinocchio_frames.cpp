// Pinocchio's side of benchmarks/harness.py for named frames (symdyn's frame_poses,
// frame_jacobians, frame_jacobian_dot_v and frame_kinematics): compiled as the part FRAMES of the
// harness's cached objects, beside benchmarks/harness_pinocchio.cpp (whose Model and Data it
// uses).  The frames are the model's frames named "frame_..." (symdyn's build_model adds one per
// frame of the robot), in LOCAL_WORLD_ALIGNED; q is read as nq numbers.  Entry points, declared in
// harness_cases.h:
//   pin_framePoses_all(q, out)        framesForwardKinematics (every frame of the model)
//   pin_framePoses_each(q, out)       forwardKinematics + updateFramePlacement per frame (the named frames only)
//   pin_frameJacobians_all(q, out)    computeJointJacobians + updateFramePlacements + getFrameJacobian per frame
//   pin_frameJacobians_each(q, out)   computeFrameJacobian per frame (the joints supporting it only)
// (the harness reports the faster of each pair: Pinocchio's fastest composition for the task)
//   pin_frameJacobianDotV(q, v, out)  forwardKinematics(q, v, 0) + getFrameClassicalAcceleration per frame
//   pin_frameKinematics(q, v, out)    forwardKinematics(q, v, 0) + computeJointJacobians + updateFramePlacements
//                                     + getFrameJacobian and getFrameClassicalAcceleration per frame
#include <vector>
#include <pinocchio/multibody.hpp>
#include <pinocchio/algorithm/frames.hpp>
#include <pinocchio/algorithm/jacobian.hpp>
#include <pinocchio/algorithm/kinematics.hpp>

extern pinocchio::Model *harness_model;
extern pinocchio::Data *harness_data;
typedef Eigen::Map<const Eigen::VectorXd> In;

extern "C" {
void pin_framePoses_all(const double *q, double *out);
void pin_framePoses_each(const double *q, double *out);
void pin_frameJacobians_all(const double *q, double *out);
void pin_frameJacobians_each(const double *q, double *out);
void pin_frameJacobianDotV(const double *q, const double *v, double *out);
void pin_frameKinematics(const double *q, const double *v, double *out);
}

static const std::vector<pinocchio::FrameIndex> &frames() {
  static std::vector<pinocchio::FrameIndex> ids;
  if (ids.empty())
    for (pinocchio::FrameIndex k = 0; k < harness_model->frames.size(); ++k)
      if (harness_model->frames[k].name.rfind("frame_", 0) == 0) ids.push_back(k);
  return ids;
}

static Eigen::Matrix<double, 6, Eigen::Dynamic> &jacobian() {
  static Eigen::Matrix<double, 6, Eigen::Dynamic> J = Eigen::Matrix<double, 6, Eigen::Dynamic>::Zero(6, harness_model->nv);
  return J;
}

static const Eigen::VectorXd &zero() {
  static const Eigen::VectorXd z = Eigen::VectorXd::Zero(harness_model->nv);
  return z;
}

void pin_framePoses_all(const double *q, double *out) {
  pinocchio::framesForwardKinematics(*harness_model, *harness_data, In(q, harness_model->nq));
  out[0] = harness_data->oMf[frames()[0]].translation()[0];
}

void pin_framePoses_each(const double *q, double *out) {
  pinocchio::forwardKinematics(*harness_model, *harness_data, In(q, harness_model->nq));
  double sum = 0.0;
  for (pinocchio::FrameIndex id : frames())
    sum += pinocchio::updateFramePlacement(*harness_model, *harness_data, id).translation()[0];
  out[0] = sum;
}

static double jacobians(void) {
  Eigen::Matrix<double, 6, Eigen::Dynamic> &J = jacobian();
  double sum = 0.0;
  for (pinocchio::FrameIndex id : frames()) {
    J.setZero();
    pinocchio::getFrameJacobian(*harness_model, *harness_data, id, pinocchio::LOCAL_WORLD_ALIGNED, J);
    sum += J(0, 0);
  }
  return sum;
}

static double accelerations(void) {
  double sum = 0.0;
  for (pinocchio::FrameIndex id : frames())
    sum += pinocchio::getFrameClassicalAcceleration(*harness_model, *harness_data, id,
                                                    pinocchio::LOCAL_WORLD_ALIGNED).linear()[0];
  return sum;
}

void pin_frameJacobians_all(const double *q, double *out) {
  pinocchio::computeJointJacobians(*harness_model, *harness_data, In(q, harness_model->nq));
  pinocchio::updateFramePlacements(*harness_model, *harness_data);
  out[0] = jacobians();
}

void pin_frameJacobians_each(const double *q, double *out) {
  Eigen::Matrix<double, 6, Eigen::Dynamic> &J = jacobian();
  double sum = 0.0;
  for (pinocchio::FrameIndex id : frames()) {
    J.setZero();
    pinocchio::computeFrameJacobian(*harness_model, *harness_data, In(q, harness_model->nq), id,
                                    pinocchio::LOCAL_WORLD_ALIGNED, J);
    sum += J(0, 0);
  }
  out[0] = sum;
}

void pin_frameJacobianDotV(const double *q, const double *v, double *out) {
  pinocchio::forwardKinematics(*harness_model, *harness_data, In(q, harness_model->nq), In(v, harness_model->nv), zero());
  out[0] = accelerations();
}

void pin_frameKinematics(const double *q, const double *v, double *out) {
  pinocchio::forwardKinematics(*harness_model, *harness_data, In(q, harness_model->nq), In(v, harness_model->nv), zero());
  pinocchio::computeJointJacobians(*harness_model, *harness_data, In(q, harness_model->nq));
  pinocchio::updateFramePlacements(*harness_model, *harness_data);
  out[0] = jacobians() + accelerations();
}
