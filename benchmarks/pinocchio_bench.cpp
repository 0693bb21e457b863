// Times Pinocchio's own C++ algorithms on a model saved by benchmarks/c_speed.py
// (pinocchio::Model::saveToText). Prints "name ns_per_call" lines (median of repeats).
#include <pinocchio/multibody.hpp>
#include <pinocchio/algorithm/aba.hpp>
#include <pinocchio/algorithm/crba.hpp>
#include <pinocchio/algorithm/rnea.hpp>
#include <pinocchio/algorithm/compute-all-terms.hpp>
#include <pinocchio/serialization.hpp>
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <vector>

#include "bench_timing.hpp"

int main(int argc, char **argv) {
  if (argc < 2) return 2;
  pinocchio::Model model;
  model.loadFromText(argv[1]);
  pinocchio::Data data(model);
  const int calls = 20000, states = 10000;  // distinct random states, cycled
  std::vector<Eigen::VectorXd> q, v, a;
  for (int k = 0; k < states; ++k) {
    q.push_back(Eigen::VectorXd::Random(model.nq)); v.push_back(Eigen::VectorXd::Random(model.nv));
    a.push_back(Eigen::VectorXd::Random(model.nv));
  }
  double sink = 0;
  std::printf("rnea %.1f\n", time_ns([&](int i) { sink += pinocchio::rnea(model, data, q[i % states], v[i % states], a[i % states])[0]; }, calls));
  std::printf("crba %.1f\n", time_ns([&](int i) { sink += pinocchio::crba(model, data, q[i % states])(0, 0); }, calls));
  std::printf("computeGeneralizedGravity %.1f\n", time_ns([&](int i) { sink += pinocchio::computeGeneralizedGravity(model, data, q[i % states])[0]; }, calls));
  std::printf("nonLinearEffects %.1f\n", time_ns([&](int i) { sink += pinocchio::nonLinearEffects(model, data, q[i % states], v[i % states])[0]; }, calls));
  std::printf("computeCoriolisMatrix %.1f\n", time_ns([&](int i) { sink += pinocchio::computeCoriolisMatrix(model, data, q[i % states], v[i % states])(0, 0); }, calls));
  std::printf("aba %.1f\n", time_ns([&](int i) { sink += pinocchio::aba(model, data, q[i % states], v[i % states], a[i % states])[0]; }, calls));
  std::fprintf(stderr, "checksum %g\n", sink);
  return 0;
}
