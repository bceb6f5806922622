// What the first bytes of an encoded image say: PNG or JPEG by their magic, and the size their header states,
// read without decoding.
#include "image_header.h"

#include <algorithm>
#include <array>
#include <cstdio>

namespace quiver::agents::inline view::images::internal {

namespace {

constexpr std::array<std::uint8_t, 8> kPngMagic = {0x89, 'P', 'N', 'G', 0x0D, 0x0A, 0x1A, 0x0A};
constexpr std::array<std::uint8_t, 3> kJpegMagic = {0xFF, 0xD8, 0xFF};

template <std::size_t N>
bool starts_with(std::span<const std::uint8_t> bytes, const std::array<std::uint8_t, N>& magic) {
  return bytes.size() >= N && std::equal(magic.begin(), magic.end(), bytes.begin());
}

std::uint32_t big_endian(std::span<const std::uint8_t> b, std::size_t at, int n) {
  std::uint32_t v = 0;
  for (int i = 0; i < n; ++i) v = (v << 8) | b[at + static_cast<std::size_t>(i)];
  return v;
}

// PNG: the signature, then the IHDR chunk (length 13, "IHDR", width, height: big-endian).
std::optional<HeaderSize> png_size(std::span<const std::uint8_t> b) {
  if (b.size() < 24 || big_endian(b, 8, 4) != 13 || big_endian(b, 12, 4) != 0x49484452u) {
    return std::nullopt;
  }
  return HeaderSize{big_endian(b, 16, 4), big_endian(b, 20, 4)};
}

// A start-of-frame marker (C0..CF but DHT C4, JPG C8 and DAC CC): it holds the frame's size.
bool is_start_of_frame(std::uint8_t m) {
  return m >= 0xC0 && m <= 0xCF && m != 0xC4 && m != 0xC8 && m != 0xCC;
}

// JPEG: segments from SOI on, each `FF marker [length(2) payload]`, until a start of frame
// (length, precision, height(2), width(2)).
std::optional<HeaderSize> jpeg_size(std::span<const std::uint8_t> b) {
  std::size_t i = 2;  // after SOI
  while (i + 1 < b.size()) {
    if (b[i] != 0xFF) return std::nullopt;
    std::uint8_t m = b[i + 1];
    if (m == 0xFF) {  // fill byte
      ++i;
      continue;
    }
    i += 2;
    if (m == 0x01 || (m >= 0xD0 && m <= 0xD8)) continue;  // no length
    if (m == 0xD9 || m == 0xDA) return std::nullopt;      // end, or scan data before a frame
    if (i + 2 > b.size()) return std::nullopt;
    const std::uint32_t length = big_endian(b, i, 2);
    if (length < 2) return std::nullopt;
    if (is_start_of_frame(m)) {
      if (length < 7 || i + 7 > b.size()) return std::nullopt;
      HeaderSize s{big_endian(b, i + 5, 2), big_endian(b, i + 3, 2)};
      if (s.width == 0 || s.height == 0) return std::nullopt;  // height 0: set later by DNL
      return s;
    }
    i += length;
  }
  return std::nullopt;
}

}  // namespace

std::optional<ImageEncoding> sniff_encoding(std::span<const std::uint8_t> bytes) {
  if (starts_with(bytes, kPngMagic)) return ImageEncoding::kPng;
  if (starts_with(bytes, kJpegMagic)) return ImageEncoding::kJpeg;
  return std::nullopt;
}

std::optional<HeaderSize> header_size(std::span<const std::uint8_t> bytes, ImageEncoding e) {
  return e == ImageEncoding::kPng ? png_size(bytes) : jpeg_size(bytes);
}

std::string first_bytes_hex(std::span<const std::uint8_t> bytes, std::size_t n) {
  std::string out;
  for (std::size_t i = 0; i < std::min(n, bytes.size()); ++i) {
    char hex[4];
    std::snprintf(hex, sizeof hex, "%02x", bytes[i]);
    if (!out.empty()) out += ' ';
    out += hex;
  }
  return out;
}

}  // namespace quiver::agents::inline view::images::internal
