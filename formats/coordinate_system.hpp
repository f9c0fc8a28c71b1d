#pragma once
// The site's coordinate system, named as PROJ reads it ("EPSG:25832", a WKT, a PROJ string),
// turned into the OGC WKT a LAS 1.4 file carries (R15 §2.5.2: the OGC coordinate system WKT
// record) and the URN a GeoJSON file's "crs" member names. PROJ (Debian's libproj) is
// included by formats/coordinate_system.cpp alone.
#include <string>

namespace tlsmon {

struct CoordinateSystem {
    // WKT1 as GDAL writes it (what LAS readers expect); WKT2:2019 for a system WKT1 cannot
    // express.
    std::string wkt;
    // "urn:ogc:def:crs:EPSG::25832" when the system has an authority and code; "" otherwise.
    std::string urn;
};

// Throws Error with PROJ's reason for text that names no coordinate reference system.
CoordinateSystem coordinate_system(const std::string& crs);

}  // namespace tlsmon
