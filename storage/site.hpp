#pragma once
// The monitored site as configured: scanner stations and zones (named parts of the
// structure), upserted by name at start and on reload.
#include <array>
#include <string>
#include <utility>
#include <vector>

#include "storage/ids.hpp"

namespace tlsmon {

struct Station {
    StationId id = 0;
    std::string name;
    std::array<double, 3> position{};  // project frame, metres
};

class Site {
  public:
    explicit Site(Connection& connection) : c_(&connection) {}

    StationId upsert_station(const std::string& name, const std::array<double, 3>& position);
    std::vector<Station> stations() const;
    ZoneId upsert_zone(const std::string& name, const std::string& definition_json);
    std::vector<std::pair<std::string, std::string>> zones() const;  // name, definition
    // Every zone's id and name, by id (ids follow the order of first appearance).
    std::vector<std::pair<ZoneId, std::string>> zone_ids() const;

  private:
    Connection* c_;
};

}  // namespace tlsmon
