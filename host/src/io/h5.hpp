#pragma once
// The one HDF5 layer of libnoether (internal header, not installed): H5Handle, an identifier
// that closes itself, and the helpers that create, write and read through it. Every
// identifier a helper opens is held by an H5Handle, so no error path leaks one; every failure
// becomes a noether::OutputError.
#include <noether/error.hpp>

#include <hdf5.h>

#include <cerrno>

#include <algorithm>
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <utility>
#include <vector>

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

  // Passed straight to the C API (a temporary's identifier lives to the end of the call that
  // takes it: never keep it in an hid_t).
  operator hid_t() const { return id_; }  // NOLINT
  bool valid() const { return id_ >= 0; }
  void reset() {
    if (id_ >= 0) H5Idec_ref(id_);  // closes any kind of identifier
    id_ = -1;
  }
  // Closes it and says whether that failed (a file's last writes happen when it closes).
  [[nodiscard]] bool close() {
    const bool ok = id_ < 0 || H5Idec_ref(id_) >= 0;
    id_ = -1;
    return ok;
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

// What the system said when HDF5 failed, if it is a condition a user can act on.
inline std::string system_reason() {
  const int e = errno;
  if (e == ENOSPC) return ": no space left on the device (ENOSPC)";
  if (e == EDQUOT) return ": disk quota exceeded (EDQUOT)";
  if (e == EROFS) return ": read-only file system (EROFS)";
  if (e == EIO) return ": input/output error (EIO)";
  return "";
}
inline void check(herr_t status, const char* what) {
  if (status < 0) throw OutputError(std::string("HDF5 error while ") + what + system_reason());
}
// An identifier HDF5 just made, held; OutputError (with `what`) when it failed.
inline H5Handle check_id(hid_t id, const char* what) {
  if (id < 0) throw OutputError(std::string("HDF5 error while ") + what + system_reason());
  return H5Handle(id);
}

inline H5Handle make_group(hid_t parent, const char* name) {
  return check_id(H5Gcreate2(parent, name, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT), name);
}

// A variable-length UTF-8 string type (h5py reads it as str, not bytes), and a fixed-size one.
inline H5Handle utf8_string_type(std::size_t size = H5T_VARIABLE) {
  H5Handle type(H5Tcopy(H5T_C_S1));
  H5Tset_size(type, size);
  H5Tset_cset(type, H5T_CSET_UTF8);
  return type;
}

// The group at an absolute `path` ("/a/b/c"), opened, or created with the groups on its way;
// `created` tells whether the last one was made here.
inline H5Handle group_at(hid_t file, const std::string& path, bool* created = nullptr) {
  H5Handle group = check_id(H5Gopen2(file, "/", H5P_DEFAULT), "opening the root group");
  bool made = false;
  for (std::size_t begin = 1; begin <= path.size();) {
    std::size_t end = path.find('/', begin);
    if (end == std::string::npos) end = path.size();
    const std::string name = path.substr(begin, end - begin);
    begin = end + 1;
    if (name.empty()) continue;
    const htri_t exists = H5Lexists(group, name.c_str(), H5P_DEFAULT);
    made = exists <= 0;
    group = check_id(made ? H5Gcreate2(group, name.c_str(), H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT)
                          : H5Gopen2(group, name.c_str(), H5P_DEFAULT),
                     path.c_str());
  }
  if (created) *created = made;
  return group;
}

// A variable-length UTF-8 string attribute (h5py reads it as str, not bytes).
inline void string_attribute(hid_t obj, const char* name, const std::string& value) {
  const H5Handle type = utf8_string_type(), space(H5Screate(H5S_SCALAR));
  const H5Handle attr = check_id(H5Acreate2(obj, name, type, space, H5P_DEFAULT, H5P_DEFAULT), name);
  const char* text = value.c_str();
  check(H5Awrite(attr, type, &text), name);
}

template <class T>
void numeric_attribute(hid_t obj, const char* name, hid_t type, const std::vector<T>& values) {
  const hsize_t n = values.size();
  const H5Handle space(H5Screate_simple(1, &n, nullptr));
  const H5Handle attr = check_id(H5Acreate2(obj, name, type, space, H5P_DEFAULT, H5P_DEFAULT), name);
  check(H5Awrite(attr, type, values.data()), name);
}

inline void string_list_dataset(hid_t parent, const char* name, const std::vector<std::string>& list) {
  std::vector<const char*> ptrs;
  for (const auto& s : list) ptrs.push_back(s.c_str());
  const H5Handle type = utf8_string_type();
  const hsize_t n = list.size();
  const H5Handle space(H5Screate_simple(1, &n, nullptr));
  const H5Handle d = check_id(H5Dcreate2(parent, name, type, space, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT), name);
  if (n) check(H5Dwrite(d, type, H5S_ALL, H5S_ALL, H5P_DEFAULT, ptrs.data()), name);
}

inline void double_dataset(hid_t parent, const char* name, const std::vector<double>& values) {
  const hsize_t n = values.size();
  const H5Handle space(H5Screate_simple(1, &n, nullptr));
  const H5Handle d =
      check_id(H5Dcreate2(parent, name, H5T_NATIVE_DOUBLE, space, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT), name);
  if (n) check(H5Dwrite(d, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, values.data()), name);
}

// A scalar UTF-8 string dataset (no 64 KiB limit, unlike an attribute), with a description.
inline void string_dataset(hid_t parent, const char* name, const std::string& value, const std::string& description) {
  const H5Handle type = utf8_string_type(std::max<std::size_t>(1, value.size())), space(H5Screate(H5S_SCALAR));
  const H5Handle d = check_id(H5Dcreate2(parent, name, type, space, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT), name);
  check(H5Dwrite(d, type, H5S_ALL, H5S_ALL, H5P_DEFAULT, value.empty() ? "" : value.data()), name);
  string_attribute(d, "description", description);
}

// A scalar attribute of an HDF5 type (a double by default).
template <class T>
void scalar_attribute(hid_t obj, const char* name, hid_t type, T value) {
  const H5Handle space(H5Screate(H5S_SCALAR));
  const H5Handle attr = check_id(H5Acreate2(obj, name, type, space, H5P_DEFAULT, H5P_DEFAULT), name);
  check(H5Awrite(attr, type, &value), name);
}
inline void scalar_attribute(hid_t obj, const char* name, double value) {
  scalar_attribute(obj, name, H5T_NATIVE_DOUBLE, value);
}

// The non-empty lines of a newline-joined attribute (/parameters overrides).
inline std::vector<std::string> lines_of(const std::string& joined) {
  std::vector<std::string> out;
  for (std::size_t a = 0; a < joined.size();) {
    const std::size_t b = std::min(joined.find('\n', a), joined.size());
    if (b > a) out.push_back(joined.substr(a, b - a));
    a = b + 1;
  }
  return out;
}

// Deletes an attribute if there is one (before writing it again).
inline void remove_attribute(hid_t obj, const char* name) {
  if (H5Aexists(obj, name) > 0) H5Adelete(obj, name);
}

// A string attribute or a scalar string dataset, variable- or fixed-length; "" when absent.
inline std::string read_string(hid_t obj, const char* name, bool dataset) {
  if (dataset ? H5Lexists(obj, name, H5P_DEFAULT) <= 0 : H5Aexists(obj, name) <= 0) return {};
  const H5Handle id(dataset ? H5Dopen2(obj, name, H5P_DEFAULT) : H5Aopen(obj, name, H5P_DEFAULT));
  const H5Handle type(dataset ? H5Dget_type(id) : H5Aget_type(id));
  std::string out;
  if (H5Tis_variable_str(type) > 0) {
    char* text = nullptr;
    const H5Handle mem(H5Tcopy(H5T_C_S1));
    H5Tset_size(mem, H5T_VARIABLE);
    H5Tset_cset(mem, H5Tget_cset(type));
    const herr_t status = dataset ? H5Dread(id, mem, H5S_ALL, H5S_ALL, H5P_DEFAULT, &text) : H5Aread(id, mem, &text);
    if (status >= 0 && text) out = text;
    if (text) H5free_memory(text);
  } else {
    out.resize(H5Tget_size(type));
    if (!out.empty()) {
      if (dataset) H5Dread(id, type, H5S_ALL, H5S_ALL, H5P_DEFAULT, out.data());
      else H5Aread(id, type, out.data());
    }
    out = out.c_str();  // up to a terminating NUL, if any
  }
  return out;
}

// A 1-D dataset of variable-length strings (string_list_dataset's); OutputError when it is
// missing or of another kind.
inline std::vector<std::string> read_string_list(hid_t parent, const char* path) {
  const H5Handle d(H5Dopen2(parent, path, H5P_DEFAULT));
  if (!d.valid()) throw OutputError(std::string("the output has no ") + path);
  const H5Handle type(H5Dget_type(d)), space(H5Dget_space(d));
  hsize_t n = 0;
  const bool ok = H5Tget_class(type) == H5T_STRING && H5Tis_variable_str(type) > 0 &&
                  H5Sget_simple_extent_ndims(space) == 1 && H5Sget_simple_extent_dims(space, &n, nullptr) == 1;
  std::vector<char*> raw(ok ? n : 0, nullptr);
  herr_t status = -1;
  if (ok) {
    const H5Handle mem(H5Tcopy(H5T_C_S1));
    H5Tset_size(mem, H5T_VARIABLE);
    H5Tset_cset(mem, H5Tget_cset(type));
    status = n ? H5Dread(d, mem, H5S_ALL, H5S_ALL, H5P_DEFAULT, raw.data()) : 0;
  }
  std::vector<std::string> out;
  for (char* s : raw) {
    out.emplace_back(s ? s : "");
    if (s) H5free_memory(s);
  }
  if (!ok || status < 0) throw OutputError(std::string("the output's ") + path + " is not a list of strings");
  return out;
}

// The first `frames` frames of a [frame][...] dataset, as `mem_type`.
template <class T>
std::vector<T> read_frames(hid_t file, const char* path, hid_t mem_type, hsize_t frames) {
  const H5Handle d(H5Dopen2(file, path, H5P_DEFAULT));
  if (!d.valid()) throw OutputError(std::string("the output has no ") + path);
  const H5Handle space(H5Dget_space(d));
  const int rank = H5Sget_simple_extent_ndims(space);
  std::vector<hsize_t> dims(static_cast<std::size_t>(rank)), start(dims.size(), 0);
  H5Sget_simple_extent_dims(space, dims.data(), nullptr);
  if (rank < 1 || dims[0] < frames)
    throw OutputError(std::string("the output's ") + path + " holds fewer frames than /frames_complete");
  dims[0] = frames;
  std::size_t n = 1;
  for (auto x : dims) n *= x;
  std::vector<T> out(n);
  if (n > 0) {
    H5Sselect_hyperslab(space, H5S_SELECT_SET, start.data(), nullptr, dims.data(), nullptr);
    const H5Handle mem(H5Screate_simple(rank, dims.data(), nullptr));
    if (H5Dread(d, mem_type, mem, space, H5P_DEFAULT, out.data()) < 0)
      throw OutputError(std::string("cannot read ") + path + " of the output");
  }
  return out;
}

}  // namespace noether::io
