// The platform: the robot's true pose over time along a route of legs (the world the agents sense).
#include "quiver/agents/apps/agm/platform.h"

#include <algorithm>
#include <cmath>

namespace quiver::agents::inline apps::agm {

namespace {
std::int64_t ns(double s) { return static_cast<std::int64_t>(std::llround(s * 1e9)); }
}  // namespace

std::vector<Leg> default_route() {
  using K = Leg::Kind;
  return {
      {K::kStand, 0, 0, 0, 2.0},        // ready
      {K::kDrive, 8.0, 2.0, 0.5, 0},    // kitchen -> corridor (x = 4) -> living room (x = 6)
      {K::kStand, 0, 0, 0, 2.0},        // short of the table: the mug is out of reach
      {K::kDrive, 8.25, 2.0, 0.25, 0},  // the approach: the mug comes within reach
      {K::kStand, 0, 0, 0, 1.6},        // the grasp starts once movedInLastSeconds clears
      {K::kDrive, 8.15, 2.0, 0.25, 0},  // a nudge back mid-grasp: the grasp pauses; the mug
      {K::kStand, 0, 0, 0, 0.4},        // stays in reach (hysteresis)
      {K::kDrive, 8.25, 2.0, 0.25, 0},  // and forward again, well within reach
      {K::kWait, 0, 0, 0, 40.0},        // until the mug is carried
      {K::kStand, 0, 0, 0, 1.0},
      {K::kDrive, 2.0, 2.0, 0.5, 0},  // back: living room -> corridor -> kitchen, mug in hand
  };
}

Pose2 default_start() { return {1.0, 2.0, 0.0}; }

Platform::Platform(std::vector<Leg> route, Pose2 start) : route_(std::move(route)), start_(start) {}

void Platform::start(std::int64_t t0) {
  if (!t0_) t0_ = t0;
}

std::vector<Platform::Span> Platform::spans() const {
  std::vector<Span> out;
  if (!t0_) return out;
  std::int64_t t = *t0_;
  Pose2 at = start_;
  for (const Leg& leg : route_) {
    Span s;
    s.begin = t;
    s.from = at;
    s.kind = leg.kind;
    switch (leg.kind) {
      case Leg::Kind::kDrive: {
        const double d = std::hypot(leg.x - at.x, leg.y - at.y);
        s.to = {leg.x, leg.y, at.yaw};
        s.end = t + ns(d / std::max(leg.speed, 1e-6));
        break;
      }
      case Leg::Kind::kStand:
        s.to = at;
        s.end = t + ns(leg.seconds);
        break;
      case Leg::Kind::kWait:
        // Until the release, or the timeout: while unreleased, the timeout (later queries are
        // never earlier than a release, so what they see is the same).
        s.to = at;
        s.end = t + ns(leg.seconds);
        if (release_ && *release_ >= t) s.end = std::min(*release_, s.end);
        break;
    }
    out.push_back(s);
    t = s.end;
    at = s.to;
  }
  return out;
}

Pose2 Platform::pose(std::int64_t t) const {
  auto sp = spans();
  if (sp.empty() || t <= sp.front().begin) return start_;
  for (const Span& s : sp) {
    if (t >= s.end) continue;
    if (s.kind != Leg::Kind::kDrive || s.end == s.begin) return s.from;
    const double f = static_cast<double>(t - s.begin) / static_cast<double>(s.end - s.begin);
    return {s.from.x + f * (s.to.x - s.from.x), s.from.y + f * (s.to.y - s.from.y), s.from.yaw};
  }
  return sp.back().to;
}

bool Platform::moving(std::int64_t t) const { return moved_between(t - 1, t); }

bool Platform::moved_between(std::int64_t a, std::int64_t b) const {
  for (auto [begin, end] : drives())
    if (begin < b && end > a) return true;
  return false;
}

bool Platform::waiting(std::int64_t t) const {
  for (const Span& s : spans())
    if (s.kind == Leg::Kind::kWait && t >= s.begin && t < s.end) return true;
  return false;
}

void Platform::go_to(std::int64_t t, double x, double y, double speed) {
  if (!t0_) t0_ = t;
  const std::int64_t end = end_time().value_or(t);
  if (t > end) route_.push_back({Leg::Kind::kStand, 0, 0, 0, static_cast<double>(t - end) / 1e9});
  route_.push_back({Leg::Kind::kDrive, x, y, speed, 0});
}

bool Platform::release(std::int64_t t) {
  if (release_ || !waiting(t)) return false;
  release_ = t;
  return true;
}

std::vector<std::pair<std::int64_t, std::int64_t>> Platform::drives() const {
  std::vector<std::pair<std::int64_t, std::int64_t>> out;
  for (const Span& s : spans())
    if (s.kind == Leg::Kind::kDrive && s.end > s.begin) out.emplace_back(s.begin, s.end);
  return out;
}

std::optional<std::int64_t> Platform::end_time() const {
  if (!t0_) return std::nullopt;
  auto sp = spans();
  if (sp.empty()) return *t0_;
  return sp.back().end;
}

bool Platform::finished(std::int64_t t) const {
  auto end = end_time();
  return end && t >= *end;
}

}  // namespace quiver::agents::inline apps::agm
