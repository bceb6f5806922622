// What must hold in an AGM run, for the simulator and the processes over DDS alike.
#include "quiver/agents/apps/agm/agm_checks.h"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "quiver/agents/apps/agm/agm_schema.h"
#include "quiver/agents/apps/agm/clean_table.h"

namespace quiver::agents::inline apps::agm {
namespace {

using graph::NodeId;
constexpr std::int64_t kMs = 1'000'000;

// The scenario's geometry, as the world file states it (the checks compute independently of the
// agents' FCL scene): the gripper, a sphere at X_RG from the robot; the mug, an upright cylinder.
constexpr double kGripperX = 0.35, kGripperRadius = 0.04;
constexpr double kMugX = 8.70, kMugY = 2.0, kMugRadius = 0.04;

// Closed-form distance between the gripper and the mug (same height, so horizontal).
double gripper_mug_distance(const Pose2& p) {
  const double gx = p.x + kGripperX * std::cos(p.yaw), gy = p.y + kGripperX * std::sin(p.yaw);
  return std::max(0.0, std::hypot(gx - kMugX, gy - kMugY) - kMugRadius - kGripperRadius);
}

std::string room_name(const graph::Graph& g, std::optional<NodeId> room) {
  return room ? g.name_of(*room) : std::string();
}

}  // namespace

std::string seconds_text(std::int64_t t_ns) {
  std::ostringstream o;
  o.precision(3);
  o << std::fixed << static_cast<double>(t_ns) / 1e9 << " s";
  return o.str();
}

std::vector<std::string> end_state_failures(const graph::Graph& g, std::string_view mission) {
  std::vector<std::string> f;
  const NodeId robot = node_id(g, node::kRobot), mug = node_id(g, "mug");
  if (mission == kCleanTable) {
    const CleanTableReport rep = check_clean_table(g);
    if (!rep.mission_holds) {
      std::string why;
      for (const auto& m : rep.missing) why += (why.empty() ? "" : "; ") + m;
      f.push_back("the mission does not hold on the final replica: " + why);
    }
    if (rep.plan_status != "achieved") f.push_back("the plan node says '" + rep.plan_status + "'");
  } else {
    const std::string final_room = room_name(g, room_of(g, robot));
    if (final_room != "kitchen")
      f.push_back("the robot ends in '" + final_room + "', not in the kitchen");
    if (!g.has_edge(robot, mug, edge::kCarrying)) f.push_back("the robot does not carry the mug");
    if (const std::string mr = room_name(g, room_of(g, mug)); mr != "kitchen")
      f.push_back("the mug is in '" + mr + "', not in the kitchen with the robot");
  }
  if (g.has_edge(robot, robot, edge::kMoved))
    f.push_back("movedInLastSeconds still set on a parked robot");
  if (!g.edges_from(robot, edge::kGrasping).empty())
    f.push_back("a grasp still announced at the end");
  if (mission != kCleanTable &&
      (!g.has_edge(robot, mug, edge::kReach) || g.has_edge(robot, mug, edge::kNoReach)))
    f.push_back("the mug in the gripper is not (only) in reach");
  return f;
}

std::vector<Crossing> crossings(const Platform& truth, const graph::Graph& g, std::int64_t end_ns) {
  std::vector<Crossing> out;
  if (!truth.started()) return out;
  std::string prev;
  for (std::int64_t t = truth.t0(); t <= end_ns; t += kMs) {
    const Pose2 p = truth.pose(t);
    auto in = room_at(g, p.x, p.y);
    std::string name = in ? g.name_of(*in) : prev;
    if (!prev.empty() && name != prev) out.emplace_back(prev, name);
    prev = name;
  }
  return out;
}

std::vector<std::string> room_change_failures(const graph::Graph& g, const Platform& truth,
                                              const std::vector<RoomChange>& changes, bool exact,
                                              double lag_ms, std::int64_t frame_ns) {
  std::vector<std::string> f;
  for (const RoomChange& c : changes) {
    const std::string what = "changeRoom " + c.from + " -> " + c.to;
    const Pose2 at = truth.pose(c.stamp_ns);
    auto to = g.find_node(c.to);
    auto limits =
        to ? room_limits(g, *to) : Result<Polygon>(make_error(ErrorCode::kNotFound, c.to));
    if (!limits.ok() || !limits->contains(c.x, c.y))
      f.push_back(what + " at " + seconds_text(c.committed_ns) + " on a pose outside " + c.to);
    if (std::hypot(at.x - c.x, at.y - c.y) > 0.01)
      f.push_back(what + " on a pose the platform never had");
    if (!exact) continue;
    const Pose2 before = truth.pose(c.stamp_ns - 2 * frame_ns);
    auto was = room_at(g, before.x, before.y);
    if (!was || g.name_of(*was) != c.from)
      f.push_back(what + " late: two frames before its pose the robot was already out of " +
                  c.from);
    if (static_cast<double>(c.committed_ns - c.stamp_ns) > lag_ms * 1e6)
      f.push_back(what + " committed " + std::to_string((c.committed_ns - c.stamp_ns) / kMs) +
                  " ms after its pose");
  }
  return f;
}

std::vector<std::string> crossing_count_failures(const std::vector<RoomChange>& changes,
                                                 const std::vector<Crossing>& expected,
                                                 bool exact) {
  std::vector<std::string> f;
  if (exact) {
    std::vector<Crossing> got;
    for (const auto& c : changes) got.emplace_back(c.from, c.to);
    if (got != expected)
      f.push_back("changeRoom issued " + std::to_string(got.size()) +
                  " times, the platform crossed " + std::to_string(expected.size()) +
                  " room limits (or in another order)");
  } else if (changes.size() < expected.size()) {
    f.push_back("fewer changeRoom (" + std::to_string(changes.size()) + ") than crossings (" +
                std::to_string(expected.size()) + ")");
  }
  return f;
}

std::vector<std::string> reach_failures(const std::vector<GraspEvent>& events,
                                        const Platform& truth, double reach_on_m, bool once) {
  std::vector<std::string> f;
  int reach = 0, changes = 0;
  for (const GraspEvent& e : events) {
    if (e.kind == GraspEvent::Kind::kReach) {
      ++reach;
      ++changes;
      const double d = gripper_mug_distance(truth.pose(e.stamp_ns));
      if (e.distance >= reach_on_m || d >= reach_on_m + 0.01)
        f.push_back("reach set at " + seconds_text(e.t_ns) + " with FCL distance " +
                    std::to_string(e.distance) + " m (true " + std::to_string(d) +
                    " m), threshold " + std::to_string(reach_on_m) + " m");
    } else if (e.kind == GraspEvent::Kind::kNoReach) {
      ++changes;
      f.push_back("noReach set again at " + seconds_text(e.t_ns) + " (distance " +
                  std::to_string(e.distance) + " m): reach flickered");
    }
  }
  if (changes == 0)
    f.push_back("reach never set");
  else if (once && reach != 1)
    f.push_back("reach set " + std::to_string(reach) + " times (expected once)");
  return f;
}

std::vector<std::string> grasp_motion_failures(const std::vector<GraspEvent>& events,
                                               const Platform& truth, std::int64_t allowance_ns,
                                               std::int64_t moved_window_ns) {
  std::vector<std::string> f;
  std::map<std::string, std::int64_t> run_started;
  for (const GraspEvent& e : events) {
    if (e.kind == GraspEvent::Kind::kStarted) {
      run_started[e.object] = e.t_ns;
    } else if (e.kind == GraspEvent::Kind::kGrasped) {
      const std::int64_t began = run_started.count(e.object) ? run_started[e.object] : e.t_ns;
      for (auto [b, en] : truth.drives())
        if (en > began && b < e.t_ns - allowance_ns)
          f.push_back("grasped " + e.object + " at " + seconds_text(e.t_ns) +
                      " though the platform drove from " + seconds_text(b) + " to " +
                      seconds_text(en) + " during the grasp (from " + seconds_text(began) + ")");
    } else if (e.kind == GraspEvent::Kind::kReleased) {
      if (truth.moved_between(e.t_ns - moved_window_ns + allowance_ns, e.t_ns))
        f.push_back("released " + e.object + " at " + seconds_text(e.t_ns) +
                    " while the platform moved");
    }
  }
  return f;
}

std::vector<std::string> carry_failures(const std::vector<GraspEvent>& events, bool once_each) {
  std::vector<std::string> f;
  std::map<std::string, int> grasped, released;
  int carrying = 0;
  for (const GraspEvent& e : events) {
    if (e.kind == GraspEvent::Kind::kGrasped) {
      ++grasped[e.object];
      if (++carrying > 1)
        f.push_back("two objects carried at once (" + e.object + " grasped at " +
                    seconds_text(e.t_ns) + ")");
    } else if (e.kind == GraspEvent::Kind::kReleased) {
      ++released[e.object];
      carrying = std::max(0, carrying - 1);
    }
  }
  for (const char* mug : {"mug", "mug2"}) {
    if (grasped[mug] == 0) f.push_back(std::string(mug) + " was never grasped");
    if (released[mug] == 0) f.push_back(std::string(mug) + " was never released");
    if (once_each && (grasped[mug] != 1 || released[mug] != 1))
      f.push_back(std::string(mug) + " grasped " + std::to_string(grasped[mug]) + " and released " +
                  std::to_string(released[mug]) + " times (once each expected)");
  }
  return f;
}

std::vector<std::string> first_plan_failures(const std::map<std::int64_t, std::string>& plans,
                                             std::string& verified) {
  if (plans.empty()) return {"no plan was seen"};
  std::vector<std::string> f;
  const Status v = verify_clean_table_plan(plans.begin()->second);
  verified = v.ok() ? "ok" : v.error().to_string();
  if (!v.ok()) f.push_back("the first plan does not replay through the grammar guard: " + verified);
  if (plans.begin()->first != 1)
    f.push_back("the first plan seen is version " + std::to_string(plans.begin()->first));
  return f;
}

}  // namespace quiver::agents::inline apps::agm
