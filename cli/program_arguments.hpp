#pragma once
// The command line as the program received it, kept by main() for the commands that hand
// themselves over to tlsmon-analysis with the same arguments (cli/analysis_handoff.cpp).

namespace tlsmon {

void remember_program_arguments(int argc, char** argv);
// argv as given to main(), terminated by a null pointer (as execv wants it).
char** program_arguments();

}  // namespace tlsmon
