#pragma once
// Processing one pending epoch: claim -> read the scan -> the stages that exist (recording
// what was done: point count, timings) -> commit in one transaction -> archive the file.
// An unreadable file goes to quarantine and the epoch is `failed` with the reason; a disk
// or database failure puts the epoch back to `pending` for a later retry.
#include "daemon/ingest.hpp"

namespace tlsmon {

enum class EpochOutcome { done, failed, retry_later, skipped };

EpochOutcome process_epoch(IngestContext& ctx, const Epoch& epoch);

// The reference epoch (epoch 0 of the analyses), set once: the epoch named by
// ingest.reference_epoch (file name or sha256), else the first accepted one (earliest
// acquisition among the done epochs). Called after each commit and at start, so a stop
// or a database error between a commit and this call is repaired later.
void ensure_reference(IngestContext& ctx);

}  // namespace tlsmon
