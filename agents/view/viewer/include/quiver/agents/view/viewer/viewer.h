#pragma once
/// @file
/// The live viewer: serves a page (on 127.0.0.1 unless told otherwise) that shows one graph
/// replica, pushes its changes as server-sent events, and keeps a timeline of the changes it
/// received so that the page can show the state after any of them. The page and its protocol:
/// docs/viewer.md.
///
/// Threading: the graph belongs to its owner thread (a DdsReplica's, or whoever holds a static
/// graph). The Viewer is made and ticked there; the HTTP threads read the graph only through
/// `Hooks::run_on_owner`, which runs a task on the owner thread and waits for it.

#include <cstdint>
#include <functional>
#include <memory>
#include <string>

#include <nlohmann/json.hpp>

#include "quiver/agents/view/recording/graph_recorder.h"
#include "quiver/agents/view/viewer/event_hub.h"
#include "quiver/agents/view/viewer/change_timeline.h"
#include "quiver/agents/view/viewer/view_json.h"
#include "quiver/graph/graph.h"
#include "quiver/base/result.h"

namespace quiver::agents::inline view::viewer {

struct ViewerOptions {
  std::string host = "127.0.0.1";  ///< another address only when asked for explicitly
  int port = 8080;                 ///< 0: any free port (see Viewer::port())
  std::string assets_dir;          ///< index.html, viewer.js, viewer.css (default_assets_dir())
  std::string d3_dir = "/usr/share/javascript/d3";        ///< Debian libjs-d3
  std::string three_dir = "/usr/share/javascript/three";  ///< Debian libjs-three
  std::string mode = "live";       ///< "live", "replay" or "world": shown on the page
  std::string title;               ///< e.g. "DDS domain 0"
  std::uint64_t history_bytes = 64ull << 20;
  std::uint64_t history_changes = 200'000;
  /// Changes are pushed at most this often, and less often when pushing takes more than a tenth
  /// of the time.
  std::int64_t flush_ns = 33'000'000;
  /// The shared vocabulary (docs/schema.md, Schema::to_json() parsed) the page shows: units and
  /// declarations beside attributes, node types with their bases. Null: none.
  nlohmann::json schema;
};

/// Where the page's files are: $QUIVER_VIEWER_ASSETS, else the source tree (a build that was not
/// installed), else <prefix>/share/quiver/viewer next to the running executable.
std::string default_assets_dir();

struct Hooks {
  /// Runs a task on the graph's owner thread and returns when it ran. Required.
  std::function<void(std::function<void()>)> run_on_owner;
  /// The recorder's clock for change times (ns). Required.
  std::function<std::int64_t()> clock;
  /// The name of the agent behind a replica id (writers, change origins). Null: ids.
  std::function<std::string(const graph::ReplicaId&)> name_of;
  /// Owner thread: locks and violations to show. Null: none.
  std::function<void(Decor&)> decorate;
  /// Owner thread: the agents connected, as [{"name", "id", "observer", "alive"}]. Null: none.
  std::function<nlohmann::json()> agents;
};

class Viewer {
 public:
  /// Owner thread. Starts recording `g`'s incoming changes and serving. kIo when the address
  /// cannot be bound, kNotFound when the assets directory lacks index.html.
  static Result<std::unique_ptr<Viewer>> start(graph::Graph& g, ViewerOptions options, Hooks hooks);
  /// Stops serving (open pages see the connection end).
  ~Viewer();
  Viewer(const Viewer&) = delete;
  Viewer& operator=(const Viewer&) = delete;

  /// Owner thread: pushes the changes gathered since the last push (at most every flush_ns),
  /// and the agents list when it changed. Call often (every few ms).
  void tick(std::int64_t now_ns);

  int port() const { return port_; }
  const std::string& url() const { return url_; }
  const Timeline& timeline() const { return timeline_; }
  std::uint64_t messages_published() const { return hub_.next(); }

 private:
  Viewer(graph::Graph& g, ViewerOptions o, Hooks h);
  Decor decor() const;
  void routes();
  graph::Graph& g_;
  ViewerOptions opt_;
  Hooks hooks_;
  Timeline timeline_;
  ChangeAccumulator pending_;
  EventHub hub_;
  std::unique_ptr<recording::GraphRecorder> recorder_;
  graph::Graph::SubscriptionId sub_ = 0;
  std::int64_t next_flush_ = 0;
  std::string last_agents_;
  std::string last_violations_;
  int port_ = 0;
  std::string url_;
  struct Http;
  std::unique_ptr<Http> http_;
};

}  // namespace quiver::agents::inline view::viewer
