#include <gtest/gtest.h>

#include <vector>

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

namespace {
struct Block {
  size_t offset, count;
  bool last;
};
std::vector<Block> split(size_t available, size_t block_samples, bool end, size_t* consumed) {
  std::vector<Block> blocks;
  *consumed = railvib::splitIntoBlocks(available, block_samples, end, [&](size_t o, size_t c, bool l) {
    blocks.push_back({o, c, l});
  });
  return blocks;
}
}  // namespace

TEST(SplitIntoBlocks, OnlyFullBlocksWhileTheStreamRuns) {
  size_t consumed = 0;
  const auto blocks = split(250, 100, false, &consumed);
  ASSERT_EQ(blocks.size(), 2u);
  EXPECT_EQ(blocks[0].offset, 0u);
  EXPECT_EQ(blocks[1].offset, 100u);
  EXPECT_EQ(blocks[1].count, 100u);
  EXPECT_FALSE(blocks[1].last);
  EXPECT_EQ(consumed, 200u);  // 50 samples wait for the next call
  EXPECT_TRUE(split(99, 100, false, &consumed).empty());
  EXPECT_EQ(consumed, 0u);
}

TEST(SplitIntoBlocks, TheEndFlushesTheRemainderAndFlagsTheLastBlock) {
  size_t consumed = 0;
  auto blocks = split(250, 100, true, &consumed);
  ASSERT_EQ(blocks.size(), 3u);
  EXPECT_EQ(blocks[2].count, 50u);
  EXPECT_TRUE(blocks[2].last);
  EXPECT_FALSE(blocks[0].last || blocks[1].last);
  EXPECT_EQ(consumed, 250u);
  // A multiple of the block size: no empty trailer, the last full block is flagged.
  blocks = split(200, 100, true, &consumed);
  ASSERT_EQ(blocks.size(), 2u);
  EXPECT_TRUE(blocks[1].last);
  // Nothing pending at the end: one empty block carries the end of the stream.
  blocks = split(0, 100, true, &consumed);
  ASSERT_EQ(blocks.size(), 1u);
  EXPECT_EQ(blocks[0].count, 0u);
  EXPECT_TRUE(blocks[0].last);
  EXPECT_EQ(consumed, 0u);
}
