#pragma once
/// @file
/// The ten items of the Barthel index of activities of daily living (Mahoney & Barthel, 1965,
/// in its usual 0-100 scoring), with their standard options and scores.

#include <string>
#include <string_view>
#include <vector>

#include "quiver/base/result.h"

namespace quiver::agents::inline apps::barthel {

/// One answer to an item and its score.
struct BarthelOption {
  std::string label;  ///< the standard wording, e.g. "independent"
  int score;
};

/// One item: what is asked and the answers it admits, by ascending score.
struct BarthelItem {
  std::string id;        ///< stable key: "feeding", "bathing", ..., "stairs"
  std::string name;      ///< e.g. "Toilet use"
  std::string question;  ///< a friendly spoken question
  std::vector<BarthelOption> options;
};

/// The ten items, in the standard order: feeding, bathing, grooming, dressing, bowels, bladder,
/// toilet_use, transfers, mobility, stairs.
const std::vector<BarthelItem>& barthel_items();

/// The item with id `id`, or nullptr.
const BarthelItem* find_barthel_item(std::string_view id);

/// The highest total: the sum of every item's highest score (100).
int max_total();

/// Checks the shape of a Barthel table: 10 items with distinct non-empty ids; each with at
/// least two options whose labels are non-empty and whose scores start at 0 and ascend in
/// steps of 5; the highest scores sum to 100.
/// @returns kInvalidArgument naming the item and the value that breaks a rule.
Status check_barthel_items(const std::vector<BarthelItem>& items);

}  // namespace quiver::agents::inline apps::barthel
