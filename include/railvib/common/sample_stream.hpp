// railvib/common: continuity of sample streams between nodes.
//
// Every stream block carries the index of its first sample; a consumer keeps
// a SampleIndexTracker and refuses a block that does not start where the last
// one ended, so a lost or reordered block is detected, never silently skipped.
#pragma once

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

}  // namespace railvib
