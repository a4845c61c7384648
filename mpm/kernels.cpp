#include "mpm/kernels.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <new>

#include "common/base/error.hpp"
#include "common/base/pair.hpp"
#include "mpm/shape_functions.hpp"

namespace slide::mpm {

namespace {

// Block sizes. Blocks of a few thousand particles keep a window's overhead (zeroing and
// reducing its band, ~3 node columns wider than the particles' own cells) at a few per
// cent of the scatter work; counts are multiples of 24 so that 1, 2, 3, 4, 6, 8, 12 or
// 24 threads share them evenly.
constexpr std::size_t smallest_block = 256;
constexpr std::size_t block_multiple = 24;
constexpr std::size_t particles_per_block_target = 4096;

// The nodal x/y fields the kernels load and store as pairs sit side by side.
static_assert(offsetof(NodeSums, momentum_y) == offsetof(NodeSums, momentum_x) + sizeof(double));
static_assert(offsetof(NodeSums, force_y) == offsetof(NodeSums, force_x) + sizeof(double));
static_assert(offsetof(NodeMotion, velocity_y) ==
              offsetof(NodeMotion, velocity_x) + sizeof(double));
static_assert(offsetof(NodeMotion, acceleration_y) ==
              offsetof(NodeMotion, acceleration_x) + sizeof(double));

/// The 2D weights of one particle: tensor products of the 1-D ones, S_a S_b with S_a the
/// x axis's weight of stencil column a and S_b the y axis's of row b.
template <class Shape>
struct ParticleWeights {
  Weights2d<Shape::support> axes;  ///< both axes' weights, lane 0 x, lane 1 y
  std::size_t first_node;          ///< storage index of the stencil's first node (the axes' bases)
  double inv_h;

  double value_x(int a) const { return axes.value[a][0]; }            ///< S_a
  double value_y(int b) const { return axes.value[b][1]; }            ///< S_b
  double derivative_x(int a) const { return axes.derivative[a][0]; }  ///< S'_a
  double derivative_y(int b) const { return axes.derivative[b][1]; }  ///< S'_b

  /// `inv_cell_size` is 1/h, divided once by the caller (a loop's stores to the weights
  /// might alias grid.cell_size, so the compiler would divide for every particle).
  ParticleWeights(const GridGeometry& grid, double inv_cell_size, const Vec2& position,
                  const Vec2& size) {
    // Both axes at once (pair.hpp): the bits of the axis-by-axis arithmetic.
    inv_h = inv_cell_size;
    const Pair cell_units =
        (Pair{position.x(), position.y()} - Pair{grid.origin.x(), grid.origin.y()}) * inv_h;
    // At most ½: a domain never spans more than a cell; and no further than the grid's
    // edge (clipped_half_size).
    const Pair half_size =
        clipped_half_size(cell_units, Pair{double(grid.cells_x), double(grid.cells_y)},
                          lanes::min(0.5 * Pair{size.x(), size.y()} * inv_h, Pair{} + 0.5));
    Shape::weights(cell_units, half_size, axes);
    first_node = grid.node_index(axes.base[0], axes.base[1]);
  }
  /// Storage index of the first node of stencil column a (node columns hold `rows`).
  std::size_t column_start(std::size_t rows, int a) const {
    return first_node + static_cast<std::size_t>(a) * rows;
  }
  /// Where the cell averages of the particle are kept: the storage index of the node at
  /// the lower-left corner of its cell (⌊ξ⌋, ⌊η⌋). That node is in the stencil (linear:
  /// nodes ⌊ξ⌋, ⌊ξ⌋ + 1; uGIMP: the nearest node ± 1), hence in its block's window. A
  /// particle in the grid's half-cell margin has a cell of its own there. The particle
  /// has not moved since P2G computed the weights.
  std::size_t cell_slot(std::size_t rows) const {
    return column_start(rows, axes.cell[0]) + static_cast<std::size_t>(axes.cell[1]);
  }
};

/// The weights P2G computed for the step (ParticleBlocks::shape_weights): an array of
/// ParticleWeights<Shape>, which P2G constructs in place and the later passes read.
template <class Shape>
const ParticleWeights<Shape>* step_weights(const ParticleBlocks& blocks) {
  return std::launder(reinterpret_cast<const ParticleWeights<Shape>*>(blocks.shape_weights.data()));
}
/// The same array to construct the weights in (P2G).
template <class Shape>
ParticleWeights<Shape>* step_weights(ParticleBlocks& blocks) {
  return const_cast<ParticleWeights<Shape>*>(
      step_weights<Shape>(static_cast<const ParticleBlocks&>(blocks)));
}

/// The part of a particle's stencil its domain reaches (Weights2d): `columns` stencil
/// columns by `rows` rows from the first reached node. The counts are constants, so loops
/// over them unroll like loops over the whole stencil.
template <int Columns, int Rows>
struct Stencil {
  static constexpr int columns = Columns, rows = Rows;
};

/// Calls body(Stencil<…>{}) for the particle's reached stencil: 2 or 3 columns by 2 or 3
/// rows for uGIMP, 2 × 2 for linear hats.
template <class Shape, class Body>
[[gnu::always_inline]] inline void on_stencil(const ParticleWeights<Shape>& w, Body&& body) {
  if constexpr (Shape::support == 2) {
    body(Stencil<2, 2>{});
  } else if (w.axes.count[0] == 3) {
    if (w.axes.count[1] == 3) {
      body(Stencil<3, 3>{});
    } else {
      body(Stencil<3, 2>{});
    }
  } else if (w.axes.count[1] == 3) {
    body(Stencil<2, 3>{});
  } else {
    body(Stencil<2, 2>{});
  }
}

/// APIC's moments of one particle's weights (shape_functions.hpp), lane 0 x and lane 1 y:
/// D_p = h² diag(inertia) and N_ip D_p⁻¹ (x_i − x_p) = (e_a S_b, S_a e_b)/h with
/// e_a = value_x(a), e_b = value_y(b); the first moments μ_a = moment_x(a), μ_b = moment_y(b).
template <class Shape>
struct ParticleAffine {
  AffineWeights2d<Shape::support> axes;

  explicit ParticleAffine(const ParticleWeights<Shape>& w) { Shape::affine(w.axes, axes); }
  double value_x(int a) const { return axes.value[a][0]; }
  double value_y(int b) const { return axes.value[b][1]; }
  double moment_x(int a) const { return axes.moment[a][0]; }
  double moment_y(int b) const { return axes.moment[b][1]; }
};

/// What a FLIP/PIC kernel computes in place of ParticleAffine: nothing.
struct NoAffine {};

/// The particle's APIC moments in an APIC kernel, nothing in a FLIP/PIC one.
template <VelocityTransfer Transfer, class Shape>
auto affine_moments(const ParticleWeights<Shape>& w) {
  if constexpr (Transfer == VelocityTransfer::apic) {
    return ParticleAffine<Shape>(w);
  } else {
    return NoAffine{};
  }
}

/// The diagonal of D_p, m², of a particle at `position`.
template <class Shape>
Vec2 inertia_at(const GridGeometry& grid, const Vec2& position, const Vec2& size) {
  const ParticleAffine<Shape> e(ParticleWeights<Shape>(grid, 1.0 / grid.cell_size, position, size));
  const double h2 = grid.cell_size * grid.cell_size;
  return Vec2(e.axes.inertia[0] * h2, e.axes.inertia[1] * h2);
}

/// APIC's gather at one particle of the end-of-step nodal velocities v^L: the value
/// v_p = Σ N_ip v_i and C_p = Σ v_i (N_ip D_p⁻¹ (x_i − x_p))ᵀ (cell units: × 1/h). With
/// N_ip = S_a S_b and N_ip D_p⁻¹ (x_i − x_p) = (e_a S_b, S_a e_b) both sums separate:
/// per stencil column a, u = Σ_b S_b v_ab and t = Σ_b e_b v_ab; then v_p = Σ_a S_a u,
/// C_·x = Σ_a e_a u, C_·y = Σ_a S_a t (half the products of the node-by-node sums).
struct AffineGather {
  Pair value{};  ///< v_p
  Pair c_x{};    ///< (C_xx, C_yx) × h: C_p's first column
  Pair c_y{};    ///< (C_xy, C_yy) × h
  Vec2 velocity() const { return {value[0], value[1]}; }
  /// C_p = [C_xx, C_xy, C_yx, C_yy], 1/s.
  Vec4 affine_velocity(double inv_h) const { return Vec4(c_x[0], c_y[0], c_x[1], c_y[1]) * inv_h; }
};

template <class Shape, class S>
[[gnu::always_inline]] inline AffineGather gather_affine(const GridState& state, std::size_t rows,
                                                         const ParticleWeights<Shape>& w,
                                                         const ParticleAffine<Shape>& e,
                                                         const S& s) {
  AffineGather g;
  for (int a = 0; a < s.columns; ++a) {
    const NodeMotion* column = state.motion.data() + w.column_start(rows, a);
    Pair u{}, t{};
    for (int b = 0; b < s.rows; ++b) {
      const Pair v = load_pair(&column[b].velocity_x);
      u += w.value_y(b) * v;
      t += e.value_y(b) * v;
    }
    g.value += w.value_x(a) * u;
    g.c_x += e.value_x(a) * u;
    g.c_y += w.value_x(a) * t;
  }
  return g;
}

template <class Shape>
int first_node(double xi) {
  return Shape::weights(xi, 0.5).base;
}

template <class Shape>
void locate_block(const Particles& particles, const GridGeometry& grid, std::size_t begin,
                  std::size_t end, int& column_begin, int& column_end, std::int64_t& non_finite,
                  std::vector<std::size_t>& outside) {
  double xi_min = std::numeric_limits<double>::infinity();
  double xi_max = -xi_min;
  // A copy of the grid and the positions' address, which the loop's stores
  // (outside.push_back) cannot alias: they stay in registers instead of being loaded for
  // every particle.
  const GridGeometry g = grid;
  const Vec2* const coordinates = particles.coordinates.data();
  const double inv_h = 1.0 / g.cell_size;
  for (std::size_t p = begin; p < end; ++p) {
    const Vec2& x = coordinates[p];
    if (!lanes::all_finite(load_pair(x.data()))) {
      if (non_finite < 0) non_finite = static_cast<std::int64_t>(p);
      continue;
    }
    if (!g.contains(x)) {
      outside.push_back(p);
      continue;
    }
    const double xi = (x.x() - g.origin.x()) * inv_h;
    xi_min = std::min(xi_min, xi);
    xi_max = std::max(xi_max, xi);
  }
  if (xi_min > xi_max) {  // no particle on the grid
    column_begin = column_end = 0;
    return;
  }
  // Storage column of node i is i + 1.
  column_begin = first_node<Shape>(xi_min) + 1;
  column_end = first_node<Shape>(xi_max) + Shape::support + 1;
}

template <class Shape, VelocityTransfer Transfer>
void scatter_block(const Particles& particles, const GridGeometry& grid, const Vec2& gravity,
                   const Reservoir& reservoir, std::size_t begin, std::size_t end, int column_begin,
                   std::vector<NodeSums>& window, ParticleBlocks& blocks) {
  ParticleWeights<Shape>* const weights = step_weights<Shape>(blocks);
  const auto rows = static_cast<std::size_t>(grid.node_rows());
  const std::size_t offset = static_cast<std::size_t>(column_begin) * rows;
  constexpr bool apic = Transfer == VelocityTransfer::apic;
  const double inv_h = 1.0 / grid.cell_size;
  for (std::size_t p = begin; p < end; ++p) {
    const ParticleWeights<Shape>& w = *new (weights + p) ParticleWeights<Shape>(
        grid, inv_h, particles.coordinates[p], particles.size[p]);
    const double m = particles.mass[p];
    const Vec2& v = particles.velocity[p];
    const Vec4& sigma = particles.stress[p];
    const double volume = particles.volume[p];
    const Pair mv{m * v.x(), m * v.y()};
    // The water's pressure below the reservoir level and its buoyancy γ_w V (kernels.hpp).
    const double p_water = reservoir.pressure(particles.coordinates[p]);
    const double buoyancy = p_water > 0.0 ? reservoir.unit_weight * volume : 0.0;
    const Pair mg{m * gravity.x(), m * gravity.y() + buoyancy};
    // −V (σ′ − (p − p_w) I)·∇N with ∇N in physical units: fold V/h in once. The force of
    // a node is σ_x ∂N/∂x + σ_y ∂N/∂y with the stress's columns σ_x = (σxx, σxy) and
    // σ_y = (σxy, σyy).
    const double vh = volume * w.inv_h;
    const double pressure = particles.pore_pressure[p] - p_water;
    const double sxy = vh * sigma[3];
    const Pair stress_x{vh * (sigma[0] - pressure), sxy};
    const Pair stress_y{sxy, vh * (sigma[1] - pressure)};
    // APIC: the momentum of the particle's affine velocity field v_p + C_p (x − x_p):
    // N_ip m (v_p + C_p (x_i − x_p)) with N_ip (x_i − x_p) = h (μ_a S_b, S_a μ_b), μ the
    // weights' first moments in cell units (ParticleAffine::moment_x, moment_y). Per stencil column
    // a: S_b (S_a m v + m h C_·x μ_a) + μ_b (S_a m h C_·y).
    [[maybe_unused]] const auto affine = affine_moments<Transfer>(w);
    [[maybe_unused]] Pair c_x{}, c_y{};  // m h (C_xx, C_yx), m h (C_xy, C_yy)
    if constexpr (apic) {
      const Vec4& c = particles.affine_velocity[p];
      const double mh = m * grid.cell_size;
      c_x = Pair{mh * c[0], mh * c[2]};
      c_y = Pair{mh * c[1], mh * c[3]};
    }
    // The sums separate like the weights, S_a S_b: per stencil column a the pairs its
    // nodes b take in proportion to S_b or S'_b, then per node two products. Force:
    // N m g − σ_x ∂N/∂x − σ_y ∂N/∂y = S_b (S_a m g − S'_a σ_x) − S'_b (S_a σ_y).
    on_stencil(w, [&](const auto& s) {
      for (int a = 0; a < s.columns; ++a) {
        NodeSums* column = window.data() + (w.column_start(rows, a) - offset);
        const double sa = w.value_x(a);
        const double mass_a = sa * m;
        const Pair force_along = sa * mg - w.derivative_x(a) * stress_x;  // × S_b
        const Pair force_across = sa * stress_y;                          // × S'_b
        Pair along = sa * mv, across{};
        if constexpr (apic) {
          along += c_x * affine.moment_x(a);
          across = sa * c_y;
        }
        for (int b = 0; b < s.rows; ++b) {
          const double sb = w.value_y(b);
          NodeSums& node = column[b];
          node.mass += sb * mass_a;
          if constexpr (apic) {
            add_pair(&node.momentum_x, sb * along + affine.moment_y(b) * across);
          } else {
            add_pair(&node.momentum_x, sb * along);
          }
          add_pair(&node.force_x, sb * force_along - w.derivative_y(b) * force_across);
        }
      }
    });
  }
}

/// Sums the blocks' windows into one node column of the grid, node by node in block
/// order (the order that makes every sum independent of the thread count).
template <class T, class Add>
void sum_column(const ParticleBlocks& blocks, const std::vector<std::vector<T>>& windows,
                int column, std::size_t rows, T* target, const T& zero, Add add) {
  std::fill(target, target + rows, zero);
  for (std::size_t b = 0; b < blocks.count(); ++b) {
    const int c0 = blocks.column_begin[b];
    const int c1 = blocks.column_end[b];
    if (column < c0 || column >= c1) continue;
    const T* source = windows[b].data() + static_cast<std::size_t>(column - c0) * rows;
    for (std::size_t r = 0; r < rows; ++r) add(target[r], source[r]);
  }
}

template <class Shape, VelocityTransfer Transfer>
void velocity_and_remap_block(Particles& particles, const GridGeometry& grid,
                              const GridState& state, const StepLengths& step, double pic_fraction,
                              std::size_t begin, std::size_t end, int column_begin,
                              std::vector<Vec2>& window, ParticleBlocks& blocks) {
  const ParticleWeights<Shape>* const weights = step_weights<Shape>(blocks);
  const auto rows = static_cast<std::size_t>(grid.node_rows());
  const std::size_t offset = static_cast<std::size_t>(column_begin) * rows;
  const double dt_velocity = step.dt_velocity;
  const double flip = 1.0 - pic_fraction;
  for (std::size_t p = begin; p < end; ++p) {
    const ParticleWeights<Shape>& w = weights[p];
    Vec2& v = particles.velocity[p];
    if constexpr (Transfer == VelocityTransfer::apic) {
      // The particle takes the nodal field's value and first moment C_p, which it keeps
      // and which goes into the re-projection below.
      const ParticleAffine<Shape> e(w);
      const double m = particles.mass[p];
      on_stencil(w, [&](const auto& s) {
        const AffineGather g = gather_affine(state, rows, w, e, s);
        v = g.velocity();
        particles.affine_velocity[p] = g.affine_velocity(w.inv_h);
        // The momenta of the affine field, N_ip m (v_p + C_p (x_i − x_p)), with N_ip (x_i −
        // x_p) = h (moment_a S_b, S_a moment_b) and C_p = c/h (the h cancel): per column,
        // S_b (S_a m v + m c_·x moment_a) + moment_b (S_a m c_·y).
        for (int a = 0; a < s.columns; ++a) {
          Vec2* column = window.data() + (w.column_start(rows, a) - offset);
          const double sa = w.value_x(a);
          const Pair along = m * (sa * g.value + g.c_x * e.moment_x(a));
          const Pair across = m * sa * g.c_y;
          for (int b = 0; b < s.rows; ++b) {
            add_pair(column[b].data(), w.value_y(b) * along + e.moment_y(b) * across);
          }
        }
      });
    } else {
      on_stencil(w, [&](const auto& s) {
        Pair acceleration{}, velocity{};
        for (int a = 0; a < s.columns; ++a) {
          const NodeMotion* column = state.motion.data() + w.column_start(rows, a);
          for (int b = 0; b < s.rows; ++b) {
            const double weight = w.value_x(a) * w.value_y(b);
            acceleration += weight * load_pair(&column[b].acceleration_x);
            velocity += weight * load_pair(&column[b].velocity_x);
          }
        }
        v.x() = flip * (v.x() + dt_velocity * acceleration[0]) + pic_fraction * velocity[0];
        v.y() = flip * (v.y() + dt_velocity * acceleration[1]) + pic_fraction * velocity[1];
        const Pair mv{particles.mass[p] * v.x(), particles.mass[p] * v.y()};
        for (int a = 0; a < s.columns; ++a) {
          Vec2* column = window.data() + (w.column_start(rows, a) - offset);
          for (int b = 0; b < s.rows; ++b) {
            add_pair(column[b].data(), w.value_x(a) * w.value_y(b) * mv);
          }
        }
      });
    }
  }
}

/// Undrained pore water: ṗ = −(K_f/n) tr ε̇, no suction (cavitation at p = 0).
inline void update_pore_water(Particles& particles, const ConstitutiveModel& model, double dt,
                              const Vec4& l, std::size_t p) {
  if (const double stiffness = model.pore_fluid_stiffness();
      stiffness > 0.0 && holds_water(particles, p)) {
    double& pressure = particles.pore_pressure[p];
    const double change = std::max(-stiffness * dt * (l[0] + l[3]), -pressure);
    pressure += change;
    if (!particles.excess_pore_pressure.empty()) particles.excess_pore_pressure[p] += change;
  }
}

/// det(I + Δt L) for L = [l0, l1; l2, l3]: a particle's own volume ratio over the step,
/// for one particle (Real = double) or two side by side (Real = Pair, the same bits).
template <class Real>
Real volume_ratio(double dt, Real l0, Real l1, Real l2, Real l3) {
  return (1.0 + dt * l0) * (1.0 + dt * l3) - dt * dt * l1 * l2;
}

/// What follows the constitutive update of particle p (update_stress): its εq, its pore
/// water, its volume.
inline void finish_point_update(Particles& particles, const ConstitutiveModel& model, double dt,
                                const Vec4& l, std::size_t p) {
  particles.eps_q[p] = deviatoric_strain(particles.strain[p]);
  update_pore_water(particles, model, dt, l, p);
  particles.volume[p] *= volume_ratio(dt, l[0], l[1], l[2], l[3]);
}

/// One particle's stress update from its velocity gradient l = [∂vx/∂x, ∂vx/∂y, ∂vy/∂x,
/// ∂vy/∂y]: the point update FE Gauss points share (advance_point: strain increment,
/// Jaumann rotation, the constitutive update of the particle's material), the εq of the
/// accumulated strain, and the volume from the deformation-gradient increment,
/// V_{n+1} = det(I + Δt l) V_n (with volumetric smoothing, l carries the cell's volumetric
/// rate). Not inlined into the gather: it then compiles to the arithmetic of the former
/// separate stress pass (inlined, -march=native contracts some products into FMAs
/// differently), so results stay bit-identical to that pass's.
[[gnu::noinline]] void update_stress(Particles& particles,
                                     std::span<const ConstitutiveModel> models, double dt,
                                     const Vec4& l, std::size_t p) {
  const std::size_t model = particle_model(particles, p, models.size() / 2);
  on_model_stress(models[model], particles, p, [&](Vec4& stress) {
    return advance_point(models[model], l, dt, true, stress, particles.state[p],
                         particles.surface_stress.of(p), particles.strain[p]);
  });
  finish_point_update(particles, models[model], dt, l, p);
}

/// Whether particles p and p + 1 can take update_stress_pair: one Mohr–Coulomb model,
/// no per-point records.
inline bool pairs_with_next(const Particles& particles, std::span<const ConstitutiveModel> models,
                            std::size_t p) {
  const std::size_t model = particle_model(particles, p, models.size() / 2);
  return model == particle_model(particles, p + 1, models.size() / 2) &&
         models[model].model() == MaterialModel::mohr_coulomb &&
         particles.surface_stress.of(p).empty();
}

/// update_stress of particles p and p + 1 (pairs_with_next; velocity gradients l_p and
/// l_q) at once: advance_mohr_coulomb_pair, the bits of two update_stress calls.
[[gnu::noinline]] void update_stress_pair(Particles& particles,
                                          std::span<const ConstitutiveModel> models, double dt,
                                          const Vec4& l_p, const Vec4& l_q, std::size_t p) {
  const std::size_t q = p + 1;
  const ConstitutiveModel& model = models[particle_model(particles, p, models.size() / 2)];
  advance_mohr_coulomb_pair(
      model, dt, true,
      {{{l_p, &particles.stress[p], &particles.state[p], &particles.strain[p]},
        {l_q, &particles.stress[q], &particles.state[q], &particles.strain[q]}}});
  // finish_point_update of both: εq and the volume side by side, the pore water one by one.
  const Vec4& e_p = particles.strain[p];
  const Vec4& e_q = particles.strain[q];
  const Pair eps_q = deviatoric_strain(Pair{e_p[0], e_q[0]}, Pair{e_p[1], e_q[1]},
                                       Pair{e_p[2], e_q[2]}, Pair{e_p[3], e_q[3]});
  particles.eps_q[p] = eps_q[0];
  particles.eps_q[q] = eps_q[1];
  if (model.pore_fluid_stiffness() > 0.0) {
    update_pore_water(particles, model, dt, l_p, p);
    update_pore_water(particles, model, dt, l_q, q);
  }
  const Pair l0{l_p[0], l_q[0]}, l1{l_p[1], l_q[1]}, l2{l_p[2], l_q[2]}, l3{l_p[3], l_q[3]};
  const Pair jacobian = volume_ratio(dt, l0, l1, l2, l3);
  particles.volume[p] *= jacobian[0];
  particles.volume[q] *= jacobian[1];
}

/// The final pass's gather over one block (kernels.hpp, grid_to_particles). Without
/// smoothing it moves the particles and updates their stresses; with it, it keeps L_p and
/// the displacement and adds the particle's V_p, V_p tr L_p and V_p p_p to its cell in the
/// block's window; smooth_block finishes the step.
template <class Shape, UpdateScheme Scheme, VelocityTransfer Transfer,
          VolumetricSmoothing Smoothing>
double gather_block(Particles& particles, const GridGeometry& grid, const GridState& state,
                    const StepLengths& step, double pic_fraction,
                    std::span<const ConstitutiveModel> models, std::size_t begin, std::size_t end,
                    ParticleBlocks& blocks, std::size_t block) {
  [[maybe_unused]] const std::size_t offset = static_cast<std::size_t>(blocks.column_begin[block]) *
                                              static_cast<std::size_t>(grid.node_rows());
  [[maybe_unused]] CellSums* window = blocks.cell_window[block].data();
  constexpr bool apic = Transfer == VelocityTransfer::apic;
  const double flip = 1.0 - pic_fraction;
  double kinetic = 0.0;
  const ParticleWeights<Shape>* const weights = step_weights<Shape>(blocks);
  const auto rows = static_cast<std::size_t>(grid.node_rows());
  for (std::size_t p = begin; p < end; ++p) {
    const ParticleWeights<Shape>& w = weights[p];
    // Σ N a, Σ N v (FLIP/PIC), and the velocity gradient's columns (∂v/∂x, ∂v/∂y) × h,
    // separated like the weights: per stencil column a, u_a = Σ_b S_b u_ab and
    // t_a = Σ_b S'_b u_ab, then ∂u/∂x = Σ_a S'_a u_a and ∂u/∂y = Σ_a S_a t_a.
    Pair acceleration{}, velocity{}, gradient_x{}, gradient_y{};
    on_stencil(w, [&](const auto& s) {
      for (int a = 0; a < s.columns; ++a) {
        const std::size_t start = w.column_start(rows, a);
        const NodeMotion* column = state.motion.data() + start;
        [[maybe_unused]] const Vec2* remapped = state.remapped_velocity.data() + start;
        Pair along{}, across{};  // u_a, t_a
        [[maybe_unused]] Pair acceleration_a{}, velocity_a{};
        for (int b = 0; b < s.rows; ++b) {
          if constexpr (!apic) {
            velocity_a += w.value_y(b) * load_pair(&column[b].velocity_x);
            if constexpr (Scheme == UpdateScheme::usl) {
              acceleration_a += w.value_y(b) * load_pair(&column[b].acceleration_x);
            }
          }
          // The velocity field the gradient is taken of: MUSL's re-projected one, USL's v^L.
          const Pair u = Scheme == UpdateScheme::musl ? load_pair(remapped[b].data())
                                                      : load_pair(&column[b].velocity_x);
          along += w.value_y(b) * u;
          across += w.derivative_y(b) * u;
        }
        gradient_x += w.derivative_x(a) * along;
        gradient_y += w.value_x(a) * across;
        if constexpr (!apic) {
          velocity += w.value_x(a) * velocity_a;
          acceleration += w.value_x(a) * acceleration_a;
        }
      }
    });
    double vx = velocity[0], vy = velocity[1];
    Vec2& v = particles.velocity[p];
    if constexpr (apic) {
      // v_p and C_p from v^L (for linear hats C_p is the gradient of v^L). MUSL: the
      // velocity pass did this already.
      if constexpr (Scheme == UpdateScheme::usl) {
        on_stencil(w, [&](const auto& s) {
          const AffineGather g = gather_affine(state, rows, w, ParticleAffine<Shape>(w), s);
          v = g.velocity();
          particles.affine_velocity[p] = g.affine_velocity(w.inv_h);
        });
      }
      vx = v.x();  // Σ N v^L: the position update's velocity
      vy = v.y();
    } else if constexpr (Scheme == UpdateScheme::usl) {
      v.x() = flip * (v.x() + step.dt_velocity * acceleration[0]) + pic_fraction * vx;
      v.y() = flip * (v.y() + step.dt_velocity * acceleration[1]) + pic_fraction * vy;
    }
    const Vec2 dx(step.dt * vx, step.dt * vy);
    kinetic += 0.5 * particles.mass[p] * v.squaredNorm();
    const Vec4 l = Vec4(gradient_x[0], gradient_y[0], gradient_x[1], gradient_y[1]) * w.inv_h;
    if constexpr (Smoothing == VolumetricSmoothing::none) {
      particles.coordinates[p] += dx;
      particles.displacement[p] += dx;
      // The stress update while the particle is in registers: no per-particle scratch
      // array for the velocity gradient.
      update_stress(particles, models, step.dt, l, p);
    } else {
      blocks.step_displacement[p] = dx;
      blocks.velocity_gradient[p] = l;
      const double volume = particles.volume[p];
      CellSums& cell = window[w.cell_slot(rows) - offset];
      cell.volume += volume;
      cell.volumetric_rate += volume * (l[0] + l[3]);
      cell.mean_stress += volume * mean_stress(particles.stress[p]);
    }
  }
  return kinetic;
}

/// The second half of a smoothed final pass over one block: the particle takes its cell's
/// mean stress and, in L_p, its cell's volumetric rate; then the stress and volume update
/// and the move.
template <class Shape>
void smooth_block(Particles& particles, const GridGeometry& grid, const GridState& state, double dt,
                  std::span<const ConstitutiveModel> models, const ParticleBlocks& blocks,
                  std::size_t begin, std::size_t end) {
  const ParticleWeights<Shape>* const weights = step_weights<Shape>(blocks);
  const auto rows = static_cast<std::size_t>(grid.node_rows());
  // Each particle's stress shifted to its cell's mean, σ_ii += p_p − p̄ (p compression
  // positive: the deviator kept), and its velocity gradient with the cell's volumetric
  // rate in place of its own.
  const auto smooth = [&](std::size_t p) {
    const CellAverages& cell = state.cell_averages[weights[p].cell_slot(rows)];
    Vec4& stress = particles.stress[p];
    const double pressure_shift = mean_stress(stress) - cell.mean_stress;
    stress[0] += pressure_shift;
    stress[1] += pressure_shift;
    stress[2] += pressure_shift;
    const Vec4& l = blocks.velocity_gradient[p];
    const double rate_shift = 0.5 * (cell.volumetric_rate - (l[0] + l[3]));
    return Vec4(l[0] + rate_shift, l[1], l[2], l[3] + rate_shift);
  };
  const auto move = [&](std::size_t p) {
    const Vec2& dx = blocks.step_displacement[p];
    particles.coordinates[p] += dx;
    particles.displacement[p] += dx;
  };
  // Two particles at a time: their stress updates side by side (update_stress_pair).
  std::size_t p = begin;
  for (; p + 1 < end; p += 2) {
    const Vec4 l_p = smooth(p), l_q = smooth(p + 1);
    if (pairs_with_next(particles, models, p)) {
      update_stress_pair(particles, models, dt, l_p, l_q, p);
    } else {
      update_stress(particles, models, dt, l_p, p);
      update_stress(particles, models, dt, l_q, p + 1);
    }
    move(p);
    move(p + 1);
  }
  if (p < end) {
    update_stress(particles, models, dt, smooth(p), p);
    move(p);
  }
}

}  // namespace

void move_particle(Particles& p, std::size_t to, std::size_t from) {
  move_row(particle_fields, p, to, from);
}

namespace {

/// Particle k takes the place of old particle order[k] (`order` is a permutation of
/// [0, n)), in place, field by field along the permutation's cycles (RowCycles): no second
/// copy of any field; the sort of a nearly sorted body has short, local cycles, so it is
/// cache-friendly too.
void permute_in_place(Particles& particles, std::vector<std::uint32_t>& order) {
  permute_rows(particle_fields, particles, order);
}

}  // namespace

void ParticleBlocks::partition(std::size_t active_count) {
  std::size_t n_blocks = 1;
  if (active_count >= block_multiple * smallest_block) {
    const std::size_t per_round = block_multiple * particles_per_block_target;
    n_blocks = block_multiple * ((active_count + per_round - 1) / per_round);
  } else if (active_count > smallest_block) {
    n_blocks = active_count / smallest_block;
  }
  // Below this many particles a fork/join per kernel costs more than it saves.
  parallel = n_blocks > 1 && active_count >= 8192;
  offsets.resize(n_blocks + 1);
  for (std::size_t b = 0; b <= n_blocks; ++b) offsets[b] = b * active_count / n_blocks;
  column_begin.assign(n_blocks, 0);
  column_end.assign(n_blocks, 0);
  sums_window.resize(n_blocks);
  momentum_window.resize(n_blocks);
  cell_window.resize(n_blocks);
  kinetic_energy.assign(n_blocks, 0.0);
}

std::size_t ParticleBlocks::bytes() const {
  std::size_t total = offsets.capacity() * sizeof(std::size_t) +
                      (column_begin.capacity() + column_end.capacity()) * sizeof(int) +
                      kinetic_energy.capacity() * sizeof(double);
  for (const auto& w : sums_window) total += w.capacity() * sizeof(NodeSums);
  for (const auto& w : momentum_window) total += w.capacity() * sizeof(Vec2);
  for (const auto& w : cell_window) total += w.capacity() * sizeof(CellSums);
  total += velocity_gradient.capacity() * sizeof(Vec4) +
           step_displacement.capacity() * sizeof(Vec2) + shape_weights.capacity();
  return total;
}

LocateResult locate_particles(const Particles& particles, std::size_t active_count,
                              const GridGeometry& grid, ShapeFunction shape,
                              ParticleBlocks& blocks) {
  if (blocks.count() == 0 || blocks.offsets.back() != active_count) blocks.partition(active_count);
  const auto nblocks = static_cast<int>(blocks.count());
  std::vector<std::int64_t> non_finite(blocks.count(), -1);
  std::vector<std::vector<std::size_t>> outside(blocks.count());
#pragma omp parallel for schedule(dynamic, 1) if (blocks.parallel)
  for (int b = 0; b < nblocks; ++b) {
    const auto k = static_cast<std::size_t>(b);
    auto locate =
        shape == ShapeFunction::gimp ? locate_block<GimpShape> : locate_block<LinearShape>;
    locate(particles, grid, blocks.offsets[k], blocks.offsets[k + 1], blocks.column_begin[k],
           blocks.column_end[k], non_finite[k], outside[k]);
  }
  LocateResult result;
  for (std::size_t b = 0; b < blocks.count(); ++b) {
    if (result.non_finite < 0) result.non_finite = non_finite[b];
    result.outside.insert(result.outside.end(), outside[b].begin(), outside[b].end());
  }
  return result;
}

Vec2 affine_inertia(const GridGeometry& grid, ShapeFunction shape, const Vec2& position,
                    const Vec2& size) {
  return shape == ShapeFunction::gimp ? inertia_at<GimpShape>(grid, position, size)
                                      : inertia_at<LinearShape>(grid, position, size);
}

void particles_to_grid(const Particles& particles, const GridGeometry& grid, ShapeFunction shape,
                       VelocityTransfer transfer, const Vec2& gravity, ParticleBlocks& blocks,
                       GridState& state, const Reservoir& reservoir) {
  const auto rows = static_cast<std::size_t>(grid.node_rows());
  const auto nblocks = static_cast<int>(blocks.count());
  int active_begin = std::numeric_limits<int>::max(), active_end = 0;
  for (std::size_t b = 0; b < blocks.count(); ++b) {
    if (blocks.column_end[b] <= blocks.column_begin[b]) continue;
    active_begin = std::min(active_begin, blocks.column_begin[b]);
    active_end = std::max(active_end, blocks.column_end[b]);
  }
  if (active_end == 0) active_begin = 0;
  state.active_begin = active_begin;
  state.active_end = active_end;
  state.parallel = blocks.parallel;
  const std::size_t active = blocks.offsets.empty() ? 0 : blocks.offsets.back();
  blocks.shape_weights.resize(active * (shape == ShapeFunction::gimp
                                            ? sizeof(ParticleWeights<GimpShape>)
                                            : sizeof(ParticleWeights<LinearShape>)));
#pragma omp parallel for schedule(dynamic, 1) if (blocks.parallel)
  for (int b = 0; b < nblocks; ++b) {
    const auto k = static_cast<std::size_t>(b);
    auto& window = blocks.sums_window[k];
    const auto width = static_cast<std::size_t>(blocks.column_end[k] - blocks.column_begin[k]);
    window.assign(width * rows, NodeSums{});
    using Scatter =
        void (*)(const Particles&, const GridGeometry&, const Vec2&, const Reservoir&, std::size_t,
                 std::size_t, int, std::vector<NodeSums>&, ParticleBlocks&);
    const bool apic = transfer == VelocityTransfer::apic;
    Scatter scatter = nullptr;
    if (shape == ShapeFunction::gimp) {
      scatter = apic ? scatter_block<GimpShape, VelocityTransfer::apic>
                     : scatter_block<GimpShape, VelocityTransfer::flip_pic>;
    } else {
      scatter = apic ? scatter_block<LinearShape, VelocityTransfer::apic>
                     : scatter_block<LinearShape, VelocityTransfer::flip_pic>;
    }
    scatter(particles, grid, gravity, reservoir, blocks.offsets[k], blocks.offsets[k + 1],
            blocks.column_begin[k], window, blocks);
  }
}

void sum_node_windows(const GridGeometry& grid, const ParticleBlocks& blocks, GridState& state) {
  const auto rows = static_cast<std::size_t>(grid.node_rows());
  auto add = [](NodeSums& to, const NodeSums& from) {
    to.mass += from.mass;
    to.momentum_x += from.momentum_x;
    to.momentum_y += from.momentum_y;
    to.force_x += from.force_x;
    to.force_y += from.force_y;
  };
#pragma omp parallel for schedule(static) if (state.parallel)
  for (int column = state.active_begin; column < state.active_end; ++column) {
    const std::size_t first = static_cast<std::size_t>(column) * rows;
    sum_column(blocks, blocks.sums_window, column, rows, state.sums.data() + first, NodeSums{},
               add);
  }
}

double update_nodes(const GridGeometry& grid, const GridBoundaries& boundaries,
                    const NodalDamping& damping, double dt_velocity, double mass_floor,
                    GridState& state) {
  const auto rows = static_cast<std::size_t>(grid.node_rows());
  const Vec2 frame = boundaries.frame_velocity;
  double power = 0.0;
#pragma omp parallel for schedule(static) if (state.parallel) reduction(+ : power)
  for (int column = state.active_begin; column < state.active_end; ++column) {
    const std::size_t first = static_cast<std::size_t>(column) * rows;
    // A node shared with a neighbouring rank does its work on the rank that owns it.
    const bool own = column >= state.own_begin && column < state.own_end;
    for (std::size_t row = 0; row < rows; ++row) {
      const NodeSums& s = state.sums[first + row];
      NodeMotion& motion = state.motion[first + row];
      if (!(s.mass > mass_floor)) {
        motion = NodeMotion{};
        continue;
      }
      const Vec2 velocity(s.momentum_x / s.mass, s.momentum_y / s.mass);
      const Vec2 trial =
          damped_trial_velocity(s.mass, velocity, Vec2(s.force_x, s.force_y), dt_velocity, damping);
      std::array<NodalConstraint, 2> constraints;
      const int count =
          boundaries.constraints_of(grid, column - 1, static_cast<int>(row) - 1, constraints);
      // Constraints act on the velocity relative to the moving base (zero: at rest).
      const Vec2 end_velocity =
          count == 0 ? trial
                     : frame + apply_constraints(
                                   std::span(constraints.data(), static_cast<std::size_t>(count)),
                                   boundaries.friction_coefficient, trial - frame);
      if (boundaries.moving && count > 0 && own) {
        power += s.mass * (end_velocity - trial).dot(end_velocity) / dt_velocity;
      }
      const Vec2 acceleration = (end_velocity - velocity) / dt_velocity;
      motion = {acceleration.x(), acceleration.y(), end_velocity.x(), end_velocity.y()};
    }
  }
  return power;
}

double update_grid(const GridGeometry& grid, const GridBoundaries& boundaries,
                   const NodalDamping& damping, double dt_velocity, double mass_floor,
                   const ParticleBlocks& blocks, GridState& state) {
  sum_node_windows(grid, blocks, state);
  return update_nodes(grid, boundaries, damping, dt_velocity, mass_floor, state);
}

void remap_momenta(Particles& particles, const GridGeometry& grid, ShapeFunction shape,
                   VelocityTransfer transfer, const StepLengths& step, double pic_fraction,
                   ParticleBlocks& blocks, GridState& state) {
  const auto rows = static_cast<std::size_t>(grid.node_rows());
  const auto nblocks = static_cast<int>(blocks.count());
#pragma omp parallel for schedule(dynamic, 1) if (blocks.parallel)
  for (int b = 0; b < nblocks; ++b) {
    const auto k = static_cast<std::size_t>(b);
    auto& window = blocks.momentum_window[k];
    const auto width = static_cast<std::size_t>(blocks.column_end[k] - blocks.column_begin[k]);
    window.assign(width * rows, Vec2::Zero());
    using Remap =
        void (*)(Particles&, const GridGeometry&, const GridState&, const StepLengths&, double,
                 std::size_t, std::size_t, int, std::vector<Vec2>&, ParticleBlocks&);
    const bool apic = transfer == VelocityTransfer::apic;
    Remap remap = nullptr;
    if (shape == ShapeFunction::gimp) {
      remap = apic ? velocity_and_remap_block<GimpShape, VelocityTransfer::apic>
                   : velocity_and_remap_block<GimpShape, VelocityTransfer::flip_pic>;
    } else {
      remap = apic ? velocity_and_remap_block<LinearShape, VelocityTransfer::apic>
                   : velocity_and_remap_block<LinearShape, VelocityTransfer::flip_pic>;
    }
    remap(particles, grid, state, step, pic_fraction, blocks.offsets[k], blocks.offsets[k + 1],
          blocks.column_begin[k], window, blocks);
  }
  // Momenta summed in block order.
#pragma omp parallel for schedule(static) if (blocks.parallel)
  for (int column = state.active_begin; column < state.active_end; ++column) {
    const std::size_t first = static_cast<std::size_t>(column) * rows;
    sum_column(blocks, blocks.momentum_window, column, rows, state.remapped_velocity.data() + first,
               Vec2::Zero().eval(), [](Vec2& to, const Vec2& from) { to += from; });
  }
}

void finish_remapped_velocities(const GridGeometry& grid, const GridBoundaries& boundaries,
                                double mass_floor, GridState& state) {
  const auto rows = static_cast<std::size_t>(grid.node_rows());
  // Momentum → velocity, with the kinematic part of the edge constraints (μ = 0 turns a
  // friction edge into a roller).
#pragma omp parallel for schedule(static) if (state.parallel)
  for (int column = state.active_begin; column < state.active_end; ++column) {
    const std::size_t first = static_cast<std::size_t>(column) * rows;
    for (std::size_t row = 0; row < rows; ++row) {
      const double m = state.sums[first + row].mass;
      Vec2& v = state.remapped_velocity[first + row];
      if (!(m > mass_floor)) {
        v.setZero();
        continue;
      }
      v /= m;
      std::array<NodalConstraint, 2> constraints;
      const int count =
          boundaries.constraints_of(grid, column - 1, static_cast<int>(row) - 1, constraints);
      if (count > 0) {
        v = boundaries.frame_velocity +
            apply_constraints(std::span(constraints.data(), static_cast<std::size_t>(count)), 0.0,
                              v - boundaries.frame_velocity);
      }
    }
  }
}

void update_particle_velocities_and_remap(Particles& particles, const GridGeometry& grid,
                                          const GridBoundaries& boundaries, ShapeFunction shape,
                                          VelocityTransfer transfer, const StepLengths& step,
                                          double pic_fraction, double mass_floor,
                                          ParticleBlocks& blocks, GridState& state) {
  remap_momenta(particles, grid, shape, transfer, step, pic_fraction, blocks, state);
  finish_remapped_velocities(grid, boundaries, mass_floor, state);
}

namespace {

using Gather = double (*)(Particles&, const GridGeometry&, const GridState&, const StepLengths&,
                          double, std::span<const ConstitutiveModel>, std::size_t, std::size_t,
                          ParticleBlocks&, std::size_t);

template <class Shape, UpdateScheme Scheme, VelocityTransfer Transfer>
Gather gather_for(VolumetricSmoothing smoothing) {
  return smoothing == VolumetricSmoothing::cell
             ? gather_block<Shape, Scheme, Transfer, VolumetricSmoothing::cell>
             : gather_block<Shape, Scheme, Transfer, VolumetricSmoothing::none>;
}

template <class Shape, UpdateScheme Scheme>
Gather gather_for(VelocityTransfer transfer, VolumetricSmoothing smoothing) {
  return transfer == VelocityTransfer::apic
             ? gather_for<Shape, Scheme, VelocityTransfer::apic>(smoothing)
             : gather_for<Shape, Scheme, VelocityTransfer::flip_pic>(smoothing);
}

template <class Shape>
Gather gather_for(UpdateScheme scheme, VelocityTransfer transfer, VolumetricSmoothing smoothing) {
  return scheme == UpdateScheme::musl ? gather_for<Shape, UpdateScheme::musl>(transfer, smoothing)
                                      : gather_for<Shape, UpdateScheme::usl>(transfer, smoothing);
}

/// The cell averages of the blocks' windows, column by column (sums in block order).
/// A slot no particle sits in keeps zeros; no particle reads it.
void average_cells(const GridGeometry& grid, const ParticleBlocks& blocks, GridState& state) {
  const auto rows = static_cast<std::size_t>(grid.node_rows());
  std::vector<CellSums> column_sums(rows);
#pragma omp parallel for schedule(static) firstprivate(column_sums) if (state.parallel)
  for (int column = state.active_begin; column < state.active_end; ++column) {
    sum_column(blocks, blocks.cell_window, column, rows, column_sums.data(), CellSums{},
               [](CellSums& to, const CellSums& from) {
                 to.volume += from.volume;
                 to.volumetric_rate += from.volumetric_rate;
                 to.mean_stress += from.mean_stress;
               });
    CellAverages* target = state.cell_averages.data() + static_cast<std::size_t>(column) * rows;
    for (std::size_t row = 0; row < rows; ++row) {
      const CellSums& sums = column_sums[row];
      target[row] = sums.volume > 0.0 ? CellAverages{sums.volumetric_rate / sums.volume,
                                                     sums.mean_stress / sums.volume}
                                      : CellAverages{};
    }
  }
}

}  // namespace

LocateResult grid_to_particles(Particles& particles, const GridGeometry& grid, ShapeFunction shape,
                               UpdateScheme scheme, VelocityTransfer transfer,
                               const StepLengths& step, double pic_fraction,
                               VolumetricSmoothing smoothing,
                               std::span<const ConstitutiveModel> models, ParticleBlocks& blocks,
                               GridState& state) {
  const auto nblocks = static_cast<int>(blocks.count());
  const bool gimp = shape == ShapeFunction::gimp;
  const Gather gather = gimp ? gather_for<GimpShape>(scheme, transfer, smoothing)
                             : gather_for<LinearShape>(scheme, transfer, smoothing);
  auto locate = gimp ? locate_block<GimpShape> : locate_block<LinearShape>;
  auto smooth = gimp ? smooth_block<GimpShape> : smooth_block<LinearShape>;
  std::vector<std::int64_t> non_finite(blocks.count(), -1);
  std::vector<std::vector<std::size_t>> outside(blocks.count());
  const bool smoothed = smoothing != VolumetricSmoothing::none;
  const std::size_t active = blocks.offsets.empty() ? 0 : blocks.offsets.back();
  if (smoothed) {
    blocks.step_displacement.resize(active);
    blocks.velocity_gradient.resize(active);
  }
  const auto rows = static_cast<std::size_t>(grid.node_rows());
  // Block by block: the gather with each particle's stress update, then (unsmoothed) the
  // location for the next step while the block's particles are still in cache.
#pragma omp parallel for schedule(dynamic, 1) if (blocks.parallel)
  for (int b = 0; b < nblocks; ++b) {
    const auto k = static_cast<std::size_t>(b);
    const std::size_t begin = blocks.offsets[k], end = blocks.offsets[k + 1];
    if (smoothed) {
      const auto width = static_cast<std::size_t>(blocks.column_end[k] - blocks.column_begin[k]);
      blocks.cell_window[k].assign(width * rows, CellSums{});
    }
    blocks.kinetic_energy[k] =
        gather(particles, grid, state, step, pic_fraction, models, begin, end, blocks, k);
    if (!smoothed) {
      locate(particles, grid, begin, end, blocks.column_begin[k], blocks.column_end[k],
             non_finite[k], outside[k]);
    }
  }
  if (smoothed) {
    average_cells(grid, blocks, state);
#pragma omp parallel for schedule(dynamic, 1) if (blocks.parallel)
    for (int b = 0; b < nblocks; ++b) {
      const auto k = static_cast<std::size_t>(b);
      const std::size_t begin = blocks.offsets[k], end = blocks.offsets[k + 1];
      smooth(particles, grid, state, step.dt, models, blocks, begin, end);
      locate(particles, grid, begin, end, blocks.column_begin[k], blocks.column_end[k],
             non_finite[k], outside[k]);
    }
  }
  LocateResult result;
  for (std::size_t b = 0; b < blocks.count(); ++b) {
    if (result.non_finite < 0) result.non_finite = non_finite[b];
    result.outside.insert(result.outside.end(), outside[b].begin(), outside[b].end());
  }
  return result;
}

void sort_particles_by_cell(Particles& particles, std::size_t active_count,
                            const GridGeometry& grid) {
  const std::size_t n = particles.count();
  if (n > RowCycles::max_rows) {
    throw Error("mpm: {} particles, more than the sort's {} (its 31-bit indices)", n,
                RowCycles::max_rows);
  }
  const std::size_t frozen_bucket = grid.cell_count();
  // Counting sort: each particle's cell once, bucket sizes, exclusive prefix sums, then a
  // stable placement.
  std::vector<std::uint32_t> order(n);
  {
    std::vector<std::uint32_t> key(n);
    for (std::size_t p = 0; p < n; ++p) {
      key[p] = static_cast<std::uint32_t>(p < active_count ? grid.cell_of(particles.coordinates[p])
                                                           : frozen_bucket);
    }
    std::vector<std::uint32_t> start(frozen_bucket + 2, 0);
    for (std::size_t p = 0; p < n; ++p) ++start[key[p] + 1];
    for (std::size_t c = 1; c < start.size(); ++c) start[c] += start[c - 1];
    for (std::size_t p = 0; p < n; ++p) order[start[key[p]]++] = static_cast<std::uint32_t>(p);
  }
  permute_in_place(particles, order);
}

std::size_t retire_particles(Particles& particles, std::size_t active_count,
                             std::span<const std::size_t> indices, ParticleExit mode) {
  const std::size_t n = particles.count();
  std::vector<std::uint32_t> order;
  order.reserve(n);
  std::vector<std::uint8_t> leaving(n, 0);
  for (std::size_t p : indices) leaving[p] = 1;
  for (std::size_t p = 0; p < active_count; ++p) {
    if (!leaving[p]) order.push_back(static_cast<std::uint32_t>(p));
  }
  const std::size_t new_active = order.size();
  if (mode == ParticleExit::freeze) {
    for (std::size_t p : indices) {
      particles.velocity[p].setZero();
      if (!particles.affine_velocity.empty()) particles.affine_velocity[p].setZero();
      order.push_back(static_cast<std::uint32_t>(p));
    }
  }
  for (std::size_t p = active_count; p < n; ++p) order.push_back(static_cast<std::uint32_t>(p));
  const std::size_t kept = order.size();
  // Removed particles go last (the in-place move needs a whole permutation), then are cut.
  if (mode == ParticleExit::remove) {
    for (std::size_t p : indices) order.push_back(static_cast<std::uint32_t>(p));
  }
  permute_in_place(particles, order);
  particles.resize(kept);
  return new_active;
}

}  // namespace slide::mpm
