// The viewer attached to a DDS benchmark: `quiver view` as a child process, its page's event
// stream read by a thread.
#include "quiver/tools/bench/attached_viewer.h"

#include <httplib.h>
#include <signal.h>

#include <chrono>
#include <vector>

#include "quiver/agents/runtime/process/logging.h"

namespace quiver::tools::bench {

using agents::Subprocess;

std::unique_ptr<AttachedViewer> AttachedViewer::start(const std::string& exe,
                                                      const agents::ProcessFlags& dds,
                                                      bool every_delta) {
  std::vector<std::string> argv = {exe,
                                   "--log-level",
                                   "warn",
                                   "view",
                                   "--domain",
                                   std::to_string(dds.domain),
                                   "--dds-config",
                                   dds.dds_config,
                                   "--listen",
                                   "127.0.0.1:0"};
  if (every_delta) argv.push_back("--every-delta");
  auto p = Subprocess::spawn(argv);
  if (!p) return nullptr;
  auto line = p->read_line(20'000);
  const auto at = line ? line->find("http://127.0.0.1:") : std::string::npos;
  if (at == std::string::npos) {
    agents::named_logger("quiver bench dds")->error("quiver view did not start");
    return nullptr;
  }
  auto v = std::make_unique<AttachedViewer>();
  v->process_ = std::make_unique<Subprocess>(std::move(*p));
  v->state_ = std::make_shared<State>();
  const int port = std::stoi(line->substr(at + 17));
  v->reader_ = std::thread([state = v->state_, port] {
    httplib::Client c("127.0.0.1", port);
    c.set_read_timeout(1, 0);
    while (!state->stop.load())
      (void)c.Get("/api/events", [&](const char*, std::size_t n) {
        state->bytes += n;
        return !state->stop.load();
      });
  });
  // Measured attached, not starting: the viewer joins, loads the graph and opens its page
  // before the writers begin (its start-up is a one-off, not a cost per change).
  std::this_thread::sleep_for(std::chrono::seconds(2));
  return v;
}

std::uint64_t AttachedViewer::stop() {
  if (state_) state_->stop.store(true);
  if (reader_.joinable()) reader_.join();
  if (process_) {
    ::kill(process_->pid(), SIGTERM);
    process_->wait(10'000);
    process_.reset();
  }
  return state_ ? state_->bytes.load() : 0;
}

}  // namespace quiver::tools::bench
