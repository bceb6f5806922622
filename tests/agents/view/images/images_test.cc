// Images stored as node attributes: round trips (PNG exact, JPEG close), 1- and 4-channel
// images, prefixes, already-encoded bytes, replication through the codec, and every refusal with
// a message that names the function, the node and the attribute.

#include <gtest/gtest.h>

#include <chrono>
#include <cstdio>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <string>
#include <vector>

#include "graph/graph_test_util.h"
#include "quiver/agents/view/images/image_attrs.h"
#include "quiver/graph/limits.h"

namespace quiver::agents::images {
namespace {

using graph::Bytes;
using graph::NodeId;
using graph::Value;
using graph::testing::Peer;

// A deterministic picture: smooth gradients (one per channel) and a white rectangle.
cv::Mat picture(int width, int height, int type) {
  cv::Mat m(height, width, type);
  for (int y = 0; y < height; ++y) {
    for (int x = 0; x < width; ++x) {
      for (int c = 0; c < m.channels(); ++c) {
        const int v = c % 2 == 0 ? x * 200 / width + y * 55 / height : y * 200 / height + 40;
        m.ptr<std::uint8_t>(y)[x * m.channels() + c] = static_cast<std::uint8_t>(v);
      }
    }
  }
  cv::rectangle(m, cv::Rect(width / 4, height / 4, width / 3, height / 3), cv::Scalar::all(255),
                cv::FILLED);
  return m;
}

// Noise from OpenCV's seeded generator (incompressible).
cv::Mat noise(int width, int height, int type, std::uint64_t seed) {
  cv::Mat m(height, width, type);
  cv::RNG rng(seed);
  rng.fill(m, cv::RNG::UNIFORM, 0, 256);
  return m;
}

bool same_pixels(const cv::Mat& a, const cv::Mat& b) {
  return a.size() == b.size() && a.type() == b.type() && cv::norm(a, b, cv::NORM_INF) == 0;
}

bool contains(const std::string& text, const std::string& part) {
  return text.find(part) != std::string::npos;
}

class ImagesTest : public ::testing::Test {
 protected:
  ImagesTest() : a(1) { camera = a.add("camera", "camera"); }

  // "node 'camera' (id ...)", as every read error names it.
  std::string camera_text() const { return "node 'camera' (id " + camera.to_string() + ")"; }

  void commit_image(const cv::Mat& m, ImageEncoding e = ImageEncoding::kPng,
                    std::string_view prefix = kDefaultPrefix) {
    auto tx = a.g.begin();
    Status s = set_image(tx, camera, m, e, prefix);
    ASSERT_TRUE(s.ok()) << s.error().to_string();
    ASSERT_TRUE(tx.commit().ok());
  }
  // Writes raw attributes, as a peer with a bug (or a forger) could: removed first, since a write
  // alone never changes an attribute's value type.
  void set_raw(std::string_view attr, Value v) {
    auto tx = a.g.begin();
    ASSERT_TRUE(tx.remove_attr(camera, attr).ok());
    ASSERT_TRUE(tx.set(camera, attr, std::move(v)).ok());
    ASSERT_TRUE(tx.commit().ok());
  }
  Error read_error() {
    auto r = get_image(a.g, camera);
    EXPECT_FALSE(r.ok());
    return r.ok() ? Error{} : r.error();
  }

  Peer a;
  NodeId camera;
};

TEST_F(ImagesTest, PngRoundTripIsExact) {
  const cv::Mat bgr = noise(64, 48, CV_8UC3, 7);
  commit_image(bgr);
  EXPECT_EQ(a.g.get<std::int64_t>(camera, "image_width").value(), 64);
  EXPECT_EQ(a.g.get<std::int64_t>(camera, "image_height").value(), 48);
  EXPECT_EQ(a.g.get<std::string>(camera, "image_encoding").value(), "png");
  ASSERT_NE(a.g.attr(camera, "image"), nullptr);
  ASSERT_NE(a.g.attr(camera, "image")->get_if<Bytes>(), nullptr);

  auto back = get_image(a.g, camera);
  ASSERT_TRUE(back.ok()) << back.error().to_string();
  EXPECT_TRUE(same_pixels(*back, bgr));

  auto info = image_info(a.g, camera);
  ASSERT_TRUE(info.ok()) << info.error().to_string();
  EXPECT_EQ(info->width, 64);
  EXPECT_EQ(info->height, 48);
  EXPECT_EQ(info->encoding, ImageEncoding::kPng);
  const Bytes& stored = *a.g.attr(camera, "image")->get_if<Bytes>();
  EXPECT_EQ(info->bytes.data(), stored.data()) << "image_info() copies nothing";
  EXPECT_EQ(info->bytes.size(), stored.size());
  EXPECT_STREQ(mime_type(info->encoding), "image/png");
  EXPECT_STREQ(mime_type(ImageEncoding::kJpeg), "image/jpeg");
  EXPECT_STREQ(to_string(ImageEncoding::kJpeg), "jpeg");
}

TEST_F(ImagesTest, JpegRoundTripIsClose) {
  const cv::Mat bgr = picture(160, 120, CV_8UC3);
  commit_image(bgr, ImageEncoding::kJpeg);
  EXPECT_EQ(a.g.get<std::string>(camera, "image_encoding").value(), "jpeg");
  auto back = get_image(a.g, camera);
  ASSERT_TRUE(back.ok()) << back.error().to_string();
  ASSERT_EQ(back->size(), bgr.size());
  ASSERT_EQ(back->type(), CV_8UC3);
  // Quality 90: close to the original (PSNR above 35 dB), not equal.
  std::printf("JPEG quality 90: PSNR %.1f dB\n", cv::PSNR(*back, bgr));
  EXPECT_GT(cv::PSNR(*back, bgr), 35.0);
  EXPECT_GT(cv::norm(*back, bgr, cv::NORM_INF), 0.0);
  EXPECT_STREQ(mime_type(image_info(a.g, camera)->encoding), "image/jpeg");

  // A grey JPEG stays grey; a lower quality makes fewer bytes.
  const cv::Mat grey = picture(160, 120, CV_8UC1);
  auto q90 = encode_image(grey, ImageEncoding::kJpeg);
  auto q20 = encode_image(grey, ImageEncoding::kJpeg, 20);
  ASSERT_TRUE(q90.ok() && q20.ok());
  EXPECT_LT(q20->size(), q90->size());
  commit_image(grey, ImageEncoding::kJpeg);
  auto grey_back = get_image(a.g, camera);
  ASSERT_TRUE(grey_back.ok()) << grey_back.error().to_string();
  EXPECT_EQ(grey_back->type(), CV_8UC1);
  EXPECT_GT(cv::PSNR(*grey_back, grey), 35.0);
}

TEST_F(ImagesTest, OneAndFourChannelPngsKeepTheirChannels) {
  const cv::Mat grey = noise(33, 17, CV_8UC1, 1);
  commit_image(grey);
  auto g1 = get_image(a.g, camera);
  ASSERT_TRUE(g1.ok()) << g1.error().to_string();
  EXPECT_EQ(g1->type(), CV_8UC1);
  EXPECT_TRUE(same_pixels(*g1, grey));

  const cv::Mat bgra = noise(31, 19, CV_8UC4, 2);  // alpha varies too
  commit_image(bgra);
  auto g4 = get_image(a.g, camera);
  ASSERT_TRUE(g4.ok()) << g4.error().to_string();
  EXPECT_EQ(g4->type(), CV_8UC4);
  EXPECT_TRUE(same_pixels(*g4, bgra));
  EXPECT_EQ(a.g.get<std::int64_t>(camera, "image_width").value(), 31);
}

TEST_F(ImagesTest, PrefixesLetOneNodeHoldSeveralImages) {
  const cv::Mat first = noise(20, 10, CV_8UC3, 3);
  const cv::Mat second = picture(40, 30, CV_8UC1);
  commit_image(first);
  commit_image(second, ImageEncoding::kPng, "screen");
  const ImageAttrNames names = image_attr_names("screen");
  EXPECT_EQ(names.bytes, "screen");
  EXPECT_EQ(names.width, "screen_width");
  EXPECT_EQ(names.height, "screen_height");
  EXPECT_EQ(names.encoding, "screen_encoding");
  EXPECT_EQ(a.g.get<std::int64_t>(camera, "screen_width").value(), 40);
  EXPECT_TRUE(same_pixels(get_image(a.g, camera).value(), first));
  EXPECT_TRUE(same_pixels(get_image(a.g, camera, "screen").value(), second));

  // remove_image() removes one image's four attributes, and changes nothing when none is there.
  auto tx = a.g.begin();
  ASSERT_TRUE(remove_image(tx, camera, "screen").ok());
  EXPECT_EQ(tx.size(), 4u);
  ASSERT_TRUE(tx.commit().ok());
  EXPECT_EQ(get_image(a.g, camera, "screen").error().code, ErrorCode::kNotFound);
  EXPECT_TRUE(get_image(a.g, camera).ok());
  auto again = a.g.begin();
  ASSERT_TRUE(remove_image(again, camera, "screen").ok());
  EXPECT_TRUE(again.empty());
}

TEST_F(ImagesTest, EncodedBytesAreStoredAsTheyAreWithTheirFormatAndSize) {
  const cv::Mat bgr = picture(90, 70, CV_8UC3);
  for (const char* ext : {".png", ".jpg"}) {
    std::vector<std::uint8_t> file;
    ASSERT_TRUE(cv::imencode(ext, bgr, file));
    auto tx = a.g.begin();
    Status s = set_encoded_image(tx, camera, file, "photo");
    ASSERT_TRUE(s.ok()) << ext << ": " << s.error().to_string();
    ASSERT_TRUE(tx.commit().ok());
    auto info = image_info(a.g, camera, "photo");
    ASSERT_TRUE(info.ok()) << info.error().to_string();
    EXPECT_EQ(info->encoding,
              std::string(ext) == ".png" ? ImageEncoding::kPng : ImageEncoding::kJpeg);
    EXPECT_EQ(info->width, 90);
    EXPECT_EQ(info->height, 70);
    EXPECT_TRUE(std::equal(info->bytes.begin(), info->bytes.end(), file.begin(), file.end()))
        << "the bytes are stored as given";
    EXPECT_EQ(get_image(a.g, camera, "photo")->size(), cv::Size(90, 70));
  }
}

TEST_F(ImagesTest, EncodedBytesThatAreNotAnImageAreRefused) {
  std::vector<std::uint8_t> png;
  ASSERT_TRUE(cv::imencode(".png", picture(50, 40, CV_8UC3), png));
  auto refused = [&](Bytes bytes) {
    auto tx = a.g.begin();
    Status s = set_encoded_image(tx, camera, std::move(bytes));
    EXPECT_FALSE(s.ok());
    EXPECT_TRUE(tx.empty()) << "nothing is written on an error";
    return s.ok() ? Error{} : s.error();
  };
  Error empty = refused({});
  EXPECT_EQ(empty.code, ErrorCode::kInvalidArgument);
  EXPECT_TRUE(contains(empty.message, "set_encoded_image(): the bytes are empty")) << empty.message;

  Error gif = refused({'G', 'I', 'F', '8', '9', 'a', 1, 0, 1, 0});
  EXPECT_EQ(gif.code, ErrorCode::kInvalidArgument);
  EXPECT_TRUE(contains(gif.message, "neither PNG nor JPEG (first bytes: 47 49 46 38 39 61 01 00)"))
      << gif.message;

  Error magic_only = refused(Bytes(png.begin(), png.begin() + 8));
  EXPECT_TRUE(contains(magic_only.message, "the PNG header of 8 bytes states no image size"))
      << magic_only.message;

  Error cut = refused(Bytes(png.begin(), png.begin() + 60));  // header, then half a chunk
  EXPECT_EQ(cut.code, ErrorCode::kInvalidArgument);
  EXPECT_TRUE(contains(cut.message, "the 60-byte PNG (header 50x40) does not decode"))
      << cut.message;

  Error jpeg_head = refused({0xFF, 0xD8, 0xFF, 0xD9});
  EXPECT_TRUE(contains(jpeg_head.message, "JPEG header of 4 bytes states no image size"))
      << jpeg_head.message;
}

TEST_F(ImagesTest, EncodingRefusesWhatItCannotStore) {
  auto refused = [](const cv::Mat& m, ImageEncoding e = ImageEncoding::kPng, int quality = 90) {
    auto r = encode_image(m, e, quality);
    EXPECT_FALSE(r.ok());
    return r.ok() ? Error{} : r.error();
  };
  Error empty = refused(cv::Mat());
  EXPECT_EQ(empty.code, ErrorCode::kInvalidArgument);
  EXPECT_EQ(empty.message, "encode_image(): the image is empty");

  Error deep = refused(cv::Mat(4, 4, CV_16UC3, cv::Scalar::all(1000)));
  EXPECT_EQ(deep.code, ErrorCode::kInvalidArgument);
  EXPECT_TRUE(contains(deep.message, "the image is CV_16UC3: only 8-bit images")) << deep.message;
  EXPECT_TRUE(contains(refused(cv::Mat(4, 4, CV_32FC1, 0.5)).message, "CV_32FC1"));

  Error two = refused(cv::Mat(4, 4, CV_8UC2, cv::Scalar::all(9)));
  EXPECT_TRUE(contains(two.message, "the image has 2 channels: only 1 (grey), 3 (BGR) or 4 (BGRA)"))
      << two.message;

  Error alpha = refused(cv::Mat(4, 4, CV_8UC4, cv::Scalar::all(9)), ImageEncoding::kJpeg);
  EXPECT_TRUE(contains(alpha.message, "JPEG has no alpha channel")) << alpha.message;

  Error quality = refused(cv::Mat(4, 4, CV_8UC3, cv::Scalar::all(9)), ImageEncoding::kJpeg, 101);
  EXPECT_TRUE(contains(quality.message, "jpeg_quality 101 is outside 0..100")) << quality.message;

  // set_image() refuses the same way and writes nothing.
  auto tx = a.g.begin();
  Status s = set_image(tx, camera, cv::Mat());
  EXPECT_EQ(s.error().message, "encode_image(): the image is empty");
  EXPECT_TRUE(tx.empty());
  // ...and so does a node that is not there.
  Status gone = set_image(tx, NodeId{}, picture(8, 8, CV_8UC3));
  EXPECT_EQ(gone.error().code, ErrorCode::kNotFound);
  EXPECT_TRUE(tx.empty());
}

TEST_F(ImagesTest, ValuesBeyondTheGraphLimitAreRefusedWithTheSizeAndTheLimit) {
  const std::string limit = std::to_string(graph::limits::kMaxValueBytes);

  // Bytes already encoded: refused before anything is decoded.
  Bytes huge(graph::limits::kMaxValueBytes + 1, 0);
  const std::uint8_t magic[] = {0x89, 'P', 'N', 'G', 0x0D, 0x0A, 0x1A, 0x0A};
  std::copy(std::begin(magic), std::end(magic), huge.begin());
  auto tx = a.g.begin();
  Status s = set_encoded_image(tx, camera, std::move(huge));
  ASSERT_FALSE(s.ok());
  EXPECT_EQ(s.error().code, ErrorCode::kTooLarge);
  EXPECT_TRUE(contains(s.error().message, "set_encoded_image(): the image is " +
                                              std::to_string(graph::limits::kMaxValueBytes + 1) +
                                              " bytes, over the limit of " + limit))
      << s.error().message;
  EXPECT_TRUE(tx.empty());

  // A PNG of 4200x4200 pixels of BGRA noise is about 70 MB: over the 64 MiB of one value.
  const cv::Mat big = noise(4200, 4200, CV_8UC4, 11);
  const auto t0 = std::chrono::steady_clock::now();
  auto encoded = encode_image(big, ImageEncoding::kPng);
  std::printf("encoding 4200x4200 BGRA noise took %lld ms\n",
              static_cast<long long>(std::chrono::duration_cast<std::chrono::milliseconds>(
                                         std::chrono::steady_clock::now() - t0)
                                         .count()));
  ASSERT_FALSE(encoded.ok());
  EXPECT_EQ(encoded.error().code, ErrorCode::kTooLarge);
  EXPECT_TRUE(contains(encoded.error().message,
                       "encode_image(): the PNG encoding of the 4200x4200 image is "))
      << encoded.error().message;
  EXPECT_TRUE(contains(encoded.error().message, "bytes, over the limit of " + limit + " bytes"))
      << encoded.error().message;

  // More pixels than kMaxImagePixels: refused before encoding.
  auto wide =
      encode_image(cv::Mat(1, static_cast<int>(kMaxImagePixels) + 1, CV_8UC1, cv::Scalar(0)),
                   ImageEncoding::kPng);
  ASSERT_FALSE(wide.ok());
  EXPECT_EQ(wide.error().code, ErrorCode::kTooLarge);
  EXPECT_TRUE(contains(wide.error().message, "more than " + std::to_string(kMaxImagePixels)))
      << wide.error().message;
}

TEST_F(ImagesTest, ReadErrorsNameTheNodeAndTheAttribute) {
  Error none = read_error();
  EXPECT_EQ(none.code, ErrorCode::kNotFound);
  EXPECT_EQ(none.message, "get_image(): " + camera_text() + " has no attribute 'image'");

  const cv::Mat m = picture(64, 48, CV_8UC3);
  commit_image(m);
  auto tx = a.g.begin();
  ASSERT_TRUE(tx.remove_attr(camera, "image_height").ok());
  ASSERT_TRUE(tx.commit().ok());
  Error height = read_error();
  EXPECT_EQ(height.code, ErrorCode::kNotFound);
  EXPECT_EQ(height.message, "get_image(): " + camera_text() + " has no attribute 'image_height'");
  EXPECT_EQ(image_info(a.g, camera).error().message,
            "image_info(): " + camera_text() + " has no attribute 'image_height'");

  // Attributes a peer with a bug (or a forger) could write: each error names the attribute.
  struct Broken {
    const char* attr;
    Value value;
    ErrorCode code;
    std::string message;
  };
  const std::string of_camera = " of " + camera_text();
  const std::vector<Broken> broken = {
      {"image_width", Value("64"), ErrorCode::kTypeMismatch,
       "get_image(): attribute 'image_width'" + of_camera + " is a string, not an int64"},
      {"image", Value("not bytes"), ErrorCode::kTypeMismatch,
       "get_image(): attribute 'image'" + of_camera + " is a string, not a bytes"},
      {"image_encoding", Value("gif"), ErrorCode::kMalformed,
       "get_image(): attribute 'image_encoding'" + of_camera + " is 'gif', not 'png' or 'jpeg'"},
      {"image_encoding", Value("jpeg"), ErrorCode::kMalformed,
       "get_image(): attribute 'image'" + of_camera +
           " does not begin like a JPEG file (image_encoding is 'jpeg'; first bytes: 89 50 4e 47"},
      {"image_height", Value(std::int64_t{0}), ErrorCode::kMalformed,
       "get_image(): attribute 'image_height'" + of_camera + " is 0, not a size in pixels"},
      // The size attributes disagree with the image: found from the header, before decoding.
      {"image_width", Value(std::int64_t{65}), ErrorCode::kMalformed,
       "get_image(): attribute 'image'" + of_camera +
           " holds a 64x48 PNG but image_width x image_height say 65x48"},
  };
  for (const Broken& b : broken) {
    commit_image(m);
    set_raw(b.attr, b.value);
    Error e = read_error();
    EXPECT_EQ(e.code, b.code) << b.message;
    EXPECT_TRUE(contains(e.message, b.message)) << e.message;
    auto info = image_info(a.g, camera);
    EXPECT_FALSE(info.ok()) << "image_info() checks the same: " << b.message;
  }

  // A whole header but bytes that do not decode.
  commit_image(m);
  Bytes cut = *a.g.attr(camera, "image")->get_if<Bytes>();
  cut.resize(40);
  set_raw("image", Value(cut));
  EXPECT_TRUE(image_info(a.g, camera).ok()) << "image_info() does not decode";
  Error undecodable = read_error();
  EXPECT_EQ(undecodable.code, ErrorCode::kMalformed);
  EXPECT_EQ(undecodable.message, "get_image(): attribute 'image' of " + camera_text() +
                                     " does not decode (40 bytes of PNG)");

  // A node that is not there, and prefixes that are not attribute names.
  auto ghost = get_image(a.g, NodeId{});
  EXPECT_EQ(ghost.error().code, ErrorCode::kNotFound);
  EXPECT_TRUE(contains(ghost.error().message, "does not exist")) << ghost.error().message;
  EXPECT_EQ(get_image(a.g, camera, "").error().message, "get_image(): the prefix is empty");
  Error runtime = get_image(a.g, camera, "__lock").error();
  EXPECT_EQ(runtime.code, ErrorCode::kInvalidArgument);
  EXPECT_TRUE(contains(runtime.message, "'__lock' begins with '__'")) << runtime.message;
}

TEST_F(ImagesTest, AHeaderStatingAHugeSizeIsRefusedBeforeDecoding) {
  // A small PNG whose header claims 100000 x 100000 pixels (10 G), attributes agreeing.
  commit_image(picture(16, 16, CV_8UC1));
  Bytes bomb = *a.g.attr(camera, "image")->get_if<Bytes>();
  for (int at : {16, 20}) {  // IHDR width, height (big-endian)
    const std::uint32_t n = 100000;
    for (int i = 0; i < 4; ++i) bomb[static_cast<std::size_t>(at + i)] = (n >> (24 - 8 * i)) & 0xFF;
  }
  set_raw("image", Value(bomb));
  set_raw("image_width", Value(std::int64_t{100000}));
  set_raw("image_height", Value(std::int64_t{100000}));
  Error e = read_error();
  EXPECT_EQ(e.code, ErrorCode::kTooLarge);
  EXPECT_TRUE(contains(e.message, "get_image(): the image is 100000x100000 pixels, more than"))
      << e.message;
  auto tx = a.g.begin();
  EXPECT_EQ(set_encoded_image(tx, camera, bomb).error().code, ErrorCode::kTooLarge);
  // The largest sides a header can state (their product overflows 64 bits).
  std::fill(bomb.begin() + 16, bomb.begin() + 24, 0xFF);
  Status widest = set_encoded_image(tx, camera, bomb);
  EXPECT_EQ(widest.error().code, ErrorCode::kTooLarge);
  EXPECT_TRUE(contains(widest.error().message, "the image is 4294967295x4294967295 pixels"))
      << widest.error().message;
  EXPECT_TRUE(tx.empty());
}

TEST_F(ImagesTest, AnImageReplicatesThroughTheCodec) {
  const cv::Mat m = noise(120, 80, CV_8UC3, 5);
  commit_image(m, ImageEncoding::kPng, "screen");
  Peer b(2);
  b.receive_all(a);
  auto camera_b = b.g.find_node("camera");
  ASSERT_TRUE(camera_b.has_value());
  auto back = get_image(b.g, *camera_b, "screen");
  ASSERT_TRUE(back.ok()) << back.error().to_string();
  EXPECT_TRUE(same_pixels(*back, m));
}

}  // namespace
}  // namespace quiver::agents::images
