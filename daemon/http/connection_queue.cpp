#include "daemon/http/connection_queue.hpp"

#include <spdlog/spdlog.h>

#include <exception>

namespace tlsmon {

ConnectionQueue::ConnectionQueue(std::size_t threads, std::size_t waiting)
    : capacity_(waiting == 0 ? 1 : waiting) {
    workers_.reserve(threads);
    for (std::size_t i = 0; i < (threads == 0 ? 1 : threads); ++i) {
        workers_.emplace_back([this] { work(); });
    }
}

ConnectionQueue::~ConnectionQueue() {
    shutdown();
}

void ConnectionQueue::enqueue(std::function<void()> job) {
    {
        std::unique_lock lock(mutex_);
        slot_free_.wait(lock, [&] { return stopping_ || jobs_.size() < capacity_; });
        if (!stopping_) {
            jobs_.push_back(std::move(job));
            job_ready_.notify_one();
            return;
        }
    }
    job();
}

void ConnectionQueue::shutdown() {
    {
        std::lock_guard lock(mutex_);
        if (stopping_ && workers_.empty()) return;
        stopping_ = true;
    }
    job_ready_.notify_all();
    slot_free_.notify_all();
    for (auto& w : workers_) w.join();
    workers_.clear();
}

std::size_t ConnectionQueue::waiting() const {
    std::lock_guard lock(mutex_);
    return jobs_.size();
}

void ConnectionQueue::work() {
    for (;;) {
        std::function<void()> job;
        {
            std::unique_lock lock(mutex_);
            job_ready_.wait(lock, [&] { return stopping_ || !jobs_.empty(); });
            if (jobs_.empty()) return;  // stopping, and nothing left
            job = std::move(jobs_.front());
            jobs_.pop_front();
        }
        slot_free_.notify_one();
        try {
            job();
        } catch (const std::exception& e) {  // a connection's failure is not the server's
            spdlog::error("http connection: {}", e.what());
        } catch (...) {
            spdlog::error("http connection: unknown error");
        }
    }
}

}  // namespace tlsmon
