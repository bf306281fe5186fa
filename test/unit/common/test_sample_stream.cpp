#include <gtest/gtest.h>

#include "railvib/common/sample_stream.hpp"

using railvib::SampleIndexTracker;
using railvib::StreamGapError;

TEST(SampleIndexTracker, AcceptsContiguousBlocksAndRejectsGaps) {
  SampleIndexTracker tracker("soil_loads");
  tracker.accept(0, 10);
  tracker.accept(10, 5);
  EXPECT_EQ(tracker.nextIndex(), 15u);
  EXPECT_EQ(tracker.blockCount(), 2u);
  EXPECT_THROW(tracker.accept(20, 5), StreamGapError);  // 5 samples lost
  EXPECT_THROW(tracker.accept(10, 5), StreamGapError);  // duplicate
  tracker.accept(15, 1);
  EXPECT_EQ(tracker.nextIndex(), 16u);
}
