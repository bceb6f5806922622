#pragma once
// What the first bytes of an encoded image say: its format (magic bytes) and its size (the PNG
// IHDR chunk, the JPEG start-of-frame segment), read without decoding, so that a small file
// that would decode to gigabytes is refused before OpenCV allocates anything.

#include <cstdint>
#include <optional>
#include <span>
#include <string>

#include "quiver/agents/view/images/image_attrs.h"

namespace quiver::agents::inline view::images::internal {

/// The format the magic bytes announce: PNG (89 'PNG' 0D 0A 1A 0A) or JPEG (FF D8 FF).
std::optional<ImageEncoding> sniff_encoding(std::span<const std::uint8_t> bytes);

struct HeaderSize {
  std::int64_t width = 0;
  std::int64_t height = 0;
};

/// The size the header of a file of format `e` states; nullopt when the header is cut short or
/// malformed (a JPEG whose frame header is missing, or states height 0).
std::optional<HeaderSize> header_size(std::span<const std::uint8_t> bytes, ImageEncoding e);

/// "89 50 4e 47 ...": the first bytes, for an error message.
std::string first_bytes_hex(std::span<const std::uint8_t> bytes, std::size_t n = 8);

}  // namespace quiver::agents::inline view::images::internal
