#include "common/program.hpp"

#include <exception>

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
