#include "db/zone_store.h"

#include <gtest/gtest.h>

#include "db/map_store.h"

namespace mobot::db {
namespace {

class ZoneStoreTest : public ::testing::Test {
 protected:
  std::int64_t add_map(const std::string& name) {
    return maps_.insert(name, mapping::OccupancyGrid(4, 4, 0.05, {}), 1.0);
  }

  Database database_ = Database::open_in_memory();
  MapStore maps_{database_};
  ZoneStore zones_{database_};
  const std::vector<geometry::Point2D> square_{{0, 0}, {1, 0}, {1, 1.5}, {-0.25, 1}};
};

TEST_F(ZoneStoreTest, StoresPolygonsExactlyPerMap) {
  const auto lab = add_map("lab");
  const auto hall = add_map("hall");
  const auto first = zones_.insert(lab, "stairs", square_, 2.0);
  const auto second = zones_.insert(hall, "wet", {{5, 5}, {6, 5}, {6, 6}}, 3.0);
  ASSERT_TRUE(first && second);
  const auto listed = zones_.list(lab);
  ASSERT_TRUE(listed);
  ASSERT_EQ(listed->size(), 1U);
  EXPECT_EQ(listed->front().id, *first);
  EXPECT_EQ(listed->front().name, "stairs");
  ASSERT_EQ(listed->front().polygon.size(), square_.size());
  for (std::size_t i = 0; i < square_.size(); ++i) {
    EXPECT_EQ(listed->front().polygon[i].x, square_[i].x);
    EXPECT_EQ(listed->front().polygon[i].y, square_[i].y);
  }
  EXPECT_EQ(zones_.list(hall)->size(), 1U);
}

TEST_F(ZoneStoreTest, UnknownMapsAreRefusedAndNothingIsStored) {
  EXPECT_FALSE(zones_.insert(99, "x", square_, 1.0));
  EXPECT_FALSE(zones_.list(99));
  EXPECT_EQ(zones_.remove(99, 1), ZoneStore::RemoveResult::kNoMap);
}

TEST_F(ZoneStoreTest, RemovesOnlyTheZoneOfThatMap) {
  const auto lab = add_map("lab");
  const auto hall = add_map("hall");
  const auto zone = *zones_.insert(lab, "stairs", square_, 2.0);
  EXPECT_EQ(zones_.remove(hall, zone), ZoneStore::RemoveResult::kNoZone);
  EXPECT_EQ(zones_.list(lab)->size(), 1U);
  EXPECT_EQ(zones_.remove(lab, zone), ZoneStore::RemoveResult::kRemoved);
  EXPECT_TRUE(zones_.list(lab)->empty());
  EXPECT_EQ(zones_.remove(lab, zone), ZoneStore::RemoveResult::kNoZone);
}

TEST_F(ZoneStoreTest, ZonesGoWithTheirMap) {
  const auto lab = add_map("lab");
  const auto other = add_map("other");
  ASSERT_TRUE(maps_.activate(other));
  ASSERT_TRUE(zones_.insert(lab, "stairs", square_, 2.0));
  ASSERT_EQ(maps_.remove(lab), MapStore::RemoveResult::kRemoved);
  EXPECT_FALSE(zones_.list(lab));
  const auto again = add_map("lab2");
  EXPECT_TRUE(zones_.list(again)->empty());
}

}  // namespace
}  // namespace mobot::db
