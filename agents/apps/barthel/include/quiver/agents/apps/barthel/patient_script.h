#pragma once
/// @file
/// What the simulated patient will do: per Barthel item, how it replies to the first question and
/// to the repeated options (by voice, by touch, silence, or something the robot cannot
/// understand), and when it leaves its chair mid-sentence and for how long. A script is data
/// (JSON) or drawn from a seed; expected() is the outcome it implies, which the stored result
/// must equal.
#include <cstdint>
#include <nlohmann/json_fwd.hpp>
#include <optional>
#include <string>
#include <vector>

#include "quiver/base/result.h"

namespace quiver::agents::inline apps::barthel {

enum class ReplyKind : std::uint8_t { kVoice, kTouch, kSilent, kMisunderstand };
const char* to_string(ReplyKind k);

struct Reply {
  ReplyKind kind = ReplyKind::kSilent;
  int option = 0;  ///< kVoice/kTouch: index into the item's options
  bool valid() const { return kind == ReplyKind::kVoice || kind == ReplyKind::kTouch; }
};

struct ItemPlan {
  Reply first;   ///< to the question
  Reply second;  ///< to the options repeated (only asked when `first` is not valid)
};

/// Leaves the chair `after_ns` into the first question of `item`, for `for_ns`.
struct Leave {
  int item = 0;
  std::int64_t after_ns = 500'000'000;
  std::int64_t for_ns = 3'000'000'000;
};

struct PatientScript {
  std::string patient = "patient-1";
  std::vector<ItemPlan> items;  ///< one per Barthel item, in order
  std::vector<Leave> leaves;
  std::int64_t think_min_ns = 300'000'000;
  std::int64_t think_max_ns = 1'500'000'000;

  /// Cooperative: answers every item by voice on the first question, the option `seed` picks.
  static PatientScript random(std::uint64_t seed);
  /// Any behaviour, drawn from `seed`: silences, misunderstandings, touches on the repeated
  /// options, and up to two absences mid-question.
  static PatientScript varied(std::uint64_t seed);
  /// Reads {"patient", "items": [{"first": "voice:2"|"touch:1"|"silent"|"misunderstand",
  /// "second": ...}, x10], "leaves": [{"item", "after_ms", "for_ms"}], "think_ms": [min, max]}.
  /// @returns kInvalidArgument naming the JSON pointer of a bad value.
  static Result<PatientScript> from_json(const nlohmann::json& j);
  /// Reads the script from the file at `path` (as from_json()).
  /// @returns kIo when it cannot be opened, kInvalidArgument (naming the file) when it is not
  /// JSON or not a script.
  static Result<PatientScript> load(const std::string& path);
  nlohmann::json to_json() const;

  /// The outcome the script implies.
  struct Outcome {
    std::string status;              ///< "completed" | "clinician_called"
    std::vector<std::optional<int>> scores;  ///< per item asked; nullopt: unanswered
    int total = 0;
  };
  Outcome expected() const;
};

}  // namespace quiver::agents::inline apps::barthel
