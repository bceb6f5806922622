// Graph data checked against the one table of size limits: UTF-8 validity, names and values.
#include "quiver/graph/limits.h"

#include <string>

#include "quiver/graph/value.h"

namespace quiver::graph {

bool valid_utf8(std::string_view s) {
  const auto* p = reinterpret_cast<const unsigned char*>(s.data());
  const auto* end = p + s.size();
  while (p < end) {
    unsigned char c = *p;
    if (c < 0x80) {
      ++p;
      continue;
    }
    int n;
    std::uint32_t cp;
    if ((c & 0xe0) == 0xc0) {
      n = 1;
      cp = c & 0x1f;
    } else if ((c & 0xf0) == 0xe0) {
      n = 2;
      cp = c & 0x0f;
    } else if ((c & 0xf8) == 0xf0) {
      n = 3;
      cp = c & 0x07;
    } else {
      return false;
    }
    if (end - p <= n) return false;
    for (int i = 1; i <= n; ++i) {
      if ((p[i] & 0xc0) != 0x80) return false;
      cp = cp << 6 | (p[i] & 0x3f);
    }
    static constexpr std::uint32_t kMin[4] = {0, 0x80, 0x800, 0x10000};
    if (cp < kMin[n] || cp > 0x10ffff || (cp >= 0xd800 && cp <= 0xdfff)) return false;
    p += n + 1;
  }
  return true;
}

std::string quote_name(std::string_view name) {
  constexpr std::size_t kShown = 40;
  std::string out = "'";
  if (name.size() <= kShown) {
    out += name;
  } else {
    out += name.substr(0, kShown);
    out += "...(" + std::to_string(name.size()) + " bytes)";
  }
  return out + "'";
}

Status check_name(std::string_view what, std::string_view name) {
  if (name.empty()) return make_error(ErrorCode::kInvalidArgument, std::string(what) + " is empty");
  if (name.size() > limits::kMaxNameBytes)
    return make_error(ErrorCode::kTooLarge, std::string(what) + " " + quote_name(name) + " is " +
                                                std::to_string(name.size()) + " bytes long (the limit is " +
                                                std::to_string(limits::kMaxNameBytes) + ")");
  if (!valid_utf8(name))
    return make_error(ErrorCode::kInvalidArgument, std::string(what) + " " + quote_name(name) + " is not valid UTF-8");
  return {};
}

Status check_attribute(std::string_view fn, std::string_view name, const Value& v) {
  if (name.empty() || name.size() > limits::kMaxNameBytes || !valid_utf8(name))
    return check_name(std::string(fn) + ": the attribute name", name);
  if (v.payload_bytes() > limits::kMaxValueBytes)
    return check_value(std::string(fn) + ": attribute '" + std::string(name) + "'", v);
  return {};
}

Status check_value(std::string_view what, const Value& v) {
  if (v.payload_bytes() > limits::kMaxValueBytes)
    return make_error(ErrorCode::kTooLarge, std::string(what) + " holds " + std::to_string(v.payload_bytes()) +
                                                " bytes of " + to_string(v.type()) + " (the limit is " +
                                                std::to_string(limits::kMaxValueBytes) + ")");
  return {};
}

}  // namespace quiver::graph
