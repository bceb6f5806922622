// The human tracker: people's joints as kinematic frames, published at the tracker's rate.
#include "quiver/agents/apps/agm/humans.h"

#include <cmath>
#include <nlohmann/json.hpp>
#include <string>

#include "quiver/agents/apps/agm/agm_schema.h"

namespace quiver::agents::inline apps::agm {

using graph::NodeId;

namespace {

// A standing body in the person's frame (metres): x to the person's left, z up.
constexpr double kRest[15][3] = {{0.0, 0.0, 1.65},   {0.0, 0.0, 1.50},    {0.0, 0.0, 1.20},
                                 {0.20, 0.0, 1.45},  {0.28, 0.0, 1.18},   {0.30, 0.05, 0.92},
                                 {-0.20, 0.0, 1.45}, {-0.28, 0.0, 1.18},  {-0.30, 0.05, 0.92},
                                 {0.10, 0.0, 0.95},  {0.11, 0.02, 0.52},  {0.11, 0.0, 0.08},
                                 {-0.10, 0.0, 0.95}, {-0.11, 0.02, 0.52}, {-0.11, 0.0, 0.08}};

}  // namespace

const std::vector<std::string>& joint_names() {
  static const std::vector<std::string> kNames = {
      "head",   "neck",  "torso",  "l_shoulder", "l_elbow", "l_hand", "r_shoulder", "r_elbow",
      "r_hand", "l_hip", "l_knee", "l_foot",     "r_hip",   "r_knee", "r_foot"};
  return kNames;
}

Humans::Humans(HumansOptions o, std::string name) : Agent(std::move(name)), opt_(o) {
  set_grammar_text(std::string(role_grammar("humans")), "humans.aggl");
}

void Humans::setup(AgentContext& ctx) {
  ctx.every(static_cast<std::int64_t>(1e9 / opt_.rate_hz), [this, &ctx] { frame(ctx); });
}

void Humans::frame(AgentContext& ctx) {
  if (stopped_) return;
  graph::Graph& g = ctx.graph();
  const auto& names = joint_names();
  for (int p = 0; p < opt_.people; ++p) {
    const std::string person_name = "person" + std::to_string(p);
    const NodeId person = node_id(g, person_name);
    if (person.is_null()) continue;
    const std::int64_t now = ctx.now();
    const double t = static_cast<double>(now) * 1e-9;
    graph::Transaction tx = g.begin();
    Status s;
    for (std::size_t j = 0; j < names.size() && s.ok(); ++j) {
      const NodeId joint = node_id(g, person_name + "_" + names[j]);
      if (joint.is_null()) continue;
      const double phase = 1.1 * t + 0.7 * p + 0.3 * static_cast<double>(j);
      const double arm = (j >= 3 && j <= 8) ? 0.04 : 0.01;  // arms swing more than the rest
      graph::Pose X_PJ;
      X_PJ.translation = {kRest[j][0] + 0.01 * std::sin(phase),
                          kRest[j][1] + arm * std::sin(0.8 * phase),
                          kRest[j][2] + 0.005 * std::sin(2 * phase)};
      s = tx.set_rt(person, joint, X_PJ, now);
    }
    if (!s.ok() || !tx.commit().ok()) {
      ++refused_;
      continue;
    }
    updates_ += names.size();
    if (first_ns_ < 0) first_ns_ = now;
    last_ns_ = now;
  }
  ++frames_;
}

void Humans::status(nlohmann::json& out) const {
  out["frames"] = frames_;
  out["rt_updates"] = updates_;
  out["refused"] = refused_;
  out["first_ns"] = first_ns_;
  out["last_ns"] = last_ns_;
}

}  // namespace quiver::agents::inline apps::agm
