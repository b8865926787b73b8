// Plot scripts: found next to the installed driver or in the source tree, run by the python3
// on the user's PATH (their virtual environment, if any) with an argument vector, never
// through a shell; by Debian's /usr/bin/python3 when the PATH's has no matplotlib.
#include "commands.hpp"

#include <filesystem>
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
  const int status = spawn("python3");
  // Exit 3: the PATH's python3 has no matplotlib; Debian's (tools/install-deps.sh) has.
  if (status == 3 && std::filesystem::exists("/usr/bin/python3")) {
    shown.replace(0, 7, "/usr/bin/python3");
    return spawn("/usr/bin/python3") == 0;
  }
  return status == 0;
}

}  // namespace noether::app
