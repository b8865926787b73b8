// noether: the driver. `noether run | plugins | compare | ensemble | orbit | check-potential | observe | fit`,
// `--version`. Each command lives in its own file, which registers its options (commands.hpp).
#include "commands.hpp"

#include <noether/error.hpp>
#include <noether/params.hpp>
#include <noether/version.hpp>

#include <CLI/CLI.hpp>
#include <spdlog/sinks/stdout_sinks.h>
#include <spdlog/spdlog.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <limits>
#include <iostream>

namespace {

// After a usage error: "did you mean --force?" for each option the command does not have.
void suggest_options(CLI::App& app, int argc, char** argv) {
  std::vector<std::string> known;
  auto collect = [&known](const CLI::App* a) {
    for (const CLI::Option* o : a->get_options()) {
      for (const auto& name : o->get_lnames()) known.push_back("--" + name);
      for (const auto& name : o->get_snames()) known.push_back("-" + name);
    }
  };
  collect(&app);
  for (const CLI::App* sub : app.get_subcommands()) collect(sub);
  for (int i = 1; i < argc; ++i) {
    std::string word = argv[i];
    if (word.size() < 2 || word[0] != '-' || (word[1] >= '0' && word[1] <= '9') || word[1] == '.') continue;
    word = word.substr(0, word.find('='));
    if (std::find(known.begin(), known.end(), word) != known.end()) continue;
    if (const std::string near = noether::closest_match(word, known); !near.empty())
      std::cerr << "noether: " << word << " is not an option of this command; did you mean " << near << "?\n";
  }
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"noether: bodies under mutual gravity — the full body problem and point masses"};
  app.set_version_flag("--version", std::string("noether ") + NOETHER_VERSION);
  app.require_subcommand(1);
  app.fallthrough();  // --log-level also after the subcommand
  app.name("noether");
  std::string level = "warn";
  app.add_option("--log-level", level, "trace, debug, info, warn, error")
      ->check(CLI::IsMember({"trace", "debug", "info", "warn", "error", "off"}));

  noether::app::Command chosen;
  using namespace noether::app;
  add_run_command(app, chosen);
  add_plugins_command(app, chosen);
  add_compare_command(app, chosen);
  add_ensemble_command(app, chosen);
  add_orbit_command(app, chosen);
  add_check_potential_command(app, chosen);
  add_observe_command(app, chosen);
  add_fit_command(app, chosen);
  add_shape_command(app, chosen);
  add_view_command(app, chosen);
  add_export_command(app, chosen);

  if (argc == 1) {  // bare `noether`: the help
    std::cout << app.help();
    return 0;
  }
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    const int code = app.exit(e);  // prints help, the version, or the usage error
    if (code != 0) suggest_options(app, argc, argv);
    return code == 0 ? 0 : 2;      // usage errors exit 2, as documented
  }
  // Warnings on stderr (stdout carries results: --summary json), as "noether: warning: …".
  spdlog::set_default_logger(spdlog::stderr_logger_mt("noether"));
  spdlog::set_pattern("noether: %l: %v");
  spdlog::set_level(spdlog::level::from_str(level));
  try {
    if (chosen) return chosen();
  } catch (const noether::Error& e) {
    std::cerr << "noether: " << e.what() << "\n";
    return 2;
  } catch (const std::filesystem::filesystem_error& e) {  // e.g. a read-only --out-dir
    std::cerr << "noether: " << e.what() << "\n";
    return 2;
  } catch (const std::exception& e) {
    std::cerr << "noether: unexpected error: " << e.what() << "\n";
    return 4;
  }
  return 0;
}
