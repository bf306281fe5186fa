// The stream contract every consumer applies to a block before using it, and a property fuzz of
// it: random and adversarial mutations of a valid block (counts, sizes, period, NaN/inf, huge
// values, index overflow) are either refused with a message naming the stream and the field, or
// are a valid block by an independent check. Run under AddressSanitizer too (./railvib test).
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include "railvib/common/stream_contract.hpp"

using railvib::BlockArray;
using railvib::BlockContract;
using railvib::BlockHead;
using railvib::StreamContractError;
using railvib::validateBlock;

namespace {

BlockContract soilLoadsContract(uint32_t sleepers) {
  BlockContract c;
  c.stream = "/soil_loads";
  c.sample_period_s = 1.0 / 2000.0;
  c.period_source = "track.output.load_sample_rate_hz = 2000 Hz";
  c.count_field = "sleeper_count";
  c.point_label = "sleeper";
  c.point_count = sleepers;
  c.point_source = "the sleeper_layout";
  c.max_block_samples = 1000;
  return c;
}

std::string errorOf(const BlockContract& c, const BlockHead& h, const std::vector<double>& values, uint32_t comps,
                    double bound) {
  try {
    validateBlock(c, h, {{"force_n", &values, comps, bound, "limits.soil_load_n", "N"}});
  } catch (const StreamContractError& e) {
    return e.what();
  }
  return "";
}

// The oracle: what a valid block is, written independently of validateBlock.
bool independentlyValid(const BlockContract& c, const BlockHead& h, const std::vector<double>& v, uint32_t comps,
                        double bound) {
  if (!(h.sample_period_s > 0.0) || !std::isfinite(h.sample_period_s)) return false;
  if (std::fabs(h.sample_period_s / c.sample_period_s - 1.0) > 1e-9) return false;
  if (h.point_count != c.point_count || h.sample_count > c.max_block_samples) return false;
  if (h.first_sample_index > std::numeric_limits<uint64_t>::max() - h.sample_count) return false;
  if (v.size() != static_cast<size_t>(h.sample_count) * h.point_count * comps) return false;
  for (double x : v) {
    if (std::isnan(x) || std::isinf(x) || std::fabs(x) > bound) return false;
  }
  return true;
}

}  // namespace

TEST(StreamContract, AValidBlockPasses) {
  const BlockContract c = soilLoadsContract(3);
  const std::vector<double> f{1, 2, 3, 4, 5, 6};
  EXPECT_EQ(errorOf(c, {10, false, 5e-4, 2, 3}, f, 1, 1e6), "");
  EXPECT_EQ(errorOf(c, {12, true, 5e-4, 0, 3}, {}, 1, 1e6), "") << "an empty last block is valid";
}

TEST(StreamContract, EachViolationNamesStreamFieldValueAndSample) {
  const BlockContract c = soilLoadsContract(3);
  const std::vector<double> f{1, 2, 3, 4, 5, 6};
  auto expect = [&](const std::string& message, const std::vector<std::string>& parts) {
    ASSERT_FALSE(message.empty());
    for (const auto& p : parts) EXPECT_NE(message.find(p), std::string::npos) << p << " not in: " << message;
  };
  expect(errorOf(c, {10, false, 0.0, 2, 3}, f, 1, 1e6),
         {"/soil_loads", "sample_period_s = 0", "finite positive", "load_sample_rate_hz", "sample 10"});
  expect(errorOf(c, {10, false, std::nan(""), 2, 3}, f, 1, 1e6), {"sample_period_s = nan"});
  expect(errorOf(c, {10, false, 1e-3, 2, 3}, f, 1, 1e6), {"sample_period_s = 0.001", "differs", "0.0005"});
  expect(errorOf(c, {10, false, 5e-4, 2, 1}, f, 1, 1e6), {"sleeper_count = 1", "sleeper_layout has 3"});
  expect(errorOf(c, {10, false, 5e-4, 3, 3}, f, 1, 1e6), {"force_n has 6 values", "3 x 3 = 9"});
  expect(errorOf(c, {10, false, 5e-4, 4000000000u, 3}, f, 1, 1e6), {"sample_count = 4000000000", "more than"});
  expect(errorOf(c, {std::numeric_limits<uint64_t>::max() - 1, false, 5e-4, 2, 3}, f, 1, 1e6),
         {"first_sample_index", "largest sample index"});
  std::vector<double> bad = f;
  bad[4] = std::nan("");
  expect(errorOf(c, {10, false, 5e-4, 2, 3}, bad, 1, 1e6),
         {"force_n[sample 11, sleeper 1] = nan", "limits.soil_load_n"});
  bad[4] = 1e300;
  expect(errorOf(c, {10, false, 5e-4, 2, 3}, bad, 1, 1e6), {"= 1e+300", "<= 1e+06 N"});
  bad[4] = -std::numeric_limits<double>::infinity();
  expect(errorOf(c, {10, false, 5e-4, 2, 3}, bad, 1, 1e6), {"= -inf"});
  // Three components per point: the component is named.
  BlockContract v = soilLoadsContract(2);
  std::vector<double> xyz(6, 0.0);
  xyz[5] = 20.0;
  expect(errorOf(v, {0, false, 5e-4, 1, 2}, xyz, 3, 10.0), {"[sample 0, sleeper 1, z] = 20"});
}

TEST(StreamContract, LayoutsAreCheckedForCountsNamesAndFiniteness) {
  using railvib::validatePointLayout;
  using railvib::validateSleeperPositions;
  EXPECT_NO_THROW(validatePointLayout("/surface_points", {"a", "b"}, 2, {0, 0, 0, 1, 1, 0}, 10));
  EXPECT_THROW(validatePointLayout("/surface_points", {}, 0, {}, 10), StreamContractError);
  EXPECT_THROW(validatePointLayout("/surface_points", {"a", "a"}, 2, {0, 0, 0, 1, 1, 0}, 10), StreamContractError);
  EXPECT_THROW(validatePointLayout("/surface_points", {"a", ""}, 2, {0, 0, 0, 1, 1, 0}, 10), StreamContractError);
  EXPECT_THROW(validatePointLayout("/surface_points", {"a", "b"}, 1, {0, 0, 0}, 10), StreamContractError);
  EXPECT_THROW(validatePointLayout("/surface_points", {"a", "b"}, 2, {0, 0, 0, 1, std::nan(""), 0}, 10),
               StreamContractError);
  EXPECT_THROW(validatePointLayout("/surface_points", {"a", "b", "c"}, 3, std::vector<double>(9, 0.0), 2),
               StreamContractError);
  EXPECT_NO_THROW(validateSleeperPositions("/sleeper_layout", {-0.72, 0.0, 0.72}, 10));
  EXPECT_THROW(validateSleeperPositions("/sleeper_layout", {0.0, 0.0}, 10), StreamContractError);
  EXPECT_THROW(validateSleeperPositions("/sleeper_layout", {0.72, 0.0}, 10), StreamContractError);
  EXPECT_THROW(validateSleeperPositions("/sleeper_layout", {0.0, INFINITY}, 10), StreamContractError);
  EXPECT_THROW(validateSleeperPositions("/sleeper_layout", {}, 10), StreamContractError);
}

// The property: 20 000 mutated blocks, each refused by name or valid by the oracle.
TEST(StreamContractFuzz, MutatedBlocksAreRefusedByNameOrValid) {
  std::mt19937_64 rng(20260101);
  const uint32_t sleepers = 7;
  const BlockContract c = soilLoadsContract(sleepers);
  const std::vector<double> specials{std::nan(""),
                                     INFINITY,
                                     -INFINITY,
                                     1e300,
                                     -1e300,
                                     1e6,
                                     1e6 + 1,
                                     0.0,
                                     -0.0,
                                     std::numeric_limits<double>::denorm_min(),
                                     std::numeric_limits<double>::max()};
  size_t refused = 0, accepted = 0;
  for (int iteration = 0; iteration < 20000; ++iteration) {
    BlockHead h{static_cast<uint64_t>(rng() % 1000), (rng() % 5) == 0, c.sample_period_s,
                static_cast<uint32_t>(1 + rng() % 50), sleepers};
    std::vector<double> v(static_cast<size_t>(h.sample_count) * sleepers);
    for (double& x : v) x = std::uniform_real_distribution<double>(-5e5, 5e5)(rng);
    const int mutations = static_cast<int>(rng() % 4);
    for (int m = 0; m < mutations; ++m) {
      switch (rng() % 9) {
        case 0:  // count fields
          h.sample_count = (rng() % 2) ? static_cast<uint32_t>(rng()) : h.sample_count + 1;
          break;
        case 1:
          h.point_count = static_cast<uint32_t>(rng() % 2 ? rng() : rng() % 10);
          break;
        case 2:  // array size: truncated, grown, emptied
          v.resize(rng() % 3 == 0 ? 0 : static_cast<size_t>(rng() % (v.size() + 20)));
          break;
        case 3:  // period: zero, negative, NaN, another rate, nearly equal
          h.sample_period_s =
              std::vector<double>{0.0, -5e-4, std::nan(""), 1e-3, 5e-4 * (1 + 1e-12), INFINITY, 1e-300}[rng() % 7];
          break;
        case 4:  // a special value somewhere
          if (!v.empty()) v[rng() % v.size()] = specials[rng() % specials.size()];
          break;
        case 5:  // index near overflow
          h.first_sample_index = std::numeric_limits<uint64_t>::max() - rng() % 100;
          break;
        case 6:  // duplicated samples (sizes stay consistent when counts follow)
          v.insert(v.end(), v.begin(), v.begin() + static_cast<long>(std::min<size_t>(v.size(), sleepers)));
          h.sample_count += (rng() % 2);
          break;
        case 7:  // reordered values: valid if nothing else changed
          std::shuffle(v.begin(), v.end(), rng);
          break;
        default:  // huge but finite values
          for (double& x : v) x *= 1e3;
          break;
      }
    }
    const std::string message = errorOf(c, h, v, 1, 1e6);
    const bool valid = independentlyValid(c, h, v, 1, 1e6);
    if (valid) {
      EXPECT_EQ(message, "") << "valid block refused, iteration " << iteration;
      ++accepted;
    } else {
      ASSERT_FALSE(message.empty()) << "invalid block accepted, iteration " << iteration;
      EXPECT_EQ(message.rfind("stream /soil_loads: ", 0), 0u) << message;
      ++refused;
    }
  }
  // Both outcomes were exercised.
  EXPECT_GT(refused, 5000u);
  EXPECT_GT(accepted, 1000u);
}

TEST(StreamContract, FirstValueOutsideFindsNaNAndBounds) {
  const std::vector<double> v{0.0, 1.0, -2.0, std::nan(""), 5.0};
  EXPECT_EQ(railvib::firstValueOutside(v.data(), v.size(), 10.0), 3u);
  EXPECT_EQ(railvib::firstValueOutside(v.data(), 3, 10.0), 3u);
  EXPECT_EQ(railvib::firstValueOutside(v.data(), 3, 1.5), 2u);
  EXPECT_EQ(railvib::firstValueOutside(v.data(), 0, 1.5), 0u);
}
