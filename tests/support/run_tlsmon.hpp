#pragma once
// The built `tlsmon` binary (TLSMON_BINARY, set for the process tests) run with arguments
// through the shell: its exit status and what it printed.
#include <sys/wait.h>

#include <array>
#include <cstdio>
#include <string>

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

}  // namespace tlsmon::test
