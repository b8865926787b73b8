#pragma once
// Series: one [frame][shape...] series of an output file, written in blocks (internal to
// libnoether).
#include "io/h5.hpp"

#include <hdf5.h>

#include <noether/error.hpp>

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <vector>

namespace noether::io {

// A series [frame][shape...] of 8-byte numbers (double, int64 or uint64: `type`): a chunked
// dataset whose chunks are all allocated (and filled with `fill`) when it is created or grown,
// so that writing frames changes raw data only, never the file's metadata (docs/user-guide.md,
// "Output files": a kill at any moment leaves a consistent file).
struct Series {
  H5Handle dataset;
  hid_t type = -1;  // a predefined type (not closed)
  std::vector<hsize_t> frame_shape;
  std::size_t frame_size = 1;           // numbers per frame

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
    const H5Handle space(H5Screate_simple(static_cast<int>(dims.size()), dims.data(), maxdims.data()));
    const H5Handle plist(H5Pcreate(H5P_DATASET_CREATE));
    H5Pset_chunk(plist, static_cast<int>(chunk.size()), chunk.data());
    H5Pset_alloc_time(plist, H5D_ALLOC_TIME_EARLY);
    H5Pset_fill_value(plist, type, fill);
    H5Pset_fill_time(plist, H5D_FILL_TIME_ALLOC);
    dataset = check_id(H5Dcreate2(parent, name, type, space, H5P_DEFAULT, plist, H5P_DEFAULT), name);
  }
  Series(const Series&) = delete;
  Series& operator=(const Series&) = delete;

  // One frame more, to be filled in place — every number of it: the memory is reused, not
  // cleared (valid until the next append or hand_over).
  std::uint64_t* append_frame() {
    const std::size_t at = buffered_ * frame_size;
    if (buffer_.size() < at + frame_size) buffer_.resize(std::max(at + frame_size, 2 * buffer_.size()));
    ++buffered_;
    return buffer_.data() + at;
  }

  // Room for a block of `frames` frames in both buffers, so that appending never reallocates.
  void reserve_frames(std::size_t frames) {
    buffer_.resize(std::max(buffer_.size(), frames * frame_size));
    handed_.resize(std::max(handed_.size(), frames * frame_size));
  }

  // Sets the number of frames (growing allocates and fills the new chunks).
  void resize(hsize_t frames) {
    std::vector<hsize_t> dims{frames};
    dims.insert(dims.end(), frame_shape.begin(), frame_shape.end());
    check(H5Dset_extent(dataset, dims.data()), "resizing a dataset");
  }

  // The buffered frames become the block to write (`handed`), and the buffer takes the next
  // frames meanwhile: a block may be written on another thread while frames are appended.
  void hand_over() {
    std::swap(buffer_, handed_);
    handed_frames_ = buffered_;
    buffered_ = 0;
  }
  // The handed block's frame i, [shape...] (read when its block is completed).
  const std::uint64_t* handed_frame(std::size_t i) const { return handed_.data() + i * frame_size; }
  // A series that takes no frames as they arrive, filled when its block is written: its handed
  // block made `frames` frames long, to be filled in place.
  std::uint64_t* handed_block(std::size_t frames) {
    if (handed_.size() < frames * frame_size) handed_.resize(frames * frame_size);
    handed_frames_ = frames;
    return handed_.data();
  }
  // Writes the handed block from `first_frame` on.
  void write_handed(hsize_t first_frame) {
    const hsize_t frames = handed_frames_;
    handed_frames_ = 0;
    if (frames == 0 || frame_size == 0) return;
    std::vector<hsize_t> start{first_frame}, count{frames};
    for (auto d : frame_shape) {
      start.push_back(0);
      count.push_back(d);
    }
    const H5Handle file_space(H5Dget_space(dataset));
    H5Sselect_hyperslab(file_space, H5S_SELECT_SET, start.data(), nullptr, count.data(), nullptr);
    const H5Handle mem_space(H5Screate_simple(static_cast<int>(count.size()), count.data(), nullptr));
    const herr_t status = H5Dwrite(dataset, type, mem_space, file_space, H5P_DEFAULT, handed_.data());
    check(status, "writing a block of frames");
  }

 private:
  // The frames not yet written, as raw 8-byte words: `buffered_` frames taking new ones, and the
  // block being written (`handed_frames_` of them). Both keep their memory from block to block.
  std::vector<std::uint64_t> buffer_, handed_;
  std::size_t buffered_ = 0, handed_frames_ = 0;
};

}  // namespace noether::io
