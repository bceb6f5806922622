// The Barthel test's shared world model as the agents read it: nodes by name, the person's presence, prompts and
// their answers, marks taken back, attributes with fallbacks.
#include "quiver/agents/apps/barthel/barthel_schema.h"

#include <algorithm>

namespace quiver::agents::inline apps::barthel {

using graph::NodeId;
using graph::Symbol;

const std::vector<std::string>& joint_names() {
  static const std::vector<std::string> kJoints = {
      "head",       "neck",        "torso",      "left_shoulder", "left_elbow",
      "left_hand",  "right_shoulder", "right_elbow", "right_hand", "left_hip",
      "left_knee",  "left_foot",   "right_hip",  "right_knee",    "right_foot"};
  return kJoints;
}

NodeId node_id(const graph::Graph& g, std::string_view name) {
  auto id = g.find_node(name);
  return id ? *id : NodeId{};
}

bool person_present(const graph::Graph& g) {
  NodeId p = node_id(g, node::kPerson), r = node_id(g, node::kRobot);
  return !p.is_null() && !r.is_null() && g.has_edge(p, r, Symbol(edge::kInFrontOf));
}

bool patient_in_front(const graph::Graph& g, std::int64_t now_ns, std::int64_t stale_ns) {
  NodeId p = node_id(g, node::kPerson);
  return person_present(g) && attr_bool(g, p, "present") && now_ns - attr_int(g, p, "seen_ns") <= stale_ns;
}

std::int64_t person_seen_ns(const graph::Graph& g) {
  NodeId p = node_id(g, node::kPerson);
  return p.is_null() ? 0 : attr_int(g, p, "seen_ns");
}

Status take_back(graph::Graph& g, std::string_view from, std::string_view type, NodeId to) {
  NodeId f = node_id(g, from);
  if (f.is_null()) return {};
  for (const graph::EdgeKey& e : g.edges_from(f, Symbol(type))) {
    if (!to.is_null() && e.to != to) continue;
    graph::Transaction tx = g.begin();
    if (Status s = tx.delete_edge(e.from, e.to, e.type); !s.ok()) return s;
    if (auto c = tx.commit(); !c.ok()) return c.error();
  }
  return {};
}

std::string attr_string(const graph::Graph& g, NodeId n, Symbol name, std::string fallback) {
  const graph::Value* v = g.attr(n, name);
  if (!v) return fallback;
  if (const auto* s = v->get_if<std::string>()) return *s;
  return fallback;
}

std::int64_t attr_int(const graph::Graph& g, NodeId n, Symbol name, std::int64_t fallback) {
  const graph::Value* v = g.attr(n, name);
  if (!v) return fallback;
  if (const auto* x = v->get_if<std::int64_t>()) return *x;
  if (const auto* x = v->get_if<std::int32_t>()) return *x;
  if (const auto* x = v->get_if<std::uint32_t>()) return *x;
  if (const auto* x = v->get_if<std::uint64_t>()) return static_cast<std::int64_t>(*x);
  return fallback;
}

bool attr_bool(const graph::Graph& g, NodeId n, Symbol name, bool fallback) {
  const graph::Value* v = g.attr(n, name);
  if (!v) return fallback;
  if (const auto* b = v->get_if<bool>()) return *b;
  return fallback;
}

std::string join_lines(const std::vector<std::string>& lines) {
  std::string out;
  for (std::size_t i = 0; i < lines.size(); ++i) {
    if (i) out += '\n';
    out += lines[i];
  }
  return out;
}

std::vector<std::string> split_lines(std::string_view text) {
  std::vector<std::string> out;
  if (text.empty()) return out;
  std::size_t start = 0;
  while (true) {
    std::size_t nl = text.find('\n', start);
    out.emplace_back(text.substr(start, nl == std::string_view::npos ? std::string_view::npos : nl - start));
    if (nl == std::string_view::npos) break;
    start = nl + 1;
  }
  return out;
}

namespace {
// Every agent reads every prompt on most of its rounds: the names are interned once.
struct PromptNames {
  Symbol say{edge::kSay}, seq{"seq"}, text{"text"}, purpose{"purpose"}, item{"item"}, attempt{"attempt"},
      title{"title"}, screen_text{"screen_text"}, options{"options"}, buttons{"buttons"};
};
const PromptNames& names() {
  static const PromptNames n;
  return n;
}
}  // namespace

std::optional<Prompt> prompt_at(const graph::Graph& g, NodeId u) {
  const PromptNames& k = names();
  if (!g.has_node(u)) return std::nullopt;
  Prompt p;
  p.id = u;
  p.seq = attr_int(g, u, k.seq, -1);
  if (p.seq < 0) return std::nullopt;
  p.text = attr_string(g, u, k.text);
  p.purpose = attr_string(g, u, k.purpose);
  p.item = static_cast<int>(attr_int(g, u, k.item, -1));
  p.attempt = static_cast<int>(attr_int(g, u, k.attempt, 0));
  p.title = attr_string(g, u, k.title);
  p.screen_text = attr_string(g, u, k.screen_text);
  if (const graph::Value* o = g.attr(u, k.options))
    if (const auto* text = o->get_if<std::string>()) p.options = split_lines(*text);
  p.buttons = attr_bool(g, u, k.buttons);
  return p;
}

namespace {
// Every utterance the test says, as (seq, id), in no order; only its seq is read.
std::vector<std::pair<std::int64_t, NodeId>> said(const graph::Graph& g) {
  std::vector<std::pair<std::int64_t, NodeId>> out;
  NodeId t = node_id(g, node::kTest);
  if (t.is_null()) return out;
  for (const graph::EdgeKey& e : g.edges_from(t, names().say))
    if (g.has_node(e.to))
      if (std::int64_t seq = attr_int(g, e.to, names().seq, -1); seq >= 0) out.emplace_back(seq, e.to);
  return out;
}
}  // namespace

std::vector<NodeId> prompt_ids(const graph::Graph& g) {
  auto order = said(g);
  std::sort(order.begin(), order.end());
  std::vector<NodeId> out;
  out.reserve(order.size());
  for (const auto& [seq, id] : order) out.push_back(id);
  return out;
}

std::vector<Prompt> prompts(const graph::Graph& g) {
  std::vector<Prompt> out;
  for (NodeId id : prompt_ids(g))
    if (auto p = prompt_at(g, id)) out.push_back(std::move(*p));
  return out;
}

std::optional<Prompt> prompt_by_seq(const graph::Graph& g, std::int64_t seq) {
  // The first by id among the prompts with this seq, as prompts() orders them; only it is read whole.
  NodeId first;
  for (const auto& [s, id] : said(g))
    if (s == seq && (first.is_null() || id < first)) first = id;
  if (first.is_null()) return std::nullopt;
  return prompt_at(g, first);
}

bool marked(const graph::Graph& g, std::string_view from, std::string_view type, NodeId u) {
  NodeId f = node_id(g, from);
  return !f.is_null() && g.has_edge(f, u, Symbol(type));
}

std::optional<Answer> answer_to(const graph::Graph& g, NodeId u) {
  for (auto [from, type, channel] : {std::tuple{node::kSpeaker, edge::kHeard, "voice"},
                                     std::tuple{node::kPanel, edge::kTapped, "touch"}}) {
    NodeId f = node_id(g, from);
    if (f.is_null()) continue;
    graph::EdgeKey k{f, u, Symbol(type)};
    if (!g.has_edge(f, u, k.type)) continue;
    Answer a;
    a.channel = channel;
    if (const graph::Value* v = g.edge_attr(k, Symbol("option"))) {
      if (const auto* x = v->get_if<std::int64_t>()) a.option = static_cast<int>(*x);
    }
    if (const graph::Value* v = g.edge_attr(k, Symbol("text"))) {
      if (const auto* s = v->get_if<std::string>()) a.text = *s;
    }
    return a;
  }
  return std::nullopt;
}

}  // namespace quiver::agents::inline apps::barthel
