// Times a platform robot's closed-loop dynamics: Pinocchio's C++ (the model and loop closures
// written by benchmarks/parallel_speed.py) against symdyn's generated C (linked in), in the same
// run, over the same states, with the method of benchmarks/harness.py (bench_timing.hpp's
// interleaved_passes: one warm-up pass, then PASSES passes of every state per side, the sides of
// one function taking turns; thread CPU time; "time FUNCTION SIDE ns ..." lines), and writes every
// state's results to a binary file for the accuracy comparison (RESULTS.bin "-": not written).
//
//   pinocchio_platform_bench MODEL.txt CLOSURES.txt STATES.bin RESULTS.bin MODEL_NO_ARMATURE.txt [PASSES]
//
// (PASSES: default 15.)
//
// MODEL.txt has a 1e-9 armature on the legs' joints (Pinocchio's constraint solvers factorize the
// joint-space mass matrix, which the legs' massless crosses leave singular); inverse dynamics uses
// MODEL_NO_ARMATURE.txt, the same model without it (as the generated functions).
//
// Pinocchio's inverse dynamics: rnea of the open tree, the constraint Jacobian, and the square
// system [Jc^T S] [lambda; phi] = tau solved by blocks, as a hand-written solver would: each
// leg's 6 rows give its closure force lambda_J = y_J - z_J phi_J (one 6x6 LU per leg), and the
// platform's 6 rows then a 6x6 system in phi (a dense 42x42 LU where the structure is not
// one closure per leg with 6 joints each).  Its forward dynamics:
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
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <vector>

// The generated functions: with PLATFORM_HEADER ("NAME_dynamics.h"), PLATFORM_inverse_dynamics
// and PLATFORM_forward_dynamics defined on the command line, from that header; else declared here
// as platform_inverse_dynamics and platform_forward_dynamics, which the link maps to the platform's
// (benchmarks/parallel_speed.py: -Wl,--defsym, so that this file compiles once for every platform)
#ifdef PLATFORM_HEADER
extern "C" {
#include PLATFORM_HEADER
}
#else
extern "C" int platform_inverse_dynamics(const double pose[7], const double twist[6], const double twist_rate[6],
                                         double phi[6]);
extern "C" int platform_forward_dynamics(const double pose[7], const double twist[6], const double phi[6],
                                         double twist_rate[6], double qdd[6]);
#define PLATFORM_inverse_dynamics platform_inverse_dynamics
#define PLATFORM_forward_dynamics platform_forward_dynamics
#endif

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
  // the block structure: a velocity column used by several closures is the platform's, one used
  // by a single closure belongs to that closure's leg (the pattern of a few states, so that a
  // coincidental zero does not hide an entry)
  std::vector<std::vector<int>> leg_columns(count);
  std::vector<int> platform_columns, leg_actuated(count, -1);
  {
    Eigen::MatrixXd pattern = Eigen::MatrixXd::Zero(nc, nv);
    for (int s = 0; s < std::min(states, 5); ++s) {
      pinocchio::computeJointJacobians(model_id, data_id, q[s]);
      Jc.setZero();
      pinocchio::getConstraintsJacobian(model_id, data_id, cmodels, cdatas, Jc);
      pattern += Jc.cwiseAbs();
    }
    for (int c = 0; c < nv; ++c) {
      int users = 0, last = -1;
      for (int J = 0; J < count; ++J)
        if (pattern.block(6 * J, c, 6, 1).maxCoeff() > 0) { ++users; last = J; }
      if (users > 1) platform_columns.push_back(c);
      else if (users == 1) leg_columns[last].push_back(c);
    }
    for (int J = 0; J < count; ++J)
      for (int k = 0; k < 6; ++k)
        for (int r = 0; r < (int)leg_columns[J].size(); ++r)
          if (leg_columns[J][r] == actuated[k]) leg_actuated[J] = k;
  }
  bool blocked = count == 6 && (int)platform_columns.size() == 6;
  for (int J = 0; J < count && blocked; ++J)
    blocked = leg_columns[J].size() == 6 && leg_actuated[J] >= 0;
  std::fprintf(stderr, "inverse dynamics: %s solve\n", blocked ? "block" : "dense LU");
  Eigen::Matrix<double, 6, 6> A, P, Z;
  Eigen::Matrix<double, 6, 1> y, z, t_leg, y_sum, t_platform;
  Eigen::PartialPivLU<Eigen::Matrix<double, 6, 6>> leg_lu, platform_lu;
  auto pin_inverse = [&](int s) {
    const Eigen::VectorXd &t = pinocchio::rnea(model_id, data_id, q[s], v[s], a[s]);
    pinocchio::computeJointJacobians(model_id, data_id, q[s]);
    Jc.setZero();
    pinocchio::getConstraintsJacobian(model_id, data_id, cmodels, cdatas, Jc);
    if (!blocked) {
      system.leftCols(nc) = Jc.transpose();
      lu.compute(system);
      solution = lu.solve(t);
      return solution[nv - 1];
    }
    Z.setZero();
    y_sum.setZero();
    for (int J = 0; J < count; ++J) {
      for (int r = 0; r < 6; ++r) {
        t_leg(r) = t(leg_columns[J][r]);
        for (int c = 0; c < 6; ++c) {
          A(r, c) = Jc(6 * J + c, leg_columns[J][r]);
          P(r, c) = Jc(6 * J + c, platform_columns[r]);
        }
      }
      leg_lu.compute(A);
      y = leg_lu.solve(t_leg);
      z.setZero();
      for (int r = 0; r < 6; ++r) z(r) = leg_columns[J][r] == actuated[leg_actuated[J]] ? 1.0 : 0.0;
      z = leg_lu.solve(z);
      y_sum.noalias() += P * y;
      Z.col(leg_actuated[J]).noalias() += P * z;
    }
    for (int r = 0; r < 6; ++r) t_platform(r) = t(platform_columns[r]);
    platform_lu.compute(Z);
    solution.tail(6) = platform_lu.solve(y_sum - t_platform);
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
  // algorithms), symdyn's phi, twist rate and actuated accelerations, and the statuses; "-": none
  if (std::strcmp(argv[4], "-") != 0) {
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
  }

  const int passes = argc > 6 ? std::atoi(argv[6]) : 15;
  double sink = 0;
  std::vector<TimedCase> cases;
  cases.push_back(timed_case("inverse_dynamics", "symdyn", ours_inverse, states, sink));
  cases.push_back(timed_case("inverse_dynamics", "pinocchio", pin_inverse, states, sink));
  cases.push_back(timed_case("forward_dynamics", "symdyn", ours_forward, states, sink));
  cases.push_back(timed_case("forward_dynamics", "pinocchio_constraintDynamics", pin_forward, states, sink));
  cases.push_back(timed_case("forward_dynamics", "pinocchio_lcaba", pin_lcaba, states, sink));
  interleaved_passes(cases, passes);
  std::printf("states %d\nchecksum %.17g\n", states, sink);
  return 0;
}
