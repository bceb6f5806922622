#pragma once
/// @file
/// The recording file (`.qrec`): a header, then changes, each checked by its own hash.
///
///   header: magic "QREC", format version u8 (1), wall-clock start (fixed64, ns since the epoch,
///           for people only)
///   change:  length fixed32 (of what follows up to the hash), then
///           t_ns svarint, origin string, delta bytes (graph codec), then
///           hash fixed64 (FNV-1a of the change's bytes, length included)
///
/// A file is bounded: a writer whose file would pass `max_bytes / 2` moves it to `PATH.1`
/// (replacing an older one) and starts a new file whose first change is the replica's whole
/// state. So at most max_bytes lie on disk, each file replays on its own, and PATH.1 holds the
/// history just before PATH.
///
/// A file is untrusted input: every change is decoded by the graph codec with its limits. A change
/// cut short at the end (a recorder killed while writing) is left out and reported in
/// Recording::note; any other damage is an error naming the file, the change and its offset.

#include <cstdint>
#include <functional>
#include <memory>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "quiver/agents/view/recording/recorded_change.h"
#include "quiver/base/result.h"

namespace quiver::agents::inline view::recording {

inline constexpr std::uint8_t kFormatVersion = 1;
/// The longest change a file may hold (a whole state included).
inline constexpr std::uint64_t kMaxFrameBytes = 1ull << 30;

struct WriterOptions {
  std::uint64_t max_bytes = 256ull << 20;  ///< the file and its predecessor PATH.1 together
  std::uint64_t start_wall_ns = 0;         ///< written into the header (people read it)
};

class RecordWriter {
 public:
  /// Creates (truncates) `path`. kIo naming the path when it cannot be opened.
  static Result<std::unique_ptr<RecordWriter>> create(std::string path, WriterOptions options = {});
  ~RecordWriter();
  RecordWriter(const RecordWriter&) = delete;
  RecordWriter& operator=(const RecordWriter&) = delete;

  /// Appends a change. When the file would pass max_bytes / 2, it first rotates: PATH becomes
  /// PATH.1 and the new PATH starts with `snapshot()` (the state before `f`, as a kState
  /// fragment) at `f`'s time. kIo when writing fails; kTooLarge for a change over kMaxFrameBytes.
  Status append(const RecordedChange& f, const std::function<graph::GraphDelta()>& snapshot);
  /// Pushes what was written to the operating system.
  Status flush();

  const std::string& path() const { return path_; }
  std::uint64_t bytes() const { return bytes_; }            ///< of the current file
  std::uint64_t changes_written() const { return changes_; }  ///< over all files
  std::uint64_t rotations() const { return rotations_; }

 private:
  RecordWriter() = default;
  Status open_file();
  Status write_change(const RecordedChange& f);
  std::string path_;
  WriterOptions opt_;
  struct File;
  std::unique_ptr<File> file_;
  std::uint64_t bytes_ = 0, changes_ = 0, rotations_ = 0;
  std::vector<std::uint8_t> buf_;
};

/// What a file holds.
struct Recording {
  std::uint64_t start_wall_ns = 0;
  std::vector<RecordedChange> changes;
  /// Empty, or what was left out and why ("the last frame, at byte 81234, is cut short: ...").
  std::string note;
};

/// Reads a recording. kIo when the file cannot be read; kMalformed / kTruncated naming the file,
/// the change number and its byte offset when it is damaged (not a .qrec file, another version, a
/// change whose hash or delta does not hold).
Result<Recording> read_recording(const std::string& path);
/// The same from bytes; `source` names them in errors.
Result<Recording> parse_recording(std::span<const std::uint8_t> bytes, std::string_view source);

/// Encodes one change as the file holds it (for tests and tools that build files).
void encode_change(const RecordedChange& f, std::vector<std::uint8_t>& out);
/// The header of a file.
void encode_header(std::uint64_t start_wall_ns, std::vector<std::uint8_t>& out);

}  // namespace quiver::agents::inline view::recording
