// The planner: A* over symbolic states towards a mission, with a lower-bound heuristic from the rules, and
// hierarchical steps decomposed by sub-searches.
#include "quiver/agents/rules/planner/planner.h"

#include <algorithm>
#include <cmath>
#include <deque>
#include <limits>
#include <queue>
#include <unordered_map>

namespace quiver::agents::inline rules::planner {

using symbolic::Binding;
using symbolic::CEdge;
using symbolic::kNoNode;
using symbolic::LabelIx;
using symbolic::NodeIx;
using symbolic::State;
using symbolic::TypeIx;

namespace {
constexpr double kUnreachable = std::numeric_limits<double>::infinity();
}

const char* to_string(PlanResult::Outcome o) {
  switch (o) {
    case PlanResult::Outcome::kFound:
      return "found";
    case PlanResult::Outcome::kExhausted:
      return "exhausted";
    case PlanResult::Outcome::kLimit:
      return "limit";
    case PlanResult::Outcome::kUnsolvable:
      return "unsolvable";
  }
  return "?";
}

double heuristic(const Domain& domain, const State& s, const CompiledMission& m) {
  if (!m.unresolved.empty()) return kUnreachable;
  const symbolic::Vocabulary& voc = domain.vocabulary();
  const RuleBounds& rb = domain.bounds();
  const symbolic::CPattern& p = m.pattern;
  auto type_of_slot = [&](int slot) -> TypeIx {
    for (std::size_t k = 0; k < p.slots.size(); ++k)
      if (p.slots[k] == slot) return p.types[k];
    return 0;
  };
  std::vector<int> lack_add, lack_remove, lack_create;
  auto bump = [](std::vector<int>& v, std::size_t i) {
    if (v.size() <= i) v.resize(i + 1, 0);
    ++v[i];
  };
  for (const CEdge& e : p.edges) {
    const NodeIx a = m.prebound[e.from], c = m.prebound[e.to];
    const bool a_const = a != kNoNode, c_const = c != kNoNode;
    if (e.negated) {
      if (a_const && c_const && s.alive(a) && s.alive(c) && s.has_edge(a, c, e.label)) bump(lack_remove, e.label);
      continue;
    }
    bool possible = false;
    const TypeIx ta = type_of_slot(e.from), tc = type_of_slot(e.to);
    // A node fits a variable's type if it has it, or if some rule could retype a node into it.
    auto fits = [&](NodeIx n, TypeIx t, NodeIx fixed) {
      if (fixed != kNoNode) return n == fixed;
      return s.alive(n) && (voc.is_a(s.type(n), t) || (t < rb.retype_into.size() && rb.retype_into[t]));
    };
    if (a_const && c_const) {
      possible = s.alive(a) && s.alive(c) && s.has_edge(a, c, e.label);
    } else if (a_const) {
      if (s.alive(a)) {
        auto [lo, hi] = s.out(a, e.label);
        for (auto* q = lo; q != hi && !possible; ++q) possible = fits(q->to, tc, kNoNode) && (e.from != e.to || q->to == a);
      }
    } else if (c_const) {
      if (s.alive(c)) {
        auto [lo, hi] = s.in(c, e.label);
        for (auto* q = lo; q != hi && !possible; ++q) possible = fits(q->to, ta, kNoNode) && (e.from != e.to || q->to == c);
      }
    } else {
      for (const symbolic::Edge& x : s.edges()) {
        if (x.label != e.label) continue;
        if (fits(x.from, ta, kNoNode) && fits(x.to, tc, kNoNode) && (e.from != e.to || x.from == x.to)) {
          possible = true;
          break;
        }
      }
    }
    if (!possible) bump(lack_add, e.label);
  }
  // Nodes: constants that are gone, and more variables of a type than nodes that could be them.
  std::vector<std::pair<TypeIx, int>> vars_of_type;
  for (std::size_t k = 0; k < p.slots.size(); ++k) {
    const NodeIx n = m.prebound[p.slots[k]];
    if (n != kNoNode) {
      if (!s.alive(n) || !voc.is_a(s.type(n), p.types[k])) bump(lack_create, p.types[k]);
      continue;
    }
    auto it = std::find_if(vars_of_type.begin(), vars_of_type.end(), [&](auto& v) { return v.first == p.types[k]; });
    if (it == vars_of_type.end())
      vars_of_type.emplace_back(p.types[k], 1);
    else
      ++it->second;
  }
  for (auto [t, count] : vars_of_type) {
    int have = 0;
    for (NodeIx n = 0; n < s.size() && have < count; ++n) have += s.alive(n) && voc.is_a(s.type(n), t);
    for (int i = have; i < count; ++i) bump(lack_create, t);
  }
  double h = 0;
  auto bound = [&](const std::vector<int>& lack, const std::vector<int>& max, const std::vector<double>& min,
                   double alt_cost) {
    for (std::size_t i = 0; i < lack.size(); ++i) {
      if (lack[i] == 0) continue;
      // Only rules that do it: ceil(lack / most per application) of them, at the cheapest
      // cost; with one application of an alternative (deleting nodes removes any number of
      // links) at least that one.
      const int most = i < max.size() ? max[i] : 0;
      const double cheapest = i < min.size() ? min[i] : kUnreachable;
      const double by_rules = most > 0 && !std::isinf(cheapest) ? ((lack[i] + most - 1) / most) * cheapest : kUnreachable;
      const double lower = std::min(by_rules, alt_cost);
      if (std::isinf(lower)) return false;
      h = std::max(h, lower);
    }
    return true;
  };
  if (!bound(lack_add, rb.max_add, rb.min_add, kUnreachable)) return kUnreachable;
  if (!bound(lack_remove, rb.max_remove, rb.min_remove, rb.min_delete)) return kUnreachable;
  if (!bound(lack_create, rb.max_create, rb.min_create, kUnreachable)) return kUnreachable;
  return h;
}

namespace {

struct SearchNode {
  State state;
  int parent = -1;
  Step step;
  double g = 0, plain = 0;
  bool dead = false;  // a cheaper path to the same state was found after it was queued
};

struct Entry {
  double f, g;
  std::uint64_t seq;
  int idx;
  bool operator<(const Entry& o) const {  // priority_queue pops the largest: invert
    if (f != o.f) return f > o.f;
    if (g != o.g) return g < o.g;
    return seq > o.seq;
  }
};

struct Search {
  const Domain& d;
  const PlannerOptions& opt;
  std::size_t expansions = 0, generated = 0;

  PlanResult run(const State& start, const CompiledMission& goal, const std::vector<bool>& excluded,
                 std::int64_t deadline) {
    PlanResult r;
    r.searches = 1;
    const std::size_t max_nodes = start.alive_count() + static_cast<std::size_t>(std::max(0, opt.max_world_increment));
    auto h_of = [&](const State& s) { return opt.heuristic ? heuristic(d, s, goal) : 0.0; };
    if (!goal.unresolved.empty()) {
      r.outcome = PlanResult::Outcome::kUnsolvable;
      r.why = "the mission names node " + goal.unresolved.front() + ", which the world does not have";
      return r;
    }
    const double h0 = h_of(start);
    if (std::isinf(h0)) {
      r.outcome = PlanResult::Outcome::kUnsolvable;
      r.why = "no rule can make what the mission lacks (the heuristic is infinite at the start)";
      return r;
    }
    std::deque<SearchNode> nodes;
    std::unordered_map<std::uint64_t, std::vector<int>> seen;
    std::priority_queue<Entry> open;
    std::uint64_t seq = 0;
    nodes.push_back(SearchNode{start, -1, Step{}, 0, 0, false});
    seen[start.hash()].push_back(0);
    open.push(Entry{h0, 0, seq++, 0});
    while (!open.empty()) {
      const Entry top = open.top();
      open.pop();
      if (nodes[top.idx].dead) continue;
      const SearchNode& cur = nodes[top.idx];
      if (mission_holds(cur.state, d.vocabulary(), goal)) {
        std::vector<int> path;
        for (int i = top.idx; i >= 0; i = nodes[i].parent) path.push_back(i);
        std::reverse(path.begin(), path.end());
        for (std::size_t k = 0; k < path.size(); ++k) {
          if (k > 0) r.steps.push_back(nodes[path[k]].step);
          r.states.push_back(nodes[path[k]].state);
        }
        r.cost = plan_cost(d, r.steps);
        r.outcome = PlanResult::Outcome::kFound;
        break;
      }
      if (opt.max_expansions > 0 && expansions >= opt.max_expansions) {
        r.outcome = PlanResult::Outcome::kLimit;
        r.why = "stopped after " + std::to_string(expansions) + " expansions (max_expansions)";
        break;
      }
      if (deadline > 0 && (expansions & 31) == 0 && opt.clock() > deadline) {
        r.outcome = PlanResult::Outcome::kLimit;
        r.why = "stopped at the time limit after " + std::to_string(expansions) + " expansions";
        break;
      }
      ++expansions;
      const int parent = top.idx;
      const double g = cur.g, plain = cur.plain;
      // Successors are collected first: the deque may grow while `cur` is referenced.
      std::vector<std::pair<Step, State>> succ;
      d.successors(nodes[parent].state, excluded, true, [&](const Step& st, State&& next) {
        if (next.alive_count() > max_nodes) return;
        succ.emplace_back(st, std::move(next));
      });
      for (auto& [st, next] : succ) {
        ++generated;
        const double c = d.cost(st.rule);
        const double np = plain + c;
        const double ng = g + c + (1.0 - d.success(st.rule)) * np;
        auto& bucket = seen[next.hash()];
        bool skip = false;
        for (int other : bucket) {
          if (!(nodes[other].state == next)) continue;
          if (nodes[other].g <= ng) {
            skip = true;
          } else {
            nodes[other].dead = true;
          }
          break;
        }
        if (skip) continue;
        const double h = h_of(next);
        if (std::isinf(h)) continue;
        const int idx = static_cast<int>(nodes.size());
        nodes.push_back(SearchNode{std::move(next), parent, st, ng, np, false});
        bucket.push_back(idx);
        open.push(Entry{ng + h, ng, seq++, idx});
      }
    }
    if (r.outcome != PlanResult::Outcome::kFound && r.why.empty()) {
      r.outcome = PlanResult::Outcome::kExhausted;
      r.why = "no plan within the growth bound (max_world_increment " + std::to_string(opt.max_world_increment) +
              "): " + std::to_string(nodes.size()) + " states searched";
    }
    r.expansions = expansions;
    r.generated = generated;
    return r;
  }
};

// Decomposes the first hierarchical step of `r` (then the rest, recursively).
PlanResult expand(const Domain& d, const PlannerOptions& opt, PlanResult r, const CompiledMission& goal,
                  const std::vector<bool>& excluded, int depth, std::int64_t deadline) {
  if (!r.found()) return r;
  std::size_t i = 0;
  while (i < r.steps.size() && !r.steps[i].hierarchical) ++i;
  if (i == r.steps.size()) return r;
  if (depth >= opt.max_decomposition_depth) {
    r.outcome = PlanResult::Outcome::kLimit;
    r.why = "hierarchical steps nest deeper than max_decomposition_depth";
    return r;
  }
  const Step h = r.steps[i];
  auto [pattern, binding] = d.hierarchical_goal(h);
  CompiledMission sub_goal;
  sub_goal.pattern = *pattern;
  sub_goal.prebound = binding;
  sub_goal.slots = static_cast<int>(binding.size());
  std::vector<bool> sub_excluded = excluded;
  sub_excluded.resize(d.rule_count(), false);
  sub_excluded[h.rule] = true;
  Search sub_search{d, opt};
  PlanResult sub = sub_search.run(r.states[i], sub_goal, sub_excluded, deadline);
  sub = expand(d, opt, std::move(sub), sub_goal, sub_excluded, depth + 1, deadline);
  PlanResult out;
  out.expansions = r.expansions + sub.expansions;
  out.generated = r.generated + sub.generated;
  out.searches = r.searches + sub.searches;
  if (!sub.found()) {
    out.outcome = sub.outcome == PlanResult::Outcome::kLimit ? PlanResult::Outcome::kLimit
                                                             : PlanResult::Outcome::kExhausted;
    out.why = "hierarchical step " + h.name + " could not be decomposed: " + sub.why;
    return out;
  }
  Search rest_search{d, opt};
  PlanResult rest = rest_search.run(sub.states.back(), goal, excluded, deadline);
  rest = expand(d, opt, std::move(rest), goal, excluded, depth + 1, deadline);
  out.expansions += rest.expansions;
  out.generated += rest.generated;
  out.searches += rest.searches;
  if (!rest.found()) {
    out.outcome = rest.outcome;
    out.why = "after decomposing " + h.name + ": " + rest.why;
    return out;
  }
  out.outcome = PlanResult::Outcome::kFound;
  out.steps.assign(r.steps.begin(), r.steps.begin() + static_cast<long>(i));
  out.states.assign(r.states.begin(), r.states.begin() + static_cast<long>(i) + 1);
  out.steps.insert(out.steps.end(), sub.steps.begin(), sub.steps.end());
  out.states.insert(out.states.end(), sub.states.begin() + 1, sub.states.end());
  out.steps.insert(out.steps.end(), rest.steps.begin(), rest.steps.end());
  out.states.insert(out.states.end(), rest.states.begin() + 1, rest.states.end());
  out.cost = plan_cost(d, out.steps);
  return out;
}

}  // namespace

PlanResult plan(const Domain& domain, const State& start, const CompiledMission& mission, const PlannerOptions& options) {
  std::int64_t deadline = 0;
  if (options.max_time_ns > 0 && options.clock) deadline = options.clock() + options.max_time_ns;
  Search search{domain, options};
  std::vector<bool> excluded(domain.rule_count(), false);
  PlanResult r = search.run(start, mission, excluded, deadline);
  r.search_cost = r.cost;
  if (!options.decompose) return r;
  const double searched = r.cost;
  PlanResult out = expand(domain, options, std::move(r), mission, excluded, 0, deadline);
  out.search_cost = searched;
  return out;
}

}  // namespace quiver::agents::inline rules::planner
