// What a constitutive model carries per point (a Gauss point or a material point) beyond
// its stress: the accumulated plastic strains, the multi-yield model's frozen strength and
// the stresses of its surfaces. common/physics/constitutive.hpp's models update it, the
// field tables (field_table.hpp) move and store it.
#pragma once

#include <cstddef>
#include <span>
#include <vector>

#include "common/base/types.hpp"

namespace slide {

/// Algorithmic state carried per point (Gauss point or material point).
struct MaterialState {
  /// Accumulated deviatoric plastic strain, Σ sqrt(2/3 Δe^p : Δe^p) (–).
  double plastic_shear_strain = 0.0;
  /// Accumulated volumetric plastic strain, Σ tr Δε^p (–), dilation positive.
  double plastic_volumetric_strain = 0.0;
  /// Pressure-independent multi-yield: the peak strength q_f (von Mises equivalent
  /// stress, Pa) frozen at the switch to the model; negative until then.
  double peak_strength = -1.0;
};

/// The surface state of a set of points: `per_point` deviatoric stresses
/// [sxx, syy, szz, sxy] per point, point-major (per_point = 0: no point needs any).
struct SurfaceStresses {
  std::size_t per_point = 0;
  std::vector<Vec4> values;

  /// The surfaces of point i (empty when per_point = 0).
  std::span<Vec4> of(std::size_t i) {
    return per_point == 0 ? std::span<Vec4>{}
                          : std::span<Vec4>(values).subspan(i * per_point, per_point);
  }
  std::span<const Vec4> of(std::size_t i) const {
    return per_point == 0 ? std::span<const Vec4>{}
                          : std::span<const Vec4>(values).subspan(i * per_point, per_point);
  }
  std::size_t points() const { return per_point == 0 ? 0 : values.size() / per_point; }
  void resize(std::size_t points) { values.resize(points * per_point, Vec4::Zero()); }
};

}  // namespace slide
