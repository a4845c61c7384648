// What a restart must find unchanged: the parts of a case that change the physics of a
// stage, each as one canonical line of text (a file the case names by a hash of its
// content), kept in the checkpoints' restart record (/solver, keys case_<part>). A restart
// from a checkpoint compares them with the case it is given: a part that differs is an
// error naming it, unless the user allows that part to change (--allow-changed PART).
// The end time and the output cadences are not among them: a restart may run further and
// write more or less often. Restarts used to take every change of a case (the Young's
// modulus, the motion, the boundaries, the damping, the step, the gravity angle…) without
// a word.
#pragma once

#include <string>
#include <vector>

#include "common/base/log.hpp"
#include "common/input/case_file.hpp"
#include "common/io/checkpoint.hpp"

namespace slide {

/// The parts fem-solve records: materials, gravity, mesh, boundaries, damping, step,
/// motion, recorders.
SolverSettings fem_fingerprint(const Case& c);
/// The parts mpm-solve records: materials, gravity, grid, algorithms, boundaries,
/// damping, step, rest, and for pure MPM the geometry and the motion.
SolverSettings mpm_fingerprint(const Case& c, bool pure_mpm);

/// The names of the parts (without the case_ prefix) a stage records, for --allow-changed.
std::vector<std::string> fingerprint_parts(const SolverSettings& fingerprint);

/// Error naming the first part of `now` whose line differs from the one `recorded` (a
/// checkpoint's /solver), unless `allowed` names it (its change is logged instead). A
/// checkpoint written before parts were recorded: one warning that changes go unchecked.
void check_unchanged(const SolverSettings& recorded, const SolverSettings& now,
                     const std::vector<std::string>& allowed, const std::string& source,
                     const Logger& log);

}  // namespace slide
