// lrd::util::WorkQueue between threads (it also runs in the tsan preset): every item from several
// producers reaches the consumer once and in each producer's order; stop() lets the queue drain
// and then wakes a blocked consumer; drain() stops after a throwing item.
#include <gtest/gtest.h>

#include <atomic>
#include <stdexcept>
#include <thread>
#include <vector>

#include "lrd/util/work_queue.h"

namespace {

using lrd::util::WorkQueue;

TEST(WorkQueue, ItemsFromSeveralProducersArriveOnceAndInEachProducersOrder) {
  WorkQueue<int> queue;
  constexpr int kProducers = 3, kItems = 2000;
  std::atomic<int> busy{0};
  std::vector<int> got;
  std::thread consumer([&] {
    while (auto item = queue.wait_pop([&] { busy.store(1); })) {
      got.push_back(*item);
      busy.store(0);
    }
  });
  std::vector<std::thread> producers;
  for (int p = 0; p < kProducers; ++p)
    producers.emplace_back([&queue, p] {
      for (int i = 0; i < kItems; ++i) queue.push(p * kItems + i);
    });
  for (std::thread& t : producers) t.join();
  queue.stop();  // what is queued still comes out first
  consumer.join();
  ASSERT_EQ(got.size(), static_cast<std::size_t>(kProducers * kItems));
  std::vector<int> last(kProducers, -1);
  for (int v : got) {
    const int p = v / kItems;
    EXPECT_GT(v, last[p]);
    last[p] = v;
  }
  EXPECT_EQ(queue.size(), 0u);
}

TEST(WorkQueue, StopWakesABlockedConsumer) {
  WorkQueue<int> queue;
  std::atomic<bool> returned{false};
  std::thread consumer([&] {
    EXPECT_FALSE(queue.wait_pop().has_value());
    returned = true;
  });
  std::this_thread::sleep_for(std::chrono::milliseconds(20));
  EXPECT_FALSE(returned.load());
  queue.stop();
  consumer.join();
  EXPECT_TRUE(returned.load());
}

TEST(WorkQueue, DrainStopsForGoodAfterAThrowingItem) {
  WorkQueue<int> queue;
  for (int i = 0; i < 5; ++i) queue.push(i);
  std::vector<int> seen;
  const auto process = [&](int v) {
    if (v == 2) throw std::runtime_error("bad item");
    seen.push_back(v);
  };
  EXPECT_THROW(queue.drain(process), std::runtime_error);
  queue.drain(process);  // nothing more
  EXPECT_EQ(seen, (std::vector<int>{0, 1}));
  EXPECT_EQ(queue.size(), 2u);
}

}  // namespace
