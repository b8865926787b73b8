#include "io/read_probe.hpp"

#include <noether/error.hpp>

#include <cerrno>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <string>

#include <fcntl.h>
#include <poll.h>
#include <sys/wait.h>
#include <unistd.h>

namespace noether::io {

namespace {

// The child's report on the pipe: "ok", or "error:" and the message.
void report(int fd, const std::string& text) {
  std::size_t done = 0;
  while (done < text.size()) {
    const ssize_t n = ::write(fd, text.data() + done, text.size() - done);
    if (n <= 0) break;
    done += static_cast<std::size_t>(n);
  }
}

}  // namespace

double read_probe_seconds(const std::filesystem::path& file) {
  double base = 10.0;  // a healthy file of a few MB reads in well under a second, even under ASan
  if (const char* given = std::getenv("NOETHER_READ_PROBE_SECONDS")) {
    char* end = nullptr;
    const double value = std::strtod(given, &end);
    if (end == given || *end != '\0' || !(value > 0) || !std::isfinite(value))
      throw Error(std::string("NOETHER_READ_PROBE_SECONDS='") + given + "': expected a positive number of seconds");
    base = value;
  }
  std::error_code ec;
  const auto bytes = std::filesystem::file_size(file, ec);
  return base + (ec ? 0.0 : 10.0 * static_cast<double>(bytes) / 1e8);
}

void read_probe(const std::filesystem::path& file, const std::function<void()>& read, double seconds,
                const volatile std::sig_atomic_t* interrupt) {
  int fds[2];
  if (::pipe2(fds, O_CLOEXEC) != 0) throw OutputError(std::string("cannot check ") + file.string() + ": pipe: " + std::strerror(errno));
  const pid_t pid = ::fork();
  if (pid < 0) {
    ::close(fds[0]);
    ::close(fds[1]);
    throw OutputError(std::string("cannot check ") + file.string() + ": fork: " + std::strerror(errno));
  }
  if (pid == 0) {  // the child: read, report, and leave without running any exit handler
    ::close(fds[0]);
    std::string outcome = "ok";
    try {
      read();
    } catch (const std::exception& e) {
      outcome = std::string("error:") + e.what();
    } catch (...) {
      outcome = "error:" + file.string() + " could not be read";
    }
    report(fds[1], outcome);
    ::_exit(0);
  }
  ::close(fds[1]);
  std::string message;
  const auto start = std::chrono::steady_clock::now();
  bool timed_out = false, interrupted = false;
  for (;;) {
    pollfd p{fds[0], POLLIN, 0};
    const int ready = ::poll(&p, 1, 100);
    if (ready > 0) {
      char buffer[4096];
      const ssize_t n = ::read(fds[0], buffer, sizeof buffer);
      if (n > 0) {
        message.append(buffer, static_cast<std::size_t>(n));
        continue;
      }
      if (n == 0) break;  // the child closed the pipe: it ended
      if (errno == EINTR) continue;
      break;
    }
    if (ready < 0 && errno != EINTR) break;
    if (interrupt && *interrupt) {
      interrupted = true;
      break;
    }
    if (std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count() > seconds) {
      timed_out = true;
      break;
    }
  }
  ::close(fds[0]);
  if (timed_out || interrupted) ::kill(pid, SIGKILL);
  int status = 0;
  while (::waitpid(pid, &status, 0) < 0 && errno == EINTR) {
  }
  if (interrupted)
    throw Error(file.string() + " was being read back when the continuation was interrupted; it is unchanged");
  if (timed_out)
    throw OutputError(file.string() + " is damaged: reading it back did not end within " +
                      std::to_string(static_cast<long>(seconds)) +
                      " s (HDF5 loops on a damaged index); it was only read, not changed");
  if (WIFSIGNALED(status))
    throw OutputError(file.string() + " is damaged: HDF5 crashed reading it back (" + strsignal(WTERMSIG(status)) +
                      "; a damaged heap or index); it was only read, not changed");
  if (message.rfind("error:", 0) == 0) throw OutputError(message.substr(6));
  if (message != "ok")
    throw OutputError(file.string() + " could not be checked (the reading process ended without a report)");
}

}  // namespace noether::io
