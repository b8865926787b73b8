#include "io/safe_publish.hpp"

#include <noether/error.hpp>

#include <cerrno>
#include <cstdlib>
#include <cstring>

#include <fcntl.h>
#include <sys/file.h>
#include <unistd.h>

#include <utility>

namespace noether::io {

namespace fs = std::filesystem;

namespace {

int lock_or_refuse(int fd, const fs::path& path) {
  if (::flock(fd, LOCK_EX | LOCK_NB) == 0) return fd;
  const int e = errno;
  ::close(fd);
  if (e == EWOULDBLOCK)
    throw OutputError("another process is writing " + path.string() +
                      " (a second noether run on the same output, or a reader holding HDF5's lock); "
                      "the file is left untouched");
  throw OutputError("cannot lock the output file " + path.string() + ": " + std::strerror(e));
}

}  // namespace

// Refuses a symbolic link, anything but a regular file, one of the run's inputs, and an
// existing file unless `overwrite`; locks an existing file. Returns its descriptor, or −1.
int claim_output(const fs::path& path, bool overwrite, const std::vector<fs::path>& inputs) {
  std::error_code ec;
  const fs::file_status link = fs::symlink_status(path, ec);
  if (fs::is_symlink(link))
    throw OutputError(path.string() + " is a symbolic link; noether does not write through links: give the file "
                      "it points to, or another path");
  const bool exists = fs::exists(link);
  if (exists && !fs::is_regular_file(link))
    throw OutputError(path.string() + " exists and is not a regular file");
  for (const auto& input : inputs)
    if (exists && fs::equivalent(path, input, ec))
      throw OutputError("the output " + path.string() + " is the run's input " + input.string() +
                        "; choose another output file");
  if (exists && !overwrite)
    throw OutputError(path.string() + " exists; noether does not overwrite output unless asked: pass --force, "
                      "or choose another output file");
  ::setenv("HDF5_USE_FILE_LOCKING", "FALSE", 0);
  if (!exists) return -1;
  const int fd = ::open(path.c_str(), O_RDONLY | O_NOFOLLOW | O_CLOEXEC);
  if (fd < 0) throw OutputError("cannot open the existing output file " + path.string() + ": " + std::strerror(errno));
  return lock_or_refuse(fd, path);
}

// The hidden name the file is built under: .<name>.partial-<pid>, next to it.
fs::path partial_name(const fs::path& path) {
  std::string name = ".";
  name += path.filename().string();
  name += ".partial-";
  name += std::to_string(::getpid());
  return path.parent_path() / name;
}

int create_partial(const fs::path& partial, const fs::path& path) {
  const auto create = [&] { return ::open(partial.c_str(), O_RDWR | O_CREAT | O_EXCL | O_NOFOLLOW | O_CLOEXEC, 0644); };
  int fd = create();
  if (fd < 0 && errno == EEXIST) {
    // The name carries this process's pid, so the file was left by a killed run that had the
    // same pid before (pids are reused): stale, unless a writer still holds its lock (one on
    // another machine sharing the folder). A stale one is removed and the file made afresh.
    const int old = ::open(partial.c_str(), O_RDONLY | O_NOFOLLOW | O_CLOEXEC);
    if (old >= 0) {
      const bool stale = ::flock(old, LOCK_EX | LOCK_NB) == 0;
      if (stale) ::unlink(partial.c_str());
      ::close(old);
      if (stale)
        fd = create();
      else
        errno = EEXIST;
    } else {
      errno = EEXIST;
    }
  }
  if (fd < 0)
    throw OutputError("cannot create the output file " + path.string() + ": " + std::strerror(errno) +
                      " (does its folder exist, and is it writable?)");
  return lock_or_refuse(fd, path);
}

// Moves the finished layout to `path`: replacing the claimed file, or only if no other
// process created `path` meanwhile.
void publish_file(const fs::path& partial, const fs::path& path, bool replace) {
  if (replace) {
    if (::rename(partial.c_str(), path.c_str()) != 0)
      throw OutputError("cannot replace " + path.string() + ": " + std::strerror(errno));
    return;
  }
  if (::renameat2(AT_FDCWD, partial.c_str(), AT_FDCWD, path.c_str(), RENAME_NOREPLACE) == 0) return;
  int e = errno;
  if (e == EINVAL || e == ENOSYS) {  // a file system without RENAME_NOREPLACE: link, then unlink
    if (::link(partial.c_str(), path.c_str()) == 0) {
      ::unlink(partial.c_str());
      return;
    }
    e = errno;
  }
  if (e == EEXIST)
    throw OutputError("another process created " + path.string() +
                      " while this run was starting; nothing was overwritten");
  throw OutputError("cannot create the output file " + path.string() + ": " + std::strerror(e));
}

void write_whole_file(const fs::path& path, const std::string& bytes, bool overwrite, const std::vector<fs::path>& inputs) {
  const int claimed = claim_output(path, overwrite, inputs);
  const fs::path partial = partial_name(path);
  int fd = -1;
  bool created = false;  // the hidden file is ours to remove
  try {
    fd = create_partial(partial, path);
    created = true;
    for (std::size_t done = 0; done < bytes.size();) {
      const ssize_t n = ::write(fd, bytes.data() + done, bytes.size() - done);
      if (n < 0 && errno == EINTR) continue;
      if (n < 0) throw OutputError("cannot write " + path.string() + ": " + std::strerror(errno));
      done += static_cast<std::size_t>(n);
    }
    if (::close(std::exchange(fd, -1)) != 0) throw OutputError("cannot write " + path.string() + ": " + std::strerror(errno));
    publish_file(partial, path, claimed >= 0);
  } catch (...) {
    if (fd >= 0) ::close(fd);
    if (created) ::unlink(partial.c_str());
    if (claimed >= 0) ::close(claimed);
    throw;
  }
  if (claimed >= 0) ::close(claimed);
}

}  // namespace noether::io
