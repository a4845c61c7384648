#include "common/physics/particles.hpp"

#include "common/base/error.hpp"

namespace slide {

void Particles::resize(std::size_t n) {
  coordinates.resize(n, Vec2::Zero());
  displacement.resize(n, Vec2::Zero());
  velocity.resize(n, Vec2::Zero());
  stress.resize(n, Vec4::Zero());
  strain.resize(n, Vec4::Zero());
  eps_q.resize(n, 0.0);
  pore_pressure.resize(n, 0.0);
  volume.resize(n, 0.0);
  mass.resize(n, 0.0);
  size.resize(n, Vec2::Zero());
  material_id.resize(n, 0);
  element.resize(n, -1);
  id.resize(n, 0);
  state.resize(n, MaterialState{});
  surface_stress.resize(n);
  if (!affine_velocity.empty()) affine_velocity.resize(n, Vec4::Zero());
}

void Particles::shrink_to_fit() {
  coordinates.shrink_to_fit();
  displacement.shrink_to_fit();
  velocity.shrink_to_fit();
  stress.shrink_to_fit();
  strain.shrink_to_fit();
  eps_q.shrink_to_fit();
  pore_pressure.shrink_to_fit();
  volume.shrink_to_fit();
  mass.shrink_to_fit();
  size.shrink_to_fit();
  material_id.shrink_to_fit();
  element.shrink_to_fit();
  id.shrink_to_fit();
  state.shrink_to_fit();
  surface_stress.values.shrink_to_fit();
  affine_velocity.shrink_to_fit();
}

void Particles::check_consistent_sizes() const {
  const std::size_t n = coordinates.size();
  auto check = [n](std::size_t entries, const char* name) {
    if (entries != n)
      throw Error("particles: field {} has {} entries, expected {}", name, entries, n);
  };
  check(displacement.size(), "displacement");
  check(velocity.size(), "velocity");
  check(stress.size(), "stress");
  check(strain.size(), "strain");
  check(eps_q.size(), "eps_q");
  check(pore_pressure.size(), "pore_pressure");
  check(volume.size(), "volume");
  check(mass.size(), "mass");
  check(size.size(), "size");
  check(material_id.size(), "material_id");
  check(element.size(), "element");
  check(id.size(), "id");
  check(state.size(), "state");
  if (!affine_velocity.empty()) check(affine_velocity.size(), "affine_velocity");
  if (surface_stress.values.size() != n * surface_stress.per_point) {
    throw Error("particles: field surface_stress has {} entries, expected {} ({} per particle)",
                surface_stress.values.size(), n * surface_stress.per_point,
                surface_stress.per_point);
  }
}

}  // namespace slide
