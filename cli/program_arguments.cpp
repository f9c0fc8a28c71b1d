#include "cli/program_arguments.hpp"

namespace tlsmon {
namespace {
char** g_argv = nullptr;
}

void remember_program_arguments(int /*argc*/, char** argv) {
    g_argv = argv;
}

char** program_arguments() {
    return g_argv;
}

}  // namespace tlsmon
