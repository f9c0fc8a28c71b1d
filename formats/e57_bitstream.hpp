#pragma once
// Decoding of an E57 compressed vector (ASTM E2807-11 §10.6, Annex: binary section
// layouts): a 32-byte section header, then data packets of at most 64 KiB, each carrying
// one buffer per bytestream. Bytestream k holds prototype field k, bit-packed
// least-significant bit first (bitPackCodec); a stream continues across packets.
// Packets are decoded one at a time, so memory stays bounded by a packet plus the
// values not yet paired into whole records.
#include <cstdint>
#include <functional>
#include <vector>

#include "formats/e57_pages.hpp"
#include "formats/e57_xml.hpp"

namespace tlsmon {

// Values of the wanted fields for `count` consecutive records: column k belongs to
// wanted[k]; each column holds at least `count` values.
using E57RecordBatch =
    std::function<void(const std::vector<std::vector<double>>& columns, std::size_t count)>;

// Checks the section header (also for zero-record vectors), then decodes all records,
// calling `batch` after each packet with the records it completed. `wanted` are indices
// into cv.fields; the other bytestreams are skipped undecoded.
void decode_e57_records(E57Pages& pages, const E57CompressedVector& cv,
                        const std::vector<std::size_t>& wanted, const E57RecordBatch& batch);

}  // namespace tlsmon
