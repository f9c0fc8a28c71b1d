#pragma once
// The daemon of `tlsmon demo`: `tlsmon run --config FILE` as a child process of the same
// binary, in its own process group (so a Ctrl-C reaches the demo, which stops it in order),
// its log in a file.
#include <sys/types.h>

#include <filesystem>

namespace tlsmon {

class DaemonChild {
  public:
    // Starts `binary run --config config`, stdout and stderr appended to `log`. Throws Error
    // when it cannot fork.
    DaemonChild(const std::filesystem::path& binary, const std::filesystem::path& config,
                const std::filesystem::path& log);
    ~DaemonChild();  // stops it if still running
    DaemonChild(const DaemonChild&) = delete;
    DaemonChild& operator=(const DaemonChild&) = delete;

    pid_t pid() const { return pid_; }
    bool running();
    // SIGTERM, then waits up to `seconds` (SIGKILL after that). The exit code; -1 when it had
    // to be killed or died of a signal.
    int stop(double seconds = 30.0);
    // The exit code once it has exited on its own (running() false); -1 for a signal.
    int exit_code() const;

  private:
    pid_t pid_ = -1;
    bool exited_ = false;
    int status_ = 0;
};

// This executable's path (/proc/self/exe).
std::filesystem::path own_executable();

}  // namespace tlsmon
