#pragma once
/// @file
/// The header of a RIFF/WAVE audio file: enough to know how long it plays.

#include <cstdint>
#include <string>

#include "quiver/base/result.h"

namespace quiver::agents::devices {

/// What a WAV file's `fmt ` and `data` chunks say.
struct WavInfo {
  std::uint16_t format_tag = 0;       ///< 1 PCM, 3 IEEE float, 0xFFFE extensible
  std::uint16_t channels = 0;
  std::uint32_t sample_rate = 0;      ///< frames per second
  std::uint16_t bits_per_sample = 0;
  std::uint64_t data_bytes = 0;       ///< size of the `data` chunk
  std::int64_t duration_ns = 0;       ///< data_bytes / (sample_rate * channels * bytes_per_sample)
};

/// Reads the header of the WAV file at `path`. Chunks may come in any order; unknown chunks are
/// skipped (with their pad byte when odd-sized); the first `fmt ` and `data` chunks count.
/// @returns the header, or an error whose message names `path`: kNotFound (no such file), kIo
///   (cannot read), kMalformed (not RIFF/WAVE, no `fmt ` or `data` chunk, a `fmt ` chunk under
///   16 bytes, zero channels, rate or sample size, a compressed format), kTruncated (the file
///   ends inside a chunk header, inside `fmt `, or before the end that `data` declares).
Result<WavInfo> read_wav_info(const std::string& path);

}  // namespace quiver::agents::devices
