// The Person agent: the person sensor read at its rate, the 15 body joints posed under `body`, and presence
// written as `person -[in_front_of]-> robot` under the person scope it holds.
#include "quiver/agents/apps/barthel/person.h"

#include <cmath>
#include <nlohmann/json.hpp>

#include "quiver/agents/apps/barthel/grammars.h"
#include "quiver/agents/apps/barthel/barthel_schema.h"
#include "quiver/agents/rules/locks/locks.h"

namespace quiver::agents::inline apps::barthel {

using graph::NodeId;
using graph::Symbol;

namespace {

// Where each joint sits in the body frame (metres), seated, facing the robot.
constexpr double kJointRest[15][3] = {
    {0, 0, 0.80},     {0, 0, 0.65},     {0, 0, 0.40},     {0.18, 0, 0.60}, {0.25, 0.05, 0.35},
    {0.22, 0.25, 0.30}, {-0.18, 0, 0.60}, {-0.25, 0.05, 0.35}, {-0.22, 0.25, 0.30}, {0.10, 0, 0.10},
    {0.12, 0.40, 0.10}, {0.12, 0.45, -0.35}, {-0.10, 0, 0.10}, {-0.12, 0.40, 0.10}, {-0.12, 0.45, -0.35}};

}  // namespace

Person::Person(std::unique_ptr<PersonSensor> sensor, PersonOptions o, std::string name)
    : Agent(std::move(name)), sensor_(std::move(sensor)), opt_(o) {
  set_grammar_text(std::string(role_grammar("person")), "person.aggl");
}

Person::~Person() = default;

void Person::setup(AgentContext& ctx) {
  const auto period = static_cast<std::int64_t>(1e9 / opt_.rate_hz);
  ctx.every(period, [this, &ctx] { read(ctx); });
}

void Person::read(AgentContext& ctx) {
  graph::Graph& g = ctx.graph();
  NodeId person = node_id(g, node::kPerson), robot = node_id(g, node::kRobot), body = node_id(g, node::kBody);
  if (person.is_null() || robot.is_null()) return;
  // The person scope is ours, above everyone (claimed again if a restart or partition lost it).
  LockManager& locks = ctx.locks();
  if (!locks.holds(person) && !locks.pending(person)) (void)locks.acquire(person, opt_.lock_priority);
  auto present = sensor_->present(g);
  if (!present) return;
  const std::int64_t now = ctx.now();
  const bool was = person_present(g);
  graph::Transaction tx = g.begin();
  Status s = tx.set(person, "seen_ns", graph::Value(now));
  if (s.ok()) s = tx.set(person, "present", graph::Value(*present));
  if (s.ok() && *present != was) {
    if (*present) {
      s = tx.insert_edge(person, robot, edge::kInFrontOf);
    } else {
      s = tx.delete_edge(person, robot, Symbol(edge::kInFrontOf));
      if (s.ok()) s = tx.set(person, "lost_ns", graph::Value(now));
    }
  }
  if (s.ok() && opt_.joints && *present && !body.is_null()) {
    const double t = static_cast<double>(now) * 1e-9;
    const auto& names = joint_names();
    for (std::size_t j = 0; j < names.size() && s.ok(); ++j) {
      NodeId joint = node_id(g, names[j]);
      if (joint.is_null()) continue;
      graph::Pose X;
      // Breathing and a little sway: small, smooth motions of every joint.
      const double phase = t * 1.3 + 0.4 * static_cast<double>(j);
      X.translation = {kJointRest[j][0] + 0.01 * std::sin(phase), kJointRest[j][1] + 0.008 * std::cos(phase),
                       kJointRest[j][2] + 0.005 * std::sin(2 * phase)};
      s = tx.set_rt(body, joint, X, now);
    }
  }
  if (!s.ok()) {
    ++refused_;
    return;
  }
  if (auto c = tx.commit(); !c.ok()) {
    ++refused_;
    return;
  }
  ++readings_;
  if (*present != was) {
    ++(*present ? arrived_ : lost_);
    ctx.log(*present ? "the person sits in front of the robot" : "the person was lost");
  }
}

void Person::status(nlohmann::json& out) const {
  out["readings"] = readings_;
  out["refused"] = refused_;
  out["lost"] = lost_;
  out["arrived"] = arrived_;
}

}  // namespace quiver::agents::inline apps::barthel
