#pragma once
// Epoch rows from discovery to a final status: insert-or-get by sha256, the processing order,
// status transitions, crash recovery, and the reference epoch (epoch 0 of the analyses).
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "core/utc_time.hpp"
#include "storage/ids.hpp"

namespace tlsmon {

enum class EpochStatus { pending, processing, done, failed, rejected };
// Done, failed or rejected: nothing more happens to the epoch.
constexpr bool is_finished(EpochStatus s) {
    return s == EpochStatus::done || s == EpochStatus::failed || s == EpochStatus::rejected;
}
std::string_view to_string(EpochStatus status);
// Throws StorageError for an unknown name.
EpochStatus epoch_status_from_string(std::string_view name);

// A newly complete file in the ingest folder.
struct NewEpoch {
    std::string sha256;  // 64 lowercase hex digits: the identity of the scan
    UtcSeconds acquired = 0;
    std::filesystem::path file_path;
    std::int64_t file_size = 0;
    std::optional<StationId> station;
};

struct EpochInsert {
    EpochId id = 0;
    bool inserted = false;  // false: this sha256 was already an epoch; `id` is that epoch
};

// Milliseconds spent per stage (absent when the stage did not run).
struct EpochTimings {
    std::optional<double> read_ms, register_ms, analyse_ms, total_ms;
};

struct Epoch {
    EpochId id = 0;
    std::string sha256;
    UtcSeconds acquired = 0;
    UtcSeconds discovered = 0;  // when the row was inserted
    UtcSeconds updated = 0;     // last status change
    std::string file_path;
    std::int64_t file_size = 0;
    std::optional<StationId> station;
    EpochStatus status = EpochStatus::pending;
    std::string reason;  // why failed / rejected ("" otherwise)
    std::optional<std::int64_t> point_count;
    EpochTimings timings;
    std::optional<std::string> archive_path;  // where the file was moved (archive/quarantine)
};

class Epochs {
  public:
    explicit Epochs(Connection& connection) : c_(&connection) {}

    // Insert-or-get by sha256: a new file becomes a `pending` epoch.
    EpochInsert insert(const NewEpoch& epoch);
    std::optional<Epoch> find(EpochId id) const;
    std::optional<Epoch> find_by_sha256(const std::string& sha256) const;
    // The newest epoch recorded from `file` (its path in the ingest folder), if any.
    std::optional<Epoch> find_by_file(const std::filesystem::path& file) const;
    // Pending epochs, oldest acquisition first (ties by id): the processing order.
    std::vector<Epoch> pending() const;
    // pending -> processing. False if the epoch is not pending (someone else took it).
    bool claim(EpochId id);
    // processing -> pending (e.g. disk full: retry later).
    void release(EpochId id);
    // processing -> failed / rejected with a reason; the file may have moved (quarantine).
    void fail(EpochId id, const std::string& reason,
              std::optional<std::string> moved_to = std::nullopt);
    void reject(EpochId id, const std::string& reason,
                std::optional<std::string> moved_to = std::nullopt);
    // The content of an epoch that was never read (pending, or failed without a file to
    // move because its file had vanished) was found again at `file` (renamed, copied in
    // again): the epoch now points at `file` and is pending. False if the epoch is in
    // another state.
    bool relocate(EpochId id, const std::filesystem::path& file);
    // At start: every `processing` epoch left by a crash goes back to `pending`. Returns how
    // many.
    std::int64_t recover_interrupted();

    // The reference epoch: set once; setting the same epoch again is a no-op, another one a
    // StorageError.
    void set_reference(EpochId id);
    std::optional<EpochId> reference() const;

  private:
    Connection* c_;
};

}  // namespace tlsmon
