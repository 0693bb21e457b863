// The Pinocchio -> CasADi code-generation peer of benchmarks/harness.py: loads a model saved by
// pinocchio::Model::saveToText, casts it to casadi::SX (model.cast<casadi::SX>()), runs
// Pinocchio's own algorithms on symbolic inputs, wraps the results in casadi::Function objects
// (option cse: CasADi's common-subexpression elimination) and writes CasADi's generated C.
//
// Usage: harness_peer MODEL.txt OUT_DIR FUNCTION...
//   FUNCTION: rnea crba_local crba_world computeGeneralizedGravity nonLinearEffects
//             computeCoriolisMatrix aba_local aba_world rneaDerivatives abaDerivatives
//             computeMinverse
// The derivatives are CasADi's automatic differentiation (casadi::SX::jacobian) of Pinocchio's
// rnea and aba on SX, side by side in one output: rneaDerivatives [dtau/dq dtau/dv] (n x 2n),
// abaDerivatives [dqdd/dq dqdd/dv dqdd/dtau] (n x 3n); computeMinverse is Pinocchio's own on SX.
// Writes OUT_DIR/peer.c and OUT_DIR/peer.h with one C function peer_FUNCTION per argument
// (CasADi's calling convention: arg, res, iw, w, mem).
#include <pinocchio/autodiff/casadi.hpp>
#include <pinocchio/multibody.hpp>
#include <pinocchio/algorithm/aba.hpp>
#include <pinocchio/algorithm/crba.hpp>
#include <pinocchio/algorithm/rnea.hpp>
#include <pinocchio/serialization.hpp>

#include <casadi/casadi.hpp>
#include <cstdio>
#include <string>
#include <vector>

typedef casadi::SX SX;
typedef pinocchio::ModelTpl<SX> ADModel;
typedef pinocchio::DataTpl<SX> ADData;
typedef Eigen::Matrix<SX, Eigen::Dynamic, 1> ADVector;
typedef Eigen::Matrix<SX, Eigen::Dynamic, Eigen::Dynamic> ADMatrix;

static ADVector entries(const SX &symbols) {
  ADVector out(symbols.size1());
  for (casadi_int i = 0; i < symbols.size1(); ++i) out[i] = symbols(i);
  return out;
}

template <typename Derived> static SX to_sx(const Eigen::MatrixBase<Derived> &value) {
  SX out = SX::zeros(value.rows(), value.cols());
  for (Eigen::Index i = 0; i < value.rows(); ++i)
    for (Eigen::Index j = 0; j < value.cols(); ++j) out(i, j) = value(i, j);
  return out;
}

// data.M from crba holds the upper triangle only: mirror it (assignments, no arithmetic) so the
// peer returns the whole matrix, as symdyn's mass_matrix does
static SX symmetric(const ADMatrix &upper) {
  ADMatrix full = upper;
  full.triangularView<Eigen::StrictlyLower>() = upper.transpose().triangularView<Eigen::StrictlyLower>();
  return to_sx(full);
}

static casadi::Function build(const std::string &name, const ADModel &model, ADData &data) {
  SX q = SX::sym("q", model.nq), v = SX::sym("v", model.nv), a = SX::sym("a", model.nv);
  ADVector qa = entries(q), va = entries(v), aa = entries(a);
  const pinocchio::Convention local = pinocchio::Convention::LOCAL, world = pinocchio::Convention::WORLD;
  std::vector<SX> in, out;
  if (name == "rnea") { in = {q, v, a}; out = {to_sx(pinocchio::rnea(model, data, qa, va, aa))}; }
  else if (name == "crba_local") { in = {q}; out = {symmetric(pinocchio::crba(model, data, qa, local))}; }
  else if (name == "crba_world") { in = {q}; out = {symmetric(pinocchio::crba(model, data, qa, world))}; }
  else if (name == "computeGeneralizedGravity") { in = {q}; out = {to_sx(pinocchio::computeGeneralizedGravity(model, data, qa))}; }
  else if (name == "nonLinearEffects") { in = {q, v}; out = {to_sx(pinocchio::nonLinearEffects(model, data, qa, va))}; }
  else if (name == "computeCoriolisMatrix") { in = {q, v}; out = {to_sx(pinocchio::computeCoriolisMatrix(model, data, qa, va))}; }
  else if (name == "aba_local") { in = {q, v, a}; out = {to_sx(pinocchio::aba(model, data, qa, va, aa, local))}; }
  else if (name == "aba_world") { in = {q, v, a}; out = {to_sx(pinocchio::aba(model, data, qa, va, aa, world))}; }
  else if (name == "rneaDerivatives") {
    in = {q, v, a};
    SX tau = to_sx(pinocchio::rnea(model, data, qa, va, aa));
    out = {SX::densify(SX::horzcat({SX::jacobian(tau, q), SX::jacobian(tau, v)}))};  // dense, as the others
  } else if (name == "abaDerivatives") {
    in = {q, v, a};  // a: the torques
    SX qdd = to_sx(pinocchio::aba(model, data, qa, va, aa, local));
    out = {SX::densify(SX::horzcat({SX::jacobian(qdd, q), SX::jacobian(qdd, v), SX::jacobian(qdd, a)}))};
  } else if (name == "computeMinverse") { in = {q}; out = {symmetric(pinocchio::computeMinverse(model, data, qa))}; }
  else throw std::invalid_argument("unknown function " + name);
  return casadi::Function("peer_" + name, in, out, casadi::Dict{{"cse", true}});
}

int main(int argc, char **argv) {
  if (argc < 4) { std::fprintf(stderr, "usage: %s MODEL.txt OUT_DIR FUNCTION...\n", argv[0]); return 2; }
  pinocchio::Model model;
  model.loadFromText(argv[1]);
  ADModel ad_model = model.cast<SX>();
  ADData ad_data(ad_model);
  casadi::CodeGenerator generator("peer.c", casadi::Dict{{"with_header", true}});
  for (int k = 3; k < argc; ++k) {
    casadi::Function f = build(argv[k], ad_model, ad_data);
    std::printf("%s %lld\n", argv[k], (long long)f.n_instructions());
    generator.add(f);
  }
  generator.generate(std::string(argv[2]) + "/");
  return 0;
}
