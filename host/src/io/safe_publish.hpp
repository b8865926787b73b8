#pragma once
// Claiming and publishing an output file (docs/user-guide.md, "Output files"). The file is
// built under a hidden name in the same folder and renamed into place once its layout is
// complete and flushed, so the path holds either what was there before or a readable file; an
// existing file is locked (flock) from the claim until it is replaced, and the new file from its
// creation until it is closed, so a second run on the same path is refused and loses nothing.
// (HDF5 1.10 locks only after opening with O_TRUNC, and a record lock would be dropped when
// HDF5 closes any descriptor of the file, so the lock is ours and HDF5's own is switched off for
// the files noether writes: HDF5_USE_FILE_LOCKING=FALSE unless the user set it.)
//
// Used by every file noether writes for a user: run output (output.cpp), ensembles
// (ensemble.cpp), saved simulations (continuation.cpp), views and exports (view.cpp,
// export_vtk.cpp: write_whole_file).
#include <filesystem>
#include <string>
#include <vector>

namespace noether::io {

// Refuses a symbolic link, anything but a regular file, one of `inputs`, and an existing file
// unless `overwrite`; locks an existing file. Returns its descriptor (held until the new file
// replaces it), or −1 when the path is free.
int claim_output(const std::filesystem::path& path, bool overwrite, const std::vector<std::filesystem::path>& inputs = {});

// The hidden name a file for `path` is built under: .<name>.partial-<pid>, next to it.
std::filesystem::path partial_name(const std::filesystem::path& path);

// Creates the hidden file (never an existing one) and locks it; returns the descriptor.
int create_partial(const std::filesystem::path& partial, const std::filesystem::path& path);

// Moves the finished file to `path`: replacing the claimed file (`replace`), or only if no other
// process created `path` meanwhile.
void publish_file(const std::filesystem::path& partial, const std::filesystem::path& path, bool replace);

// A file made in one piece (a page, a collection) by the rules above: claimed, written under its
// hidden name, published. OutputError (nothing changed at `path`) when it cannot be.
void write_whole_file(const std::filesystem::path& path, const std::string& bytes, bool overwrite,
                      const std::vector<std::filesystem::path>& inputs = {});

}  // namespace noether::io
