#pragma once
// Flushing and closing a file that a kill may interrupt: the file is first made longer than
// HDF5's end of allocation, so that a kill anywhere in a flush leaves a file HDF5 opens; after
// the close the extension is cut off again (docs/reliability.md, "Kills").
#include "io/h5.hpp"
#include "io/file_access.hpp"
#include "io/superblock.hpp"

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <string>

#include <sys/stat.h>
#include <unistd.h>

namespace noether::io {

// The flush writes the superblock, which records the end of allocation, last. A kill before it
// would leave metadata pointing past the end the file records ("addr overflow"), and a file
// shorter than that end is refused ("truncated file"). So before the flush the file is made
// `margin` longer than HDF5's end of allocation (a hole) and its superblock records that longer
// end; the margin covers what the flush itself allocates (~1 KiB of metadata gets its file space
// only when written). After the flush the superblock records HDF5's own end again (HDF5 rewrote
// it if the end moved; if not, this rewrite does). `fd`: a descriptor of the file.
inline void flush_extended(hid_t file, int fd, const char* what) {
  constexpr haddr_t margin = 1 << 20;
  haddr_t eoa = 0;
  struct stat st {};
  const bool known = H5Fget_eoa(file, &eoa) >= 0 && ::fstat(fd, &st) == 0;
  if (known && static_cast<haddr_t>(st.st_size) < eoa + margin &&
      ::ftruncate(fd, static_cast<off_t>(eoa + margin)) != 0)
    throw OutputError(std::string("cannot extend the file while ") + what + ": " + std::strerror(errno));
  const bool recorded = known && record_end_of_allocation(fd, eoa + margin);
  check(H5Fflush(file, H5F_SCOPE_GLOBAL), what);
  if (recorded && H5Fget_eoa(file, &eoa) >= 0) record_end_of_allocation(fd, eoa);
}

// After the file at `path` (descriptor `fd`) is closed: cuts off what flush_extended added past
// the end of allocation its superblock records (HDF5 never learns of the extension).
inline void trim_extension(const std::filesystem::path& path, int fd) noexcept {
  haddr_t eoa = 0;
  {
    const H5Handle file(H5Fopen(path.c_str(), H5F_ACC_RDONLY, file_access(0)));
    if (file < 0 || H5Fget_eoa(file, &eoa) < 0) return;
  }
  struct stat st {};
  if (eoa > 0 && ::fstat(fd, &st) == 0 && static_cast<haddr_t>(st.st_size) > eoa) {
    [[maybe_unused]] const int ignored = ::ftruncate(fd, static_cast<off_t>(eoa));
  }
}

}  // namespace noether::io
