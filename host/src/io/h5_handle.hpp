#pragma once
// H5Handle: an HDF5 identifier that closes itself (file, group, dataset, dataspace, type,
// attribute or property list), so that no error path leaks one. Internal to libnoether.
#include <noether/error.hpp>

#include <hdf5.h>

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

}  // namespace noether::io
