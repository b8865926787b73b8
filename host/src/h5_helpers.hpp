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

// A scalar double attribute.
inline void scalar_attribute(hid_t obj, const char* name, double value) {
  hid_t space = H5Screate(H5S_SCALAR);
  hid_t attr = check_id(H5Acreate2(obj, name, H5T_NATIVE_DOUBLE, space, H5P_DEFAULT, H5P_DEFAULT), name);
  check(H5Awrite(attr, H5T_NATIVE_DOUBLE, &value), name);
  H5Aclose(attr);
  H5Sclose(space);
}

}  // namespace noether::h5
