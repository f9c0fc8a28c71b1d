#pragma once
// The HTTP server's workers, bounded in threads and in waiting connections (docs/http.md,
// "Limits"). `threads` workers each serve one connection at a time; at most `waiting` more
// connections wait for one. enqueue() blocks while that many wait, so the server's accepting
// thread stops accepting: further connections wait in the kernel's listen backlog (and beyond
// it are refused by the kernel), holding none of the daemon's file descriptors. 10,000 idle
// connections therefore cost the daemon threads + waiting descriptors, and the ingest, which
// needs descriptors to open scans and the database, goes on.
#include <condition_variable>
#include <cstddef>
#include <deque>
#include <functional>
#include <mutex>
#include <thread>
#include <vector>

namespace tlsmon {

class ConnectionQueue {
  public:
    ConnectionQueue(std::size_t threads, std::size_t waiting);
    ~ConnectionQueue();
    ConnectionQueue(const ConnectionQueue&) = delete;
    ConnectionQueue& operator=(const ConnectionQueue&) = delete;

    // Hands the job to a worker; waits while `waiting` jobs already wait. After shutdown()
    // the job runs at once on the caller's thread (the server closes its connection).
    void enqueue(std::function<void()> job);
    // The jobs already waiting still run; then the workers end.
    void shutdown();

    std::size_t waiting() const;

  private:
    void work();

    const std::size_t capacity_;
    mutable std::mutex mutex_;
    std::condition_variable job_ready_, slot_free_;
    std::deque<std::function<void()>> jobs_;
    bool stopping_ = false;
    std::vector<std::thread> workers_;
};

}  // namespace tlsmon
