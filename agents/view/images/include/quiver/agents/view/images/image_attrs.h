#pragma once
/// @file
/// Images stored as node attributes: a cv::Mat encoded as PNG or JPEG bytes, with its size and
/// encoding beside it, so that any replica (a viewer, a recorder, another agent) can show it or
/// serve the bytes as they are. docs/images.md describes the schema.
///
/// Schema. An image under the prefix P (default "image") is four attributes of one node:
///
/// | attribute    | type   | value                                                        |
/// | ------------ | ------ | ------------------------------------------------------------ |
/// | `P`          | bytes  | the encoded image, a whole PNG or JPEG file                  |
/// | `P_width`    | int64  | its width in pixels (> 0)                                    |
/// | `P_height`   | int64  | its height in pixels (> 0)                                   |
/// | `P_encoding` | string | "png" or "jpeg": what the bytes are (their magic agrees)     |
///
/// The four are always written together, in one transaction, so a replica sees them change
/// together. Different prefixes let one node hold several images (the Barthel panel's screen is
/// prefix "screen": `screen`, `screen_width`, `screen_height`, `screen_encoding`). A prefix is a
/// valid attribute name that does not begin with "__" (those belong to the runtime).
///
/// Pixels: encode_image() takes 8-bit images of 1 (grey), 3 (BGR) or 4 (BGRA, PNG only)
/// channels, as OpenCV lays them out; get_image() decodes as stored (cv::IMREAD_UNCHANGED: grey,
/// BGR or BGRA; a 16-bit PNG written by someone else stays 16-bit; no EXIF rotation).
///
/// Errors are values (quiver/base/result.h); each message names the function, and for reads the node
/// (its name and id) and the attribute.
///
/// Threading: the functions keep no state; the graph and transaction rules apply (a graph is
/// used on its owner thread).

#include <cstdint>
#include <opencv2/core/mat.hpp>
#include <span>
#include <string>
#include <string_view>

#include "quiver/graph/graph.h"
#include "quiver/graph/ids.h"
#include "quiver/graph/value.h"
#include "quiver/base/result.h"

namespace quiver::agents::inline view::images {

/// The default prefix: an image under "image", "image_width", "image_height", "image_encoding".
inline constexpr std::string_view kDefaultPrefix = "image";
/// Suffixes of the size and encoding attributes after the prefix.
inline constexpr std::string_view kWidthSuffix = "_width";
inline constexpr std::string_view kHeightSuffix = "_height";
inline constexpr std::string_view kEncodingSuffix = "_encoding";
/// Values of the encoding attribute.
inline constexpr std::string_view kPngName = "png";
inline constexpr std::string_view kJpegName = "jpeg";

/// The most pixels (width x height) a stored image may have (64 Mpx, e.g. 8192 x 8192). Writers
/// refuse more, and readers check the size the file's own header states before decoding, so a
/// small file that would decode to gigabytes never reaches the decoder.
inline constexpr std::int64_t kMaxImagePixels = std::int64_t{1} << 26;

/// The names of the four attributes of one image.
struct ImageAttrNames {
  std::string bytes;     ///< `prefix`
  std::string width;     ///< `prefix` + "_width"
  std::string height;    ///< `prefix` + "_height"
  std::string encoding;  ///< `prefix` + "_encoding"
};
/// The attribute names for `prefix` (no checks: set_image() and the readers check the prefix).
ImageAttrNames image_attr_names(std::string_view prefix = kDefaultPrefix);

enum class ImageEncoding : std::uint8_t { kPng, kJpeg };

/// "png" or "jpeg": the encoding attribute's value.
const char* to_string(ImageEncoding e);
/// "image/png" or "image/jpeg": the content type of the bytes, for a viewer that serves them.
const char* mime_type(ImageEncoding e);

/// Encodes `image` as PNG (lossless) or JPEG.
/// @param jpeg_quality 0..100, used for JPEG only.
/// @returns the bytes; kInvalidArgument naming the function when `image` is empty, not 8-bit, has
///   other than 1, 3 or 4 channels, has 4 channels for JPEG (JPEG has no alpha: OpenCV would drop
///   it silently), or `jpeg_quality` is outside 0..100; kTooLarge saying the size and the limit
///   when the image has more than kMaxImagePixels or its encoding exceeds
///   graph::limits::kMaxValueBytes; kInternal when OpenCV fails.
Result<graph::Bytes> encode_image(const cv::Mat& image, ImageEncoding encoding,
                                  int jpeg_quality = 90);

/// Encodes `image` (as encode_image()) and writes the four attributes under `prefix` on `node`
/// in `tx`; the caller commits.
/// @pre `tx` is the node's graph's transaction, used on its owner thread.
/// @returns encode_image()'s errors; kInvalidArgument for a bad prefix; the transaction's errors
///   (kNotFound when `node` is not visible). Nothing is written on an error.
Status set_image(graph::Transaction& tx, graph::NodeId node, const cv::Mat& image,
                 ImageEncoding encoding = ImageEncoding::kPng,
                 std::string_view prefix = kDefaultPrefix);

/// Writes bytes that are already a PNG or JPEG file (a screen's render, a camera's JPEG) under
/// `prefix` on `node` in `tx`, without re-encoding them. The encoding comes from the magic bytes
/// and the size from decoding them (cv::imdecode), so what is stored always decodes.
/// @param png_or_jpeg taken by value: pass an rvalue and the bytes move into the graph.
/// @returns kInvalidArgument naming the function when the bytes are empty, neither PNG nor JPEG
///   (their first bytes are quoted), state no size in their header, or do not decode; kTooLarge
///   (size and limit) beyond graph::limits::kMaxValueBytes or kMaxImagePixels; kInvalidArgument
///   for a bad prefix; the transaction's errors. Nothing is written on an error.
Status set_encoded_image(graph::Transaction& tx, graph::NodeId node, graph::Bytes png_or_jpeg,
                         std::string_view prefix = kDefaultPrefix);

/// Removes the image attributes under `prefix` from `node` in `tx`, those present only (no
/// change at all when none is).
/// @returns kInvalidArgument for a bad prefix; the transaction's errors.
Status remove_image(graph::Transaction& tx, graph::NodeId node,
                    std::string_view prefix = kDefaultPrefix);

/// What the attributes say about a stored image, read without decoding it.
struct ImageInfo {
  int width = 0;
  int height = 0;
  ImageEncoding encoding = ImageEncoding::kPng;
  /// The encoded file inside the graph: valid until the graph next changes (a commit or a merge).
  std::span<const std::uint8_t> bytes;
};

/// Reads and checks the four attributes under `prefix` on `node`, without decoding.
/// @returns kNotFound when the node is not visible or an attribute is missing; kTypeMismatch
///   when one has another type (both types named); kMalformed for an unknown encoding, a width
///   or height outside 1..INT_MAX, bytes whose magic is not the stated encoding's, or whose
///   header states no size or another size than the width and height attributes; kTooLarge
///   beyond kMaxImagePixels; kInvalidArgument for a bad prefix. Messages name the node (name and
///   id) and the attribute.
Result<ImageInfo> image_info(const graph::Graph& g, graph::NodeId node,
                             std::string_view prefix = kDefaultPrefix);

/// Decodes the image under `prefix` on `node`, after image_info()'s checks.
/// @returns image_info()'s errors; kMalformed naming the node and the attribute when the bytes
///   do not decode, or decode to another size than the width and height attributes say.
///   The Mat owns its pixels (a copy: nothing points into the graph).
Result<cv::Mat> get_image(const graph::Graph& g, graph::NodeId node,
                          std::string_view prefix = kDefaultPrefix);

}  // namespace quiver::agents::inline view::images
