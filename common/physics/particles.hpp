// Material points as a structure of arrays: one contiguous vector per field, indexed by
// particle. The transfer fills it, the MPM kernels run over index ranges of it, and the
// checkpoint module writes each vector as one dataset. No per-particle objects.
#pragma once

#include <cstdint>
#include <vector>

#include "common/base/types.hpp"
#include "common/physics/constitutive.hpp"

namespace slide {

struct Particles {
  std::vector<Vec2> coordinates;      ///< current position x_p, m
  std::vector<Vec2> displacement;     ///< since t = 0 (start of the failure stage), m
  std::vector<Vec2> velocity;         ///< m/s
  std::vector<Vec4> stress;           ///< [σxx, σyy, σzz, σxy], Pa, tension positive
  std::vector<Vec4> strain;           ///< [εxx, εyy, εzz, γxy], total since t = 0
  std::vector<double> eps_q;          ///< deviatoric strain invariant εq of `strain`
  std::vector<double> pore_pressure;  ///< Pa (0 for dry analyses)
  std::vector<double> volume;         ///< V_p, m³ per m
  std::vector<double> mass;           ///< M_p, kg per m
  std::vector<Vec2> size;             ///< GIMP domain lengths (l_x, l_y), m
  std::vector<std::int32_t> material_id;
  std::vector<std::int64_t> element;  ///< source FE element, −1 for pure MPM
  std::vector<std::int64_t> id;       ///< stable identity (creation index), survives sorting
  std::vector<MaterialState> state;
  /// Multi-yield surface stresses (per_point = 0 when no material uses the model).
  SurfaceStresses surface_stress;
  /// APIC's affine velocity gradient C_p as [Cxx, Cxy, Cyx, Cyy] (C_ab = ∂v_a/∂x_b of
  /// the particle's affine field v_p + C_p (x − x_p)), 1/s (mpm/kernels.hpp). Empty when
  /// the run does not use APIC (FLIP/PIC carries no affine state), else one per particle.
  std::vector<Vec4> affine_velocity;

  std::size_t count() const { return coordinates.size(); }
  /// Resizes every field to n (new entries zero-initialised); an empty affine_velocity
  /// stays empty.
  void resize(std::size_t n);
  /// Releases the spare capacity of every field (one field reallocated at a time).
  void shrink_to_fit();
  /// Throws Error naming the field when the fields do not all have the same length.
  void check_consistent_sizes() const;
};

}  // namespace slide
