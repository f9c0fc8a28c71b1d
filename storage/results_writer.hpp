#pragma once
// The end of an epoch's processing: all its results and its final status in ONE transaction
// (DESIGN.md "SQLite"), so a crash leaves an epoch either complete or absent.
#include "storage/epoch_results.hpp"
#include "storage/ids.hpp"

namespace tlsmon {

class ResultsWriter {
  public:
    explicit ResultsWriter(Connection& connection) : c_(&connection) {}

    // Everything of one epoch plus its status processing -> results.outcome. On any error
    // nothing of it is stored and the epoch stays `processing`.
    void commit(EpochId id, const EpochResults& results);

  private:
    Connection* c_;
};

}  // namespace tlsmon
