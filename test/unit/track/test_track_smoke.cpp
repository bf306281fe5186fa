#include <gtest/gtest.h>

#include "railvib/track/track_model.hpp"
#include "railvib/track/track_newmark.hpp"

TEST(TrackSmoke, Builds) {
  railvib::track::TrackParams p;
  railvib::track::TrackModel m(p);
  EXPECT_GT(m.dofCount(), 0);
}
