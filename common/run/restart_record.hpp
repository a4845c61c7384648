// The restart record: what a checkpoint's /solver group holds so that a run continues
// from it (common/io/checkpoint-schema.md, "/solver"): the stage that wrote it, the counters
// of the stage's clock beyond the header's time and step, the instability guard's
// references, and the settings the state was computed with.
//
// Each stage lists its record once, as a table of entries (the /solver key, the member,
// the admissible values, whether files of earlier versions may lack it); write_record
// and read_record walk the table, so both stages write and read the group the same way,
// and every value is checked on reading: a missing key, a value of the wrong type or out
// of range is one line naming the file and the key, before anything is written.
// The settings a run ran with (the grid, the algorithms) are kept beside the record as
// plain key-value pairs: a restart compares them with its own and says what changed.
#pragma once

#include <cmath>
#include <cstdint>
#include <limits>
#include <optional>
#include <string>
#include <string_view>
#include <variant>
#include <vector>

#include <fmt/format.h>

#include "common/base/error.hpp"
#include "common/io/checkpoint.hpp"
#include "common/run/stability_guard.hpp"

namespace slide::run {

/// What both stages' records hold: the stage that wrote the checkpoint, the guard's
/// energy reference (E and the energy scale at the start of the stage, J/m; none before
/// the stage starts, e.g. in fem-solve's geostatic checkpoint) and the work the moving
/// boundaries of a shaken stage have done on the body (J/m; none without shaking).
struct RunRecord {
  std::string stage;
  std::optional<double> initial_energy;
  std::optional<double> energy_scale;
  std::optional<double> boundary_work;

  /// The energy reference, when the record has both values.
  std::optional<EnergyReference> energy() const {
    if (!initial_energy || !energy_scale) return std::nullopt;
    return EnergyReference{*initial_energy, *energy_scale};
  }
  void set_energy(const EnergyReference& reference) {
    initial_energy = reference.initial_energy;
    energy_scale = reference.energy_scale;
  }
};

inline constexpr double unbounded = std::numeric_limits<double>::infinity();

/// Whether files may lack an entry. required: an Error names it. optional: the member
/// keeps its value (a std::optional one stays empty), and a std::optional member is
/// written only when it has one.
enum class Need : std::uint8_t { required, optional };

/// One entry of a record table: the /solver key of `member`, the admissible range of a
/// number (finite, low ≤ value ≤ high; a flag is 0 or 1), and `alias`, the key earlier
/// versions wrote it under (read when the key is absent).
template <class Record>
struct RecordEntry {
  using Member = std::variant<double Record::*, std::optional<double> Record::*,
                              std::int64_t Record::*, bool Record::*, std::string Record::*>;
  std::string_view key;
  Member member;
  double low = -unbounded;
  double high = unbounded;
  Need need = Need::required;
  std::string_view alias = {};
};

/// The record as /solver attributes (a flag as 0 or 1).
template <class Record, class Table>
SolverSettings write_record(const Record& record, const Table& table) {
  SolverSettings settings;
  for (const RecordEntry<Record>& entry : table) {
    std::visit(
        [&](auto member) {
          const auto& value = record.*member;
          using T = std::remove_cvref_t<decltype(value)>;
          if constexpr (std::is_same_v<T, std::optional<double>>) {
            if (value) settings[std::string(entry.key)] = *value;
          } else if constexpr (std::is_same_v<T, bool>) {
            settings[std::string(entry.key)] = std::int64_t{value ? 1 : 0};
          } else {
            settings[std::string(entry.key)] = value;
          }
        },
        entry.member);
  }
  return settings;
}

namespace detail {

/// Error unless `value` is finite and within the entry's range.
template <class Record>
void check_range(const RecordEntry<Record>& entry, double value, std::string_view source) {
  if (std::isfinite(value) && value >= entry.low && value <= entry.high) return;
  const std::string expected =
      entry.high == unbounded
          ? (entry.low == -unbounded ? std::string("a finite value")
                                     : fmt::format("a finite value ≥ {}", entry.low))
          : fmt::format("a finite value in [{}, {}]", entry.low, entry.high);
  throw Error("{}: /solver attribute {} = {} is out of range (expected {})", source, entry.key,
              value, expected);
}

}  // namespace detail

/// The record of `settings` (a checkpoint's /solver group), every entry checked; Error
/// naming `source` and the key otherwise.
template <class Record, class Table>
Record read_record(const SolverSettings& settings, const Table& table, std::string_view source,
                   Record record = {}) {
  for (const RecordEntry<Record>& entry : table) {
    auto found = settings.find(std::string(entry.key));
    if (found == settings.end() && !entry.alias.empty())
      found = settings.find(std::string(entry.alias));
    if (found == settings.end()) {
      if (entry.need == Need::optional) continue;
      throw Error("{}: /solver attribute {} missing (not a checkpoint of this stage?)", source,
                  entry.key);
    }
    const SettingValue& value = found->second;
    const auto wrong_type = [&] {
      return Error("{}: /solver attribute {} has the wrong type", source, entry.key);
    };
    std::visit(
        [&](auto member) {
          auto& target = record.*member;
          using T = std::remove_cvref_t<decltype(target)>;
          if constexpr (std::is_same_v<T, std::string>) {
            const auto* text = std::get_if<std::string>(&value);
            if (!text) throw wrong_type();
            target = *text;
          } else if constexpr (std::is_same_v<T, double> ||
                               std::is_same_v<T, std::optional<double>>) {
            const auto* number = std::get_if<double>(&value);
            if (!number) throw wrong_type();
            detail::check_range(entry, *number, source);
            target = *number;
          } else {
            const auto* integer = std::get_if<std::int64_t>(&value);
            if (!integer) throw wrong_type();
            const bool flag = std::is_same_v<T, bool>;
            if (flag && *integer != 0 && *integer != 1) {
              throw Error("{}: /solver attribute {} = {} is out of range (expected 0 or 1)", source,
                          entry.key, *integer);
            }
            detail::check_range(entry, static_cast<double>(*integer), source);
            target = static_cast<T>(*integer);
          }
        },
        entry.member);
  }
  return record;
}

/// The entries of `ran_with` that `stored` records with another value ("key: old →
/// new"), to report when a restart runs with an edited case.
std::vector<std::string> changed_settings(const SolverSettings& stored,
                                          const SolverSettings& ran_with);

/// `settings` with the entries of `more` added.
SolverSettings merged(SolverSettings settings, const SolverSettings& more);

}  // namespace slide::run
