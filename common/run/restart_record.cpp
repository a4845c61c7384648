#include "common/run/restart_record.hpp"

namespace slide::run {

namespace {

std::string show(const SettingValue& v) {
  return std::visit([](const auto& x) { return fmt::format("{}", x); }, v);
}

}  // namespace

std::vector<std::string> changed_settings(const SolverSettings& stored,
                                          const SolverSettings& ran_with) {
  std::vector<std::string> changes;
  for (const auto& [key, value] : ran_with) {
    const auto found = stored.find(key);
    if (found == stored.end()) continue;
    if (found->second != value)
      changes.push_back(fmt::format("{} {} → {}", key, show(found->second), show(value)));
  }
  return changes;
}

SolverSettings merged(SolverSettings settings, const SolverSettings& more) {
  for (const auto& [key, value] : more) settings[key] = value;
  return settings;
}

}  // namespace slide::run
