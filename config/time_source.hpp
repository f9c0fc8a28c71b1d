#pragma once
// Where an epoch's acquisition time can come from (ingest.acquisition_time); the service
// reads them in the configured order (daemon/ingest_files.hpp).

namespace tlsmon {

enum class TimeSource {
    scan,       // the file's own header time (E57's acquisitionStart; other formats have none)
    file_name,  // a YYYYMMDDTHHMMSSZ stamp in the name
    mtime,      // the file's modification time
};

}  // namespace tlsmon
