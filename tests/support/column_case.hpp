// A small column case file for the fem-solve command-line tests.
#pragma once

#include <string>

namespace slide::testing {

/// A column case for fem-solve: `width` × `height` m of the soil on a rough base, the
/// right face released in the failure stage (docs/method.md §7 column cases, scaled down).
struct ColumnCase {
  std::string name = "test-column";
  double width = 10.0;
  double height = 8.0;
  double element_size = 1.0;
  std::string element = "quad4-1gp";
  std::string model = "mohr-coulomb";
  std::string kinematics = "small-strain";
  double end_time = 0.4;
  double checkpoint_every = 0.2;
  double output_every = 0.1;
  double cohesion = 1000.0;
  double friction_angle = 22.2;
  double time_step = 0.0;
  /// Replaces the generated [mesh] table when not empty.
  std::string mesh;
  /// More lines of the material table (a porosity and its conductivity).
  std::string extra_material;
  /// More lines of the [fem] table.
  std::string extra_fem;
  std::string geostatic_boundaries = "left = \"roller\"\nright = \"roller\"\nbase = \"roller\"\n";
  std::string failure_boundaries = "left = \"roller\"\nright = \"free\"\nbase = \"friction\"\n";

  std::string text() const {
    const std::string mesh_table = !mesh.empty()
                                       ? mesh
                                       : "[mesh]\ngenerator = \"profile\"\nelement = \"" + element +
                                             "\"\nelement_size = " + std::to_string(element_size) +
                                             "\nsurface = [[0.0, " + std::to_string(height) +
                                             "], [" + std::to_string(width) + ", " +
                                             std::to_string(height) + "]]\nmaterial = \"soil\"\n";
    return "[case]\nname = \"" + name + "\"\n\n[[materials]]\nname = \"soil\"\nmodel = \"" + model +
           "\"\ndensity = 1700.0\nyoungs_modulus = 23.8e6\npoisson_ratio = 0.23\n"
           "friction_angle = " +
           std::to_string(friction_angle) + "\ncohesion = " + std::to_string(cohesion) + "\n" +
           extra_material + "\n" + mesh_table + "\n[fem]\nkinematics = \"" + kinematics +
           "\"\nend_time = " + std::to_string(end_time) +
           "\ncheckpoint_every = " + std::to_string(checkpoint_every) +
           "\noutput_every = " + std::to_string(output_every) +
           "\ntime_step = " + std::to_string(time_step) + "\nfriction_coefficient = 0.466\n" +
           extra_fem + "\n[fem.geostatic.boundaries]\n" + geostatic_boundaries +
           "\n[fem.failure.boundaries]\n" + failure_boundaries +
           "\n[mpm]\ndomain = [[0.0, 0.0], [40.0, 20.0]]\ncell_size = 1.0\nend_time = 1.0\n"
           "friction_coefficient = 0.466\n\n[mpm.boundaries]\nleft = \"roller\"\n"
           "right = \"roller\"\nbase = \"friction\"\ntop = \"free\"\n\n[metrics]\n"
           "initial_length = " +
           std::to_string(width) + "\ninitial_height = " + std::to_string(height) + "\n";
  }
};

}  // namespace slide::testing
