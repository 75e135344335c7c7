#include "wire/cli/args.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <utility>

#include "wire/log.h"

namespace troupe::cli {
namespace {

// The help every tool prints: "usage: ...", what it does, its options (one
// line each: names, value, text with units), then "examples:".
class HouseFormatter : public CLI::FormatterBase {
 public:
  explicit HouseFormatter(Help help) : help_(std::move(help)) {}

  std::string make_help(const CLI::App* app, std::string, CLI::AppFormatMode) const override {
    std::string out = "usage: " + help_.usage + "\n";
    if (!help_.about.empty()) out += "\n" + help_.about;
    // One row per option: its group (a heading when it changes), names and value, text.
    struct Row {
      std::string group, names, text;
    };
    std::vector<Row> rows;
    for (const CLI::Option* opt : app->get_options()) {
      // Hidden options (group "") are not listed.
      if (!opt->nonpositional() || opt == app->get_help_ptr() || opt->get_group().empty()) continue;
      std::string names;
      for (const std::string& s : opt->get_snames()) names += (names.empty() ? "-" : ", -") + s;
      for (const std::string& l : opt->get_lnames()) names += (names.empty() ? "--" : ", --") + l;
      // The value's name, without what validators append ("N:POSITIVE").
      std::string value = opt->get_type_name();
      value = value.substr(0, value.find(':'));
      if (opt->get_type_size() != 0 && !value.empty()) names += " " + value;
      rows.push_back({opt->get_group(), names, opt->get_description()});
    }
    if (!rows.empty()) {
      size_t width = 0;
      for (const Row& row : rows) width = std::max(width, row.names.size());
      out += "\n";
      std::string group = rows.front().group;
      for (const auto& [row_group, names, text] : rows) {
        if (row_group != group) out += "\n" + row_group + ":\n";
        group = row_group;
        std::string line = "  " + names + std::string(width - names.size() + 2, ' ');
        // A text of several lines keeps its column.
        for (char c : text) line += c == '\n' ? "\n" + std::string(width + 4, ' ') : std::string(1, c);
        out += line + "\n";
      }
    }
    if (!help_.examples.empty()) {
      out += "\nexamples:\n";
      for (const std::string& example : help_.examples) out += "  " + example + "\n";
    }
    return out;
  }

 private:
  Help help_;
};

}  // namespace

std::unique_ptr<CLI::App> make_app(const std::string& name, Help help) {
  if (help.usage.empty()) help.usage = name + " [options]";
  auto app = std::make_unique<CLI::App>(help.about, name);
  app->formatter(std::make_shared<HouseFormatter>(std::move(help)));
  app->set_help_flag("-h,--help", "this text");
  return app;
}

int parse(CLI::App& app, int argc, const char* const* argv) {
  return parse(app, std::vector<std::string>(argv + 1, argv + argc));
}

int parse(CLI::App& app, const std::vector<std::string>& args) {
  // --help wins wherever it stands (before a "--"), even after a mistake.
  for (const std::string& a : args) {
    if (a == "--") break;
    if (a == "-h" || a == "--help") {
      fputs(app.help().c_str(), stdout);
      return 0;
    }
  }
  // CLI11 takes the arguments last first, and "-.5" for an option named "."
  // (a number is never an option here).
  std::vector<std::string> reversed;
  for (auto it = args.rbegin(); it != args.rend(); ++it) {
    bool short_number = it->size() > 2 && it->rfind("-.", 0) == 0 && isdigit(static_cast<unsigned char>((*it)[2]));
    reversed.push_back(short_number ? "-0" + it->substr(1) : *it);
  }
  try {
    app.parse(reversed);
  } catch (const CLI::ParseError& e) {
    std::string message = e.what();
    // CLI11's sentences start with a capital; ours are lower-case clauses.
    if (message.size() > 1 && isupper(static_cast<unsigned char>(message[0])) &&
        islower(static_cast<unsigned char>(message[1]))) {
      message[0] = char(tolower(static_cast<unsigned char>(message[0])));
    }
    return usage_error(app, message);
  }
  return -1;
}

int usage_error(const CLI::App& app, const std::string& message) {
  const std::string& name = app.get_name();
  fprintf(stderr, "%s: %s (see: %s --help)\n", name.c_str(), message.c_str(), name.c_str());
  return kExitUsage;
}

namespace {

// A number compared with `bound` by `op` (">=", ">" or "<=").
CLI::Validator compare(const std::string& op, double bound) {
  return CLI::Validator(
      [op, bound](std::string& text) -> std::string {
        double v = 0;
        bool ok = CLI::detail::lexical_cast(text, v) && std::isfinite(v) &&
                  (op == ">=" ? v >= bound : op == ">" ? v > bound : v <= bound);
        return ok ? "" : "needs a number " + op + " " + CLI::detail::to_string(bound) + ", not '" + text + "'";
      },
      "", "bound " + op);
}

}  // namespace

CLI::Validator at_least(double min) { return compare(">=", min); }
CLI::Validator above(double min) { return compare(">", min); }
CLI::Validator at_most(double max) { return compare("<=", max); }

CLI::Validator between(double min, double max) {
  return CLI::Validator(
      [min, max](std::string& text) -> std::string {
        double v = 0;
        bool ok = CLI::detail::lexical_cast(text, v) && std::isfinite(v) && v >= min && v <= max;
        return ok ? ""
                  : "needs a number from " + CLI::detail::to_string(min) + " to " +
                        CLI::detail::to_string(max) + ", not '" + text + "'";
      },
      "", "range");
}

CLI::Option* add_log_level(CLI::App& app) {
  return app
      .add_option_function<std::string>(
          "--log-level",
          [](const std::string& text) {
            LogLevel level{};
            if (parse_log_level(text.c_str(), level)) set_log_level(level);
          },
          "error, warn, info (default) or debug")
      ->type_name("LEVEL")
      ->check(CLI::IsMember({"error", "warn", "info", "debug"}));
}

void add_secure_session(CLI::App& app, wire::noise::ClientKeys& keys) {
  app.add_option("--identity", keys.identity,
                 "a secure session: our secret key file (troupe keygen NAME writes one)")
      ->type_name("FILE");
  app.add_option("--node-key", keys.node_key,
                 "a secure session: the node's public key (its NAME.pub, or 64 hex digits); default: "
                 "the node's line in the known-nodes file (~/.config/troupe/known_nodes)")
      ->type_name("KEY");
}

CLI::Option* add_port(CLI::App& app, const std::string& flag, uint16_t& port, const std::string& what) {
  return app.add_option(flag, port, what)->type_name("P")->check(between(0, 65535));
}

}  // namespace troupe::cli
