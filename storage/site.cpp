// Stations and zones from the configuration, upserted by name.
#include "storage/site.hpp"

#include "storage/connection.hpp"

namespace tlsmon {

StationId Site::upsert_station(const std::string& name, const std::array<double, 3>& position) {
    return guarded(*c_, "upserting a station", [&] {
        SQLite::Statement s(c_->db,
                            "INSERT INTO stations (name, x, y, z) VALUES (?,?,?,?)"
                            " ON CONFLICT (name) DO UPDATE SET x = excluded.x, y = excluded.y,"
                            " z = excluded.z RETURNING id");
        s.bind(1, name);
        for (int i = 0; i < 3; ++i) s.bind(2 + i, position[i]);
        if (!s.executeStep()) throw_storage(*c_, "upserting station '" + name + "' gave no id");
        const StationId id = s.getColumn(0).getInt64();
        while (s.executeStep()) {
        }
        return id;
    });
}

std::vector<Station> Site::stations() const {
    return guarded(*c_, "listing stations", [&] {
        SQLite::Statement s(c_->db, "SELECT id, name, x, y, z FROM stations ORDER BY id");
        std::vector<Station> out;
        while (s.executeStep()) {
            out.push_back({s.getColumn(0).getInt64(),
                           s.getColumn(1).getString(),
                           {s.getColumn(2).getDouble(), s.getColumn(3).getDouble(),
                            s.getColumn(4).getDouble()}});
        }
        return out;
    });
}

ZoneId Site::upsert_zone(const std::string& name, const std::string& definition_json) {
    return guarded(*c_, "upserting a zone", [&] {
        SQLite::Statement s(c_->db,
                            "INSERT INTO zones (name, definition) VALUES (?,?)"
                            " ON CONFLICT (name) DO UPDATE SET definition = excluded.definition"
                            " RETURNING id");
        s.bind(1, name);
        s.bind(2, definition_json);
        if (!s.executeStep()) throw_storage(*c_, "upserting zone '" + name + "' gave no id");
        const ZoneId id = s.getColumn(0).getInt64();
        while (s.executeStep()) {
        }
        return id;
    });
}

std::vector<std::pair<std::string, std::string>> Site::zones() const {
    return guarded(*c_, "listing zones", [&] {
        SQLite::Statement s(c_->db, "SELECT name, definition FROM zones ORDER BY name");
        std::vector<std::pair<std::string, std::string>> out;
        while (s.executeStep()) out.emplace_back(s.getColumn(0).getString(), s.getColumn(1));
        return out;
    });
}

std::vector<std::pair<ZoneId, std::string>> Site::zone_ids() const {
    return guarded(*c_, "listing zones", [&] {
        SQLite::Statement s(c_->db, "SELECT id, name FROM zones ORDER BY id");
        std::vector<std::pair<ZoneId, std::string>> out;
        while (s.executeStep()) out.emplace_back(s.getColumn(0).getInt64(), s.getColumn(1));
        return out;
    });
}

}  // namespace tlsmon
