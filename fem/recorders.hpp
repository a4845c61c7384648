// Recorders (docs/method.md §8): time histories of chosen nodes and elements, as users of
// OpenSees keep them, one CSV per recorder in OUT/recorders/<name>.csv.
//
// Node recorders ([[fem.recorders]] with `points`, the node nearest each point, or
// `node_set`) write, per node k, n<k>_ux, n<k>_uy, n<k>_vx, …, n<k>_ay (absolute) and the
// same with _rel (relative to the base), after the base's own columns base_ux … base_ay.
// Element recorders (`elements`, the element whose centroid is nearest each point)
// write e<k>_sxx, e<k>_syy, e<k>_szz, e<k>_sxy, e<k>_exx, e<k>_eyy, e<k>_ezz, e<k>_gxy,
// the mean over the element's Gauss points (Pa, tension positive; strain since t = 0).
// A saturated model (fem/pore_fluid.hpp) adds per node n<k>_p and n<k>_dp (pore pressure
// and its excess over the state before shaking, Pa) and per element e<k>_p and e<k>_ru
// (the means of p and of the pore-pressure ratio over its Gauss points).
//
// The values are the leapfrog's own: u at t, v over the step that ended at t (t − dt/2),
// a = F/m at the start of that step (t − dt); the base's columns are taken at the same
// instants from the motion, so relative values compare like with like. The base is the input motion
// of a rigid base, the mean of the base nodes of a compliant one, zero for a static base.
//
// Rows are kept in memory and each file is rewritten whole and atomically at every
// checkpoint and at the end of the run (common/run/recorder_file.hpp): a killed run
// leaves complete files up to its last checkpoint, from which a restart continues them.
// A recorder of many nodes recorded at every step grows by about 150 bytes per node and
// step: give it `every`.
#pragma once

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "common/base/log.hpp"
#include "common/physics/ground_motion.hpp"
#include "common/run/recorder_file.hpp"
#include "common/settings/fem_spec.hpp"
#include "fem/fem_model.hpp"

namespace slide::fem {

class Recorders {
 public:
  /// `motion` is the motion of a rigid base (nullptr otherwise); `base_nodes` the nodes
  /// whose mean is the base of a compliant one (empty otherwise). Throws Error when a
  /// node set does not exist.
  Recorders(const FemModel& model, const std::vector<RecorderSpec>& specs,
            std::filesystem::path folder, const GroundMotion* motion,
            std::vector<Index> base_nodes);

  bool empty() const { return recorders_.empty(); }
  /// The rows the recorders hold in memory (and write) over a run of `duration` s in
  /// steps of `step` s, bounded (run::bound_recorders): Error before any file is written.
  void bound(double duration, double step, std::size_t limit = run::RecorderFile::limit_bytes);
  /// On restart: keeps the rows of the existing files up to `time`.
  void resume(double time, const Logger& logger);
  /// After a step of length `dt` that ended at state.time: a row where one is due.
  void record(const FemState& state, double dt);
  /// Rewrites every file atomically.
  void write() const;
  /// The nodes and elements each recorder follows, for the log.
  std::string describe() const;

 private:
  struct Recorder {
    std::vector<Index> nodes;
    std::vector<Index> elements;
    /// A node-set recorder of a saturated model: the drained faces (indices into
    /// model.fluid.faces) with both nodes in the set, whose outflow it records.
    std::optional<std::vector<std::size_t>> drained_faces;
  };

  const FemModel& model_;
  std::filesystem::path folder_;
  const GroundMotion* motion_;
  std::vector<Index> base_nodes_;
  std::vector<Recorder> recorders_;
  std::vector<run::RecorderFile> files_;  ///< one per recorder, in the same order
};

}  // namespace slide::fem
