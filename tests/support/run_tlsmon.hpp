#pragma once
// The built `tlsmon` binary (TLSMON_BINARY, set for the process tests) run with arguments
// through the shell: its exit status and what it printed; or killed in the middle.
#include <fcntl.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <array>
#include <chrono>
#include <cstdio>
#include <string>
#include <thread>
#include <vector>

namespace tlsmon::test {

struct CommandRun {
    int status = -1;  // the exit code; -1 when it did not exit normally
    std::string out;  // standard output, and standard error unless left out
};

// `program` (a copy of the binary elsewhere, say) run with arguments.
inline CommandRun run_tlsmon_at(const std::string& program, const std::string& args,
                                bool with_stderr = true) {
    const std::string cmd = program + " " + args + (with_stderr ? " 2>&1" : " 2>/dev/null");
    CommandRun r;
    FILE* pipe = ::popen(cmd.c_str(), "r");
    if (!pipe) return r;
    std::array<char, 4096> buf{};
    std::size_t n = 0;
    while ((n = std::fread(buf.data(), 1, buf.size(), pipe)) > 0) r.out.append(buf.data(), n);
    const int status = ::pclose(pipe);
    r.status = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    return r;
}

inline CommandRun run_tlsmon(const std::string& args, bool with_stderr = true) {
    return run_tlsmon_at(TLSMON_BINARY, args, with_stderr);
}

// `tlsmon ARGS...` killed with SIGKILL after `ms` milliseconds; false when it had finished by
// then. Its output goes to /dev/null.
inline bool killed_after(const std::vector<std::string>& args, int ms) {
    std::vector<char*> argv{const_cast<char*>(TLSMON_BINARY)};
    for (const auto& a : args) argv.push_back(const_cast<char*>(a.c_str()));
    argv.push_back(nullptr);
    const pid_t pid = ::fork();
    if (pid == 0) {
        const int null = ::open("/dev/null", O_WRONLY);
        ::dup2(null, 1);
        ::dup2(null, 2);
        ::execv(TLSMON_BINARY, argv.data());
        ::_exit(127);
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(ms));
    const bool running = ::waitpid(pid, nullptr, WNOHANG) == 0;
    ::kill(pid, SIGKILL);
    ::waitpid(pid, nullptr, 0);
    return running;
}

}  // namespace tlsmon::test
