// The live viewer: an HTTP server (on 127.0.0.1 unless told otherwise) serving the page and one replica's graph
// as JSON, pushing its changes as server-sent events and keeping their timeline.
#include "quiver/agents/view/viewer/viewer.h"

#include <httplib.h>

#include "quiver/agents/view/images/image_attrs.h"
#include <unistd.h>

#include <atomic>
#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <thread>

namespace quiver::agents::inline view::viewer {

using nlohmann::json;
namespace fs = std::filesystem;

struct Viewer::Http {
  httplib::Server server;
  std::thread thread;
  std::atomic<bool> returned{false};  // listen_after_bind() came back
};

std::string default_assets_dir() {
  if (const char* env = std::getenv("QUIVER_VIEWER_ASSETS"); env != nullptr && *env != '\0') return env;
  std::error_code ec;
  const fs::path exe = fs::read_symlink("/proc/self/exe", ec);
  if (!ec) {
    const fs::path installed = exe.parent_path().parent_path() / "share" / "quiver" / "viewer";
    if (fs::exists(installed / "index.html")) return installed.string();
  }
#ifdef QUIVER_VIEWER_SOURCE_ASSETS
  if (fs::exists(fs::path(QUIVER_VIEWER_SOURCE_ASSETS) / "index.html")) return QUIVER_VIEWER_SOURCE_ASSETS;
#endif
  return {};
}

namespace {

// "00000000000000ab.3:42" -> the node id (see Dot::to_string()).
std::optional<graph::NodeId> parse_node_key(const std::string& s) {
  unsigned long long agent = 0, incarnation = 0, counter = 0;
  int used = 0;
  if (std::sscanf(s.c_str(), "%16llx.%llu:%llu%n", &agent, &incarnation, &counter, &used) != 3 ||
      used != static_cast<int>(s.size()))
    return std::nullopt;
  return graph::NodeId{graph::Dot{graph::ReplicaId{agent, incarnation}, counter}};
}

void send_json(httplib::Response& res, const json& j, int status = 200) {
  res.status = status;
  res.set_header("Cache-Control", "no-store");
  res.set_content(j.dump(), "application/json");
}

void send_error(httplib::Response& res, int status, const std::string& message) {
  send_json(res, json{{"error", message}}, status);
}

// A non-negative integer query parameter, or `fallback`; nullopt when it is not a number.
std::optional<std::uint64_t> uint_param(const httplib::Request& req, const char* name, std::uint64_t fallback) {
  if (!req.has_param(name)) return fallback;
  const std::string v = req.get_param_value(name);
  if (v.empty() || v.find_first_not_of("0123456789") != std::string::npos || v.size() > 19) return std::nullopt;
  return std::stoull(v);
}

}  // namespace

Viewer::Viewer(graph::Graph& g, ViewerOptions o, Hooks h)
    : g_(g), opt_(std::move(o)), hooks_(std::move(h)), timeline_(opt_.history_bytes, opt_.history_changes) {}

Result<std::unique_ptr<Viewer>> Viewer::start(graph::Graph& g, ViewerOptions options, Hooks hooks) {
  if (options.assets_dir.empty()) options.assets_dir = default_assets_dir();
  if (!fs::exists(fs::path(options.assets_dir) / "index.html"))
    return make_error(ErrorCode::kNotFound, "the viewer's page is not in '" + options.assets_dir +
                                                "' (no index.html; set QUIVER_VIEWER_ASSETS or install Quiver)");
  for (const auto& [dir, what] : {std::pair{options.d3_dir, "d3.min.js"}, std::pair{options.three_dir, "build/three.min.js"}})
    if (!fs::exists(fs::path(dir) / what))
      return make_error(ErrorCode::kNotFound, "'" + (fs::path(dir) / what).string() +
                                                  "' is missing (Debian packages libjs-d3 and libjs-three)");
  std::unique_ptr<Viewer> v(new Viewer(g, std::move(options), std::move(hooks)));
  Viewer* self = v.get();
  v->recorder_ = std::make_unique<recording::GraphRecorder>(
      g, self->hooks_.clock,
      [self](const graph::ReplicaId& r) { return self->hooks_.name_of ? self->hooks_.name_of(r) : r.to_string(); },
      [self](recording::RecordedChange&& f) { self->timeline_.add_change(std::move(f)); });
  v->sub_ = g.subscribe([self](const graph::ChangeBatch& b) { self->pending_.add(b); });
  v->http_ = std::make_unique<Http>();
  v->routes();
  auto& srv = v->http_->server;
  if (v->opt_.port == 0) v->port_ = srv.bind_to_any_port(v->opt_.host);
  else v->port_ = srv.bind_to_port(v->opt_.host, v->opt_.port) ? v->opt_.port : -1;
  if (v->port_ <= 0)
    return make_error(ErrorCode::kIo, "the viewer cannot listen on " + v->opt_.host + ":" + std::to_string(v->opt_.port) +
                                          " (in use, or not an address of this machine)");
  v->url_ = "http://" + v->opt_.host + ":" + std::to_string(v->port_) + "/";
  v->http_->thread = std::thread([self] {
    self->http_->server.listen_after_bind();
    self->http_->returned = true;
  });
  // httplib's stop() does nothing until listen has begun: a viewer destroyed before that (a bad
  // recording found right after start) would wait for its server thread for ever. So start()
  // returns once the server listens (or gave up).
  while (!v->http_->server.is_running() && !v->http_->returned)
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
  return v;
}

Viewer::~Viewer() {
  hub_.close();
  if (http_) {
    http_->server.stop();
    if (http_->thread.joinable()) http_->thread.join();
  }
  g_.unsubscribe(sub_);
}

Decor Viewer::decor() const {
  Decor d;
  d.name_of = hooks_.name_of;
  if (hooks_.decorate) hooks_.decorate(d);
  return d;
}

void Viewer::tick(std::int64_t now_ns) {
  if (now_ns < next_flush_) return;
  const auto t0 = std::chrono::steady_clock::now();
  const Decor d = decor();
  std::string violations = violations_json(d).dump();
  if (!pending_.empty() || violations != last_violations_) {
    json msg = pending_.drain(g_, d);
    msg["frame_end"] = timeline_.end();
    msg["violations"] = json::parse(violations);
    last_violations_ = std::move(violations);
    hub_.publish("change", msg.dump());
  }
  if (hooks_.agents) {
    std::string agents = hooks_.agents().dump();
    if (agents != last_agents_) {
      hub_.publish("agents", agents);
      last_agents_ = std::move(agents);
    }
  }
  // Pushing costs the viewer at most a tenth of its time: under a flood of changes the page is
  // updated less often rather than the viewer taking a core from the agents.
  const std::int64_t cost =
      std::chrono::duration_cast<std::chrono::nanoseconds>(std::chrono::steady_clock::now() - t0).count();
  next_flush_ = now_ns + std::max(opt_.flush_ns, 9 * cost);
}

void Viewer::routes() {
  auto& srv = http_->server;
  // Debian's cpp-httplib compresses with brotli at its slowest quality when a browser accepts it:
  // seconds for a 10k-node snapshot. A page on loopback gains nothing from compression.
  srv.set_pre_routing_handler([](const httplib::Request& req, httplib::Response&) {
    const_cast<httplib::Request&>(req).headers.erase("Accept-Encoding");  // the server's own object
    return httplib::Server::HandlerResponse::Unhandled;
  });
  srv.set_mount_point("/", opt_.assets_dir);
  srv.set_mount_point("/js/d3", opt_.d3_dir);
  srv.set_mount_point("/js/three", opt_.three_dir);

  srv.Get("/api/info", [this](const httplib::Request&, httplib::Response& res) {
    json out;
    hooks_.run_on_owner([&] {
      out = {{"mode", opt_.mode},
             {"title", opt_.title},
             {"nodes", g_.node_count()},
             {"edges", g_.edge_count()},
             {"frames", {{"begin", timeline_.begin()}, {"end", timeline_.end()}}},
             {"agents", hooks_.agents ? hooks_.agents() : json::array()},
             {"schema", opt_.schema}};
    });
    send_json(res, out);
  });

  // The whole graph now, or after change `at` of the timeline.
  srv.Get("/api/snapshot", [this](const httplib::Request& req, httplib::Response& res) {
    const auto at = uint_param(req, "at", UINT64_MAX);
    if (!at) return send_error(res, 400, "'at' must be a frame number");
    json out;
    std::optional<Error> err;
    hooks_.run_on_owner([&] {
      if (*at == UINT64_MAX) {
        out = snapshot_json(g_, decor());
        out["msg"] = hub_.next();
        out["frame_end"] = timeline_.end();
      } else if (auto r = timeline_.state_after(*at, decor()); r.ok()) {
        out = std::move(r.value());
      } else {
        err = r.error();
      }
      out["mode"] = opt_.mode;
      out["title"] = opt_.title;
      out["agents"] = hooks_.agents ? hooks_.agents() : json::array();
    });
    if (err) return send_error(res, 404, err->message);
    send_json(res, out);
  });

  srv.Get("/api/history", [this](const httplib::Request& req, httplib::Response& res) {
    const auto from = uint_param(req, "from", 0);
    const auto limit = uint_param(req, "limit", 200);
    if (!from || !limit) return send_error(res, 400, "'from' and 'limit' must be numbers");
    json out;
    hooks_.run_on_owner([&] { out = timeline_.list(*from, std::min<std::uint64_t>(*limit, 5000)); });
    send_json(res, out);
  });

  // An image attribute's bytes (the images schema, docs/images.md).
  srv.Get("/api/image", [this](const httplib::Request& req, httplib::Response& res) {
    const auto id = parse_node_key(req.get_param_value("node"));
    const std::string prefix = req.has_param("prefix") ? req.get_param_value("prefix") : "image";
    if (!id) return send_error(res, 400, "'node' must be a node id such as 00000000000000ab.3:42");
    std::string body, type, error;
    hooks_.run_on_owner([&] {
      auto info = images::image_info(g_, *id, prefix);
      if (!info.ok()) {
        error = info.error().message;
        return;
      }
      body.assign(info->bytes.begin(), info->bytes.end());
      type = images::mime_type(info->encoding);
    });
    if (!error.empty()) return send_error(res, 404, error);
    res.set_header("Cache-Control", "no-store");
    res.set_content(std::move(body), type.c_str());
  });

  // Server-sent events from message `from` on (default: the next one).
  srv.Get("/api/events", [this](const httplib::Request& req, httplib::Response& res) {
    const auto from = uint_param(req, "from", hub_.next());
    if (!from) return send_error(res, 400, "'from' must be a message number");
    auto cursor = std::make_shared<std::uint64_t>(*from);
    res.set_header("Cache-Control", "no-store");
    res.set_chunked_content_provider("text/event-stream", [this, cursor](std::size_t, httplib::DataSink& sink) {
      std::string m = hub_.wait(*cursor, 1000);
      if (hub_.closed()) {
        sink.done();
        return false;
      }
      // Whatever else is ready goes in the same write.
      for (std::string more; !(more = hub_.wait(*cursor, 0)).empty() && m.size() < (1u << 20);) m += more;
      if (m.empty()) m = ": keep-alive\n\n";
      return sink.write(m.data(), m.size());
    });
  });
}

}  // namespace quiver::agents::inline view::viewer
