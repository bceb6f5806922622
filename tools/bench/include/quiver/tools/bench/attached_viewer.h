#pragma once
// The viewer attached to a DDS benchmark: `quiver view` on the benchmark's domain with a page's
// event stream open (read by a thread of this process), so the viewer does all its work while the
// writers write.

#include <atomic>
#include <cstdint>
#include <memory>
#include <string>
#include <thread>

#include "quiver/agents/runtime/process/process_host.h"
#include "quiver/agents/runtime/process/subprocess.h"

namespace quiver::tools::bench {

class AttachedViewer {
 public:
  /// Starts `EXE view` on the domain and DDS configuration of `dds` (listening on a free port
  /// of 127.0.0.1, with --every-delta when `every_delta`), opens its event stream, and waits 2 s
  /// so that the viewer has joined and loaded the graph before the writers begin.
  /// @returns it, or null (logged) when it cannot be started.
  static std::unique_ptr<AttachedViewer> start(const std::string& exe,
                                               const agents::ProcessFlags& dds, bool every_delta);
  AttachedViewer() = default;
  AttachedViewer(const AttachedViewer&) = delete;
  AttachedViewer& operator=(const AttachedViewer&) = delete;
  ~AttachedViewer() { (void)stop(); }
  /// Stops the viewer (SIGTERM, then waits) and the stream's reader.
  /// @returns the event bytes the page received.
  std::uint64_t stop();

 private:
  struct State {
    std::atomic<bool> stop{false};
    std::atomic<std::uint64_t> bytes{0};
  };
  std::unique_ptr<agents::Subprocess> process_;
  std::shared_ptr<State> state_;
  std::thread reader_;
};

}  // namespace quiver::tools::bench
