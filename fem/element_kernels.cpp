#include "fem/element_kernels.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

#include "common/base/error.hpp"

namespace slide::fem {

namespace {

constexpr std::array<double, 4> hourglass_base{1.0, -1.0, 1.0, -1.0};  // h = ξ_k η_k

/// γ_k = ¼ [h_k − (h·x) b_kx − (h·y) b_ky] with b the gradients at the centre.
Vec4 hourglass_vector(const ElementNodes& x, const ShapeGradients& centre_gradients) {
  double hx = 0.0, hy = 0.0;
  for (int k = 0; k < 4; ++k) {
    hx += hourglass_base[static_cast<std::size_t>(k)] * x(k, 0);
    hy += hourglass_base[static_cast<std::size_t>(k)] * x(k, 1);
  }
  Vec4 gamma;
  for (int k = 0; k < 4; ++k) {
    gamma[k] = 0.25 * (hourglass_base[static_cast<std::size_t>(k)] - hx * centre_gradients(k, 0) -
                       hy * centre_gradients(k, 1));
  }
  return gamma;
}

/// K_q = (4/3) |J_0| Σ_{g ∈ {∇ξ, ∇η}} G_gᵀ C G_g, the stiffness of the hourglass mode
/// u = q ξη (see the header), with ∇ξ, ∇η the rows of J⁻¹ at the centre.
Mat2 hourglass_stiffness(const Mat2& centre_jacobian, const Mat3& c) {
  const double det = centre_jacobian.determinant();
  const Mat2 inverse = centre_jacobian.inverse();
  Mat2 k = Mat2::Zero();
  for (int row = 0; row < 2; ++row) {
    const double gx = inverse(row, 0), gy = inverse(row, 1);
    Eigen::Matrix<double, 3, 2> g;
    g << gx, 0.0,  //
        0.0, gy,   //
        gy, gx;
    k += g.transpose() * c * g;
  }
  return (4.0 / 3.0) * det * k;
}

/// The values of an element's NPE nodes.
template <int NPE>
std::array<Vec2, NPE> gather(const Index* nodes, const std::vector<Vec2>& values) {
  std::array<Vec2, NPE> out;
  for (int k = 0; k < NPE; ++k) {
    out[static_cast<std::size_t>(k)] = values[static_cast<std::size_t>(nodes[k])];
  }
  return out;
}

// VISCOUS adds the stiffness-proportional Rayleigh damping (see the header): the
// viscous stress β_K D ε̇ at every Gauss point and the viscous hourglass force β_K K_q q̇,
// both from the nodal velocities of `state`. Without it the kernel is the undamped one.
template <int NPE, int NGP, bool HOURGLASS, bool VISCOUS>
void element_forces_kernel(const FemModel& model, const ElementGeometry& geometry,
                           const FemState& state, double rayleigh_stiffness,
                           std::span<Vec2> element_force) {
  const Index n_elements = model.element_count();
  [[maybe_unused]] const Index* connectivity = model.mesh.connectivity.data();
  for (Index e = 0; e < n_elements; ++e) {
    std::array<Vec2, NPE> f;
    f.fill(Vec2::Zero());
    [[maybe_unused]] std::array<Vec2, NPE> v;
    [[maybe_unused]] Mat3 viscosity;  // β_K D, Pa·s
    if constexpr (VISCOUS) {
      v = gather<NPE>(connectivity + e * NPE, state.velocity);
      viscosity = rayleigh_stiffness * model.elastic.matrix[static_cast<std::size_t>(
                                           model.mesh.material_id[static_cast<std::size_t>(e)])];
    }
    for (int p = 0; p < NGP; ++p) {
      const auto gp = static_cast<std::size_t>(e * NGP + p);
      const ShapeGradients& b = geometry.gradients[gp];
      Vec4 s = state.stress[gp];
      if constexpr (VISCOUS) {
        // ε̇ = B v on [εxx, εyy, γxy]; σ ← σ + β_K D ε̇ (xx, yy, xy).
        double exx = 0.0, eyy = 0.0, gxy = 0.0;
        for (int k = 0; k < NPE; ++k) {
          const Vec2& vk = v[static_cast<std::size_t>(k)];
          exx += b(k, 0) * vk.x();
          eyy += b(k, 1) * vk.y();
          gxy += b(k, 1) * vk.x() + b(k, 0) * vk.y();
        }
        const Eigen::Vector3d viscous = viscosity * Eigen::Vector3d(exx, eyy, gxy);
        s[0] += viscous[0];
        s[1] += viscous[1];
        s[3] += viscous[2];
      }
      const double w = geometry.weight[gp];
      // f_k −= w Bᵀσ: [b_kx σxx + b_ky σxy, b_ky σyy + b_kx σxy]
      for (int k = 0; k < NPE; ++k) {
        f[static_cast<std::size_t>(k)].x() -= w * (b(k, 0) * s[0] + b(k, 1) * s[3]);
        f[static_cast<std::size_t>(k)].y() -= w * (b(k, 1) * s[1] + b(k, 0) * s[3]);
      }
    }
    if constexpr (HOURGLASS) {
      const Vec4& gamma = geometry.hourglass_vector[static_cast<std::size_t>(e)];
      Vec2 q_force = state.hourglass_force[static_cast<std::size_t>(e)];
      if constexpr (VISCOUS) {
        // Q ← Q + β_K K_q q̇, q̇ = Σ_k γ_k v_k: the hourglass mode damped like the others.
        Vec2 q_rate = Vec2::Zero();
        for (int k = 0; k < NPE; ++k) q_rate += gamma[k] * v[static_cast<std::size_t>(k)];
        q_force += rayleigh_stiffness *
                   (geometry.hourglass_stiffness[static_cast<std::size_t>(e)] * q_rate);
      }
      for (int k = 0; k < NPE; ++k) f[static_cast<std::size_t>(k)] -= gamma[k] * q_force;
    }
    for (int k = 0; k < NPE; ++k) {
      element_force[static_cast<std::size_t>(e * NPE + k)] = f[static_cast<std::size_t>(k)];
    }
  }
}

template <bool VISCOUS>
void dispatch_element_forces(const FemModel& model, const ElementGeometry& geometry,
                             const FemState& state, double rayleigh_stiffness,
                             std::span<Vec2> element_force) {
  switch (model.mesh.element_type) {
    case ElementType::quad4_1gp:
      if (model.hourglass_coefficient != 0.0) {
        element_forces_kernel<4, 1, true, VISCOUS>(model, geometry, state, rayleigh_stiffness,
                                                   element_force);
      } else {
        element_forces_kernel<4, 1, false, VISCOUS>(model, geometry, state, rayleigh_stiffness,
                                                    element_force);
      }
      return;
    case ElementType::quad4_2x2:
      element_forces_kernel<4, 4, false, VISCOUS>(model, geometry, state, rayleigh_stiffness,
                                                  element_force);
      return;
    case ElementType::tri3:
      element_forces_kernel<3, 1, false, VISCOUS>(model, geometry, state, rayleigh_stiffness,
                                                  element_force);
  }
}

/// Element e's velocity gradient L_ij = Σ_k v_ki ∂N_k/∂x_j at each of its Gauss points,
/// its hourglass force advanced first (Q ← Q + K_q Δq, Δq = Δt Σ_k γ_k v_k: then the
/// velocities need not be kept across the point update's call, 13 instructions an
/// element-step).
template <int NPE, int NGP, bool HOURGLASS>
[[gnu::always_inline]] inline std::array<Vec4, NGP> velocity_gradients(
    const FemModel& model, const ElementGeometry& geometry, double dt, FemState& state, Index e) {
  const auto v = gather<NPE>(model.mesh.connectivity.data() + e * NPE, state.velocity);
  if constexpr (HOURGLASS) {
    const Vec4& gamma = geometry.hourglass_vector[static_cast<std::size_t>(e)];
    Vec2 dq = Vec2::Zero();
    for (int k = 0; k < NPE; ++k) dq += gamma[k] * v[static_cast<std::size_t>(k)];
    state.hourglass_force[static_cast<std::size_t>(e)] +=
        geometry.hourglass_stiffness[static_cast<std::size_t>(e)] * (dt * dq);
  }
  std::array<Vec4, NGP> l;
  for (int p = 0; p < NGP; ++p) {
    const ShapeGradients& b = geometry.gradients[static_cast<std::size_t>(e * NGP + p)];
    double lxx = 0.0, lxy = 0.0, lyx = 0.0, lyy = 0.0;
    for (int k = 0; k < NPE; ++k) {
      const Vec2& vk = v[static_cast<std::size_t>(k)];
      lxx += vk.x() * b(k, 0);
      lxy += vk.x() * b(k, 1);
      lyx += vk.y() * b(k, 0);
      lyy += vk.y() * b(k, 1);
    }
    l[static_cast<std::size_t>(p)] = Vec4(lxx, lxy, lyx, lyy);
  }
  return l;
}

template <int NPE, int NGP, bool HOURGLASS, bool JAUMANN>
void stress_update_kernel(const FemModel& model, const ElementGeometry& geometry,
                          std::span<const ConstitutiveModel> models, double dt, FemState& state,
                          std::span<multi_yield::KeptComponents> kept) {
  const Index n_elements = model.element_count();
  const auto material_of = [&](Index e) -> const ConstitutiveModel& {
    return models[static_cast<std::size_t>(model.mesh.material_id[static_cast<std::size_t>(e)])];
  };
  const auto velocity_gradients_of = [&](Index e) {
    return velocity_gradients<NPE, NGP, HOURGLASS>(model, geometry, dt, state, e);
  };
  // The point update MPM's particles share (objective in updated Lagrangian).
  const auto advance = [&](const ConstitutiveModel& material, const Vec4& l, std::size_t gp) {
    const bool yielded = advance_point(material, l, dt, JAUMANN, state.stress[gp],
                                       state.material_state[gp], state.surface_stress.of(gp),
                                       state.strain[gp], kept.empty() ? nullptr : &kept[gp]);
    state.yielded[gp] = yielded ? 1 : 0;
  };
  Index e = 0;
  if constexpr (NGP == 1) {
    // One-point elements two at a time: two of one Mohr–Coulomb model, without records,
    // side by side (advance_mohr_coulomb_pair, the bits of two advance_point calls).
    for (; e + 1 < n_elements; e += 2) {
      const auto g = static_cast<std::size_t>(e), h = g + 1;
      const Vec4 l_e = velocity_gradients_of(e)[0], l_f = velocity_gradients_of(e + 1)[0];
      const ConstitutiveModel& material = material_of(e);
      if (&material != &material_of(e + 1) || material.model() != MaterialModel::mohr_coulomb ||
          !state.surface_stress.of(g).empty()) {
        advance(material, l_e, g);
        advance(material_of(e + 1), l_f, h);
        continue;
      }
      const auto yielded = advance_mohr_coulomb_pair(
          material, dt, JAUMANN,
          {{{l_e, &state.stress[g], &state.material_state[g], &state.strain[g]},
            {l_f, &state.stress[h], &state.material_state[h], &state.strain[h]}}});
      state.yielded[g] = yielded[0] ? 1 : 0;
      state.yielded[h] = yielded[1] ? 1 : 0;
    }
  }
  for (; e < n_elements; ++e) {
    const auto l = velocity_gradients_of(e);
    for (int p = 0; p < NGP; ++p) {
      advance(material_of(e), l[static_cast<std::size_t>(p)],
              static_cast<std::size_t>(e * NGP + p));
    }
  }
}

template <bool JAUMANN>
void dispatch_stress_update(const FemModel& model, const ElementGeometry& geometry,
                            std::span<const ConstitutiveModel> models, double dt, FemState& state,
                            std::span<multi_yield::KeptComponents> kept) {
  switch (model.mesh.element_type) {
    case ElementType::quad4_1gp:
      if (model.hourglass_coefficient != 0.0) {
        stress_update_kernel<4, 1, true, JAUMANN>(model, geometry, models, dt, state, kept);
      } else {
        stress_update_kernel<4, 1, false, JAUMANN>(model, geometry, models, dt, state, kept);
      }
      return;
    case ElementType::quad4_2x2:
      stress_update_kernel<4, 4, false, JAUMANN>(model, geometry, models, dt, state, kept);
      return;
    case ElementType::tri3:
      stress_update_kernel<3, 1, false, JAUMANN>(model, geometry, models, dt, state, kept);
  }
}

}  // namespace

Index compute_geometry(const FemModel& model, std::span<const Vec2> coordinates,
                       ElementGeometry& geometry) {
  const Mesh& mesh = model.mesh;
  const ElementShape shape = mesh.shape();
  const auto n_elements = static_cast<std::size_t>(mesh.element_count());
  const auto n_gauss = static_cast<std::size_t>(model.gauss_per_element());
  geometry.gradients.resize(n_elements * n_gauss);
  geometry.weight.resize(n_elements * n_gauss);
  if (model.hourglass) {
    geometry.hourglass_vector.resize(n_elements);
    geometry.hourglass_stiffness.resize(n_elements);
  }
  const Vec2 centre = reference_centre(shape);
  Index inverted = -1;
  for (std::size_t e = 0; e < n_elements; ++e) {
    const ElementNodes x = mesh.element_nodes(static_cast<Index>(e), coordinates);
    bool positive = true;
    for (std::size_t p = 0; p < n_gauss; ++p) {
      double det = 0.0;
      geometry.gradients[e * n_gauss + p] = physical_gradients(shape, x, model.rule.local[p], &det);
      geometry.weight[e * n_gauss + p] = model.rule.weight[p] * det;
      positive = positive && det > 0.0;
    }
    const Mat2 centre_jacobian = jacobian(shape, x, centre);
    positive = positive && centre_jacobian.determinant() > 0.0;
    if (!positive && inverted < 0) inverted = static_cast<Index>(e);
    if (model.hourglass) {
      // The one-point rule's Gauss point is the centre.
      geometry.hourglass_vector[e] = hourglass_vector(x, geometry.gradients[e]);
      const Mat3& c = model.elastic.matrix[static_cast<std::size_t>(mesh.material_id[e])];
      geometry.hourglass_stiffness[e] =
          model.hourglass_coefficient * hourglass_stiffness(centre_jacobian, c);
    }
  }
  return inverted;
}

void compute_element_forces(const FemModel& model, const ElementGeometry& geometry,
                            const FemState& state, std::span<Vec2> element_force,
                            double rayleigh_stiffness) {
  if (rayleigh_stiffness > 0.0) {
    dispatch_element_forces<true>(model, geometry, state, rayleigh_stiffness, element_force);
  } else {
    dispatch_element_forces<false>(model, geometry, state, 0.0, element_force);
  }
}

void update_stresses(const FemModel& model, const ElementGeometry& geometry,
                     std::span<const ConstitutiveModel> models, double dt, bool jaumann,
                     FemState& state, std::span<multi_yield::KeptComponents> kept) {
  if (!kept.empty() && kept.size() != static_cast<std::size_t>(model.gauss_count())) {
    throw Error("update_stresses: {} kept components for {} Gauss points", kept.size(),
                model.gauss_count());
  }
  if (jaumann) {
    dispatch_stress_update<true>(model, geometry, models, dt, state, kept);
  } else {
    dispatch_stress_update<false>(model, geometry, models, dt, state, kept);
  }
}

ElementMatrix element_stiffness(const FemModel& model, const ElementGeometry& geometry, Index e) {
  const int n = model.nodes_per_element;
  const auto n_gauss = static_cast<std::size_t>(model.gauss_per_element());
  const Mat3& c =
      model.elastic
          .matrix[static_cast<std::size_t>(model.mesh.material_id[static_cast<std::size_t>(e)])];
  ElementMatrix k = ElementMatrix::Zero();
  for (std::size_t p = 0; p < n_gauss; ++p) {
    const std::size_t gp = static_cast<std::size_t>(e) * n_gauss + p;
    const ShapeGradients& b = geometry.gradients[gp];
    // B maps nodal displacements to [εxx, εyy, γxy].
    Eigen::Matrix<double, 3, 2 * max_nodes_per_element> strain_matrix =
        Eigen::Matrix<double, 3, 2 * max_nodes_per_element>::Zero();
    for (int node = 0; node < n; ++node) {
      strain_matrix(0, 2 * node) = b(node, 0);
      strain_matrix(1, 2 * node + 1) = b(node, 1);
      strain_matrix(2, 2 * node) = b(node, 1);
      strain_matrix(2, 2 * node + 1) = b(node, 0);
    }
    k += geometry.weight[gp] * strain_matrix.transpose() * c * strain_matrix;
  }
  if (model.hourglass) {
    const Vec4& gamma = geometry.hourglass_vector[static_cast<std::size_t>(e)];
    const Mat2& kq = geometry.hourglass_stiffness[static_cast<std::size_t>(e)];
    for (int i = 0; i < n; ++i) {
      for (int j = 0; j < n; ++j) k.block<2, 2>(2 * i, 2 * j) += gamma[i] * gamma[j] * kq;
    }
  }
  return k;
}

double courant_time_step(const FemModel& model, std::span<const Vec2> coordinates, double courant) {
  return courant_time_step(model, coordinates, courant, model.elements.wave_speed);
}

double courant_time_step(const FemModel& model, std::span<const Vec2> coordinates, double courant,
                         std::span<const double> wave_speed) {
  const Mesh& mesh = model.mesh;
  const int n = model.nodes_per_element;
  const double area_factor = mesh.shape() == ElementShape::tri3 ? 2.0 : 1.0;
  double smallest = std::numeric_limits<double>::infinity();
  for (Index e = 0; e < mesh.element_count(); ++e) {
    const ElementNodes x = mesh.element_nodes(e, coordinates);
    double longest = 0.0;
    for (int k = 0; k < n; ++k) {
      longest = std::max(longest, (x.row((k + 1) % n) - x.row(k)).norm());
    }
    const double length = area_factor * std::abs(element_area(mesh.shape(), x)) / longest;
    smallest = std::min(smallest, length / wave_speed[static_cast<std::size_t>(e)]);
  }
  return courant * smallest;
}

double damped_time_step(double critical_step, double courant, double rayleigh_stiffness) {
  return damped_time_step(critical_step, courant, rayleigh_stiffness, critical_step);
}

double damped_time_step(double critical_step, double courant, double rayleigh_stiffness,
                        double skeleton_step) {
  // ξ = β_K ω_s,max² / (2 ω_max) = (β_K / dt_c) (dt_c / dt_c,s)²: β_K / dt_c when dry.
  const double ratio = critical_step / skeleton_step;
  const double xi = rayleigh_stiffness / critical_step * (ratio * ratio);
  return courant * critical_step / (std::sqrt(1.0 + xi * xi) + xi);
}

}  // namespace slide::fem
