// A Range header cannot make a small request cost a big answer (issue 36: 200 ranges of "0-"
// built 775 MB): many, open-ended or overlapping ranges are a 416 before any work; one range,
// or a few closed disjoint ones, still work.
#include <gtest/gtest.h>

#include <string>

#include "server/range_limits.h"
#include "tests/server/server_fixture.h"

namespace penumbra::server::test {
namespace {

int statusWithRange(TestClient& client, const std::string& range) {
  const auto res = client.Get("/api/health", httplib::Headers{{"Range", range}});
  return res ? res->status : -1;
}

TEST(RangeLimits, ManyOpenOrOverlappingRangesAre416) {
  RunningServer running;
  auto client = running.client();
  std::string many = "bytes=0-";
  for (int i = 1; i < 200; ++i) many += ",0-";
  const auto res = client.Get("/api/health", httplib::Headers{{"Range", many}});
  ASSERT_TRUE(res);
  EXPECT_EQ(res->status, 416);
  EXPECT_LT(res->body.size(), 1000u);
  EXPECT_EQ(bodyJson(res)["error"]["path"], "(header).Range");
  EXPECT_EQ(statusWithRange(client, "bytes=0-9,5-14"), 416);   // overlapping
  EXPECT_EQ(statusWithRange(client, "bytes=0-9,20-"), 416);    // an open one beside another
  EXPECT_EQ(statusWithRange(client, "bytes=-5,0-3"), 416);     // a suffix beside another
  std::string nine = "bytes=0-0";
  for (int i = 1; i <= int(kMaxRanges); ++i) nine += "," + std::to_string(2 * i) + "-" + std::to_string(2 * i);
  EXPECT_EQ(statusWithRange(client, nine), 416);               // kMaxRanges + 1 closed ones
  // What clients send is still answered.
  EXPECT_NE(statusWithRange(client, "bytes=0-"), 416);
  EXPECT_NE(statusWithRange(client, "bytes=-5"), 416);
  EXPECT_NE(statusWithRange(client, "bytes=0-3,10-12"), 416);
  const auto health = client.Get("/api/health");
  ASSERT_TRUE(health);
  EXPECT_EQ(health->status, 200);
}

}  // namespace
}  // namespace penumbra::server::test
