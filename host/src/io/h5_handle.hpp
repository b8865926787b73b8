#pragma once
// H5Handle: an HDF5 identifier that closes itself (file, group, dataset, dataspace, type,
// attribute or property list), so that no error path leaks one. Internal to libnoether.
#include <noether/error.hpp>

#include <hdf5.h>

#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <utility>

namespace noether::io {

class H5Handle {
 public:
  H5Handle() = default;
  explicit H5Handle(hid_t id) : id_(id) {}
  ~H5Handle() { reset(); }
  H5Handle(H5Handle&& o) noexcept : id_(std::exchange(o.id_, -1)) {}
  H5Handle& operator=(H5Handle&& o) noexcept {
    if (this != &o) {
      reset();
      id_ = std::exchange(o.id_, -1);
    }
    return *this;
  }
  H5Handle(const H5Handle&) = delete;
  H5Handle& operator=(const H5Handle&) = delete;

  operator hid_t() const { return id_; }  // NOLINT: passed straight to the C API
  bool valid() const { return id_ >= 0; }
  void reset() {
    if (id_ >= 0) H5Idec_ref(id_);  // closes any kind of identifier
    id_ = -1;
  }

 private:
  hid_t id_ = -1;
};

// A dataset opened by path; an invalid handle when it does not open.
inline H5Handle open_dataset(hid_t location, const char* path) {
  return H5Handle(H5Lexists(location, path, H5P_DEFAULT) > 0 ? H5Dopen2(location, path, H5P_DEFAULT) : -1);
}

// A uint64 attribute (a checksum): empty when it is absent or does not read.
inline std::optional<std::uint64_t> read_u64_attribute(hid_t object, const char* name) {
  if (H5Aexists(object, name) <= 0) return std::nullopt;
  std::uint64_t value = 0;
  const H5Handle a(H5Aopen(object, name, H5P_DEFAULT));
  if (!a.valid() || H5Aread(a, H5T_NATIVE_UINT64, &value) < 0) return std::nullopt;
  return value;
}

// The refusal of a file noether reads back (a run to continue, a saved simulation): `what`
// names the part that failed.
[[noreturn]] inline void throw_damaged(const std::filesystem::path& file, const std::string& what) {
  throw OutputError(file.string() + " is damaged: " + what +
                    "; it was only read, not changed (continue from a copy of the file, or run the scene afresh)");
}

}  // namespace noether::io
