#include "common/base/program.hpp"

#include <algorithm>
#include <atomic>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <string>

#include <fmt/format.h>
#include <unistd.h>

namespace slide {

void prefer_yielding_threads(char** argv) {
  if (std::getenv("OMP_WAIT_POLICY") != nullptr || std::getenv("GOMP_SPINCOUNT") != nullptr) return;
  const std::string setting = omp_wait_setting;
  const std::size_t equals = setting.find('=');
  if (setenv(setting.substr(0, equals).c_str(), setting.substr(equals + 1).c_str(), 1) != 0) return;
  execv("/proc/self/exe", argv);  // returns only on failure: run on as it is
}

std::string version_string() {
  return "slide " SLIDE_VERSION " (commit " SLIDE_COMMIT ")";
}

std::optional<int> parse_command_line(CLI::App& app, int argc, char** argv) {
  app.set_version_flag("--version", version_string());
  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp&) {
    fmt::print("{}", gnu_help(app));
    return 0;
  } catch (const CLI::CallForAllHelp&) {
    fmt::print("{}", gnu_help(app));
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

constexpr std::size_t help_width = 79;     // GNU: lines within 80 columns
constexpr std::size_t option_column = 30;  // where an option's meaning starts

/// Characters of UTF-8 text (what a terminal shows), for the columns.
std::size_t shown_width(std::string_view text) {
  return static_cast<std::size_t>(std::ranges::count_if(
      text, [](char c) { return (static_cast<unsigned char>(c) & 0xc0) != 0x80; }));
}

/// `text` wrapped at spaces into lines that start at column `indent` (the first line
/// where `first` leaves off) and end before help_width.
std::string wrapped(std::string_view text, std::size_t indent, std::size_t first) {
  std::string out;
  std::size_t column = first;
  bool line_start = true;
  while (!text.empty()) {
    const std::size_t end = std::min(text.find(' '), text.size());
    const std::string_view word = text.substr(0, end);
    text.remove_prefix(std::min(end + 1, text.size()));
    if (word.empty()) continue;
    if (!line_start && column + 1 + shown_width(word) > help_width) {
      out += '\n' + std::string(indent, ' ');
      column = indent;
      line_start = true;
    }
    if (!line_start) {
      out += ' ';
      ++column;
    }
    out += word;
    column += shown_width(word);
    line_start = false;
  }
  return out + '\n';
}

/// "  -o, --output=TEXT" and its meaning in the column.
std::string option_entry(const std::string& names, std::string_view meaning) {
  std::string line = "  " + names;
  const std::size_t width = shown_width(line);
  if (width + 2 <= option_column)
    return line + std::string(option_column - width, ' ') +
           wrapped(meaning, option_column, option_column);
  return line + '\n' + std::string(option_column, ' ') +
         wrapped(meaning, option_column, option_column);
}

/// The value an option takes as the help shows it: "TEXT", "FLOAT", "{gimp,linear}".
std::string value_name(const CLI::Option& option) {
  const std::string type = option.get_type_name();
  const std::size_t colon = type.find(':');
  if (colon != std::string::npos && type.compare(colon + 1, 1, "{") == 0)
    return type.substr(colon + 1);
  return type.substr(0, colon);
}

std::string option_names(const CLI::Option& option) {
  std::string names;
  for (const std::string& s : option.get_snames()) names += (names.empty() ? "-" : ", -") + s;
  names = names.empty() ? "    " : names + ", ";
  std::string longs;
  for (const std::string& l : option.get_lnames()) longs += (longs.empty() ? "--" : ", --") + l;
  names += longs;
  if (const std::string value = value_name(option); !value.empty()) {  // not a flag
    names += "=" + value;
    if (option.get_items_expected_max() > 1) names += "...";
  }
  return names;
}

/// "fem2mpm: converts an FE checkpoint …" as "Converts an FE checkpoint …".
std::string what_it_does(const CLI::App& app) {
  std::string text = app.get_description();
  const std::string prefix = app.get_name() + ": ";
  if (text.starts_with(prefix)) text.erase(0, prefix.size());
  if (!text.empty() && text[0] >= 'a' && text[0] <= 'z')
    text[0] = static_cast<char>(text[0] - 'a' + 'A');
  if (!text.empty() && text.back() != '.') text += '.';
  return text;
}

}  // namespace

namespace {

/// A positional argument's name as usage lines show it: "case" as CASE.
std::string argument_name(const CLI::Option& positional) {
  std::string name = positional.get_name();
  std::ranges::transform(name, name.begin(), [](char c) {
    return c == '-' ? '_' : static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
  });
  return name;
}

/// The options' entries: the program's own, then -h and --version.
std::string option_entries(const CLI::App& top, const CLI::App& app,
                           const std::vector<const CLI::Option*>& options) {
  std::string text = "\nOptions:\n";
  const CLI::Option* help = top.get_help_ptr();
  const CLI::Option* version = app.get_version_ptr();
  for (const CLI::Option* o : options) {
    if (o == help || o == version || o->get_lnames() == std::vector<std::string>{"help"}) continue;
    std::string meaning = o->get_description();
    if (o->get_required()) meaning += " (required)";
    text += option_entry(option_names(*o), meaning);
  }
  text += option_entry("-h, --help", "display this help and exit");
  if (version != nullptr) {
    text += option_entry("    --version", "output version information and exit");
  }
  return text;
}

/// The exit statuses every program shares (docs/contract.md) and where the docs are.
std::string exit_statuses(const std::string& program) {
  return "\nExit status:\n"
         " 0  done (and after --help, --version)\n"
         " 1  bad input, a missing file or a failed run: one line on stderr\n"
         "    (\"" +
         program +
         ": error: ...\")\n"
         " 2  a usage error (an unknown option, a missing or malformed value)\n\n" +
         wrapped(
             "Documentation: docs/contract.md in the source tree; where installed, "
             "PREFIX/share/doc/slide/contract.md.",
             0, 0);
}

}  // namespace

std::string gnu_help(const CLI::App& top) {
  const CLI::App* app = &top;
  std::string program = top.get_name();
  while (!app->get_subcommands().empty()) {
    app = app->get_subcommands().front();
    program += " " + app->get_name();
  }
  const auto options = app->get_options([](const CLI::Option* o) { return !o->get_positional(); });
  const auto positionals =
      app->get_options([](const CLI::Option* o) { return o->get_positional(); });
  const auto commands = app->get_subcommands([](const CLI::App*) { return true; });

  std::string usage = "Usage: " + program;
  if (!commands.empty()) usage += " COMMAND";
  if (options.size() > 2 || !commands.empty()) usage += " [OPTION]...";
  for (const CLI::Option* p : positionals) {
    const std::string name = argument_name(*p) + (p->get_items_expected_max() > 1 ? "..." : "");
    usage += " " + (p->get_required() ? name : "[" + name + "]");
  }
  std::string text = usage + '\n' + wrapped(what_it_does(*app), 0, 0);
  if (!positionals.empty()) {
    text += "\nArguments:\n";
    for (const CLI::Option* p : positionals) {
      text += option_entry(argument_name(*p), p->get_description());
    }
  }
  if (!commands.empty()) {
    text += "\nCommands:\n";
    for (const CLI::App* c : commands) text += option_entry(c->get_name(), c->get_description());
    text += fmt::format("(\"{} COMMAND --help\" gives a command's options.)\n", program);
  }
  return text + option_entries(top, *app, options) + exit_statuses(top.get_name());
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
