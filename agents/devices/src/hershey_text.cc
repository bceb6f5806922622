// UTF-8 text in the ASCII characters of OpenCV's Hershey fonts: accented Latin letters by their base letters,
// anything else as '?'.
#include "quiver/agents/devices/opencv_screen.h"

#include <string>
#include <string_view>

namespace quiver::agents::devices {

std::string to_hershey_text(std::string_view utf8) {
  // U+00C0..U+00FF by their base letters ("Núñez" reads "Nunez"), the multiplication and
  // division signs as 'x' and '/'.
  static const char* const kLatin1[64] = {
      "A", "A", "A", "A", "A", "A", "AE", "C", "E", "E", "E", "E", "I", "I", "I", "I",
      "D", "N", "O", "O", "O", "O", "O",  "x", "O", "U", "U", "U", "U", "Y", "Th", "ss",
      "a", "a", "a", "a", "a", "a", "ae", "c", "e", "e", "e", "e", "i", "i", "i", "i",
      "d", "n", "o", "o", "o", "o", "o",  "/", "o", "u", "u", "u", "u", "y", "th", "y"};
  std::string out;
  out.reserve(utf8.size());
  std::size_t i = 0;
  const std::size_t n = utf8.size();
  auto byte = [&](std::size_t k) { return static_cast<unsigned char>(utf8[k]); };
  while (i < n) {
    const unsigned char b = byte(i);
    if (b < 0x80) {
      out += (b < 0x20 || b == 0x7f) ? ' ' : static_cast<char>(b);
      ++i;
      continue;
    }
    // A two-byte sequence for U+0080..U+00FF.
    if ((b == 0xC2 || b == 0xC3) && i + 1 < n && (byte(i + 1) & 0xC0) == 0x80) {
      const unsigned cp = ((b & 0x1Fu) << 6) | (byte(i + 1) & 0x3Fu);
      i += 2;
      if (cp >= 0xC0) {
        out += kLatin1[cp - 0xC0];
      } else if (cp <= 0xA0) {
        out += ' ';  // C1 control characters and the no-break space
      } else if (cp != 0xA1 && cp != 0xBF) {  // Spanish opening marks are left out
        out += '?';
      }
      continue;
    }
    // Any other character (a lead byte with up to its count of continuation bytes), or a
    // byte that starts no UTF-8 sequence: one '?'.
    out += '?';
    ++i;
    const std::size_t continuation = (b >= 0xC2 && b <= 0xDF)   ? 1
                                     : (b >= 0xE0 && b <= 0xEF) ? 2
                                     : (b >= 0xF0 && b <= 0xF4) ? 3
                                                                : 0;
    for (std::size_t k = 0; k < continuation && i < n && (byte(i) & 0xC0) == 0x80; ++k) ++i;
  }
  return out;
}

}  // namespace quiver::agents::devices
