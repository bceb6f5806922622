// The JSON encoding of a test result that every result store shares, and its decoder naming the JSON pointer of
// any bad field.
#include "quiver/agents/devices/test_result_json.h"

#include <limits>
#include <utility>

#include <nlohmann/json.hpp>

#include "test_result_json_internal.h"
#include "utf8.h"

namespace quiver::agents::devices {
namespace {

using nlohmann::json;

// Checks that `value` (the field at JSON pointer `pointer`) is valid UTF-8.
Status check_utf8(const std::string& value, const std::string& pointer, const char* fn) {
  if (auto bad = internal::first_invalid_utf8(value)) {
    return make_error(ErrorCode::kInvalidArgument, std::string(fn) + ": " + pointer +
                                                       " is not valid UTF-8 (byte " +
                                                       std::to_string(*bad) + ")");
  }
  return Status::Ok();
}

// Reads fields of one JSON document, naming the source and the JSON pointer in every error.
class Reader {
 public:
  Reader(const char* fn, const std::string& source) : fn_(fn), source_(source) {}

  Error error(const json::json_pointer& at, const std::string& what) const {
    const std::string where = at.empty() ? std::string("the root") : at.to_string();
    return make_error(ErrorCode::kMalformed,
                      std::string(fn_) + ": '" + source_ + "' at " + where + ": " + what);
  }

  // The member `key` of object `obj` (at `at`), or an error if it is missing.
  Result<const json*> member(const json& obj, const json::json_pointer& at,
                             const std::string& key) const {
    auto it = obj.find(key);
    if (it == obj.end()) return error(at / key, "missing");
    return &*it;
  }

  Result<std::string> string(const json& obj, const json::json_pointer& at,
                             const std::string& key) const {
    Result<const json*> m = member(obj, at, key);
    if (!m) return m.error();
    if (!(*m)->is_string()) return error(at / key, "expected a string, got " + type(**m));
    return (*m)->get<std::string>();
  }

  Result<std::int64_t> integer(const json& v, const json::json_pointer& at, std::int64_t lo,
                               std::int64_t hi) const {
    if (!v.is_number_integer()) return error(at, "expected an integer, got " + type(v));
    if (v.is_number_unsigned() &&
        v.get<std::uint64_t>() > static_cast<std::uint64_t>(std::numeric_limits<std::int64_t>::max())) {
      return error(at, std::to_string(v.get<std::uint64_t>()) + " is out of range");
    }
    const std::int64_t x = v.get<std::int64_t>();
    if (x < lo || x > hi) return error(at, std::to_string(x) + " is out of range");
    return x;
  }

  static std::string type(const json& v) {
    if (v.is_number_float()) return "a non-integer number";
    return std::string(v.type_name());
  }

 private:
  const char* fn_;
  const std::string& source_;
};

}  // namespace

namespace internal {

Result<TestResult> decode_test_result(std::string_view text, const std::string& source,
                                      const char* fn) {
  Reader rd(fn, source);
  json doc;
  try {
    doc = json::parse(text.begin(), text.end());
  } catch (const json::parse_error& e) {
    return make_error(ErrorCode::kMalformed, std::string(fn) + ": '" + source +
                                                 "' is not JSON (at byte " +
                                                 std::to_string(e.byte) + "): " + e.what());
  } catch (const json::exception& e) {  // a number beyond a double (out_of_range)
    return make_error(ErrorCode::kMalformed, std::string(fn) + ": '" + source + "' is not JSON: " + e.what());
  }
  const json::json_pointer root;
  if (!doc.is_object()) return rd.error(root, "expected an object, got " + Reader::type(doc));

  constexpr std::int64_t kIntMin = std::numeric_limits<int>::min();
  constexpr std::int64_t kIntMax = std::numeric_limits<int>::max();
  TestResult r;
  {
    auto v = rd.string(doc, root, "patient");
    if (!v) return v.error();
    r.patient = std::move(*v);
  }
  {
    auto v = rd.string(doc, root, "status");
    if (!v) return v.error();
    r.status = std::move(*v);
  }
  {
    auto m = rd.member(doc, root, "total");
    if (!m) return m.error();
    auto v = rd.integer(**m, root / "total", kIntMin, kIntMax);
    if (!v) return v.error();
    r.total = static_cast<int>(*v);
  }
  {
    auto m = rd.member(doc, root, "finished_ns");
    if (!m) return m.error();
    auto v = rd.integer(**m, root / "finished_ns", std::numeric_limits<std::int64_t>::min(),
                        std::numeric_limits<std::int64_t>::max());
    if (!v) return v.error();
    r.finished_ns = *v;
  }
  if (auto it = doc.find("validated_by_clinician"); it != doc.end() && !it->is_boolean()) {
    return rd.error(root / "validated_by_clinician",
                    "expected a boolean, got " + Reader::type(*it));
  }
  auto items = rd.member(doc, root, "items");
  if (!items) return items.error();
  if (!(*items)->is_array()) {
    return rd.error(root / "items", "expected an array, got " + Reader::type(**items));
  }
  for (std::size_t i = 0; i < (*items)->size(); ++i) {
    const json& j = (**items)[i];
    const json::json_pointer at = root / "items" / i;
    if (!j.is_object()) return rd.error(at, "expected an object, got " + Reader::type(j));
    ItemResult item;
    auto id = rd.string(j, at, "item");
    if (!id) return id.error();
    item.item = std::move(*id);
    auto score = rd.member(j, at, "score");
    if (!score) return score.error();
    if (!(*score)->is_null()) {
      if (!(*score)->is_number_integer()) {
        return rd.error(at / "score", "expected an integer or null, got " + Reader::type(**score));
      }
      auto v = rd.integer(**score, at / "score", kIntMin, kIntMax);
      if (!v) return v.error();
      item.score = static_cast<int>(*v);
    }
    auto answer = rd.string(j, at, "answer");
    if (!answer) return answer.error();
    item.answer = std::move(*answer);
    auto channel = rd.string(j, at, "channel");
    if (!channel) return channel.error();
    item.channel = std::move(*channel);
    r.items.push_back(std::move(item));
  }
  return r;
}

}  // namespace internal

Result<std::string> encode_test_result(const TestResult& r, const char* fn) {
  if (Status s = check_utf8(r.patient, "/patient", fn); !s) return s.error();
  if (Status s = check_utf8(r.status, "/status", fn); !s) return s.error();
  nlohmann::ordered_json items = nlohmann::ordered_json::array();
  for (std::size_t i = 0; i < r.items.size(); ++i) {
    const ItemResult& it = r.items[i];
    const std::string at = "/items/" + std::to_string(i);
    if (Status s = check_utf8(it.item, at + "/item", fn); !s) return s.error();
    if (Status s = check_utf8(it.answer, at + "/answer", fn); !s) return s.error();
    if (Status s = check_utf8(it.channel, at + "/channel", fn); !s) return s.error();
    nlohmann::ordered_json j;
    j["item"] = it.item;
    j["score"] = it.score ? nlohmann::ordered_json(*it.score) : nlohmann::ordered_json(nullptr);
    j["answer"] = it.answer;
    j["channel"] = it.channel;
    items.push_back(std::move(j));
  }
  nlohmann::ordered_json doc;
  doc["patient"] = r.patient;
  doc["status"] = r.status;
  doc["items"] = std::move(items);
  doc["total"] = r.total;
  doc["finished_ns"] = r.finished_ns;
  doc["validated_by_clinician"] = false;
  return doc.dump(2) + "\n";
}

Result<TestResult> decode_test_result(std::string_view text, const std::string& source) {
  return internal::decode_test_result(text, source, "decode_test_result()");
}

}  // namespace quiver::agents::devices
