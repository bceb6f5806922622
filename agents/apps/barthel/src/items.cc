// The ten items of the Barthel index with their standard options and scores, and the check of a table's shape.
#include "quiver/agents/apps/barthel/items.h"

#include <set>

namespace quiver::agents::inline apps::barthel {

const std::vector<BarthelItem>& barthel_items() {
  static const std::vector<BarthelItem> kItems = {
      {"feeding",
       "Feeding",
       "Let's talk about meals. Can you eat on your own, or do you need some help, for example "
       "to cut your food or spread butter?",
       {{"unable", 0},
        {"needs help cutting, spreading butter, etc., or requires modified diet", 5},
        {"independent", 10}}},
      {"bathing",
       "Bathing",
       "Can you take a bath or a shower by yourself, without anyone's help?",
       {{"dependent", 0}, {"independent, or in shower", 5}}},
      {"grooming",
       "Grooming",
       "Can you wash your face, comb your hair, brush your teeth and shave on your own, if you "
       "have what you need at hand?",
       {{"needs help with personal care", 0},
        {"independent face, hair, teeth, shaving, implements provided", 5}}},
      {"dressing",
       "Dressing",
       "How do you manage getting dressed, with buttons, zips and shoelaces?",
       {{"dependent", 0},
        {"needs help but can do about half unaided", 5},
        {"independent, including buttons, zips, laces", 10}}},
      {"bowels",
       "Bowels",
       "This is a personal question, and it is fine to answer it: do you control your bowels, "
       "or do you have accidents now and then?",
       {{"incontinent, or needs to be given enemas", 0},
        {"occasional accident", 5},
        {"continent", 10}}},
      {"bladder",
       "Bladder",
       "And do you control your bladder, or do you have accidents now and then?",
       {{"incontinent, or catheterized and unable to manage alone", 0},
        {"occasional accident", 5},
        {"continent", 10}}},
      {"toilet_use",
       "Toilet use",
       "Can you use the toilet on your own: getting on and off, dressing and wiping?",
       {{"dependent", 0},
        {"needs some help, but can do something alone", 5},
        {"independent: on and off, dressing, wiping", 10}}},
      {"transfers",
       "Transfers (bed to chair and back)",
       "Can you get out of bed into a chair and back again by yourself?",
       {{"unable, no sitting balance", 0},
        {"major help, one or two people, physical, can sit", 5},
        {"minor help, verbal or physical", 10},
        {"independent", 15}}},
      {"mobility",
       "Mobility (on level surfaces)",
       "How do you get around on level ground, for example along a corridor of about fifty "
       "yards?",
       {{"immobile or under 50 yards", 0},
        {"wheelchair independent, including corners, over 50 yards", 5},
        {"walks with help of one person, verbal or physical, over 50 yards", 10},
        {"independent, may use any aid, for example a stick, over 50 yards", 15}}},
      {"stairs",
       "Stairs",
       "Last question: can you go up and down stairs?",
       {{"unable", 0}, {"needs help, verbal, physical, carrying aid", 5}, {"independent", 10}}},
  };
  return kItems;
}

const BarthelItem* find_barthel_item(std::string_view id) {
  for (const BarthelItem& item : barthel_items()) {
    if (item.id == id) return &item;
  }
  return nullptr;
}

int max_total() {
  int total = 0;
  for (const BarthelItem& item : barthel_items()) {
    if (!item.options.empty()) total += item.options.back().score;
  }
  return total;
}

Status check_barthel_items(const std::vector<BarthelItem>& items) {
  constexpr const char* kFn = "check_barthel_items()";
  auto bad = [&](const std::string& what) {
    return make_error(ErrorCode::kInvalidArgument, std::string(kFn) + ": " + what);
  };
  if (items.size() != 10) return bad(std::to_string(items.size()) + " items, not 10");
  std::set<std::string> ids;
  int total = 0;
  for (const BarthelItem& item : items) {
    if (item.id.empty()) return bad("an item has an empty id");
    if (!ids.insert(item.id).second) return bad("item id '" + item.id + "' appears twice");
    if (item.options.size() < 2) {
      return bad("item '" + item.id + "' has " + std::to_string(item.options.size()) +
                 " options, fewer than 2");
    }
    for (std::size_t i = 0; i < item.options.size(); ++i) {
      const BarthelOption& o = item.options[i];
      if (o.label.empty()) return bad("item '" + item.id + "' option " + std::to_string(i) +
                                      " has an empty label");
      const int expected = static_cast<int>(i) * 5;
      if (o.score != expected) {
        return bad("item '" + item.id + "' option " + std::to_string(i) + " ('" + o.label +
                   "') scores " + std::to_string(o.score) + ", not " + std::to_string(expected));
      }
    }
    total += item.options.back().score;
  }
  if (total != 100) return bad("the highest scores sum to " + std::to_string(total) + ", not 100");
  return Status::Ok();
}

}  // namespace quiver::agents::inline apps::barthel
