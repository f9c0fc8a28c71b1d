#include "central/central_forward.hpp"

namespace tlsmon {

std::string forward_batch_json(std::span<const OutboxEntry> entries) {
    std::string out = "[";
    for (const auto& e : entries) {
        if (out.size() > 1) out += ',';
        // kind is one of five fixed words (the outbox's CHECK); payload is JSON already.
        out += "{\"seq\":" + std::to_string(e.seq) + ",\"kind\":\"" + e.kind + "\",\"p\":";
        out += e.payload;
        out += '}';
    }
    return out + "]";
}

std::int64_t forward_batch(PgConnection& c, const std::string& source,
                           std::span<const OutboxEntry> entries) {
    const auto r =
        c.exec("SELECT tlsmon.forward($1, $2::jsonb)", {source, forward_batch_json(entries)});
    return std::stoll(*r.rows.at(0).at(0));
}

}  // namespace tlsmon
