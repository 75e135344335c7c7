#include <gtest/gtest.h>
#include <sys/epoll.h>
#include <unistd.h>

#include <functional>
#include <vector>

#include "runtime/event_loop.h"

namespace troupe {
namespace {

struct Log final : TimerHandler {
  std::vector<TimerId> fired;
  void on_timer(TimerId id) override { fired.push_back(id); }
};

void run_until(EventLoop& loop, const std::function<bool()>& done) {
  for (int i = 0; i < 1000 && !done(); ++i) loop.run_once(10'000);
}

TEST(EventLoop, TimersFireInDeadlineOrder) {
  EventLoop loop(8);
  Log log;
  TimerId late = loop.start_timer(30'000, 0, &log);
  TimerId early = loop.start_timer(1'000, 0, &log);
  TimerId middle = loop.start_timer(15'000, 0, &log);
  run_until(loop, [&] { return log.fired.size() == 3; });
  ASSERT_EQ(log.fired.size(), 3u);
  EXPECT_EQ(log.fired[0], early);
  EXPECT_EQ(log.fired[1], middle);
  EXPECT_EQ(log.fired[2], late);
}

TEST(EventLoop, PeriodicTimerRepeatsUntilCancelled) {
  EventLoop loop(4);
  Log log;
  TimerId tick = loop.start_timer(0, 2'000, &log);
  run_until(loop, [&] { return log.fired.size() >= 5; });
  ASSERT_GE(log.fired.size(), 5u);
  for (TimerId id : log.fired) EXPECT_EQ(id, tick);
  loop.cancel_timer(tick);
  size_t count = log.fired.size();
  for (int i = 0; i < 5; ++i) loop.run_once(3'000);
  EXPECT_EQ(log.fired.size(), count);
}

TEST(EventLoop, StaleIdDoesNotCancelTheTimerReusingItsSlot) {
  EventLoop loop(1);  // one slot: the second timer must reuse it
  Log log;
  TimerId first = loop.start_timer(0, 0, &log);
  run_until(loop, [&] { return log.fired.size() == 1; });
  TimerId second = loop.start_timer(1'000, 0, &log);
  EXPECT_NE(first, second);
  loop.cancel_timer(first);  // stale: must not touch `second`
  run_until(loop, [&] { return log.fired.size() == 2; });
  ASSERT_EQ(log.fired.size(), 2u);
  EXPECT_EQ(log.fired[1], second);
}

TEST(EventLoop, FullQueueRefusesWithZero) {
  EventLoop loop(2);
  Log log;
  EXPECT_NE(loop.start_timer(1'000'000, 0, &log), 0u);
  EXPECT_NE(loop.start_timer(1'000'000, 0, &log), 0u);
  EXPECT_EQ(loop.start_timer(1'000'000, 0, &log), 0u);
}

TEST(EventLoop, ManyCancelsDoNotOverflowTheHeap) {
  EventLoop loop(4);
  Log log;
  for (int i = 0; i < 10'000; ++i) loop.cancel_timer(loop.start_timer(1'000'000, 0, &log));
  TimerId last = loop.start_timer(0, 0, &log);
  run_until(loop, [&] { return !log.fired.empty(); });
  ASSERT_EQ(log.fired.size(), 1u);
  EXPECT_EQ(log.fired[0], last);
}

// Two pipes become readable in one batch; the first handler unwatches the
// second fd, whose event must then not be delivered.
struct Unwatcher final : FdHandler {
  EventLoop* loop = nullptr;
  int victim = -1;
  std::vector<int> seen;
  void on_fd(int fd, uint32_t) override {
    seen.push_back(fd);
    char c;
    (void)!read(fd, &c, 1);
    if (victim >= 0 && fd != victim) {
      loop->unwatch(victim);
      victim = -1;
    }
  }
};

TEST(EventLoop, UnwatchInsideABatchDropsPendingEvents) {
  EventLoop loop;
  int a[2], b[2];
  ASSERT_EQ(pipe(a), 0);
  ASSERT_EQ(pipe(b), 0);
  Unwatcher h;
  h.loop = &loop;
  ASSERT_TRUE(loop.watch(a[0], EPOLLIN, &h));
  ASSERT_TRUE(loop.watch(b[0], EPOLLIN, &h));
  ASSERT_EQ(write(a[1], "x", 1), 1);
  ASSERT_EQ(write(b[1], "x", 1), 1);
  // epoll reports fds in readiness order: a was written first.
  h.victim = b[0];
  loop.run_once(10'000);
  ASSERT_EQ(h.seen.size(), 1u);
  EXPECT_EQ(h.seen[0], a[0]);
  for (int fd : {a[0], a[1], b[0], b[1]}) close(fd);
}

}  // namespace
}  // namespace troupe
