// Particle recorders ([[mpm.recorders]], docs/method.md §8): time histories of chosen
// material points, as fem-solve's recorders keep nodes', one CSV per recorder in
// OUT/recorders/<name>.csv (common/run/recorder_file.hpp: rows kept in memory, written at
// every checkpoint and at the end, continued by a restart).
//
// A recorder follows, for each of its points, the particle whose reference position
// x − u (where it was at t = 0, the start of the failure stage) is nearest the point, the
// lowest id among equals: the choice is the same on a fresh run, a restart and any number
// of ranks, and a point on the slope's surface before the failure follows the soil that
// was there. Per particle of id k the columns are pk_x, pk_y (position), pk_ux, pk_uy
// (displacement since t = 0), pk_vx, pk_vy, pk_sxx, pk_syy, pk_szz, pk_sxy (Pa, tension
// positive) and pk_eq (εq); a run with pore water adds pk_p (pore pressure, Pa). A
// particle the run removed (particle_exit = "remove") reads nan.
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "common/base/log.hpp"
#include "common/run/recorder_file.hpp"
#include "common/settings/mpm_spec.hpp"
#include "mpm/mpm_solver.hpp"

namespace slide::mpm {

class ParticleRecorders {
 public:
  /// Picks each recorder's particles from the solver's current ones (collective); Error
  /// when a name is too long for a file.
  ParticleRecorders(const MpmSolver& solver, const std::vector<ParticleRecorderSpec>& specs,
                    std::filesystem::path folder);

  /// The rows of a run of `duration` s in steps of about `step` s, bounded
  /// (run::bound_recorders): Error before any recorder file is written.
  void bound(double duration, double step);
  /// On restart: keeps the rows of the existing files up to `time`.
  void resume(double time, const Logger& logger);
  /// A row of every recorder due at the solver's time (collective).
  void record(const MpmSolver& solver);
  /// Rewrites every file atomically (the root rank; collective, so that a failure ends
  /// every rank).
  void write(const Ranks& ranks) const;
  /// The particles each recorder follows, for the log.
  std::string describe() const;

 private:
  /// The rows of the particles `ids_` in the solver's arrays (npos: not on this rank),
  /// found again only when a sort or an exchange moved them.
  void locate(const Particles& particles);

  std::filesystem::path folder_;
  bool water_ = false;
  std::vector<std::vector<std::int64_t>> particles_;  ///< per recorder, the ids it follows
  std::vector<run::RecorderFile> files_;              ///< per recorder
  std::vector<std::int64_t> ids_;                     ///< every id followed, sorted, unique
  std::vector<std::size_t> rows_;                     ///< per id of ids_, its row or npos
};

}  // namespace slide::mpm
