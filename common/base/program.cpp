#include "common/base/program.hpp"

#include <cmath>
#include <exception>
#include <string>

#include <fmt/format.h>

namespace slide {

std::string version_string() {
  return "slide " SLIDE_VERSION;
}

std::optional<int> parse_command_line(CLI::App& app, int argc, char** argv) {
  app.set_version_flag("--version", version_string());
  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp&) {
    fmt::print("{}", app.help());
    return 0;
  } catch (const CLI::CallForAllHelp&) {
    fmt::print("{}", app.help("", CLI::AppFormatMode::All));
    return 0;
  } catch (const CLI::CallForVersion&) {
    fmt::print("{}\n", version_string());
    return 0;
  } catch (const CLI::ParseError& e) {
    fmt::print(stderr, "{}: error: {} (see {} --help)\n", app.get_name(), e.what(), app.get_name());
    return 2;
  }
  return std::nullopt;
}

namespace {

CLI::Validator number_check(const char* description, bool (*admissible)(double)) {
  return CLI::Validator(
      [description, admissible](std::string& text) -> std::string {
        double value = 0.0;
        std::size_t used = 0;
        try {
          value = std::stod(text, &used);
        } catch (const std::exception&) {
          used = 0;
        }
        if (used != text.size() || used == 0) return "'" + text + "' is not a number";
        if (!std::isfinite(value) || !admissible(value)) {
          return "must be " + std::string(description) + ", got " + text;
        }
        return {};
      },
      description);
}

}  // namespace

CLI::Validator positive_number() {
  return number_check("> 0", [](double v) { return v > 0.0; });
}

CLI::Validator non_negative_number() {
  return number_check(">= 0", [](double v) { return v >= 0.0; });
}

int run_main(const std::string& program, const std::function<void()>& body) {
  try {
    body();
    return 0;
  } catch (const std::bad_alloc&) {
    fmt::print(stderr, "{}: error: out of memory\n", program);
  } catch (const std::exception& e) {
    fmt::print(stderr, "{}: error: {}\n", program, e.what());
  }
  return 1;
}

}  // namespace slide
