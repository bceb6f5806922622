#pragma once
// Cyclone DDS's own log lines (dds_transport.h: route_dds_log()), and their capture while a
// participant is created, so that a refused participant's error can quote why. Private to the
// DDS transport.

#include <mutex>
#include <string>
#include <vector>

namespace quiver::agents::inline transport {

/// Collects Cyclone's log lines while it lives (one at a time: secured participants are created
/// one after the other), so that a refused participant's error can say why. Without a routed
/// sink the lines would have gone to stderr: they go there after all unless taken().
class LogCapture {
 public:
  LogCapture();
  ~LogCapture();
  LogCapture(const LogCapture&) = delete;
  LogCapture& operator=(const LogCapture&) = delete;
  /// The lines so far, joined; they are then not printed.
  std::string take();

 private:
  static inline std::mutex g_capture_mu;
  std::lock_guard<std::mutex> serial_;
  std::vector<std::string> lines_;
  bool routed_ = false;
  bool taken_ = false;
};

}  // namespace quiver::agents::inline transport
