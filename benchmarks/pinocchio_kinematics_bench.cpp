// Times Pinocchio's C++ kinematics of one frame on a model saved by benchmarks/kinematics_speed.py
// (pinocchio::Model::saveToText).  Usage: pinkin MODEL.txt FRAME [STATES].  Prints "name
// ns_per_call" lines (median of 7 repeats of 2 x STATES calls cycling over STATES distinct random
// states, default 10,000; thread CPU time, bench_timing.hpp).
#include <pinocchio/multibody.hpp>
#include <pinocchio/algorithm/frames.hpp>
#include <pinocchio/algorithm/jacobian.hpp>
#include <pinocchio/algorithm/kinematics.hpp>
#include <pinocchio/serialization.hpp>
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <vector>

#include "bench_timing.hpp"

int main(int argc, char **argv) {
  if (argc < 3) return 2;
  pinocchio::Model model;
  model.loadFromText(argv[1]);
  pinocchio::Data data(model);
  const pinocchio::FrameIndex frame = model.getFrameId(argv[2]);
  if (frame >= model.frames.size()) return 3;
  const int states = argc > 3 ? std::atoi(argv[3]) : 10000, calls = 2 * states;
  if (states < 1) return 2;
  std::vector<Eigen::VectorXd> q, v;
  for (int k = 0; k < states; ++k) {
    q.push_back(pinocchio::randomConfiguration(model, -Eigen::VectorXd::Ones(model.nq), Eigen::VectorXd::Ones(model.nq)));
    v.push_back(Eigen::VectorXd::Random(model.nv));
  }
  const Eigen::VectorXd zero = Eigen::VectorXd::Zero(model.nv);
  pinocchio::Data::Matrix6x J(6, model.nv);
  double sink = 0;
  const auto lwa = pinocchio::LOCAL_WORLD_ALIGNED;
  // as the issue states it: joint Jacobians + frame placements, then the frame's Jacobian
  std::printf("computeJointJacobians_framesForwardKinematics %.1f\n", time_ns([&](int i) {
    pinocchio::computeJointJacobians(model, data, q[i % states]);
    pinocchio::framesForwardKinematics(model, data, q[i % states]);
    J.setZero();
    pinocchio::getFrameJacobian(model, data, frame, lwa, J);
    sink += J(0, 0) + data.oMf[frame].translation()[0]; }, calls));
  // Pinocchio's leanest way to the same two results
  std::printf("computeFrameJacobian %.1f\n", time_ns([&](int i) {
    J.setZero();
    pinocchio::computeFrameJacobian(model, data, q[i % states], frame, lwa, J);
    sink += J(0, 0) + data.oMf[frame].translation()[0]; }, calls));
  std::printf("updateFramePlacement %.1f\n", time_ns([&](int i) {
    pinocchio::forwardKinematics(model, data, q[i % states]);
    sink += pinocchio::updateFramePlacement(model, data, frame).translation()[0]; }, calls));
  std::printf("getFrameClassicalAcceleration %.1f\n", time_ns([&](int i) {
    pinocchio::forwardKinematics(model, data, q[i % states], v[i % states], zero);
    sink += pinocchio::getFrameClassicalAcceleration(model, data, frame, lwa).linear()[0]; }, calls));
  std::fprintf(stderr, "checksum %g\n", sink);
  return 0;
}
