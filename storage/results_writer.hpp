#pragma once
// The end of an epoch's processing: all its results and its final status in ONE transaction
// (DESIGN.md "SQLite"), so a crash leaves an epoch either complete or absent.
#include <functional>

#include "storage/epoch_results.hpp"
#include "storage/ids.hpp"
#include "storage/series_reader.hpp"

namespace tlsmon {

class ResultsWriter {
  public:
    explicit ResultsWriter(Connection& connection) : c_(&connection) {}

    // Everything of one epoch plus its status processing -> results.outcome. On any error
    // nothing of it is stored and the epoch stays `processing`.
    void commit(EpochId id, const EpochResults& results);

    // The alarm evaluation of an epoch, run inside its transaction once its zone results are
    // written: it reads the alarm states and the series (this epoch's rows included) and
    // returns the alarm rows to write with them, so states and series cannot disagree.
    using AlarmEvaluation =
        std::function<AlarmRows(const AlarmStore& alarms, const SeriesReader& series)>;
    void commit(EpochId id, const EpochResults& results, const AlarmEvaluation& evaluate);

  private:
    Connection* c_;
};

}  // namespace tlsmon
