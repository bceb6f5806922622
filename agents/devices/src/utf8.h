#pragma once
// UTF-8 validity, checked before text goes into JSON (whose encoder would otherwise throw or
// silently replace bytes).

#include <cstddef>
#include <optional>
#include <string_view>

namespace quiver::agents::devices::internal {

/// The offset of the first byte of `s` that does not belong to a well-formed UTF-8 sequence
/// (overlong forms, surrogates and code points above U+10FFFF are ill-formed), or nullopt.
std::optional<std::size_t> first_invalid_utf8(std::string_view s);

}  // namespace quiver::agents::devices::internal
