// Material points as a structure of arrays: one contiguous vector per field, indexed by
// particle. The transfer fills it, the MPM kernels run over index ranges of it, and the
// checkpoint module writes each vector as one dataset. No per-particle objects.
//
// particle_fields below lists every field once (common/physics/field_table.hpp): resizing,
// the sort's permutation, the MPI packing, the memory count and the checkpoint reader and
// writer all walk it. A new field is a member here and one entry there.
#pragma once

#include <cstdint>
#include <tuple>
#include <type_traits>
#include <vector>

#include "common/base/types.hpp"
#include "common/physics/constitutive.hpp"
#include "common/physics/field_table.hpp"

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
  // Saturated soil (docs/method.md §10), empty for dry runs: per particle its excess pore
  // pressure Δp = p − p_static at the transfer, the largest pore-pressure ratio r_u,max of
  // its FE history, σ′v0 and p′₀ of the state before shaking (compression positive), and
  // whether it liquefied (its material's rule at the transfer: then its MPM model is the
  // material's liquefied state, common/physics/liquefaction.hpp).
  std::vector<double> excess_pore_pressure;
  std::vector<double> max_pore_pressure_ratio;
  std::vector<double> initial_vertical_effective_stress;
  std::vector<double> initial_mean_effective_stress;
  std::vector<std::int64_t> liquefied;  ///< 1 liquefied, 0 not

  std::size_t count() const { return coordinates.size(); }
  /// Resizes every field to n (new entries zero, element −1); an empty affine_velocity
  /// stays empty.
  void resize(std::size_t n);
  /// Sizes the saturated transfer's fields (excess_pore_pressure … liquefied) to count(),
  /// new entries 0: a run with pore water holds them, a resize then keeps them sized.
  void use_pore_water_fields();
  /// Releases the spare capacity of every field (one field reallocated at a time).
  void shrink_to_fit();
  /// Throws Error naming the field when the fields do not all have the same length.
  void check_consistent_sizes() const;
  /// Bytes held by the particle arrays.
  std::size_t bytes() const;
};

/// Every field of Particles, with its dataset under /particles and its unit
/// (common/io/checkpoint-schema.md), in the order of a checkpoint and of an MPI message.
inline constexpr std::tuple particle_fields{
    field(&Particles::coordinates, "coordinates", "m"),
    field(&Particles::displacement, "displacement", "m"),
    field(&Particles::velocity, "velocity", "m/s"),
    field(&Particles::stress, "stress", "Pa"),
    field(&Particles::strain, "strain", "1"),
    field(&Particles::eps_q, "eps_q", "1"),
    field(&Particles::pore_pressure, "pore_pressure", "Pa"),
    field(&Particles::volume, "volume", "m^3/m", {.check = Check::positive}),
    field(&Particles::mass, "mass", "kg/m", {.check = Check::positive}),
    field(&Particles::size, "size", "m", {.check = Check::positive_size}),
    field(&Particles::material_id, "material_id", "1", {.check = Check::material}),
    field(&Particles::element, "element", "1",
          {.check = Check::source_element, .fill = Fill::minus_one}),
    field(&Particles::id, "id", "1", {.check = Check::unique_id}),
    field(&Particles::state, "state", ""),
    field(&Particles::surface_stress, "state/surface_stress", "Pa"),
    field(&Particles::affine_velocity, "affine_velocity_gradient", "1/s",
          {.presence = Presence::when_used}),
    field(&Particles::excess_pore_pressure, "excess_pore_pressure", "Pa",
          {.presence = Presence::when_used}),
    field(&Particles::max_pore_pressure_ratio, "max_pore_pressure_ratio", "1",
          {.presence = Presence::when_used}),
    field(&Particles::initial_vertical_effective_stress, "initial_vertical_effective_stress", "Pa",
          {.presence = Presence::when_used}),
    field(&Particles::initial_mean_effective_stress, "initial_mean_effective_stress", "Pa",
          {.presence = Presence::when_used}),
    field(&Particles::liquefied, "liquefied", "1",
          {.presence = Presence::when_used, .check = Check::flag}),
};
using ParticleFieldTable = std::remove_const_t<decltype(particle_fields)>;
static_assert(listed_bytes<ParticleFieldTable>() == sizeof(Particles),
              "a member of Particles is missing from particle_fields");

}  // namespace slide
