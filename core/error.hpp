#pragma once
// The one exception type of the project. Kernels and readers throw it with enough context
// (file, line, byte offset, parameter name) for a site engineer to act on the message;
// boundaries (ingest, storage, Modbus) catch it, log it and mark the epoch.
#include <stdexcept>
#include <string>

namespace tlsmon {

class Error : public std::runtime_error {
  public:
    using std::runtime_error::runtime_error;
};

}  // namespace tlsmon
