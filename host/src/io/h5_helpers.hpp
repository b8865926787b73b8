#pragma once
// Small HDF5 helpers shared by the writers in core (internal header, not installed). Every
// failure becomes a noether::OutputError.
#include <noether/error.hpp>

#include <hdf5.h>

#include <cerrno>

#include <algorithm>
#include <string>
#include <vector>

namespace noether::h5 {

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
inline hid_t check_id(hid_t id, const char* what) {
  if (id < 0) throw OutputError(std::string("HDF5 error while ") + what + system_reason());
  return id;
}

inline hid_t make_group(hid_t parent, const char* name) {
  return check_id(H5Gcreate2(parent, name, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT), name);
}

// The group at an absolute `path` ("/a/b/c"), opened, or created with the groups on its way;
// `created` tells whether the last one was made here.
inline hid_t group_at(hid_t file, const std::string& path, bool* created = nullptr) {
  hid_t group = check_id(H5Gopen2(file, "/", H5P_DEFAULT), "opening the root group");
  bool made = false;
  for (std::size_t begin = 1; begin <= path.size();) {
    std::size_t end = path.find('/', begin);
    if (end == std::string::npos) end = path.size();
    const std::string name = path.substr(begin, end - begin);
    begin = end + 1;
    if (name.empty()) continue;
    const htri_t exists = H5Lexists(group, name.c_str(), H5P_DEFAULT);
    made = exists <= 0;
    const hid_t next = made ? H5Gcreate2(group, name.c_str(), H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT)
                            : H5Gopen2(group, name.c_str(), H5P_DEFAULT);
    H5Gclose(group);
    group = check_id(next, path.c_str());
  }
  if (created) *created = made;
  return group;
}

// A variable-length UTF-8 string attribute (h5py reads it as str, not bytes).
inline void string_attribute(hid_t obj, const char* name, const std::string& value) {
  hid_t type = H5Tcopy(H5T_C_S1);
  H5Tset_size(type, H5T_VARIABLE);
  H5Tset_cset(type, H5T_CSET_UTF8);
  hid_t space = H5Screate(H5S_SCALAR);
  hid_t attr = check_id(H5Acreate2(obj, name, type, space, H5P_DEFAULT, H5P_DEFAULT), name);
  const char* text = value.c_str();
  check(H5Awrite(attr, type, &text), name);
  H5Aclose(attr);
  H5Sclose(space);
  H5Tclose(type);
}

template <class T>
void numeric_attribute(hid_t obj, const char* name, hid_t type, const std::vector<T>& values) {
  const hsize_t n = values.size();
  hid_t space = H5Screate_simple(1, &n, nullptr);
  hid_t attr = check_id(H5Acreate2(obj, name, type, space, H5P_DEFAULT, H5P_DEFAULT), name);
  check(H5Awrite(attr, type, values.data()), name);
  H5Aclose(attr);
  H5Sclose(space);
}

inline void string_list_dataset(hid_t parent, const char* name, const std::vector<std::string>& list) {
  std::vector<const char*> ptrs;
  for (const auto& s : list) ptrs.push_back(s.c_str());
  hid_t type = H5Tcopy(H5T_C_S1);
  H5Tset_size(type, H5T_VARIABLE);
  H5Tset_cset(type, H5T_CSET_UTF8);
  const hsize_t n = list.size();
  hid_t space = H5Screate_simple(1, &n, nullptr);
  hid_t d = check_id(H5Dcreate2(parent, name, type, space, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT),
                     name);
  if (n) check(H5Dwrite(d, type, H5S_ALL, H5S_ALL, H5P_DEFAULT, ptrs.data()), name);
  H5Dclose(d);
  H5Sclose(space);
  H5Tclose(type);
}


inline void double_dataset(hid_t parent, const char* name, const std::vector<double>& values) {
  const hsize_t n = values.size();
  hid_t space = H5Screate_simple(1, &n, nullptr);
  hid_t d = check_id(H5Dcreate2(parent, name, H5T_NATIVE_DOUBLE, space, H5P_DEFAULT, H5P_DEFAULT,
                                H5P_DEFAULT), name);
  if (n) check(H5Dwrite(d, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, values.data()), name);
  H5Dclose(d);
  H5Sclose(space);
}

// A scalar UTF-8 string dataset (no 64 KiB limit, unlike an attribute), with a description.
inline void string_dataset(hid_t parent, const char* name, const std::string& value, const std::string& description) {
  hid_t type = H5Tcopy(H5T_C_S1);
  H5Tset_size(type, std::max<std::size_t>(1, value.size()));
  H5Tset_cset(type, H5T_CSET_UTF8);
  hid_t space = H5Screate(H5S_SCALAR);
  hid_t d = check_id(H5Dcreate2(parent, name, type, space, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT), name);
  check(H5Dwrite(d, type, H5S_ALL, H5S_ALL, H5P_DEFAULT, value.empty() ? "" : value.data()), name);
  string_attribute(d, "description", description);
  H5Dclose(d);
  H5Sclose(space);
  H5Tclose(type);
}

// A scalar attribute of an HDF5 type (a double by default).
template <class T>
void scalar_attribute(hid_t obj, const char* name, hid_t type, T value) {
  hid_t space = H5Screate(H5S_SCALAR);
  hid_t attr = check_id(H5Acreate2(obj, name, type, space, H5P_DEFAULT, H5P_DEFAULT), name);
  check(H5Awrite(attr, type, &value), name);
  H5Aclose(attr);
  H5Sclose(space);
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
  const hid_t id = dataset ? H5Dopen2(obj, name, H5P_DEFAULT) : H5Aopen(obj, name, H5P_DEFAULT);
  const hid_t type = dataset ? H5Dget_type(id) : H5Aget_type(id);
  std::string out;
  if (H5Tis_variable_str(type) > 0) {
    char* text = nullptr;
    hid_t mem = H5Tcopy(H5T_C_S1);
    H5Tset_size(mem, H5T_VARIABLE);
    H5Tset_cset(mem, H5Tget_cset(type));
    const herr_t status = dataset ? H5Dread(id, mem, H5S_ALL, H5S_ALL, H5P_DEFAULT, &text) : H5Aread(id, mem, &text);
    if (status >= 0 && text) out = text;
    if (text) H5free_memory(text);
    H5Tclose(mem);
  } else {
    out.resize(H5Tget_size(type));
    if (!out.empty()) {
      if (dataset) H5Dread(id, type, H5S_ALL, H5S_ALL, H5P_DEFAULT, out.data());
      else H5Aread(id, type, out.data());
    }
    out = out.c_str();  // up to a terminating NUL, if any
  }
  H5Tclose(type);
  if (dataset) H5Dclose(id);
  else H5Aclose(id);
  return out;
}

// A 1-D dataset of variable-length strings (string_list_dataset's); OutputError when it is
// missing or of another kind.
inline std::vector<std::string> read_string_list(hid_t parent, const char* path) {
  const hid_t d = H5Dopen2(parent, path, H5P_DEFAULT);
  if (d < 0) throw OutputError(std::string("the output has no ") + path);
  const hid_t type = H5Dget_type(d), space = H5Dget_space(d);
  hsize_t n = 0;
  const bool ok = H5Tget_class(type) == H5T_STRING && H5Tis_variable_str(type) > 0 &&
                  H5Sget_simple_extent_ndims(space) == 1 && H5Sget_simple_extent_dims(space, &n, nullptr) == 1;
  std::vector<char*> raw(ok ? n : 0, nullptr);
  herr_t status = -1;
  if (ok) {
    const hid_t mem = H5Tcopy(H5T_C_S1);
    H5Tset_size(mem, H5T_VARIABLE);
    H5Tset_cset(mem, H5Tget_cset(type));
    status = n ? H5Dread(d, mem, H5S_ALL, H5S_ALL, H5P_DEFAULT, raw.data()) : 0;
    H5Tclose(mem);
  }
  std::vector<std::string> out;
  for (char* s : raw) {
    out.emplace_back(s ? s : "");
    if (s) H5free_memory(s);
  }
  H5Sclose(space);
  H5Tclose(type);
  H5Dclose(d);
  if (!ok || status < 0) throw OutputError(std::string("the output's ") + path + " is not a list of strings");
  return out;
}

// The first `frames` frames of a [frame][...] dataset, as `mem_type`.
template <class T>
std::vector<T> read_frames(hid_t file, const char* path, hid_t mem_type, hsize_t frames) {
  hid_t d = H5Dopen2(file, path, H5P_DEFAULT);
  if (d < 0) throw OutputError(std::string("the output has no ") + path);
  hid_t space = H5Dget_space(d);
  const int rank = H5Sget_simple_extent_ndims(space);
  std::vector<hsize_t> dims(static_cast<std::size_t>(rank)), start(dims.size(), 0);
  H5Sget_simple_extent_dims(space, dims.data(), nullptr);
  if (rank < 1 || dims[0] < frames) {
    H5Sclose(space);
    H5Dclose(d);
    throw OutputError(std::string("the output's ") + path + " holds fewer frames than /frames_complete");
  }
  dims[0] = frames;
  std::size_t n = 1;
  for (auto x : dims) n *= x;
  std::vector<T> out(n);
  if (n > 0) {
    H5Sselect_hyperslab(space, H5S_SELECT_SET, start.data(), nullptr, dims.data(), nullptr);
    hid_t mem = H5Screate_simple(rank, dims.data(), nullptr);
    const herr_t status = H5Dread(d, mem_type, mem, space, H5P_DEFAULT, out.data());
    H5Sclose(mem);
    if (status < 0) {
      H5Sclose(space);
      H5Dclose(d);
      throw OutputError(std::string("cannot read ") + path + " of the output");
    }
  }
  H5Sclose(space);
  H5Dclose(d);
  return out;
}

}  // namespace noether::h5
