// The evolution of a recorded world as pictures, one per change, over one stable layout: what the change touched
// drawn bold, what it removed as ghosts, and a caption; as PNG files or an MP4 video.
#include "quiver/agents/view/render/timeline_video.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <opencv2/imgproc.hpp>
#include <unordered_map>
#include <unordered_set>

#include "picture_sink.h"
#include "painter.h"
#include "quiver/agents/view/render/geometric_part.h"
#include "quiver/agents/view/render/picture.h"
#include "quiver/agents/view/render/render_replay.h"

namespace quiver::agents::inline view::render {
namespace {

using internal::Look;

using internal::kMarginPx;
constexpr double kCaptionPx = 13;      // capital letters of the caption
constexpr double kCaptionLinePx = 22;  // baseline to baseline
constexpr int kCaptionLines = 3;
constexpr int kCaptionBandPx = static_cast<int>(kCaptionLines * kCaptionLinePx) + 14;
constexpr int kMinWidthPx = 640;  // room for the caption
constexpr std::size_t kCaptionItems = 6;

bool edge_present(const graph::Graph& g, const graph::EdgeKey& k) {
  if (is_geometric(k)) {
    const auto parent = g.rt_parent(k.to);
    return parent.has_value() && *parent == k.from;
  }
  return g.has_edge(k.from, k.to, k.type);
}
bool node_shown(const graph::Graph& g, graph::NodeId id, bool hide_geometry) {
  return g.has_node(id) && !(hide_geometry && is_geometric(g, id));
}
bool edge_shown(const graph::Graph& g, const graph::EdgeKey& k, bool hide_geometry) {
  return !(hide_geometry && is_geometric(k)) && edge_present(g, k);
}

// Every node and edge shown in any change, as one picture, with indices to find them.
struct Union {
  Picture picture;
  std::unordered_map<graph::NodeId, std::size_t> node_index;
  std::unordered_map<graph::EdgeKey, std::size_t> edge_index;
  std::vector<std::vector<std::size_t>> incident;  // node -> its edges
};

Union collect_union(std::span<const recording::RecordedChange> changes, bool hide) {
  std::unordered_map<graph::NodeId, PictureNode> nodes;
  std::unordered_set<graph::EdgeKey> edges;
  Replay r(changes);
  while (!r.done()) {
    const bool first = r.next() == 0;
    const graph::ChangeBatch& b = r.step();
    const graph::Graph& g = r.graph();
    auto see_node = [&](graph::NodeId id) {
      if (nodes.contains(id) || !node_shown(g, id, hide)) return;
      nodes.emplace(
          id, PictureNode{id, g.name_of(id), g.type_of(id).str(), is_geometric(g, id), false});
    };
    auto see_edge = [&](const graph::EdgeKey& k) {
      if (edges.contains(k) || !edge_shown(g, k, hide)) return;
      see_node(k.from);
      see_node(k.to);
      edges.insert(k);
    };
    if (first) {  // the state recording began with, whatever its change events say
      for (graph::NodeId id : g.nodes()) {
        see_node(id);
        for (const graph::EdgeKey& k : g.edges_from(id)) see_edge(k);
      }
    }
    for (const graph::NodeChange& c : b.nodes) see_node(c.id);
    for (const graph::EdgeChange& c : b.edges) see_edge(c.key);
  }

  Union u;
  u.picture.nodes.reserve(nodes.size());
  for (auto& [id, n] : nodes) u.picture.nodes.push_back(std::move(n));
  std::sort(u.picture.nodes.begin(), u.picture.nodes.end(),
            [](const PictureNode& a, const PictureNode& b) {
              return a.name != b.name ? a.name < b.name : a.id < b.id;
            });
  for (std::size_t i = 0; i < u.picture.nodes.size(); ++i)
    u.node_index.emplace(u.picture.nodes[i].id, i);
  for (const graph::EdgeKey& k : edges) {
    auto from = u.node_index.find(k.from), to = u.node_index.find(k.to);
    if (from == u.node_index.end() || to == u.node_index.end()) continue;
    u.picture.edges.push_back(
        PictureEdge{k, from->second, to->second, k.type.str(), is_geometric(k), false});
  }
  std::sort(u.picture.edges.begin(), u.picture.edges.end(),
            [](const PictureEdge& a, const PictureEdge& b) {
              if (a.from != b.from) return a.from < b.from;
              if (a.to != b.to) return a.to < b.to;
              return a.type < b.type;
            });
  u.incident.resize(u.picture.nodes.size());
  for (std::size_t i = 0; i < u.picture.edges.size(); ++i) {
    const PictureEdge& e = u.picture.edges[i];
    u.edge_index.emplace(e.key, i);
    u.incident[e.from].push_back(i);
    u.incident[e.to].push_back(i);
  }
  return u;
}

std::string join_attrs(const std::vector<graph::Symbol>& attrs) {
  std::string out;
  for (graph::Symbol a : attrs) out += (out.empty() ? "" : ", ") + a.str();
  return out;
}

// What the pictures show of one change, change after change.
class Tracker {
 public:
  Tracker(const Union& u, bool hide) : u_(u), hide_(hide) {
    node_on_.assign(u.picture.nodes.size(), 0);
    edge_on_.assign(u.picture.edges.size(), 0);
    node_looks_.assign(node_on_.size(), Look::kHidden);
    edge_looks_.assign(edge_on_.size(), Look::kHidden);
  }

  struct Changed {
    bool drawn = false;       // anything drawn changed (appeared, went, or was updated)
    bool structural = false;  // a node or an edge appeared or went
  };
  // Brings the shown sets up to date after a change. `quiet`: the recording's initial state,
  // drawn without highlights.
  Changed update(const graph::Graph& g, const graph::ChangeBatch& b, bool everything, bool quiet) {
    std::fill(node_looks_.begin(), node_looks_.end(), Look::kHidden);
    std::fill(edge_looks_.begin(), edge_looks_.end(), Look::kHidden);
    std::vector<std::size_t> nodes, edges;  // to check again
    auto node_of = [&](graph::NodeId id) {
      if (auto it = u_.node_index.find(id); it != u_.node_index.end()) nodes.push_back(it->second);
    };
    if (everything) {
      for (std::size_t i = 0; i < node_on_.size(); ++i) nodes.push_back(i);
      for (std::size_t i = 0; i < edge_on_.size(); ++i) edges.push_back(i);
    }
    for (const graph::NodeChange& c : b.nodes) node_of(c.id);
    for (const graph::EdgeChange& c : b.edges) {
      node_of(c.key.from);
      node_of(c.key.to);
      if (auto it = u_.edge_index.find(c.key); it != u_.edge_index.end())
        edges.push_back(it->second);
    }
    for (std::size_t i : nodes)
      edges.insert(edges.end(), u_.incident[i].begin(), u_.incident[i].end());

    bool drawn_change = false, structural = false;
    for (std::size_t i : nodes) {
      const bool was = node_on_[i], now = node_shown(g, u_.picture.nodes[i].id, hide_);
      node_on_[i] = now;
      if (!quiet && was != now) {
        node_looks_[i] = now ? Look::kHighlighted : Look::kGhost;
        drawn_change = structural = true;
      }
    }
    for (std::size_t i : edges) {
      const bool was = edge_on_[i], now = edge_shown(g, u_.picture.edges[i].key, hide_);
      edge_on_[i] = now;
      if (!quiet && was != now) {
        edge_looks_[i] = now ? Look::kHighlighted : Look::kGhost;
        drawn_change = structural = true;
      }
    }
    // Updates of things shown: attributes, names, poses.
    if (!quiet) {
      for (const graph::NodeChange& c : b.nodes)
        if (auto it = u_.node_index.find(c.id); it != u_.node_index.end() && node_on_[it->second]) {
          node_looks_[it->second] = Look::kHighlighted;
          drawn_change = true;
        }
      for (const graph::EdgeChange& c : b.edges)
        if (auto it = u_.edge_index.find(c.key);
            it != u_.edge_index.end() && edge_on_[it->second]) {
          edge_looks_[it->second] = Look::kHighlighted;
          drawn_change = true;
        }
    }
    for (std::size_t i = 0; i < node_on_.size(); ++i)
      if (node_on_[i] && node_looks_[i] == Look::kHidden) node_looks_[i] = Look::kNormal;
    for (std::size_t i = 0; i < edge_on_.size(); ++i)
      if (edge_on_[i] && edge_looks_[i] == Look::kHidden) edge_looks_[i] = Look::kNormal;
    return Changed{drawn_change, structural};
  }

  // The changes drawn, in words.
  std::vector<std::string> describe(const graph::ChangeBatch& b) const {
    std::vector<std::string> out;
    for (const graph::NodeChange& c : b.nodes) {
      auto it = u_.node_index.find(c.id);
      if (it == u_.node_index.end() || node_looks_[it->second] == Look::kNormal ||
          node_looks_[it->second] == Look::kHidden)
        continue;
      const PictureNode& n = u_.picture.nodes[it->second];
      switch (c.kind) {
        case graph::ChangeKind::kCreated:
          out.push_back("created " + n.name + " (" + n.type + ")");
          break;
        case graph::ChangeKind::kDeleted:
          out.push_back("deleted " + n.name);
          break;
        case graph::ChangeKind::kUpdated:
          if (!c.attrs.empty())
            out.push_back("set " + join_attrs(c.attrs) + " on " + n.name);
          else
            out.push_back((c.renamed ? "renamed " : "changed ") + n.name);
          break;
      }
    }
    for (const graph::EdgeChange& c : b.edges) {
      auto it = u_.edge_index.find(c.key);
      if (it == u_.edge_index.end() || edge_looks_[it->second] == Look::kNormal ||
          edge_looks_[it->second] == Look::kHidden)
        continue;
      const PictureEdge& e = u_.picture.edges[it->second];
      const std::string& from = u_.picture.nodes[e.from].name;
      const std::string& to = u_.picture.nodes[e.to].name;
      const std::string arrow = from + " -" + e.type + "-> " + to;
      switch (c.kind) {
        case graph::ChangeKind::kCreated:
          out.push_back("added " + arrow);
          break;
        case graph::ChangeKind::kDeleted:
          out.push_back("removed " + arrow);
          break;
        case graph::ChangeKind::kUpdated:
          if (e.geometric)
            out.push_back("moved " + to);
          else if (!c.attrs.empty())
            out.push_back("set " + join_attrs(c.attrs) + " on " + arrow);
          else
            out.push_back("re-added " + arrow);
          break;
      }
    }
    return out;
  }

  const std::vector<Look>& node_looks() const { return node_looks_; }
  const std::vector<Look>& edge_looks() const { return edge_looks_; }
  std::size_t nodes_on() const { return std::count(node_on_.begin(), node_on_.end(), 1); }
  std::size_t edges_on() const { return std::count(edge_on_.begin(), edge_on_.end(), 1); }

 private:
  const Union& u_;
  bool hide_;
  std::vector<char> node_on_, edge_on_;
  std::vector<Look> node_looks_, edge_looks_;
};

std::string caption_of(const recording::RecordedChange& f, const std::string& origin,
                       const std::vector<std::string>& changes, bool initial, const Tracker& t) {
  char head[96];
  std::snprintf(head, sizeof head, "t = %.2f s  ", static_cast<double>(f.t_ns) / 1e9);
  std::string text = head;
  text += "origin: " + (origin.empty() ? std::string("?") : origin) + "  ";
  if (initial) {
    return text + "initial state: " + std::to_string(t.nodes_on()) + " nodes, " +
           std::to_string(t.edges_on()) + " edges";
  }
  for (std::size_t i = 0; i < changes.size() && i < kCaptionItems; ++i)
    text += (i == 0 ? "" : ", ") + changes[i];
  if (changes.size() > kCaptionItems)
    text += " and " + std::to_string(changes.size() - kCaptionItems) + " more";
  return text;
}

// Breaks `text` into lines of at most `width` pixels at spaces (the last line cut with "...").
std::vector<std::string> wrap(const std::string& text, double width) {
  int baseline = 0;
  const double scale =
      kCaptionPx / cv::getTextSize("H", cv::FONT_HERSHEY_SIMPLEX, 1.0, 1, &baseline).height;
  auto fits = [&](const std::string& s) {
    return cv::getTextSize(s, cv::FONT_HERSHEY_SIMPLEX, scale, 1, &baseline).width <= width;
  };
  std::vector<std::string> lines;
  std::string line;
  std::size_t pos = 0;
  while (pos < text.size()) {
    std::size_t next = text.find(' ', pos + 1);
    if (next == std::string::npos) next = text.size();
    const std::string word = text.substr(pos, next - pos);
    if (!line.empty() && !fits(line + word)) {
      lines.push_back(line);
      line = word.substr(word.find_first_not_of(' ') == std::string::npos
                             ? word.size()
                             : word.find_first_not_of(' '));
    } else {
      line += word;
    }
    pos = next;
  }
  if (!line.empty()) lines.push_back(line);
  if (lines.size() > static_cast<std::size_t>(kCaptionLines)) {
    lines.resize(kCaptionLines);
    std::string& last = lines.back();
    while (!last.empty() && !fits(last + " ...")) last.pop_back();
    last += " ...";
  }
  return lines;
}

int even_up(double v) {
  int i = static_cast<int>(std::ceil(v));
  return i + (i % 2);
}

}  // namespace

Result<TimelineOutput> timeline_output_of(const std::string& path) {
  namespace fs = std::filesystem;
  std::string ext = fs::path(path).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char ch) { return static_cast<char>(std::tolower(ch)); });
  if (ext == ".mp4") return TimelineOutput::kMp4;
  std::error_code ec;
  if (path.empty() || path.back() == '/' || fs::is_directory(path, ec) || ext.empty())
    return TimelineOutput::kPngFrames;
  return make_error(ErrorCode::kInvalidArgument,
                    "render_timeline(): cannot tell what to write to '" + path +
                        "' from its extension '" + ext +
                        "' (an .mp4 file, or a directory for PNG frames)");
}

Result<TimelineInfo> render_timeline(std::span<const recording::RecordedChange> changes,
                                     const TimelineOptions& o, const std::string& out) {
  auto kind = timeline_output_of(out);
  if (!kind.ok()) return kind.error();
  if (changes.empty())
    return make_error(ErrorCode::kInvalidArgument,
                      "render_timeline(): the recording holds no frames");
  if (!(o.fps > 0) || o.max_width < 64 || o.max_height < 64 + kCaptionBandPx)
    return make_error(ErrorCode::kInvalidArgument,
                      "render_timeline(): fps must be positive and the size at least 64 x " +
                          std::to_string(64 + kCaptionBandPx) + " pixels");

  const Union u = collect_union(changes, o.hide_geometry);
  auto layout = lay_out_to_fit(u.picture, o.engine, o.max_width - 2.0 * kMarginPx,
                               o.max_height - 2.0 * kMarginPx - kCaptionBandPx);
  if (!layout.ok()) return layout.error();
  const Layout& l = *layout;

  const double band = kCaptionBandPx;
  const double scale = std::max(
      1e-3, std::min({96.0 / 72.0, (o.max_width - 2.0 * kMarginPx) / std::max(l.width, 1.0),
                      (o.max_height - 2.0 * kMarginPx - band) / std::max(l.height, 1.0)}));
  const int width =
      std::min(even_up(std::max<double>(kMinWidthPx, l.width * scale + 2 * kMarginPx)),
               o.max_width - o.max_width % 2);
  const int height = even_up(l.height * scale + 2 * kMarginPx + band);
  const internal::View view{scale, cv::Point2d((width - l.width * scale) / 2, kMarginPx + band)};

  auto sink = internal::open_picture_sink(*kind, out, width, height, o.fps, changes.size());
  if (!sink.ok()) return sink.error();

  TimelineInfo info;
  info.recorded = changes.size();
  info.width = width;
  info.height = height;
  info.nodes = u.picture.nodes.size();
  info.edges = u.picture.edges.size();
  info.engine = l.engine;

  Tracker tracker(u, o.hide_geometry);
  Replay r(changes);
  while (!r.done()) {
    const std::size_t i = r.next();
    const graph::ChangeBatch& b = r.step();
    const bool initial = i == 0 && changes[0].delta.kind == graph::GraphDelta::Kind::kState;
    const Tracker::Changed changed =
        tracker.update(r.graph(), b, /*everything=*/i == 0, /*quiet=*/initial);
    const bool wanted = o.structure_only ? changed.structural : changed.drawn || o.every_change;
    if (!wanted && !initial) {
      ++info.skipped;
      continue;
    }
    if (o.max_changes > 0 && info.written >= o.max_changes) {
      ++info.cut;
      continue;
    }
    const std::string caption =
        caption_of(changes[i], b.origin_name, tracker.describe(b), initial, tracker);
    cv::Mat img = internal::blank_image(width, height);
    cv::rectangle(img, cv::Rect(0, 0, width, static_cast<int>(band)), cv::Scalar(245, 245, 245),
                  cv::FILLED);
    const auto lines = wrap(caption, width - 2.0 * kMarginPx);
    for (std::size_t k = 0; k < lines.size(); ++k)
      internal::paint_text(img, lines[k], cv::Point2d(kMarginPx, 8 + k * kCaptionLinePx),
                           kCaptionPx, kInkColour);
    internal::paint(img, u.picture, l, tracker.node_looks(), tracker.edge_looks(), view);
    if (Status s = (*sink)->add(img); !s.ok()) return s.error();
    info.changes.push_back(i);
    info.captions.push_back(caption);
    ++info.written;
  }
  if (Status s = (*sink)->close(); !s.ok()) return s.error();
  return info;
}

}  // namespace quiver::agents::inline view::render
