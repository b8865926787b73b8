#pragma once
// The file-access properties of every HDF5 file noether writes or reads back: the file format,
// and caches whose size does not grow with the file (docs/reliability.md, "Checksums" and
// "Memory").
#include "io/h5.hpp"

namespace noether::io {

// `chunk_cache_bytes`: per dataset (0 for a reader that reads each chunk once).
inline H5Handle file_access(std::size_t chunk_cache_bytes) {
  H5Handle access(H5Pcreate(H5P_FILE_ACCESS));
  // The 1.8 file format: its superblock (version 2) and object headers (version 2: groups,
  // attributes, shapes) carry checksums, which HDF5 verifies on every read. Not the 1.10 format:
  // its superblock marks a file whose writer was killed, and HDF5 then refuses to open it until
  // h5clear has been run on it.
  H5Pset_libver_bounds(access, H5F_LIBVER_V18, H5F_LIBVER_V110);
  // HDF5's defaults (1 MiB of chunks per dataset, metadata up to 32 MiB) fill as a file grows:
  // a few chunks per series (blocks are written and read in order) and 4 MiB of metadata
  // (the chunk indices' nodes) keep memory flat from 10^4 to 10^6 frames.
  H5Pset_cache(access, 0, 127, chunk_cache_bytes, 0.75);
  H5AC_cache_config_t config;
  config.version = H5AC__CURR_CACHE_CONFIG_VERSION;
  H5Pget_mdc_config(access, &config);
  config.max_size = 4 << 20;
  config.min_size = 1 << 20;
  config.set_initial_size = true;
  config.initial_size = 2 << 20;
  H5Pset_mdc_config(access, &config);
  return access;
}

// The file-creation properties of the files noether writes while a kill may come (run output,
// ensembles): file space is taken only at the end of the file and never given back (no
// aggregators, no free-space managers). HDF5 otherwise gives back its aggregators' unused tail
// when it closes the file, cutting the file shorter before it writes the superblock that says
// so; a kill in between left a file HDF5 refuses to open ("truncated file"). Nothing is freed
// while a run writes, so nothing is lost.
inline H5Handle file_creation() {
  H5Handle creation(H5Pcreate(H5P_FILE_CREATE));
  H5Pset_file_space_strategy(creation, H5F_FSPACE_STRATEGY_NONE, 0, 1);
  // The root group keeps its links in its own header, with room for all of them from the start:
  // a link added after the file is published (/work, when the run ends) is then one write of
  // that header in place, never a new header chunk or a link heap whose pieces a flush writes
  // in no fixed order.
  H5Pset_link_phase_change(creation, 64, 48);
  H5Pset_est_link_info(creation, 24, 24);
  return creation;
}

// The group-creation properties of a group made and linked after the file is published: room
// in its header for the reference count linking it adds, so that the link changes its header
// in place (see file_creation).
inline H5Handle late_group_creation() {
  H5Handle creation(H5Pcreate(H5P_GROUP_CREATE));
  H5Pset_est_link_info(creation, 4, 32);
  return creation;
}

}  // namespace noether::io
