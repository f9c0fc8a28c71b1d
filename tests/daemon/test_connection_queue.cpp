// The HTTP server's bounded workers: never more than `threads` jobs at once, never more than
// `waiting` queued; a full queue holds the caller back until a worker frees a place;
// shutdown runs what waits, and a job after it runs on the caller's thread.
#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <future>
#include <latch>

#include "daemon/http/connection_queue.hpp"

namespace tlsmon {
namespace {

using namespace std::chrono_literals;

TEST(ConnectionQueue, BoundsThreadsAndWaitingAndHoldsTheCallerBack) {
    ConnectionQueue queue(2, 2);
    std::atomic<int> running{0}, most{0}, done{0};
    std::promise<void> release_promise;
    std::shared_future<void> release = release_promise.get_future().share();
    const auto job = [&] {
        const int now = ++running;
        int seen = most.load();
        while (now > seen && !most.compare_exchange_weak(seen, now)) {
        }
        release.wait();
        --running;
        ++done;
    };
    for (int i = 0; i < 4; ++i) queue.enqueue(job);  // two run, two wait
    const auto deadline = std::chrono::steady_clock::now() + 5s;
    while (running < 2 && std::chrono::steady_clock::now() < deadline)
        std::this_thread::sleep_for(1ms);
    EXPECT_EQ(running.load(), 2);
    EXPECT_EQ(queue.waiting(), 2u);
    auto fifth = std::async(std::launch::async, [&] { queue.enqueue(job); });
    EXPECT_EQ(fifth.wait_for(200ms), std::future_status::timeout) << "a full queue holds back";
    release_promise.set_value();
    EXPECT_EQ(fifth.wait_for(5s), std::future_status::ready);
    queue.shutdown();
    EXPECT_EQ(done.load(), 5);
    EXPECT_EQ(most.load(), 2);
}

TEST(ConnectionQueue, ShutdownRunsWhatWaitsAndLaterJobsRunOnTheCaller) {
    std::atomic<int> done{0};
    const auto caller = std::this_thread::get_id();
    std::thread::id ran_on;
    {
        ConnectionQueue queue(1, 8);
        std::latch hold(1);
        queue.enqueue([&] {
            hold.wait();
            ++done;
        });
        for (int i = 0; i < 5; ++i) queue.enqueue([&] { ++done; });
        hold.count_down();
        queue.shutdown();
        EXPECT_EQ(done.load(), 6);
        queue.enqueue([&] {
            ran_on = std::this_thread::get_id();
            ++done;
        });
    }
    EXPECT_EQ(done.load(), 7);
    EXPECT_EQ(ran_on, caller);
}

TEST(ConnectionQueue, AFailingJobLeavesTheWorkerServing) {
    ConnectionQueue queue(1, 4);
    std::atomic<int> done{0};
    queue.enqueue([] { throw std::runtime_error("peer reset"); });
    queue.enqueue([&] { ++done; });
    queue.shutdown();
    EXPECT_EQ(done.load(), 1);
}

}  // namespace
}  // namespace tlsmon
