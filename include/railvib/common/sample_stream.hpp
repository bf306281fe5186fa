// railvib/common: continuity of sample streams between nodes.
//
// Every stream block carries the index of its first sample; a consumer keeps
// a SampleIndexTracker and refuses a block that does not start where the last
// one ended, so a lost or reordered block is detected, never silently skipped.
#pragma once

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <stdexcept>
#include <string>

namespace railvib {

class StreamGapError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

class SampleIndexTracker {
 public:
  explicit SampleIndexTracker(std::string stream_name, uint64_t first_expected = 0)
      : name_(std::move(stream_name)), next_(first_expected) {}

  /// Accept a block [first_index, first_index + count); throws StreamGapError otherwise.
  void accept(uint64_t first_index, uint64_t count) {
    if (first_index != next_) {
      throw StreamGapError("stream '" + name_ + "': expected sample " + std::to_string(next_) +
                           ", got block starting at " + std::to_string(first_index) +
                           (first_index > next_ ? " (" + std::to_string(first_index - next_) + " samples lost)"
                                                : " (duplicate or reordered block)"));
    }
    next_ += count;
    ++blocks_;
  }
  uint64_t nextIndex() const { return next_; }
  uint64_t blockCount() const { return blocks_; }
  const std::string& name() const { return name_; }

 private:
  std::string name_;
  uint64_t next_;
  uint64_t blocks_ = 0;
};

/// Cut `available` pending samples into stream blocks of at most `block_samples`.
/// Only full blocks go out while the stream runs; at its end the remainder goes
/// too, and the last block is flagged (an empty one if nothing is left, so the
/// end is always signalled). Calls emit(offset, count, last) per block and
/// returns the number of samples consumed (to drop from the pending buffer).
template <class Emit>
size_t splitIntoBlocks(size_t available, size_t block_samples, bool end_of_stream, Emit&& emit) {
  if (block_samples == 0) throw std::invalid_argument("splitIntoBlocks: block_samples must be > 0");
  size_t offset = 0;
  while (available - offset >= block_samples || (end_of_stream && offset <= available)) {
    const size_t count = std::min(block_samples, available - offset);
    const bool last = end_of_stream && offset + count == available;
    emit(offset, count, last);
    offset += count;
    if (last) break;
  }
  return offset;
}

}  // namespace railvib
