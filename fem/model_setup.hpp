// The FE model of a mesh (docs/method.md §3): everything the kernels need, precomputed
// once (the reference geometry by the element kernels, lumped masses and gravity loads,
// the elastic constants, the node → element adjacency). Apart from fem/fem_model.hpp,
// whose types the kernels take, so that the kernels do not depend on how a model is made.
#pragma once

#include "common/base/types.hpp"
#include "common/geometry/mesh.hpp"
#include "common/physics/algorithms.hpp"
#include "common/physics/material.hpp"
#include "common/settings/fem_spec.hpp"
#include "fem/fem_model.hpp"

namespace slide::fem {

/// Precomputes everything from a validated mesh. With `water`, the elements of porous
/// materials below its level are saturated (u–p, PoreFluid) and those above it dry.
/// Throws Error when an element has det J ≤ 0 at a Gauss point of its rule, when a
/// material id is out of range or a drained node set is not the mesh's.
FemModel make_model(Mesh mesh, MaterialTable materials, Kinematics kinematics,
                    double hourglass_coefficient, const Vec2& gravity = gravity_vector(),
                    const std::optional<WaterSpec>& water = std::nullopt);

}  // namespace slide::fem
