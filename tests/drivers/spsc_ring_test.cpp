// The SPSC ring of preallocated slots (gvs/drivers/spsc_ring.hpp): the
// libcamera source's hand-offs and gvsd's frame ring. The two-thread test is
// the one to run under TSan.
#include <gtest/gtest.h>

#include <array>
#include <atomic>
#include <cstdint>
#include <stdexcept>
#include <thread>
#include <vector>

#include "gvs/drivers/spsc_ring.hpp"

namespace gvs::drivers {
namespace {

struct Item {
  std::uint64_t seq = 0;
  std::array<std::uint64_t, 32> payload{};
};

TEST(SpscRing, FullRingRefusesAndNewestSkipsOlder) {
  SpscRing<int> ring(std::vector<int>(3, 0));
  for (int i = 1; i <= 3; ++i) {
    int* slot = ring.try_claim();
    ASSERT_NE(slot, nullptr);
    *slot = i;
    ring.publish();
  }
  EXPECT_EQ(ring.try_claim(), nullptr) << "a full ring must refuse, not overwrite";
  std::uint64_t skipped = 0;
  int* newest = ring.take_newest(skipped);
  ASSERT_NE(newest, nullptr);
  EXPECT_EQ(*newest, 3);
  EXPECT_EQ(skipped, 2u);
  // The two older slots are free again while the consumer still holds the newest.
  EXPECT_NE(ring.try_claim(), nullptr);
  ring.publish();
  EXPECT_NE(ring.try_claim(), nullptr);
  ring.publish();
  EXPECT_EQ(ring.try_claim(), nullptr);
  ring.release();
  EXPECT_NE(ring.try_claim(), nullptr);
}

TEST(SpscRing, EmptyRingGivesNothing) {
  SpscRing<int> ring(std::vector<int>(2, 0));
  std::uint64_t skipped = 99;
  EXPECT_EQ(ring.take_newest(skipped), nullptr);
  EXPECT_EQ(skipped, 0u);
  EXPECT_EQ(ring.take_oldest(), nullptr);
  EXPECT_THROW(SpscRing<int>(std::vector<int>(1, 0)), std::invalid_argument);
}

TEST(SpscRing, FifoOrderWithTakeOldest) {
  SpscRing<int> ring(std::vector<int>(4, 0));
  for (int i = 0; i < 3; ++i) {
    int* slot = ring.try_claim();
    ASSERT_NE(slot, nullptr);
    *slot = i;
    ring.publish();
  }
  for (int i = 0; i < 3; ++i) {
    int* s = ring.take_oldest();
    ASSERT_NE(s, nullptr);
    EXPECT_EQ(*s, i);
    ring.release();
  }
  EXPECT_EQ(ring.take_oldest(), nullptr);
}

// Producer and consumer on two threads: every slot the consumer sees is whole
// (payload matches its sequence number), sequences only increase, and
// published = consumed + skipped.
TEST(SpscRing, TwoThreadsNeverTearAndAccountForEveryItem) {
  SpscRing<Item> ring(std::vector<Item>(4));
  constexpr std::uint64_t kItems = 200000;
  std::atomic<bool> done{false};
  std::uint64_t refused = 0;
  std::thread producer([&] {
    for (std::uint64_t s = 1; s <= kItems; ++s) {
      Item* slot = ring.try_claim();
      if (slot == nullptr) {
        ++refused;
        continue;
      }
      slot->seq = s;
      slot->payload.fill(s * 7);
      ring.publish();
    }
    done.store(true);
  });
  std::uint64_t consumed = 0, skipped_total = 0, last = 0, torn = 0, backwards = 0;
  for (;;) {
    const bool finished = done.load();
    std::uint64_t skipped = 0;
    Item* item = ring.take_newest(skipped);
    if (item == nullptr) {
      if (finished) break;
      continue;
    }
    skipped_total += skipped;
    ++consumed;
    for (std::uint64_t v : item->payload) torn += v != item->seq * 7 ? 1 : 0;
    backwards += item->seq <= last ? 1 : 0;
    last = item->seq;
    ring.release();
  }
  producer.join();
  EXPECT_EQ(torn, 0u);
  EXPECT_EQ(backwards, 0u);
  EXPECT_EQ(consumed + skipped_total + refused, kItems);
  EXPECT_GT(consumed, 0u);
}

}  // namespace
}  // namespace gvs::drivers
