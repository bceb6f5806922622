#include "quiver/base/byte_codec.h"

#include <gtest/gtest.h>

namespace quiver::bytes {
namespace {

TEST(WireTest, VarintsRoundTrip) {
  std::vector<std::uint8_t> buf;
  Writer w(buf);
  for (std::uint64_t v : {0ull, 1ull, 127ull, 128ull, 300ull, ~0ull}) w.varint(v);
  w.svarint(-1);
  w.svarint(INT64_MIN);
  w.f64(3.5);
  w.string("hi");
  Reader r(buf, "test");
  for (std::uint64_t v : {0ull, 1ull, 127ull, 128ull, 300ull, ~0ull}) EXPECT_EQ(r.varint("v"), v);
  EXPECT_EQ(r.svarint("s"), -1);
  EXPECT_EQ(r.svarint("s"), INT64_MIN);
  EXPECT_EQ(r.f64("d"), 3.5);
  EXPECT_EQ(r.string("s", 10), "hi");
  EXPECT_TRUE(r.ok());
  EXPECT_TRUE(r.at_end());
}

TEST(WireTest, FailureIsStickyAndNamesFieldAndOffset) {
  std::vector<std::uint8_t> buf = {0x80, 0x80};  // an unfinished varint
  Reader r(buf, "frame");
  EXPECT_EQ(r.varint("length"), 0u);
  EXPECT_FALSE(r.ok());
  EXPECT_EQ(r.error().code, ErrorCode::kTruncated);
  EXPECT_NE(r.error().message.find("'length'"), std::string::npos) << r.error().message;
  EXPECT_NE(r.error().message.find("frame"), std::string::npos);
  // Later reads return zero and do not overwrite the first error, nor claim huge counts.
  EXPECT_EQ(r.count("items", 1000), 0u);
  EXPECT_EQ(r.u8("x"), 0);
  EXPECT_NE(r.error().message.find("'length'"), std::string::npos);
}

TEST(WireTest, CountsAreCheckedAgainstWhatRemains) {
  std::vector<std::uint8_t> buf;
  Writer w(buf);
  w.varint(1'000'000);  // claims a million 8-byte items
  w.u8(0);
  Reader r(buf, "list");
  EXPECT_EQ(r.count("items", UINT32_MAX, 8), 0u);
  EXPECT_EQ(r.error().code, ErrorCode::kTruncated);
  Reader r2(buf, "list");
  EXPECT_EQ(r2.count("items", 10, 1), 0u);
  EXPECT_EQ(r2.error().code, ErrorCode::kTooLarge);
}

TEST(WireTest, OverlongVarintIsMalformed) {
  std::vector<std::uint8_t> buf(11, 0xff);
  Reader r(buf, "x");
  r.varint("v");
  EXPECT_EQ(r.error().code, ErrorCode::kMalformed);
}

}  // namespace
}  // namespace quiver::bytes
