// Symbolic states: typed nodes and labelled edges under a shared vocabulary, hashed exactly, and read from a
// replica as a world.
#include "quiver/agents/rules/symbolic/state.h"

#include <algorithm>
#include <charconv>

#include "quiver/base/hash.h"

namespace quiver::agents::inline rules::symbolic {

TypeIx Vocabulary::type(std::string_view name) {
  auto it = type_ix_.find(std::string(name));
  if (it != type_ix_.end()) return it->second;
  const auto ix = static_cast<TypeIx>(type_names_.size());
  type_names_.emplace_back(name);
  type_ix_.emplace(std::string(name), ix);
  return ix;
}

LabelIx Vocabulary::label(std::string_view name) {
  auto it = label_ix_.find(std::string(name));
  if (it != label_ix_.end()) return it->second;
  const auto ix = static_cast<LabelIx>(label_names_.size());
  label_names_.emplace_back(name);
  label_ix_.emplace(std::string(name), ix);
  return ix;
}

std::optional<TypeIx> Vocabulary::find_type(std::string_view name) const {
  auto it = type_ix_.find(std::string(name));
  if (it == type_ix_.end()) return std::nullopt;
  return it->second;
}

std::optional<LabelIx> Vocabulary::find_label(std::string_view name) const {
  auto it = label_ix_.find(std::string(name));
  if (it == label_ix_.end()) return std::nullopt;
  return it->second;
}

bool Vocabulary::is_a(TypeIx t, TypeIx base) const {
  if (t == base) return true;
  if (t == kAbsent || base == kAbsent) return false;
  if (is_a_.size() < type_names_.size()) is_a_.resize(type_names_.size());
  auto& row = is_a_[t];
  if (row.size() < type_names_.size()) row.resize(type_names_.size(), -1);
  if (row[base] < 0) row[base] = types_.is_a(type_names_[t], type_names_[base]) ? 1 : 0;
  return row[base] == 1;
}

bool State::has_edge(NodeIx from, NodeIx to, LabelIx label) const {
  return std::binary_search(out_.begin(), out_.end(), Edge{from, label, to});
}

std::pair<const Edge*, const Edge*> State::out(NodeIx from, LabelIx label) const {
  auto lo = std::lower_bound(out_.begin(), out_.end(), Edge{from, label, 0});
  auto hi = std::lower_bound(lo, out_.end(), Edge{from, label + 1, 0});
  return {out_.data() + (lo - out_.begin()), out_.data() + (hi - out_.begin())};
}

std::pair<const Edge*, const Edge*> State::in(NodeIx to, LabelIx label) const {
  auto lo = std::lower_bound(in_.begin(), in_.end(), Edge{to, label, 0});
  auto hi = std::lower_bound(lo, in_.end(), Edge{to, label + 1, 0});
  return {in_.data() + (lo - in_.begin()), in_.data() + (hi - in_.begin())};
}

NodeIx State::add_node(TypeIx t) {
  types_.push_back(t);
  ++alive_;
  hashed_ = false;
  return static_cast<NodeIx>(types_.size() - 1);
}

void State::delete_node(NodeIx n) {
  if (!alive(n)) return;
  types_[n] = kAbsent;
  --alive_;
  hashed_ = false;
  auto touches = [n](const Edge& e) { return e.from == n || e.to == n; };
  out_.erase(std::remove_if(out_.begin(), out_.end(), touches), out_.end());
  in_.erase(std::remove_if(in_.begin(), in_.end(), touches), in_.end());
}

void State::add_edge(NodeIx from, NodeIx to, LabelIx label) {
  if (!alive(from) || !alive(to)) return;
  const Edge e{from, label, to};
  auto it = std::lower_bound(out_.begin(), out_.end(), e);
  if (it != out_.end() && *it == e) return;
  out_.insert(it, e);
  const Edge r{to, label, from};
  in_.insert(std::lower_bound(in_.begin(), in_.end(), r), r);
  hashed_ = false;
}

void State::remove_edge(NodeIx from, NodeIx to, LabelIx label) {
  const Edge e{from, label, to};
  auto it = std::lower_bound(out_.begin(), out_.end(), e);
  if (it == out_.end() || !(*it == e)) return;
  out_.erase(it);
  const Edge r{to, label, from};
  in_.erase(std::lower_bound(in_.begin(), in_.end(), r));
  hashed_ = false;
}

std::uint64_t State::hash() const {
  if (hashed_) return hash_;
  std::uint64_t h = 0x9e3779b97f4a7c15ULL ^ types_.size();
  for (TypeIx t : types_) h = hash_combine(h, t);
  for (const Edge& e : out_)
    h = hash_combine(h, (static_cast<std::uint64_t>(e.from) << 32) ^ (static_cast<std::uint64_t>(e.label) << 16) ^
                            (static_cast<std::uint64_t>(e.to) * 0x100000001b3ULL));
  hash_ = h;
  hashed_ = true;
  return h;
}

NodeIx World::find(std::string_view key) const {
  for (NodeIx n = 0; n < initial; ++n)
    if (!agm_ids[n].empty() && agm_ids[n] == key) return n;
  for (NodeIx n = 0; n < initial; ++n)
    if (names[n] == key) return n;
  // A numeric AGM id above every id of the world: the node a plan would create with that id
  // (AGM numbers new symbols from the largest id up).
  std::int64_t id = 0;
  auto [p, ec] = std::from_chars(key.data(), key.data() + key.size(), id);
  if (ec == std::errc() && p == key.data() + key.size() && max_agm_id >= 0 && id > max_agm_id)
    return static_cast<NodeIx>(initial + static_cast<std::size_t>(id - max_agm_id - 1));
  if (key.starts_with("new_")) {
    std::size_t n = 0;
    auto [q, e2] = std::from_chars(key.data() + 4, key.data() + key.size(), n);
    if (e2 == std::errc() && q == key.data() + key.size() && n >= initial) return static_cast<NodeIx>(n);
  }
  return kNoNode;
}

std::string World::label(NodeIx n) const {
  if (n < initial) return agm_ids[n].empty() ? names[n] : agm_ids[n];
  const std::size_t k = n - initial;
  if (max_agm_id >= 0) return std::to_string(max_agm_id + 1 + static_cast<std::int64_t>(k));
  return "new_" + std::to_string(n);
}

World read_world(const graph::Graph& g, TypeSystem types, const std::function<bool(graph::NodeId)>& hide) {
  World w;
  w.vocabulary = Vocabulary(std::move(types));
  std::vector<graph::NodeId> ids = g.nodes();
  std::vector<std::pair<std::string, graph::NodeId>> named;
  named.reserve(ids.size());
  for (graph::NodeId id : ids)
    if (!hide || !hide(id)) named.emplace_back(g.name_of(id), id);
  std::sort(named.begin(), named.end());
  std::unordered_map<graph::NodeId, NodeIx> ix;
  for (auto& [name, id] : named) {
    const NodeIx n = w.state.add_node(w.vocabulary.type(g.type_of(id).str()));
    ix.emplace(id, n);
    w.ids.push_back(id);
    w.names.push_back(name);
    std::string agm;
    if (const graph::Value* v = g.attr(id, "agm_id"))
      if (const auto* s = v->get_if<std::string>()) agm = *s;
    std::int64_t num = 0;
    auto [p, ec] = std::from_chars(agm.data(), agm.data() + agm.size(), num);
    if (!agm.empty() && ec == std::errc() && p == agm.data() + agm.size())
      w.max_agm_id = std::max(w.max_agm_id, num);
    w.agm_ids.push_back(std::move(agm));
  }
  w.initial = w.names.size();
  const LabelIx rt = w.vocabulary.label("RT");
  for (auto& [name, id] : named) {
    for (const graph::EdgeKey& e : g.edges_from(id)) {
      auto to = ix.find(e.to);
      if (to == ix.end()) continue;
      w.state.add_edge(ix[id], to->second, w.vocabulary.label(e.type.str()));
    }
    if (auto parent = g.rt_parent(id)) {
      auto p = ix.find(*parent);
      if (p != ix.end()) w.state.add_edge(p->second, ix[id], rt);
    }
  }
  return w;
}

}  // namespace quiver::agents::inline rules::symbolic
