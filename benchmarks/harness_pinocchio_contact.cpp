// Pinocchio's side of benchmarks/harness.py for symdyn's contact_forward_dynamics: compiled as the
// part CONTACT of the harness's cached objects, beside benchmarks/harness_pinocchio.cpp (whose
// Model it uses, with a Data of its own that initConstraintDynamics prepares).  The contacts are
// the model's frames named "contact3d_..." and "contact6d_..." (symdyn's build_model adds one per
// contact of the robot), LOCAL_WORLD_ALIGNED, as RigidConstraintModels; q is read as nq numbers.
// constraintDynamics runs at its fastest setting: one iteration, no proximal term (exact for a
// regular contact set, which the harness's robots have).  Entry points, declared in harness_cases.h:
//   pin_constraintDynamics(q, v, tau, out)
//   pin_constraintDynamicsDerivatives(q, v, tau, out): constraintDynamics then
//     computeConstraintDynamicsDerivatives (what symdyn's contact_forward_dynamics_derivatives computes)
#include <vector>
#include <pinocchio/multibody.hpp>
#include <pinocchio/algorithm/constrained-dynamics.hpp>
#include <pinocchio/algorithm/constrained-dynamics-derivatives.hpp>

extern pinocchio::Model *harness_model;
typedef Eigen::Map<const Eigen::VectorXd> In;

extern "C" {
void pin_constraintDynamics(const double *q, const double *v, const double *tau, double *out);
void pin_constraintDynamicsDerivatives(const double *q, const double *v, const double *tau, double *out);
}

namespace {
typedef pinocchio::RigidConstraintModel ContactModel;
typedef pinocchio::RigidConstraintData ContactData;

struct Contacts {
  PINOCCHIO_STD_VECTOR_WITH_EIGEN_ALLOCATOR(ContactModel) models;
  PINOCCHIO_STD_VECTOR_WITH_EIGEN_ALLOCATOR(ContactData) datas;
  pinocchio::Data data;
  pinocchio::ProximalSettings settings;

  explicit Contacts(const pinocchio::Model &model) : data(model), settings(1e-12, 0.0, 1) {
    for (const pinocchio::Frame &frame : model.frames) {
      const bool point = frame.name.rfind("contact3d_", 0) == 0, sole = frame.name.rfind("contact6d_", 0) == 0;
      if (!point && !sole) continue;
      models.push_back(ContactModel(point ? pinocchio::CONTACT_3D : pinocchio::CONTACT_6D, model, frame.parentJoint,
                                    frame.placement, pinocchio::LOCAL_WORLD_ALIGNED));
      datas.push_back(ContactData(models.back()));
    }
    pinocchio::initConstraintDynamics(model, data, models, datas);
  }
};

Contacts &contacts() {
  static Contacts set(*harness_model);
  return set;
}
}  // namespace

void pin_constraintDynamics(const double *q, const double *v, const double *tau, double *out) {
  Contacts &set = contacts();
  const pinocchio::Model &model = *harness_model;
  out[0] = pinocchio::constraintDynamics(model, set.data, In(q, model.nq), In(v, model.nv), In(tau, model.nv),
                                         set.models, set.datas, set.settings)[0];
}

void pin_constraintDynamicsDerivatives(const double *q, const double *v, const double *tau, double *out) {
  Contacts &set = contacts();
  const pinocchio::Model &model = *harness_model;
  pinocchio::constraintDynamics(model, set.data, In(q, model.nq), In(v, model.nv), In(tau, model.nv), set.models,
                                set.datas, set.settings);
  pinocchio::computeConstraintDynamicsDerivatives(model, set.data, set.models, set.datas, set.settings);
  out[0] = set.data.ddq_dq(0, 0) + set.data.dlambda_dv(0, 0);
}
