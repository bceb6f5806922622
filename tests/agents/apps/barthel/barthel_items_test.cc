// The Barthel index items: the standard ten, their options and scores, and the check of a table.
#include <gtest/gtest.h>

#include <string>
#include <utility>
#include <vector>

#include "quiver/agents/apps/barthel/items.h"

namespace quiver::agents::barthel {
namespace {

TEST(BarthelItemsTest, TenItemsScoredAsTheStandard) {
  const std::vector<BarthelItem>& items = barthel_items();
  ASSERT_EQ(items.size(), 10u);
  EXPECT_EQ(max_total(), 100);
  const std::vector<std::pair<std::string, std::vector<int>>> standard = {
      {"feeding", {0, 5, 10}},        {"bathing", {0, 5}},          {"grooming", {0, 5}},
      {"dressing", {0, 5, 10}},       {"bowels", {0, 5, 10}},       {"bladder", {0, 5, 10}},
      {"toilet_use", {0, 5, 10}},     {"transfers", {0, 5, 10, 15}}, {"mobility", {0, 5, 10, 15}},
      {"stairs", {0, 5, 10}}};
  int total = 0;
  for (std::size_t i = 0; i < items.size(); ++i) {
    const BarthelItem& item = items[i];
    EXPECT_EQ(item.id, standard[i].first);
    EXPECT_FALSE(item.name.empty());
    EXPECT_NE(item.question.find('?'), std::string::npos) << item.id;
    std::vector<int> scores;
    for (const BarthelOption& o : item.options) {
      EXPECT_FALSE(o.label.empty());
      if (!scores.empty()) {
        EXPECT_GT(o.score, scores.back()) << item.id;
      }
      scores.push_back(o.score);
    }
    EXPECT_EQ(scores, standard[i].second) << item.id;
    total += scores.back();
    EXPECT_EQ(find_barthel_item(item.id), &item);
  }
  EXPECT_EQ(total, 100);
  EXPECT_EQ(find_barthel_item("juggling"), nullptr);
  EXPECT_EQ(items[7].options[3].label, "independent");
  EXPECT_EQ(items[8].options[1].label,
            "wheelchair independent, including corners, over 50 yards");

  EXPECT_TRUE(check_barthel_items(items).ok());
  std::vector<BarthelItem> broken = items;
  broken[4].options[2].score = 15;
  Status s = check_barthel_items(broken);
  ASSERT_FALSE(s.ok());
  EXPECT_NE(s.error().message.find("item 'bowels' option 2 ('continent') scores 15, not 10"),
            std::string::npos)
      << s.error().message;
  broken = items;
  broken.pop_back();
  EXPECT_FALSE(check_barthel_items(broken).ok());
}

}  // namespace
}  // namespace quiver::agents::barthel
