#pragma once
// The daemon's one shutdown mechanism: a stop request (SIGTERM/SIGINT or the end of
// `--once`) and a reload request (SIGHUP), set by the signal thread and seen by every loop.
// Every wait in the daemon is interruptible: poll() loops include `fd()` (an eventfd that
// becomes readable on a request), sleeps use wait_for().
#include <atomic>
#include <chrono>
#include <condition_variable>
#include <mutex>
#include <thread>

namespace tlsmon {

class Shutdown {
  public:
    Shutdown();
    ~Shutdown();
    Shutdown(const Shutdown&) = delete;
    Shutdown& operator=(const Shutdown&) = delete;

    void request_stop();
    void request_reload();
    bool stop_requested() const { return stop_.load(); }
    // True once per SIGHUP.
    bool take_reload();

    // Readable while a request is outstanding; drained by clear_wakeup().
    int fd() const { return event_fd_; }
    void clear_wakeup();
    // Sleeps up to `d`; returns early (true) when stop is requested.
    bool wait_for(std::chrono::duration<double> d);

  private:
    void wake();

    std::atomic<bool> stop_{false};
    std::atomic<bool> reload_{false};
    int event_fd_ = -1;
    std::mutex mutex_;
    std::condition_variable cv_;
};

// Blocks SIGTERM, SIGINT and SIGHUP in the calling thread (call first in main, so every
// thread started later inherits the mask) and reads them on a dedicated thread through a
// signalfd, turning them into Shutdown requests. The thread ends when stop is requested.
class SignalThread {
  public:
    explicit SignalThread(Shutdown& shutdown);
    ~SignalThread();  // requests stop and joins
    SignalThread(const SignalThread&) = delete;
    SignalThread& operator=(const SignalThread&) = delete;

    static void block_signals();

  private:
    void run();

    Shutdown& shutdown_;
    int signal_fd_ = -1;
    int quit_fd_ = -1;  // its own eventfd: a reload request must not wake this thread
    std::thread thread_;
};

}  // namespace tlsmon
