// noether: the driver. `noether run | plugins | compare | ensemble | orbit | check-potential`,
// `--version`. Each command lives in its own file, which registers its options (commands.hpp).
#include "commands.hpp"

#include <noether/error.hpp>
#include <noether/version.hpp>

#include <CLI/CLI.hpp>
#include <spdlog/sinks/stdout_sinks.h>
#include <spdlog/spdlog.h>

#include <cmath>
#include <filesystem>
#include <limits>
#include <iostream>

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

  if (argc == 1) {  // bare `noether`: the help
    std::cout << app.help();
    return 0;
  }
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    const int code = app.exit(e);  // prints help, the version, or the usage error
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
