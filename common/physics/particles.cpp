#include "common/physics/particles.hpp"

#include "common/base/error.hpp"

namespace slide {

void Particles::resize(std::size_t n) {
  resize_rows(particle_fields, *this, RowKind::particle, n);
}

void Particles::use_pore_water_fields() {
  for (auto* field : {&excess_pore_pressure, &max_pore_pressure_ratio,
                      &initial_vertical_effective_stress, &initial_mean_effective_stress}) {
    field->resize(count(), 0.0);
  }
  liquefied.resize(count(), 0);
}

void Particles::shrink_to_fit() {
  shrink_rows(particle_fields, *this);
}

std::size_t Particles::bytes() const {
  return field_bytes(particle_fields, *this);
}

void Particles::check_consistent_sizes() const {
  const std::size_t n = count();
  if (const auto name = field_of_wrong_size(particle_fields, *this, RowKind::particle, n)) {
    throw Error("particles: field {} does not have {} rows (one per particle)", *name, n);
  }
}

}  // namespace slide
