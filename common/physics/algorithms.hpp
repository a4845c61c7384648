// The algorithm choices of the three stages, with the spellings case files and reports
// use for them. Solver headers need these choices, not the case file: keeping them here
// lets a kernel header include a few enums instead of the whole case reader.
#pragma once

#include <array>
#include <cstddef>
#include <string_view>

namespace slide {

// ----------------------------------------------------------------------------- FEM

enum class Kinematics { small_strain, updated_lagrangian };

// ----------------------------------------------------------------------------- transfer

enum class StressInterpolation { rbf, rbf_local, element };
enum class RbfPolynomial { none, linear };

// ----------------------------------------------------------------------------- MPM

enum class ShapeFunction { gimp, linear };
enum class UpdateScheme { usl, musl };
/// Grid → particle velocity transfer (docs/method.md §5, mpm/README.md "Velocity transfer"):
/// FLIP with an optional PIC share (`pic_fraction`), or APIC (affine particle-in-cell:
/// each particle carries an affine velocity matrix; no PIC share needed).
enum class VelocityTransfer { flip_pic, apic };
/// Volumetric anti-locking (docs/method.md §5, mpm/README.md "Volumetric smoothing"): none, or
/// the particles of a cell share its averaged mean stress and volumetric strain rate.
enum class VolumetricSmoothing { none, cell };
enum class ParticleExit { freeze, remove };
enum class InitialStress { k0, gravity };

// ----------------------------------------------------------------------------- spellings

/// The spelling of an enumerator in case files. One table per enum serves parsing (the
/// case reader), to_string and the "expected one of" lists of the messages.
template <typename E>
struct Named {
  std::string_view name;
  E value;
};

inline constexpr std::array<Named<Kinematics>, 2> kinematics_names{{
    {"small-strain", Kinematics::small_strain},
    {"updated-lagrangian", Kinematics::updated_lagrangian},
}};
inline constexpr std::array<Named<StressInterpolation>, 3> interpolation_names{{
    {"rbf", StressInterpolation::rbf},
    {"rbf-local", StressInterpolation::rbf_local},
    {"element", StressInterpolation::element},
}};
inline constexpr std::array<Named<RbfPolynomial>, 2> polynomial_names{{
    {"none", RbfPolynomial::none},
    {"linear", RbfPolynomial::linear},
}};
inline constexpr std::array<Named<ShapeFunction>, 2> shape_function_names{{
    {"gimp", ShapeFunction::gimp},
    {"linear", ShapeFunction::linear},
}};
inline constexpr std::array<Named<UpdateScheme>, 2> update_scheme_names{{
    {"usl", UpdateScheme::usl},
    {"musl", UpdateScheme::musl},
}};
inline constexpr std::array<Named<VelocityTransfer>, 2> velocity_transfer_names{{
    {"flip-pic", VelocityTransfer::flip_pic},
    {"apic", VelocityTransfer::apic},
}};
inline constexpr std::array<Named<VolumetricSmoothing>, 2> volumetric_smoothing_names{{
    {"none", VolumetricSmoothing::none},
    {"cell", VolumetricSmoothing::cell},
}};
inline constexpr std::array<Named<ParticleExit>, 2> particle_exit_names{{
    {"freeze", ParticleExit::freeze},
    {"remove", ParticleExit::remove},
}};
inline constexpr std::array<Named<InitialStress>, 2> initial_stress_names{{
    {"k0", InitialStress::k0},
    {"gravity", InitialStress::gravity},
}};

/// The spelling of `value` in `names`, "unknown" for a value the table lacks.
template <typename E, std::size_t N>
constexpr std::string_view name_of(const std::array<Named<E>, N>& names, E value) {
  for (const auto& named : names) {
    if (named.value == value) return named.name;
  }
  return "unknown";
}

std::string_view to_string(Kinematics kinematics);
std::string_view to_string(StressInterpolation interpolation);
std::string_view to_string(RbfPolynomial polynomial);
std::string_view to_string(ShapeFunction shape_function);
std::string_view to_string(UpdateScheme scheme);
std::string_view to_string(VelocityTransfer transfer);
std::string_view to_string(VolumetricSmoothing smoothing);

}  // namespace slide
