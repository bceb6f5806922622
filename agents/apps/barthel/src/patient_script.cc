// The simulated patient's script: replies and absences drawn from a seed or read from JSON, and the outcome
// they imply.
#include "quiver/agents/apps/barthel/patient_script.h"

#include <fstream>
#include <nlohmann/json.hpp>

#include "quiver/agents/apps/barthel/items.h"
#include "quiver/base/rng.h"

namespace quiver::agents::inline apps::barthel {

const char* to_string(ReplyKind k) {
  switch (k) {
    case ReplyKind::kVoice: return "voice";
    case ReplyKind::kTouch: return "touch";
    case ReplyKind::kSilent: return "silent";
    case ReplyKind::kMisunderstand: return "misunderstand";
  }
  return "?";
}

namespace {

std::string reply_text(const Reply& r) {
  std::string s = to_string(r.kind);
  if (r.valid()) s += ":" + std::to_string(r.option);
  return s;
}

Result<Reply> parse_reply(const nlohmann::json& j, const std::string& where, std::size_t n_options,
                          bool touch_ok) {
  if (!j.is_string()) return make_error(ErrorCode::kInvalidArgument, where + ": expected a string like \"voice:2\"");
  const std::string s = j.get<std::string>();
  Reply r;
  if (s == "silent") return r;
  if (s == "misunderstand") {
    r.kind = ReplyKind::kMisunderstand;
    return r;
  }
  auto colon = s.find(':');
  std::string kind = s.substr(0, colon);
  if ((kind != "voice" && kind != "touch") || colon == std::string::npos)
    return make_error(ErrorCode::kInvalidArgument, where + ": '" + s + "' is not voice:N, touch:N, silent or misunderstand");
  if (kind == "touch" && !touch_ok)
    return make_error(ErrorCode::kInvalidArgument, where + ": the first question shows no options to touch");
  r.kind = kind == "voice" ? ReplyKind::kVoice : ReplyKind::kTouch;
  try {
    std::size_t used = 0;
    r.option = std::stoi(s.substr(colon + 1), &used);
    if (used != s.size() - colon - 1) throw std::invalid_argument("trailing");
  } catch (const std::exception&) {
    return make_error(ErrorCode::kInvalidArgument, where + ": '" + s + "' has no option number");
  }
  if (r.option < 0 || static_cast<std::size_t>(r.option) >= n_options)
    return make_error(ErrorCode::kInvalidArgument, where + ": option " + std::to_string(r.option) +
                                                       " is not in [0, " + std::to_string(n_options) + ")");
  return r;
}

}  // namespace

PatientScript PatientScript::random(std::uint64_t seed) {
  Rng rng(seed);
  PatientScript s;
  for (const auto& item : barthel_items()) {
    ItemPlan p;
    p.first.kind = ReplyKind::kVoice;
    p.first.option = static_cast<int>(rng.below(item.options.size()));
    p.second = p.first;
    s.items.push_back(p);
  }
  return s;
}

PatientScript PatientScript::varied(std::uint64_t seed) {
  Rng rng(seed);
  PatientScript s;
  const auto& table = barthel_items();
  auto draw = [&](std::size_t n, bool touch_ok) {
    Reply r;
    const double x = rng.uniform();
    if (x < 0.7) r.kind = (touch_ok && rng.chance(0.5)) ? ReplyKind::kTouch : ReplyKind::kVoice;
    else if (x < 0.85) r.kind = ReplyKind::kSilent;
    else r.kind = ReplyKind::kMisunderstand;
    r.option = static_cast<int>(rng.below(n));
    if (!r.valid()) r.option = 0;
    return r;
  };
  for (const auto& item : table) {
    ItemPlan p;
    p.first = draw(item.options.size(), false);
    p.second = draw(item.options.size(), true);
    s.items.push_back(p);
  }
  const int leaves = static_cast<int>(rng.below(3));
  for (int i = 0; i < leaves; ++i) {
    Leave l;
    l.item = static_cast<int>(rng.below(table.size()));
    l.after_ns = 200'000'000 + static_cast<std::int64_t>(rng.below(1'300'000'000));
    l.for_ns = 1'000'000'000 + static_cast<std::int64_t>(rng.below(3'000'000'000));
    s.leaves.push_back(l);
  }
  return s;
}

Result<PatientScript> PatientScript::load(const std::string& path) {
  std::ifstream in(path);
  if (!in) return Error{ErrorCode::kIo, path + ": cannot open the patient script"};
  try {
    auto s = from_json(nlohmann::json::parse(in));
    if (!s.ok()) return Error{s.error().code, path + ":" + s.error().message};
    return s;
  } catch (const nlohmann::json::exception& e) {  // a syntax error, or a number beyond a double (out_of_range)
    return Error{ErrorCode::kInvalidArgument, path + ": not JSON: " + e.what()};
  }
}

Result<PatientScript> PatientScript::from_json(const nlohmann::json& j) {
  const auto& items = barthel_items();
  PatientScript s;
  if (!j.is_object()) return make_error(ErrorCode::kInvalidArgument, "/: the patient script must be an object");
  if (j.contains("patient")) {
    if (!j["patient"].is_string()) return make_error(ErrorCode::kInvalidArgument, "/patient: expected a string");
    s.patient = j["patient"].get<std::string>();
  }
  if (!j.contains("items") || !j["items"].is_array() || j["items"].size() != items.size())
    return make_error(ErrorCode::kInvalidArgument, "/items: expected an array of " + std::to_string(items.size()) + " item plans");
  for (std::size_t i = 0; i < items.size(); ++i) {
    const auto& ji = j["items"][i];
    const std::string where = "/items/" + std::to_string(i);
    if (!ji.is_object() || !ji.contains("first"))
      return make_error(ErrorCode::kInvalidArgument, where + ": expected {\"first\": ..., \"second\": ...}");
    ItemPlan p;
    auto first = parse_reply(ji["first"], where + "/first", items[i].options.size(), false);
    if (!first.ok()) return first.error();
    p.first = *first;
    if (ji.contains("second")) {
      auto second = parse_reply(ji["second"], where + "/second", items[i].options.size(), true);
      if (!second.ok()) return second.error();
      p.second = *second;
    }
    s.items.push_back(p);
  }
  if (j.contains("leaves")) {
    if (!j["leaves"].is_array()) return make_error(ErrorCode::kInvalidArgument, "/leaves: expected an array");
    for (std::size_t i = 0; i < j["leaves"].size(); ++i) {
      const auto& jl = j["leaves"][i];
      const std::string where = "/leaves/" + std::to_string(i);
      if (!jl.is_object() || !jl.contains("item") || !jl["item"].is_number_integer())
        return make_error(ErrorCode::kInvalidArgument, where + ": expected {\"item\": N, \"after_ms\": A, \"for_ms\": F}");
      Leave l;
      l.item = jl["item"].get<int>();
      if (l.item < 0 || static_cast<std::size_t>(l.item) >= items.size())
        return make_error(ErrorCode::kInvalidArgument, where + "/item: not in [0, 10)");
      for (auto [key, out] : {std::pair{"after_ms", &l.after_ns}, std::pair{"for_ms", &l.for_ns}}) {
        if (!jl.contains(key)) continue;
        if (!jl[key].is_number() || jl[key].get<double>() < 0 || jl[key].get<double>() > 3.6e6)
          return make_error(ErrorCode::kInvalidArgument, where + "/" + key + ": expected milliseconds in [0, 3600000]");
        *out = static_cast<std::int64_t>(jl[key].get<double>() * 1e6);
      }
      s.leaves.push_back(l);
    }
  }
  if (j.contains("think_ms")) {
    const auto& t = j["think_ms"];
    if (!t.is_array() || t.size() != 2 || !t[0].is_number() || !t[1].is_number() || t[0].get<double>() < 0 ||
        t[1].get<double>() < t[0].get<double>() || t[1].get<double>() > 60'000)
      return make_error(ErrorCode::kInvalidArgument, "/think_ms: expected [min, max] milliseconds, 0 <= min <= max <= 60000");
    s.think_min_ns = static_cast<std::int64_t>(t[0].get<double>() * 1e6);
    s.think_max_ns = static_cast<std::int64_t>(t[1].get<double>() * 1e6);
  }
  return s;
}

nlohmann::json PatientScript::to_json() const {
  nlohmann::json j;
  j["patient"] = patient;
  j["items"] = nlohmann::json::array();
  for (const ItemPlan& p : items) j["items"].push_back({{"first", reply_text(p.first)}, {"second", reply_text(p.second)}});
  j["leaves"] = nlohmann::json::array();
  for (const Leave& l : leaves) j["leaves"].push_back({{"item", l.item}, {"after_ms", l.after_ns / 1e6}, {"for_ms", l.for_ns / 1e6}});
  j["think_ms"] = {think_min_ns / 1e6, think_max_ns / 1e6};
  return j;
}

PatientScript::Outcome PatientScript::expected() const {
  const auto& table = barthel_items();
  Outcome o;
  o.status = "completed";
  int unanswered = 0;
  for (std::size_t i = 0; i < items.size() && i < table.size(); ++i) {
    const ItemPlan& p = items[i];
    const Reply* r = p.first.valid() ? &p.first : p.second.valid() ? &p.second : nullptr;
    if (r) {
      int score = table[i].options[static_cast<std::size_t>(r->option)].score;
      o.scores.push_back(score);
      o.total += score;
    } else {
      o.scores.push_back(std::nullopt);
      if (++unanswered == 2) {
        o.status = "clinician_called";
        break;
      }
    }
  }
  return o;
}

}  // namespace quiver::agents::inline apps::barthel
