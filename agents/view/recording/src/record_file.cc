// The recording file (.qrec): changes appended with their hashes by a bounded writer that rotates its file, and
// a reader that checks every change.
#include "quiver/agents/view/recording/record_file.h"

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <iterator>

#include "quiver/graph/codec.h"
#include "quiver/base/hash.h"
#include "quiver/base/byte_codec.h"

namespace quiver::agents::inline view::recording {
namespace {

constexpr char kMagic[4] = {'Q', 'R', 'E', 'C'};
constexpr std::size_t kHeaderBytes = 4 + 1 + 8;
constexpr std::size_t kLengthBytes = 4;
constexpr std::size_t kHashBytes = 8;

std::uint64_t record_hash(std::span<const std::uint8_t> bytes) {
  std::uint64_t h = 0xcbf29ce484222325ULL;
  for (std::uint8_t b : bytes) {
    h ^= b;
    h *= 0x100000001b3ULL;
  }
  return h;
}

Error io_error(const std::string& what, const std::string& path) {
  return make_error(ErrorCode::kIo, what + " '" + path + "': " + std::strerror(errno));
}

}  // namespace

void encode_header(std::uint64_t start_wall_ns, std::vector<std::uint8_t>& out) {
  bytes::Writer w(out);
  w.raw(kMagic, sizeof kMagic);
  w.u8(kFormatVersion);
  w.fixed64(start_wall_ns);
}

void encode_change(const RecordedChange& f, std::vector<std::uint8_t>& out) {
  const std::size_t start = out.size();
  bytes::Writer w(out);
  w.fixed32(0);  // the length, patched below
  w.svarint(f.t_ns);
  w.string(f.origin);
  graph::encode(f.delta, out);
  const std::size_t body = out.size() - start - kLengthBytes;
  for (int i = 0; i < 4; ++i) out[start + i] = static_cast<std::uint8_t>(body >> (8 * i));
  w.fixed64(record_hash(std::span(out).subspan(start)));
}

struct RecordWriter::File {
  std::FILE* f = nullptr;
  ~File() {
    if (f != nullptr) std::fclose(f);
  }
};

RecordWriter::~RecordWriter() = default;

Result<std::unique_ptr<RecordWriter>> RecordWriter::create(std::string path,
                                                           WriterOptions options) {
  std::unique_ptr<RecordWriter> w(new RecordWriter());
  w->path_ = std::move(path);
  w->opt_ = options;
  if (Status s = w->open_file(); !s.ok()) return s.error();
  return w;
}

Status RecordWriter::open_file() {
  file_ = std::make_unique<File>();
  file_->f = std::fopen(path_.c_str(), "wb");
  if (file_->f == nullptr) return io_error("cannot create the recording", path_);
  buf_.clear();
  encode_header(opt_.start_wall_ns, buf_);
  if (std::fwrite(buf_.data(), 1, buf_.size(), file_->f) != buf_.size())
    return io_error("cannot write", path_);
  bytes_ = buf_.size();
  return {};
}

Status RecordWriter::write_change(const RecordedChange& f) {
  buf_.clear();
  encode_change(f, buf_);
  if (buf_.size() > kMaxFrameBytes)
    return make_error(ErrorCode::kTooLarge,
                      "recording '" + path_ + "': a frame of " + std::to_string(buf_.size()) +
                          " bytes (the limit is " + std::to_string(kMaxFrameBytes) + ")");
  if (std::fwrite(buf_.data(), 1, buf_.size(), file_->f) != buf_.size())
    return io_error("cannot write", path_);
  bytes_ += buf_.size();
  ++changes_;
  return {};
}

Status RecordWriter::append(const RecordedChange& f, const std::function<graph::GraphDelta()>& snapshot) {
  std::vector<std::uint8_t> probe;
  encode_change(f, probe);
  if (bytes_ > kHeaderBytes && bytes_ + probe.size() > opt_.max_bytes / 2) {
    if (std::fclose(file_->f) != 0) return io_error("cannot close", path_);
    file_->f = nullptr;
    const std::string old = path_ + ".1";
    if (std::rename(path_.c_str(), old.c_str()) != 0)
      return io_error("cannot move the recording to " + old + ":", path_);
    if (Status s = open_file(); !s.ok()) return s;
    ++rotations_;
    if (snapshot) {
      RecordedChange base{f.t_ns, "", snapshot()};
      if (!base.delta.empty())
        if (Status s = write_change(base); !s.ok()) return s;
    }
  }
  return write_change(f);
}

Status RecordWriter::flush() {
  if (std::fflush(file_->f) != 0) return io_error("cannot flush", path_);
  return {};
}

Result<Recording> parse_recording(std::span<const std::uint8_t> bytes, std::string_view source) {
  const std::string src(source);
  if (bytes.size() < kHeaderBytes || std::memcmp(bytes.data(), kMagic, sizeof kMagic) != 0)
    return make_error(ErrorCode::kMalformed, src + ": not a Quiver recording (no \"QREC\" header)");
  if (bytes[4] != kFormatVersion)
    return make_error(ErrorCode::kUnsupportedVersion,
                      src + ": recording format version " + std::to_string(bytes[4]) +
                          " (this build reads version " + std::to_string(kFormatVersion) + ")");
  Recording rec;
  {
    bytes::Reader r(bytes.subspan(5, 8), "header");
    rec.start_wall_ns = r.fixed64("start");
  }
  std::size_t at = kHeaderBytes;
  for (std::size_t n = 0; at < bytes.size(); ++n) {
    const std::string where =
        src + ": frame " + std::to_string(n) + " at byte " + std::to_string(at);
    const std::size_t left = bytes.size() - at;
    std::uint64_t body = 0;
    if (left >= kLengthBytes)
      for (int i = 0; i < 4; ++i) body |= static_cast<std::uint64_t>(bytes[at + i]) << (8 * i);
    if (left < kLengthBytes || body + kLengthBytes + kHashBytes > left) {
      rec.note = "the last frame (" + where + ") is cut short and was left out (" +
                 std::to_string(left) + " bytes remain)";
      break;
    }
    if (body > kMaxFrameBytes)
      return make_error(ErrorCode::kTooLarge,
                        where + ": length " + std::to_string(body) + " over the limit");
    const auto whole = bytes.subspan(at, kLengthBytes + body);
    bytes::Reader hr(bytes.subspan(at + kLengthBytes + body, kHashBytes), "hash");
    if (hr.fixed64("hash") != record_hash(whole))
      return make_error(ErrorCode::kMalformed,
                        where + ": its hash does not match its bytes (the file is damaged)");
    bytes::Reader r(whole.subspan(kLengthBytes), where);
    RecordedChange f;
    f.t_ns = r.svarint("time");
    f.origin = std::string(r.string("origin", 1024));
    if (!r.ok()) return r.error();
    if (Status s = graph::decode(whole.subspan(kLengthBytes + r.offset()), f.delta); !s.ok())
      return make_error(s.error().code, where + ": " + s.error().message);
    rec.changes.push_back(std::move(f));
    at += kLengthBytes + body + kHashBytes;
  }
  return rec;
}

Result<Recording> read_recording(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return io_error("cannot open the recording", path);
  std::vector<std::uint8_t> bytes((std::istreambuf_iterator<char>(in)),
                                  std::istreambuf_iterator<char>());
  if (in.bad()) return io_error("cannot read the recording", path);
  return parse_recording(bytes, path);
}

}  // namespace quiver::agents::inline view::recording
