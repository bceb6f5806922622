// Images stored as node attributes: a cv::Mat encoded as PNG or JPEG bytes, written with its width, height and
// encoding in one transaction, and read back checked and decoded.
#include "quiver/agents/view/images/image_attrs.h"

#include <climits>
#include <opencv2/core/check.hpp>
#include <opencv2/imgcodecs.hpp>
#include <string>
#include <utility>
#include <vector>

#include "image_header.h"
#include "quiver/graph/limits.h"

namespace quiver::agents::inline view::images {

using graph::Bytes;
using graph::Graph;
using graph::NodeId;
using graph::Transaction;
using graph::Value;

ImageAttrNames image_attr_names(std::string_view prefix) {
  const std::string p(prefix);
  return {p, p + std::string(kWidthSuffix), p + std::string(kHeightSuffix),
          p + std::string(kEncodingSuffix)};
}

const char* to_string(ImageEncoding e) {
  return e == ImageEncoding::kPng ? kPngName.data() : kJpegName.data();
}

const char* mime_type(ImageEncoding e) {
  return e == ImageEncoding::kPng ? "image/png" : "image/jpeg";
}

namespace {

const char* upper_name(ImageEncoding e) { return e == ImageEncoding::kPng ? "PNG" : "JPEG"; }

std::string describe_node(const Graph& g, NodeId n) {
  return "node '" + g.name_of(n) + "' (id " + n.to_string() + ")";
}

std::string size_text(std::int64_t w, std::int64_t h) {
  return std::to_string(w) + "x" + std::to_string(h);
}

// A prefix is an attribute name (limits.h) that is not the runtime's ("__...").
Status check_prefix(const char* fn, std::string_view prefix) {
  if (prefix.empty()) {
    return make_error(ErrorCode::kInvalidArgument, std::string(fn) + ": the prefix is empty");
  }
  if (prefix.starts_with("__")) {
    return make_error(ErrorCode::kInvalidArgument,
                      std::string(fn) + ": the prefix '" + std::string(prefix) +
                          "' begins with '__' (reserved for the runtime)");
  }
  // The longest of the four names.
  return graph::check_name(std::string(fn) + ": the attribute name",
                           std::string(prefix) + std::string(kEncodingSuffix));
}

Status check_encoded_size(const char* fn, std::string_view what, std::size_t n) {
  if (n <= graph::limits::kMaxValueBytes) return Status::Ok();
  return make_error(ErrorCode::kTooLarge,
                    std::string(fn) + ": " + std::string(what) + " is " + std::to_string(n) +
                        " bytes, over the limit of " +
                        std::to_string(graph::limits::kMaxValueBytes) +
                        " bytes for one attribute value (graph::limits::kMaxValueBytes)");
}

Status check_pixels(const char* fn, std::string_view what, std::int64_t w, std::int64_t h) {
  // Each side first: two 32-bit sides from a header would overflow the product.
  if (w <= kMaxImagePixels && h <= kMaxImagePixels && w * h <= kMaxImagePixels) return Status::Ok();
  return make_error(ErrorCode::kTooLarge, std::string(fn) + ": " + std::string(what) + " is " +
                                              size_text(w, h) + " pixels, more than " +
                                              std::to_string(kMaxImagePixels) +
                                              " (kMaxImagePixels)");
}

// One image attribute written whatever the node held: a value of another type (left by a broken
// peer) is removed first, since a write alone never changes an attribute's type.
Status put(Transaction& tx, NodeId node, std::string_view attr, Value v) {
  Status s = tx.set(node, attr, v);
  if (s.ok() || s.error().code != ErrorCode::kTypeMismatch) return s;
  if (auto removed = tx.remove_attr(node, attr); !removed.ok()) return removed.error();
  return tx.set(node, attr, std::move(v));
}

// Writes the four attributes; the bytes first, so that a refusal of the largest write leaves
// the transaction as it was.
Status write_attrs(Transaction& tx, NodeId node, Bytes bytes, std::int64_t w, std::int64_t h,
                   ImageEncoding e, std::string_view prefix) {
  const ImageAttrNames names = image_attr_names(prefix);
  if (Status s = put(tx, node, names.bytes, Value(std::move(bytes))); !s.ok()) return s;
  if (Status s = put(tx, node, names.width, Value(w)); !s.ok()) return s;
  if (Status s = put(tx, node, names.height, Value(h)); !s.ok()) return s;
  return put(tx, node, names.encoding, Value(std::string(to_string(e))));
}

// One typed attribute of the image, or an error naming the node and the attribute.
template <class T>
Result<const T*> read_attr(const Graph& g, NodeId node, const std::string& name, const char* fn) {
  const Value* v = g.attr(node, name);
  if (v == nullptr) {
    return make_error(ErrorCode::kNotFound, std::string(fn) + ": " + describe_node(g, node) +
                                                " has no attribute '" + name + "'");
  }
  const T* p = v->get_if<T>();
  if (p == nullptr) {
    return make_error(ErrorCode::kTypeMismatch, std::string(fn) + ": attribute '" + name + "' of " +
                                                    describe_node(g, node) + " is " +
                                                    Value::article(v->type()) + ", not " +
                                                    Value::article(graph::value_type_of<T>));
  }
  return p;
}

Result<int> read_dimension(const Graph& g, NodeId node, const std::string& name, const char* fn) {
  auto v = read_attr<std::int64_t>(g, node, name, fn);
  if (!v.ok()) return v.error();
  const std::int64_t n = **v;
  if (n < 1 || n > INT_MAX) {
    return make_error(ErrorCode::kMalformed, std::string(fn) + ": attribute '" + name + "' of " +
                                                 describe_node(g, node) + " is " +
                                                 std::to_string(n) + ", not a size in pixels (1.." +
                                                 std::to_string(INT_MAX) + ")");
  }
  return static_cast<int>(n);
}

Result<ImageInfo> read_info(const Graph& g, NodeId node, std::string_view prefix, const char* fn) {
  if (Status s = check_prefix(fn, prefix); !s.ok()) return s.error();
  if (!g.has_node(node)) {
    return make_error(ErrorCode::kNotFound,
                      std::string(fn) + ": node " + node.to_string() + " does not exist");
  }
  const ImageAttrNames names = image_attr_names(prefix);
  auto bytes = read_attr<Bytes>(g, node, names.bytes, fn);
  if (!bytes.ok()) return bytes.error();
  auto width = read_dimension(g, node, names.width, fn);
  if (!width.ok()) return width.error();
  auto height = read_dimension(g, node, names.height, fn);
  if (!height.ok()) return height.error();
  auto encoding = read_attr<std::string>(g, node, names.encoding, fn);
  if (!encoding.ok()) return encoding.error();

  ImageInfo info;
  info.width = *width;
  info.height = *height;
  info.bytes = std::span<const std::uint8_t>(**bytes);
  const std::string& enc = **encoding;
  if (enc == kPngName) {
    info.encoding = ImageEncoding::kPng;
  } else if (enc == kJpegName) {
    info.encoding = ImageEncoding::kJpeg;
  } else {
    return make_error(ErrorCode::kMalformed, std::string(fn) + ": attribute '" + names.encoding +
                                                 "' of " + describe_node(g, node) + " is '" + enc +
                                                 "', not 'png' or 'jpeg'");
  }
  const auto sniffed = internal::sniff_encoding(info.bytes);
  if (sniffed != info.encoding) {
    return make_error(ErrorCode::kMalformed,
                      std::string(fn) + ": attribute '" + names.bytes + "' of " +
                          describe_node(g, node) + " does not begin like a " +
                          upper_name(info.encoding) + " file (" + names.encoding + " is '" + enc +
                          "'; first bytes: " + internal::first_bytes_hex(info.bytes) + ")");
  }
  // The size the file states, checked before anyone decodes: a small file can decode to
  // gigabytes.
  const auto header = internal::header_size(info.bytes, info.encoding);
  if (!header) {
    return make_error(ErrorCode::kMalformed, std::string(fn) + ": attribute '" + names.bytes +
                                                 "' of " + describe_node(g, node) + " has no " +
                                                 upper_name(info.encoding) +
                                                 " header stating a size");
  }
  if (header->width != info.width || header->height != info.height) {
    return make_error(ErrorCode::kMalformed, std::string(fn) + ": attribute '" + names.bytes +
                                                 "' of " + describe_node(g, node) + " holds a " +
                                                 size_text(header->width, header->height) + " " +
                                                 upper_name(info.encoding) + " but " + names.width +
                                                 " x " + names.height + " say " +
                                                 size_text(info.width, info.height));
  }
  if (Status s = check_pixels(fn, "the image", info.width, info.height); !s.ok()) return s.error();
  return info;
}

}  // namespace

Result<Bytes> encode_image(const cv::Mat& image, ImageEncoding encoding, int jpeg_quality) {
  constexpr const char* kFn = "encode_image()";
  auto invalid = [&](const std::string& why) {
    return make_error(ErrorCode::kInvalidArgument, std::string(kFn) + ": " + why);
  };
  if (image.empty()) return invalid("the image is empty");
  if (image.dims != 2)
    return invalid("the image has " + std::to_string(image.dims) + " dimensions, not 2");
  if (image.depth() != CV_8U) {
    return invalid("the image is " + cv::typeToString(image.type()) +
                   ": only 8-bit images (CV_8UC1, CV_8UC3, CV_8UC4) are encoded");
  }
  const int channels = image.channels();
  if (channels != 1 && channels != 3 && channels != 4) {
    return invalid("the image has " + std::to_string(channels) +
                   " channels: only 1 (grey), 3 (BGR) or 4 (BGRA) are encoded");
  }
  if (encoding == ImageEncoding::kJpeg && channels == 4) {
    return invalid(
        "JPEG has no alpha channel: a 4-channel image is stored as PNG (or drop the "
        "alpha first)");
  }
  if (encoding == ImageEncoding::kJpeg && (jpeg_quality < 0 || jpeg_quality > 100)) {
    return invalid("jpeg_quality " + std::to_string(jpeg_quality) + " is outside 0..100");
  }
  if (Status s = check_pixels(kFn, "the image", image.cols, image.rows); !s.ok()) return s.error();

  std::vector<std::uint8_t> out;
  std::vector<int> params;
  if (encoding == ImageEncoding::kJpeg) params = {cv::IMWRITE_JPEG_QUALITY, jpeg_quality};
  const char* ext = encoding == ImageEncoding::kPng ? ".png" : ".jpg";
  try {
    if (!cv::imencode(ext, image, out, params)) {
      return make_error(ErrorCode::kInternal, std::string(kFn) + ": OpenCV could not encode the " +
                                                  size_text(image.cols, image.rows) + " image as " +
                                                  upper_name(encoding));
    }
  } catch (const cv::Exception& e) {
    return make_error(ErrorCode::kInternal, std::string(kFn) + ": OpenCV failed encoding " +
                                                upper_name(encoding) + ": " + e.what());
  }
  const std::string what = std::string("the ") + upper_name(encoding) + " encoding of the " +
                           size_text(image.cols, image.rows) + " image";
  if (Status s = check_encoded_size(kFn, what, out.size()); !s.ok()) return s.error();
  return Bytes(std::move(out));
}

Status set_image(Transaction& tx, NodeId node, const cv::Mat& image, ImageEncoding encoding,
                 std::string_view prefix) {
  if (Status s = check_prefix("set_image()", prefix); !s.ok()) return s;
  auto bytes = encode_image(image, encoding);
  if (!bytes.ok()) return bytes.error();
  return write_attrs(tx, node, std::move(*bytes), image.cols, image.rows, encoding, prefix);
}

Status set_encoded_image(Transaction& tx, NodeId node, Bytes png_or_jpeg, std::string_view prefix) {
  constexpr const char* kFn = "set_encoded_image()";
  if (Status s = check_prefix(kFn, prefix); !s.ok()) return s;
  if (png_or_jpeg.empty()) {
    return make_error(ErrorCode::kInvalidArgument, std::string(kFn) + ": the bytes are empty");
  }
  if (Status s = check_encoded_size(kFn, "the image", png_or_jpeg.size()); !s.ok()) return s;
  const auto encoding = internal::sniff_encoding(png_or_jpeg);
  if (!encoding) {
    return make_error(ErrorCode::kInvalidArgument,
                      std::string(kFn) + ": the bytes are neither PNG nor JPEG (first bytes: " +
                          internal::first_bytes_hex(png_or_jpeg) + ")");
  }
  const auto header = internal::header_size(png_or_jpeg, *encoding);
  if (!header) {
    return make_error(ErrorCode::kInvalidArgument,
                      std::string(kFn) + ": the " + upper_name(*encoding) + " header of " +
                          std::to_string(png_or_jpeg.size()) + " bytes states no image size");
  }
  if (Status s = check_pixels(kFn, "the image", header->width, header->height); !s.ok()) return s;
  cv::Mat decoded;
  try {
    decoded = cv::imdecode(png_or_jpeg, cv::IMREAD_UNCHANGED);
  } catch (const cv::Exception&) {
    decoded.release();
  }
  if (decoded.empty() || decoded.cols != header->width || decoded.rows != header->height) {
    return make_error(ErrorCode::kInvalidArgument,
                      std::string(kFn) + ": the " + std::to_string(png_or_jpeg.size()) + "-byte " +
                          upper_name(*encoding) + " (header " +
                          size_text(header->width, header->height) + ") does not decode");
  }
  return write_attrs(tx, node, std::move(png_or_jpeg), decoded.cols, decoded.rows, *encoding,
                     prefix);
}

Status remove_image(Transaction& tx, NodeId node, std::string_view prefix) {
  if (Status s = check_prefix("remove_image()", prefix); !s.ok()) return s;
  const ImageAttrNames names = image_attr_names(prefix);
  for (const std::string* name : {&names.bytes, &names.width, &names.height, &names.encoding}) {
    if (tx.graph().attr(node, *name) == nullptr) continue;
    if (auto removed = tx.remove_attr(node, *name); !removed.ok()) return removed.error();
  }
  return Status::Ok();
}

Result<ImageInfo> image_info(const Graph& g, NodeId node, std::string_view prefix) {
  return read_info(g, node, prefix, "image_info()");
}

Result<cv::Mat> get_image(const Graph& g, NodeId node, std::string_view prefix) {
  constexpr const char* kFn = "get_image()";
  auto info = read_info(g, node, prefix, kFn);
  if (!info.ok()) return info.error();
  const ImageAttrNames names = image_attr_names(prefix);
  auto malformed = [&](const std::string& why) {
    return make_error(ErrorCode::kMalformed, std::string(kFn) + ": attribute '" + names.bytes +
                                                 "' of " + describe_node(g, node) + " " + why);
  };
  cv::Mat decoded;
  try {
    // imdecode takes an InputArray; the graph's bytes stay untouched.
    const cv::Mat raw(1, static_cast<int>(info->bytes.size()), CV_8UC1,
                      const_cast<std::uint8_t*>(info->bytes.data()));
    decoded = cv::imdecode(raw, cv::IMREAD_UNCHANGED);
  } catch (const cv::Exception&) {
    decoded.release();
  }
  if (decoded.empty()) {
    return malformed("does not decode (" + std::to_string(info->bytes.size()) + " bytes of " +
                     upper_name(info->encoding) + ")");
  }
  if (decoded.cols != info->width || decoded.rows != info->height) {
    return malformed("decodes to " + size_text(decoded.cols, decoded.rows) + " but " + names.width +
                     " x " + names.height + " say " + size_text(info->width, info->height));
  }
  return decoded;
}

}  // namespace quiver::agents::inline view::images
