// The algorithm choices of the three stages, with the spellings case files and reports
// use for them. Solver headers need these choices, not the case file: keeping them here
// lets a kernel header include a few enums instead of the whole case reader.
#pragma once

#include <array>
#include <cstddef>
#include <string_view>

#include "common/base/names.hpp"

namespace slide {

// ----------------------------------------------------------------------------- FEM

enum class Kinematics { small_strain, updated_lagrangian };

// ----------------------------------------------------------------------------- seismic

/// Where a base acceleration component comes from (docs/method.md §8).
enum class MotionSource { ricker, sine, file };
/// Rigid: the base nodes follow the motion (fixed, roller or frictional relative to it).
/// Compliant: Lysmer–Kuhlemeyer dashpots on the base and the incident wave as a force.
enum class SeismicBase { rigid, compliant };
/// The left and right edges while the failure stage runs: as fem.failure.boundaries say
/// (moving with the base), tied to each other (the periodic free field of level ground:
/// both components, or the horizontal one only) or viscous dashpots.
enum class LateralBoundary { boundaries, tied, tied_horizontal, viscous };
/// What the motion of a compliant base is: the incident (upgoing) wave at the base, or
/// the outcrop motion of the rock, twice the incident one.
enum class MotionInput { incident, outcrop };

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

// One table per enum (common/base/names.hpp) serves parsing (the case reader), to_string
// and the "expected one of" lists of the messages.

inline constexpr std::array<Named<Kinematics>, 2> kinematics_names{{
    {"small-strain", Kinematics::small_strain},
    {"updated-lagrangian", Kinematics::updated_lagrangian},
}};
inline constexpr std::array<Named<MotionSource>, 3> motion_source_names{{
    {"ricker", MotionSource::ricker},
    {"sine", MotionSource::sine},
    {"file", MotionSource::file},
}};
inline constexpr std::array<Named<SeismicBase>, 2> seismic_base_names{{
    {"rigid", SeismicBase::rigid},
    {"compliant", SeismicBase::compliant},
}};
inline constexpr std::array<Named<LateralBoundary>, 4> lateral_boundary_names{{
    {"boundaries", LateralBoundary::boundaries},
    {"tied", LateralBoundary::tied},
    {"tied-horizontal", LateralBoundary::tied_horizontal},
    {"viscous", LateralBoundary::viscous},
}};
inline constexpr std::array<Named<MotionInput>, 2> motion_input_names{{
    {"incident", MotionInput::incident},
    {"outcrop", MotionInput::outcrop},
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

std::string_view to_string(Kinematics kinematics);
std::string_view to_string(MotionSource source);
std::string_view to_string(SeismicBase base);
std::string_view to_string(LateralBoundary lateral);
std::string_view to_string(MotionInput input);
std::string_view to_string(StressInterpolation interpolation);
std::string_view to_string(RbfPolynomial polynomial);
std::string_view to_string(ShapeFunction shape_function);
std::string_view to_string(UpdateScheme scheme);
std::string_view to_string(VelocityTransfer transfer);
std::string_view to_string(VolumetricSmoothing smoothing);

}  // namespace slide
