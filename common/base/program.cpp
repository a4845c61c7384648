#include "common/base/program.hpp"

#include <atomic>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <string>

#include <fmt/format.h>

namespace slide {

std::string version_string() {
  return "slide " SLIDE_VERSION " (commit " SLIDE_COMMIT ")";
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
    fmt::print(stderr, "{}: error: {} (see {} --help)\n", app.get_name(), printable_line(e.what()),
               app.get_name());
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

namespace {

/// The length of the well-formed UTF-8 sequence at the start of `text` (RFC 3629: no
/// overlong forms, no surrogates, nothing above U+10FFFF), or 0 if there is none.
std::size_t utf8_sequence_length(std::string_view text) {
  const auto byte = [&](std::size_t i) { return static_cast<unsigned char>(text[i]); };
  const unsigned char lead = byte(0);
  if (lead < 0x80) return 1;
  std::size_t length = 0;
  unsigned char low = 0x80;  // the admissible range of the second byte
  unsigned char high = 0xbf;
  if (lead >= 0xc2 && lead <= 0xdf) {
    length = 2;
  } else if (lead >= 0xe0 && lead <= 0xef) {
    length = 3;
    if (lead == 0xe0) low = 0xa0;
    if (lead == 0xed) high = 0x9f;
  } else if (lead >= 0xf0 && lead <= 0xf4) {
    length = 4;
    if (lead == 0xf0) low = 0x90;
    if (lead == 0xf4) high = 0x8f;
  } else {
    return 0;
  }
  if (text.size() < length) return 0;
  if (byte(1) < low || byte(1) > high) return 0;
  for (std::size_t i = 2; i < length; ++i) {
    if (byte(i) < 0x80 || byte(i) > 0xbf) return 0;
  }
  return length;
}

}  // namespace

std::string printable_line(std::string_view text) {
  std::string line;
  line.reserve(text.size());
  while (!text.empty()) {
    const auto lead = static_cast<unsigned char>(text[0]);
    const std::size_t length = utf8_sequence_length(text);
    if (lead == '\n') {
      line += "\\n";
    } else if (lead == '\t') {
      line += "\\t";
    } else if (length == 0 || lead < 0x20 || lead == 0x7f) {
      line += fmt::format("\\x{:02x}", lead);
    } else {
      line += text.substr(0, length);
      text.remove_prefix(length - 1);
    }
    text.remove_prefix(1);
  }
  return line;
}

namespace {
std::atomic<bool> damaged_library{false};
}  // namespace

void mark_library_damaged() {
  damaged_library = true;
}

int end_if_library_damaged(int status) {
  if (!damaged_library) return status;
  std::fflush(nullptr);
  std::_Exit(status);
}

int run_main(const std::string& program, const std::function<void()>& body) {
  try {
    body();
    return 0;
  } catch (const std::bad_alloc&) {
    fmt::print(stderr, "{}: error: out of memory\n", program);
  } catch (const std::exception& e) {
    fmt::print(stderr, "{}: error: {}\n", program, printable_line(e.what()));
  }
  return end_if_library_damaged(1);
}

}  // namespace slide
