// The header of a WAV file, read chunk by chunk: its format and how long its data plays.
#include "quiver/agents/devices/wav_info.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <optional>

#include "file_io.h"

namespace quiver::agents::devices {
namespace {

constexpr const char* kFn = "read_wav_info()";

std::uint16_t le16(const unsigned char* p) {
  return static_cast<std::uint16_t>(p[0] | (p[1] << 8));
}
std::uint32_t le32(const unsigned char* p) {
  return static_cast<std::uint32_t>(p[0]) | (static_cast<std::uint32_t>(p[1]) << 8) |
         (static_cast<std::uint32_t>(p[2]) << 16) | (static_cast<std::uint32_t>(p[3]) << 24);
}

// A chunk id for messages: printable as is, else in hex.
std::string chunk_name(const unsigned char* id) {
  std::string s;
  for (int i = 0; i < 4; ++i) {
    if (id[i] < 0x20 || id[i] > 0x7e) {
      static const char* hex = "0123456789abcdef";
      std::string h = "0x";
      for (int j = 0; j < 4; ++j) {
        h += hex[id[j] >> 4];
        h += hex[id[j] & 15];
      }
      return h;
    }
    s += static_cast<char>(id[i]);
  }
  return "'" + s + "'";
}

}  // namespace

Result<WavInfo> read_wav_info(const std::string& path) {
  const std::string where = std::string(kFn) + ": '" + path + "'";
  auto malformed = [&](const std::string& what) {
    return make_error(ErrorCode::kMalformed, where + ": " + what);
  };
  auto truncated = [&](const std::string& what) {
    return make_error(ErrorCode::kTruncated, where + ": " + what);
  };

  int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
  if (fd < 0) {
    int err = errno;
    if (err == ENOENT) return make_error(ErrorCode::kNotFound, where + ": no such file");
    return make_error(ErrorCode::kIo, where + ": cannot open: " + internal::errno_text(err));
  }
  struct FdCloser {
    int fd;
    ~FdCloser() { ::close(fd); }
  } closer{fd};
  struct stat st {};
  if (::fstat(fd, &st) != 0) {
    return make_error(ErrorCode::kIo, where + ": cannot stat: " + internal::errno_text(errno));
  }
  if (!S_ISREG(st.st_mode)) return make_error(ErrorCode::kIo, where + ": not a regular file");
  const std::uint64_t file_size = static_cast<std::uint64_t>(st.st_size);

  // Reads exactly n bytes at offset; false with errno set (EIO for a short read) otherwise.
  auto read_at = [&](std::uint64_t offset, unsigned char* out, std::size_t n) -> bool {
    std::size_t done = 0;
    while (done < n) {
      ssize_t got = ::pread(fd, out + done, n - done, static_cast<off_t>(offset + done));
      if (got < 0 && errno == EINTR) continue;
      if (got <= 0) {
        if (got == 0) errno = EIO;
        return false;
      }
      done += static_cast<std::size_t>(got);
    }
    return true;
  };
  auto read_error = [&]() {
    return make_error(ErrorCode::kIo, where + ": cannot read: " + internal::errno_text(errno));
  };

  unsigned char header[12];
  if (file_size < sizeof header) {
    return truncated("the file is " + std::to_string(file_size) +
                     " bytes, shorter than a RIFF/WAVE header (12)");
  }
  if (!read_at(0, header, sizeof header)) return read_error();
  if (std::memcmp(header, "RIFF", 4) != 0) return malformed("does not start with 'RIFF'");
  if (std::memcmp(header + 8, "WAVE", 4) != 0) return malformed("is RIFF but not 'WAVE'");
  // The RIFF size is not trusted (streaming writers leave placeholders there); the chunks
  // are walked to the end of the file instead.

  std::optional<WavInfo> fmt;
  std::optional<std::uint64_t> data_bytes;
  std::uint64_t pos = sizeof header;
  while (pos < file_size && (!fmt || !data_bytes)) {
    unsigned char ch[8];
    if (file_size - pos < sizeof ch) {
      return truncated("the file ends inside a chunk header at offset " + std::to_string(pos));
    }
    if (!read_at(pos, ch, sizeof ch)) return read_error();
    const std::uint64_t size = le32(ch + 4);
    const std::uint64_t body = pos + sizeof ch;
    const std::uint64_t available = file_size - body;
    if (std::memcmp(ch, "fmt ", 4) == 0 && !fmt) {
      if (size < 16) {
        return malformed("its 'fmt ' chunk is " + std::to_string(size) + " bytes, fewer than 16");
      }
      if (available < 16) {
        return truncated("the file ends inside the 'fmt ' chunk at offset " +
                         std::to_string(body));
      }
      unsigned char f[16];
      if (!read_at(body, f, sizeof f)) return read_error();
      WavInfo w;
      w.format_tag = le16(f);
      w.channels = le16(f + 2);
      w.sample_rate = le32(f + 4);
      w.bits_per_sample = le16(f + 14);
      if (w.format_tag != 1 && w.format_tag != 3 && w.format_tag != 0xFFFE) {
        return malformed("format tag " + std::to_string(w.format_tag) +
                         " is not PCM (1), float (3) or extensible (65534)");
      }
      if (w.channels == 0) return malformed("the 'fmt ' chunk says 0 channels");
      if (w.sample_rate == 0) return malformed("the 'fmt ' chunk says a sample rate of 0");
      if (w.bits_per_sample == 0) return malformed("the 'fmt ' chunk says 0 bits per sample");
      fmt = w;
    } else if (std::memcmp(ch, "data", 4) == 0 && !data_bytes) {
      if (size > available) {
        return truncated("its 'data' chunk declares " + std::to_string(size) +
                         " bytes but the file holds " + std::to_string(available) +
                         " after offset " + std::to_string(body));
      }
      data_bytes = size;
    } else if (size > available) {
      return truncated("its " + chunk_name(ch) + " chunk at offset " + std::to_string(pos) +
                       " declares " + std::to_string(size) + " bytes but the file holds " +
                       std::to_string(available));
    }
    pos = body + size + (size & 1);  // chunks are padded to an even size
  }
  if (!fmt) return malformed("has no 'fmt ' chunk");
  if (!data_bytes) return malformed("has no 'data' chunk");

  WavInfo w = *fmt;
  w.data_bytes = *data_bytes;
  const std::uint64_t bytes_per_sample = (w.bits_per_sample + 7u) / 8u;
  const std::uint64_t bytes_per_second =
      std::uint64_t{w.sample_rate} * std::uint64_t{w.channels} * bytes_per_sample;
  // data_bytes < 2^32 so data_bytes * 1e9 < 2^62: no overflow.
  w.duration_ns = static_cast<std::int64_t>(w.data_bytes * 1'000'000'000ull / bytes_per_second);
  return w;
}

}  // namespace quiver::agents::devices
