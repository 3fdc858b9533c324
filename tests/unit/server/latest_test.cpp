#include "server/latest.h"

#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <thread>
#include <vector>

namespace mobot::server {
namespace {

struct Sample {
  int sequence = 0;
  int twice = 0;  // 2 * sequence: a reader seeing anything else saw a torn value
};

TEST(Latest, IsEmptyUntilTheFirstStoreAndThenHoldsTheNewest) {
  Latest<Sample> latest;
  EXPECT_EQ(latest.load(), nullptr);
  latest.store(std::make_shared<const Sample>(Sample{1, 2}));
  latest.store(std::make_shared<const Sample>(Sample{2, 4}));
  ASSERT_NE(latest.load(), nullptr);
  EXPECT_EQ(latest.load()->sequence, 2);
}

TEST(Latest, AReaderKeepsItsValueAfterANewerOneIsStored) {
  Latest<Sample> latest;
  latest.store(std::make_shared<const Sample>(Sample{1, 2}));
  const auto held = latest.load();
  latest.store(std::make_shared<const Sample>(Sample{2, 4}));
  EXPECT_EQ(held->sequence, 1);
  EXPECT_EQ(held.use_count(), 1) << "the store dropped its own reference";
}

// One writer, four readers: every value read is whole and the sequence never goes back (the
// thread sanitizer build runs this too).
TEST(Latest, ReadersSeeWholeValuesInOrderWhileOneThreadStores) {
  Latest<Sample> latest;
  latest.store(std::make_shared<const Sample>());
  constexpr int kStores = 20000;
  std::atomic<bool> done{false};
  std::atomic<int> torn{0};
  std::atomic<int> backwards{0};
  std::vector<std::thread> readers;
  for (int i = 0; i < 4; ++i) {
    readers.emplace_back([&] {
      int last = 0;
      while (!done) {
        const auto value = latest.load();
        if (value->twice != 2 * value->sequence) ++torn;
        if (value->sequence < last) ++backwards;
        last = value->sequence;
      }
    });
  }
  for (int i = 1; i <= kStores; ++i) latest.store(std::make_shared<const Sample>(Sample{i, 2 * i}));
  done = true;
  for (auto& reader : readers) reader.join();
  EXPECT_EQ(torn.load(), 0);
  EXPECT_EQ(backwards.load(), 0);
  EXPECT_EQ(latest.load()->sequence, kStores);
}

}  // namespace
}  // namespace mobot::server
