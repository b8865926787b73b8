#pragma once
// Series: one [frame][shape...] series of an output file, written in blocks (internal to
// libnoether).
#include "../h5_helpers.hpp"

#include <hdf5.h>

#include <noether/error.hpp>

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <vector>

namespace noether::io {

using h5::check;
using h5::check_id;

// A series [frame][shape...] of 8-byte numbers (double, int64 or uint64: `type`): a chunked
// dataset whose chunks are all allocated (and filled with `fill`) when it is created or grown,
// so that writing frames changes raw data only, never the file's metadata (docs/user-guide.md,
// "Output files": a kill at any moment leaves a consistent file).
struct Series {
  hid_t dataset = -1;
  hid_t type = -1;
  std::vector<hsize_t> frame_shape;
  std::size_t frame_size = 1;           // numbers per frame
  std::vector<std::uint64_t> buffer;    // the frames not yet written, as raw 8-byte words

  Series(hid_t parent, const char* name, hid_t h5type, std::vector<hsize_t> shape, hsize_t frames,
         const void* fill)
      : type(h5type), frame_shape(std::move(shape)) {
    if (H5Tget_size(type) != sizeof(std::uint64_t)) throw OutputError("a series of numbers that are not 8 bytes");
    for (auto d : frame_shape) frame_size *= d;
    std::vector<hsize_t> dims{frames}, maxdims{H5S_UNLIMITED}, chunk;
    // Chunks of about 8 KiB (at most 1024 frames), no larger than the frames allocated: a file of
    // one frame (a saved simulation) is not padded to a thousand.
    const hsize_t frames_per_chunk = std::max<hsize_t>(
        1, std::min<hsize_t>({1024, 8192 / std::max<std::size_t>(1, frame_size), std::max<hsize_t>(1, frames)}));
    chunk.push_back(frames_per_chunk);
    for (auto d : frame_shape) {
      dims.push_back(d);
      maxdims.push_back(d);
      chunk.push_back(std::max<hsize_t>(1, d));
    }
    hid_t space = H5Screate_simple(static_cast<int>(dims.size()), dims.data(), maxdims.data());
    hid_t plist = H5Pcreate(H5P_DATASET_CREATE);
    H5Pset_chunk(plist, static_cast<int>(chunk.size()), chunk.data());
    H5Pset_alloc_time(plist, H5D_ALLOC_TIME_EARLY);
    H5Pset_fill_value(plist, type, fill);
    H5Pset_fill_time(plist, H5D_FILL_TIME_ALLOC);
    dataset = check_id(H5Dcreate2(parent, name, type, space, H5P_DEFAULT, plist, H5P_DEFAULT),
                       name);
    H5Pclose(plist);
    H5Sclose(space);
  }
  ~Series() {
    if (dataset >= 0) H5Dclose(dataset);
  }
  Series(const Series&) = delete;
  Series& operator=(const Series&) = delete;

  // One frame (frame_size numbers of the series' type).
  void push(const void* values) {
    if (frame_size) std::memcpy(append_frame(), values, frame_size * sizeof(std::uint64_t));
  }
  // One frame more, zeroed, to be filled in place (valid until the next append or hand_over).
  std::uint64_t* append_frame() {
    const std::size_t at = buffer.size();
    buffer.resize(at + frame_size);
    return buffer.data() + at;
  }

  // Room for a block of `frames` frames in both buffers, so that pushing never reallocates.
  void reserve_frames(std::size_t frames) {
    buffer.reserve(frames * frame_size);
    handed.reserve(frames * frame_size);
  }

  // Sets the number of frames (growing allocates and fills the new chunks).
  void resize(hsize_t frames) {
    std::vector<hsize_t> dims{frames};
    dims.insert(dims.end(), frame_shape.begin(), frame_shape.end());
    check(H5Dset_extent(dataset, dims.data()), "resizing a dataset");
  }

  // Writes the buffered frames from `first_frame` on (inside the allocated frames).
  void write(hsize_t first_frame) {
    hand_over();
    write_handed(first_frame);
  }
  // The buffered frames become the block to write (`handed`), and the buffer takes the next
  // frames meanwhile: a block may be written on another thread while frames are pushed.
  void hand_over() {
    std::swap(buffer, handed);
    buffer.clear();
  }
  // Writes the handed block from `first_frame` on.
  void write_handed(hsize_t first_frame) {
    if (handed.empty() || frame_size == 0) {
      handed.clear();
      return;
    }
    const hsize_t frames = handed.size() / frame_size;
    std::vector<hsize_t> start{first_frame}, count{frames};
    for (auto d : frame_shape) {
      start.push_back(0);
      count.push_back(d);
    }
    hid_t file_space = H5Dget_space(dataset);
    H5Sselect_hyperslab(file_space, H5S_SELECT_SET, start.data(), nullptr, count.data(), nullptr);
    hid_t mem_space = H5Screate_simple(static_cast<int>(count.size()), count.data(), nullptr);
    const herr_t status = H5Dwrite(dataset, type, mem_space, file_space, H5P_DEFAULT, handed.data());
    H5Sclose(mem_space);
    H5Sclose(file_space);
    handed.clear();
    check(status, "writing a block of frames");
  }

 private:
  std::vector<std::uint64_t> handed;  // the block being written
};

}  // namespace noether::io
