// One point of a constitutive model for the single-point tests (multi-yield, PM4Sand):
// its model, stress, state and per-point records, and the two calls a test makes.
#pragma once

#include <vector>

#include "common/physics/constitutive.hpp"

namespace slide::testing {

struct MaterialPoint {
  ConstitutiveModel model;
  Vec4 stress;
  MaterialState state;
  std::vector<Vec4> surfaces;  ///< the model's per-point records

  MaterialPoint(const Material& m, const Vec4& initial)
      : model(ConstitutiveModel::from(m)),
        stress(initial),
        surfaces(static_cast<std::size_t>(model.surfaces()), Vec4::Zero()) {}
  bool start() { return model.start(stress, state, surfaces); }
  bool step(const Vec4& increment) { return model.update(stress, state, increment, surfaces); }
};

}  // namespace slide::testing
