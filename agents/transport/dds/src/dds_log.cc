// Cyclone DDS's own log lines: routed to a sink (route_dds_log()) or captured while a participant
// is created (LogCapture).
#include "dds_log.h"

#include <dds/dds.h>

#include <cstdio>
#include <functional>

#include "quiver/agents/transport/dds/dds_transport.h"

namespace quiver::agents::inline transport {
namespace {

std::mutex g_log_mu;
std::function<void(const std::string&)> g_log_sink;
std::vector<std::string>* g_log_capture = nullptr;  // lines logged while a participant is created

extern "C" void forward_dds_log(void*, const dds_log_data_t* d) {
  std::string line(d->message, d->size);
  while (!line.empty() && (line.back() == '\n' || line.back() == ' ')) line.pop_back();
  std::lock_guard<std::mutex> lock(g_log_mu);
  if (g_log_capture) g_log_capture->push_back(line);
  if (g_log_sink) g_log_sink(line);
}

}  // namespace

// dds_set_log_sink is called without g_log_mu held: Cyclone holds its own log lock while it
// calls the sink, which takes g_log_mu.
LogCapture::LogCapture() : serial_(g_capture_mu) {
  {
    std::lock_guard<std::mutex> lock(g_log_mu);
    g_log_capture = &lines_;
    routed_ = static_cast<bool>(g_log_sink);
  }
  if (!routed_) dds_set_log_sink(forward_dds_log, nullptr);
}

LogCapture::~LogCapture() {
  bool unroute = false;
  {
    std::lock_guard<std::mutex> lock(g_log_mu);
    g_log_capture = nullptr;
    unroute = !routed_ && !g_log_sink;
  }
  if (unroute) dds_set_log_sink(nullptr, nullptr);
  if (!routed_ && !taken_)
    for (const std::string& l : lines_) std::fprintf(stderr, "%s\n", l.c_str());
}

std::string LogCapture::take() {
  std::lock_guard<std::mutex> lock(g_log_mu);
  taken_ = true;
  std::string out;
  for (const std::string& l : lines_) out += (out.empty() ? "" : " | ") + l;
  return out;
}

void route_dds_log(std::function<void(const std::string&)> sink) {
  bool routed = false;
  {
    std::lock_guard<std::mutex> lock(g_log_mu);
    g_log_sink = std::move(sink);
    routed = g_log_sink || g_log_capture;
  }
  if (routed) dds_set_log_sink(forward_dds_log, nullptr);
  else dds_set_log_sink(nullptr, nullptr);
}

}  // namespace quiver::agents::inline transport
