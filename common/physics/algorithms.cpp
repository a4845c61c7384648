#include "common/physics/algorithms.hpp"

namespace slide {

std::string_view to_string(Kinematics kinematics) {
  return name_of(kinematics_names, kinematics);
}
std::string_view to_string(MotionSource source) {
  return name_of(motion_source_names, source);
}
std::string_view to_string(SeismicBase base) {
  return name_of(seismic_base_names, base);
}
std::string_view to_string(LateralBoundary lateral) {
  return name_of(lateral_boundary_names, lateral);
}
std::string_view to_string(MotionInput input) {
  return name_of(motion_input_names, input);
}
std::string_view to_string(StressInterpolation interpolation) {
  return name_of(interpolation_names, interpolation);
}
std::string_view to_string(RbfPolynomial polynomial) {
  return name_of(polynomial_names, polynomial);
}
std::string_view to_string(ShapeFunction shape_function) {
  return name_of(shape_function_names, shape_function);
}
std::string_view to_string(UpdateScheme scheme) {
  return name_of(update_scheme_names, scheme);
}
std::string_view to_string(VelocityTransfer transfer) {
  return name_of(velocity_transfer_names, transfer);
}
std::string_view to_string(VolumetricSmoothing smoothing) {
  return name_of(volumetric_smoothing_names, smoothing);
}

}  // namespace slide
