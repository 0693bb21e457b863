// Times a platform robot's closed-loop dynamics: Pinocchio's C++ (the model and loop closures
// written by benchmarks/parallel_speed.py) against symdyn's generated C (linked in), in the same
// run, over the same states.  Prints "name ns_per_call" lines (median of 7 repeats of CALLS calls
// cycling over the states) and writes every state's results to a binary file for the accuracy
// comparison.
//
//   pinocchio_platform_bench MODEL.txt CLOSURES.txt STATES.bin RESULTS.bin MODEL_NO_ARMATURE.txt
//
// MODEL.txt has a 1e-9 armature on the legs' joints (Pinocchio's constraint solvers factorize the
// joint-space mass matrix, which the legs' massless crosses leave singular); inverse dynamics uses
// MODEL_NO_ARMATURE.txt, the same model without it (as the generated functions).
//
// Pinocchio's inverse dynamics: rnea of the open tree, the constraint Jacobian, and the square
// system [Jc^T S] [lambda; phi] = tau (partial-pivoting LU).  Its forward dynamics:
// constraintDynamics (initConstraintDynamics once, proximal settings 1e-12 / 1e-12 / 10 iterations)
// and the loop-constrained ABA (lcaba, settings below).  Both are given the legs' joint values: Pinocchio has no
// leg inverse kinematics, symdyn's functions compute theirs from the platform's pose.
#include <pinocchio/multibody.hpp>
#include <pinocchio/algorithm/rnea.hpp>
#include <pinocchio/algorithm/jacobian.hpp>
#include <pinocchio/algorithm/constrained-dynamics.hpp>
#include <pinocchio/algorithm/loop-constrained-aba.hpp>
#include <pinocchio/serialization.hpp>
#include <Eigen/LU>
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <fstream>
#include <vector>

// PLATFORM_HEADER ("NAME_dynamics.h"), PLATFORM_inverse_dynamics and PLATFORM_forward_dynamics
// are defined on the command line (benchmarks/parallel_speed.py)
extern "C" {
#include PLATFORM_HEADER
}

// lcaba's proximal settings: mu 1e-6 (its documentation's typical value; 1e-12 left errors of
// 1e-5 to 1e-2 in the accelerations here) and up to 50 iterations to an accuracy of 1e-12
#ifndef LCABA_MU
#define LCABA_MU 1e-6
#endif
#ifndef LCABA_ITERATIONS
#define LCABA_ITERATIONS 50
#endif

#include "bench_timing.hpp"

using Constraints = PINOCCHIO_STD_VECTOR_WITH_EIGEN_ALLOCATOR(pinocchio::RigidConstraintModel);
using ConstraintDatas = PINOCCHIO_STD_VECTOR_WITH_EIGEN_ALLOCATOR(pinocchio::RigidConstraintData);

static pinocchio::SE3 read_se3(std::istream &in) {
  Eigen::Matrix3d R;
  Eigen::Vector3d t;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) in >> R(i, j);
  for (int i = 0; i < 3; ++i) in >> t(i);
  return pinocchio::SE3(R, t);
}

int main(int argc, char **argv) {
  if (argc < 6) return 2;
  pinocchio::Model model, model_id;
  model.loadFromText(argv[1]);
  model_id.loadFromText(argv[5]);
  pinocchio::Data data(model), data_id(model_id);
  const int nq = model.nq, nv = model.nv;

  std::ifstream closures(argv[2]);
  int count = 0;
  closures >> count;
  Constraints cmodels;
  std::vector<int> actuated(6);
  for (int k = 0; k < count; ++k) {
    int j1, j2;
    closures >> j1 >> j2;
    pinocchio::SE3 p1 = read_se3(closures), p2 = read_se3(closures);
    cmodels.push_back(pinocchio::RigidConstraintModel(pinocchio::CONTACT_6D, model, j1, p1, j2, p2, pinocchio::LOCAL));
  }
  for (int k = 0; k < 6; ++k) closures >> actuated[k];
  ConstraintDatas cdatas;
  for (auto &cm : cmodels) cdatas.push_back(pinocchio::RigidConstraintData(cm));

  // states: pose 7, twist 6, twist_rate 6, phi 6, q nq, v nv, a nv (doubles)
  std::ifstream bin(argv[3], std::ios::binary);
  const int record = 25 + nq + 2 * nv;
  std::vector<double> all;
  {
    bin.seekg(0, std::ios::end);
    const std::streamoff bytes = bin.tellg();
    bin.seekg(0);
    all.resize(bytes / sizeof(double));
    bin.read(reinterpret_cast<char *>(all.data()), bytes);
  }
  const int states = (int)(all.size() / record);
  std::vector<Eigen::VectorXd> q(states), v(states), a(states), tau(states);
  std::vector<const double *> pose(states), twist(states), rate(states), phi(states);
  Eigen::MatrixXd S = Eigen::MatrixXd::Zero(nv, 6);
  for (int k = 0; k < 6; ++k) S(actuated[k], k) = 1.0;
  for (int s = 0; s < states; ++s) {
    const double *r = all.data() + (size_t)s * record;
    pose[s] = r; twist[s] = r + 7; rate[s] = r + 13; phi[s] = r + 19;
    q[s] = Eigen::Map<const Eigen::VectorXd>(r + 25, nq);
    v[s] = Eigen::Map<const Eigen::VectorXd>(r + 25 + nq, nv);
    a[s] = Eigen::Map<const Eigen::VectorXd>(r + 25 + nq + nv, nv);
    tau[s] = S * Eigen::Map<const Eigen::VectorXd>(phi[s], 6);
  }

  const int nc = 6 * count;
  Eigen::MatrixXd Jc = Eigen::MatrixXd::Zero(nc, nv), system(nv, nc + 6);
  system.rightCols(6) = S;
  Eigen::PartialPivLU<Eigen::MatrixXd> lu(nv);
  Eigen::VectorXd solution(nv);
  auto pin_inverse = [&](int s) {
    const Eigen::VectorXd &t = pinocchio::rnea(model_id, data_id, q[s], v[s], a[s]);
    pinocchio::computeJointJacobians(model_id, data_id, q[s]);
    Jc.setZero();
    pinocchio::getConstraintsJacobian(model_id, data_id, cmodels, cdatas, Jc);
    system.leftCols(nc) = Jc.transpose();
    lu.compute(system);
    solution = lu.solve(t);
    return solution[nv - 1];
  };
  pinocchio::initConstraintDynamics(model, data, cmodels, cdatas);
  pinocchio::ProximalSettings prox(1e-12, 1e-12, 10);
  auto pin_forward = [&](int s) {
    return pinocchio::constraintDynamics(model, data, q[s], v[s], tau[s], cmodels, cdatas, prox)[0];
  };
  pinocchio::Data data_lc(model);
  ConstraintDatas cdatas_lc;
  for (auto &cm : cmodels) cdatas_lc.push_back(pinocchio::RigidConstraintData(cm));
  pinocchio::computeJointMinimalOrdering(model, data_lc, cmodels);
  pinocchio::ProximalSettings prox_lc(1e-12, LCABA_MU, LCABA_ITERATIONS);
  auto pin_lcaba = [&](int s) {
    return pinocchio::lcaba(model, data_lc, q[s], v[s], tau[s], cmodels, cdatas_lc, prox_lc)[0];
  };
  double out[12];
  auto ours_inverse = [&](int s) {
    PLATFORM_inverse_dynamics(pose[s], twist[s], rate[s], out);
    return out[0];
  };
  auto ours_forward = [&](int s) {
    PLATFORM_forward_dynamics(pose[s], twist[s], phi[s], out, out + 6);
    return out[0];
  };

  // results of every state (for the accuracy comparison): Pinocchio's phi and a (both
  // algorithms), symdyn's phi, twist rate and actuated accelerations, and the statuses
  std::ofstream results(argv[4], std::ios::binary);
  for (int s = 0; s < states; ++s) {
    pin_inverse(s);
    results.write(reinterpret_cast<const char *>(solution.tail(6).data()), 6 * sizeof(double));
    Eigen::VectorXd acc = pinocchio::constraintDynamics(model, data, q[s], v[s], tau[s], cmodels, cdatas, prox);
    results.write(reinterpret_cast<const char *>(acc.data()), nv * sizeof(double));
    acc = pinocchio::lcaba(model, data_lc, q[s], v[s], tau[s], cmodels, cdatas_lc, prox_lc);
    results.write(reinterpret_cast<const char *>(acc.data()), nv * sizeof(double));
    double status[2];
    status[0] = PLATFORM_inverse_dynamics(pose[s], twist[s], rate[s], out);
    results.write(reinterpret_cast<const char *>(out), 6 * sizeof(double));
    status[1] = PLATFORM_forward_dynamics(pose[s], twist[s], phi[s], out, out + 6);
    results.write(reinterpret_cast<const char *>(out), 12 * sizeof(double));
    results.write(reinterpret_cast<const char *>(status), 2 * sizeof(double));
  }
  results.close();

  const int calls = 20000;
  double sink = 0;
  std::printf("states %d\n", states);
  std::printf("symdyn_inverse_dynamics %.1f\n", time_ns([&](int i) { sink += ours_inverse(i % states); }, calls));
  std::printf("pinocchio_inverse_dynamics %.1f\n", time_ns([&](int i) { sink += pin_inverse(i % states); }, calls));
  std::printf("symdyn_forward_dynamics %.1f\n", time_ns([&](int i) { sink += ours_forward(i % states); }, calls));
  std::printf("pinocchio_constraintDynamics %.1f\n", time_ns([&](int i) { sink += pin_forward(i % states); }, calls));
  std::printf("pinocchio_lcaba %.1f\n", time_ns([&](int i) { sink += pin_lcaba(i % states); }, calls));
  std::fprintf(stderr, "checksum %g\n", sink);
  return 0;
}
