// Plot scripts: found next to the installed driver or in the source tree, run with an argument
// vector, never through a shell, by Debian's /usr/bin/python3 (which tools/install-deps.sh gives
// matplotlib: README, "Python"), or by the PATH's python3 on a system without it.
#include "commands.hpp"

#include <noether/error.hpp>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <spawn.h>
#include <sys/wait.h>

extern char** environ;

namespace noether::app {

std::string script_dir() {
  namespace fs = std::filesystem;
  std::error_code ec;
  const fs::path exe = fs::read_symlink("/proc/self/exe", ec);
  for (const fs::path& candidate : {exe.parent_path() / ".." / "share" / "noether",
                                    fs::path(NOETHER_SOURCE_DIR) / "tools"})
    if (fs::exists(candidate / "plot_compare.py", ec)) return candidate.string();
  return {};
}

bool run_plot_script(const std::string& script, const std::vector<std::string>& args, std::string& shown) {
  const std::string dir = script_dir();
  std::vector<std::string> words{"python3", dir + "/" + script};
  words.insert(words.end(), args.begin(), args.end());
  shown.clear();
  for (const auto& w : words) shown += (shown.empty() ? "" : " ") + w;
  if (dir.empty()) return false;
  auto spawn = [&words](const char* python) {
    std::vector<char*> argv;
    for (auto& w : words) argv.push_back(w.data());
    argv.push_back(nullptr);
    pid_t pid = 0;
    if (posix_spawnp(&pid, python, nullptr, nullptr, argv.data(), environ) != 0) return -1;
    int status = 0;
    if (waitpid(pid, &status, 0) != pid || !WIFEXITED(status)) return -1;
    return WEXITSTATUS(status);
  };
  if (std::filesystem::exists("/usr/bin/python3")) {
    shown.replace(0, 7, "/usr/bin/python3");
    return spawn("/usr/bin/python3") == 0;
  }
  return spawn("python3") == 0;
}

bool draw_plot(const std::string& script, const std::vector<std::string>& args, const std::string& png,
               const std::string& data) {
  std::string shown;
  if (run_plot_script(script, args, shown)) {
    std::printf("plot: %s\n", png.c_str());
    return true;
  }
  std::fprintf(stderr, "noether: could not draw %s (needs python3-matplotlib; command: %s); its data: %s\n", png.c_str(),
               shown.c_str(), data.c_str());
  return false;
}

std::string csv_beside(const std::string& png) {
  return std::filesystem::path(png).replace_extension(".csv").string();
}

void plot_spectrum(const std::string& png, const std::vector<std::complex<double>>& values,
                   const std::vector<std::string>& labels, const std::string& kind, double scale,
                   double tolerance, const std::string& title) {
  const std::string csv = csv_beside(png);
  std::ofstream file(csv);
  file.precision(17);
  file << "re,im,label\n";
  for (std::size_t i = 0; i < values.size(); ++i)
  {
    std::string label = i < labels.size() ? labels[i] : "";
    std::replace(label.begin(), label.end(), ',', ';');  // one CSV field
    file << values[i].real() << ',' << values[i].imag() << ',' << label << "\n";
  }
  file.close();
  if (!file) throw noether::OutputError("cannot write " + csv + " (the data of --plot); choose a folder you can write");
  char number[32];
  std::snprintf(number, sizeof number, "%.17g", scale);
  const std::string scale_text = number;
  std::snprintf(number, sizeof number, "%.3g", tolerance);
  draw_plot("plot_spectrum.py", {csv, png, "--kind", kind, "--scale", scale_text, "--tolerance", number, "--title", title},
            png, csv);
}

}  // namespace noether::app
