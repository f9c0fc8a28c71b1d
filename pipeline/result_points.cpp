#include "pipeline/result_points.hpp"

#include <cmath>
#include <limits>
#include <optional>

#include "core/error.hpp"
#include "pipeline/core_point_map.hpp"
#include "pipeline/pbm3c2_reference.hpp"
#include "pipeline/pbm3c2_stage.hpp"
#include "pipeline/stored_area_vectors.hpp"
#include "pipeline/stored_product.hpp"
#include "pipeline/vector_reference.hpp"

namespace tlsmon {

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

using Type = LasAttribute::Type;

// Columns filled point by point, in the order they are declared.
class Columns {
  public:
    explicit Columns(LasPoints& points) : points_(&points) {}
    std::size_t add(std::string name, std::string description, Type type) {
        points_->attributes.push_back({std::move(name), std::move(description), type, {}});
        return points_->attributes.size() - 1;
    }
    void set(std::size_t column, double value) {
        points_->attributes[column].values.push_back(value);
    }

  private:
    LasPoints* points_;
};

std::optional<double> acquired(const EpochDatabase& db, EpochId id) {
    const auto epoch = db.epochs().find(id);
    if (!epoch) throw Error("no epoch " + std::to_string(id) + " in " + db.path().string());
    return static_cast<double>(epoch->acquired);
}

// A distance along a normal with its LoD95 and point counts: M3C2's core points and
// PB-M3C2's patches alike.
struct NormalDistanceColumns {
    std::size_t distance, lod95, significant, nx, ny, nz, n1, n2;
    NormalDistanceColumns(Columns& c, const std::string& method, const char* n1_what,
                          const char* n2_what)
        : distance(c.add(method + "_distance_m", "distance along the normal, m", Type::f32)),
          lod95(c.add(method + "_lod95_m", "level of detection (95 %), m", Type::f32)),
          significant(c.add("significant", "1: |distance| > LoD95", Type::u8)),
          nx(c.add("normal_x", "unit normal, x", Type::f32)),
          ny(c.add("normal_y", "unit normal, y", Type::f32)),
          nz(c.add("normal_z", "unit normal, z", Type::f32)),
          n1(c.add(method + "_n1", n1_what, Type::u32)),
          n2(c.add(method + "_n2", n2_what, Type::u32)) {}
    void set(Columns& c, double d, double lod, const Eigen::Vector3d& n, double count1,
             double count2) const {
        c.set(distance, d);
        c.set(lod95, lod);
        c.set(significant, std::isfinite(d) && std::abs(d) > lod ? 1 : 0);
        c.set(nx, n.x());
        c.set(ny, n.y());
        c.set(nz, n.z());
        c.set(n1, std::isfinite(count1) ? count1 : 0);
        c.set(n2, std::isfinite(count2) ? count2 : 0);
    }
};

LasPoints m3c2_points(const EpochDatabase& db, EpochId id) {
    const CorePointMap map = read_core_point_map(db, id);
    const auto& ref = map.reference.reference;
    LasPoints out;
    Columns c(out);
    const NormalDistanceColumns nd(c, "m3c2", "reference points in the cylinder",
                                   "epoch points in the cylinder");
    const auto spread = c.add("spread1_m", "reference spread along n, m", Type::f32);
    const auto radius = c.add("normal_radius_m", "normal fitting radius, m", Type::f32);
    for (std::size_t k = 0; k < ref.size(); ++k) {
        out.xyz.push_back(ref.core_points()[k]);
        nd.set(c, map.distance[k], map.lod95[k], ref.normals()[k], map.n1[k], map.n2[k]);
        c.set(spread, ref.reference_side[k].spread);
        c.set(radius, ref.normal_radius[k]);
    }
    return out;
}

LasPoints pbm3c2_points(const EpochDatabase& db, EpochId id) {
    // In kPbM3c2PatchArrays' order; an epoch stored before the shifts has none (0: the whole
    // patch's place, where its distance was then taken).
    std::vector<std::optional<std::vector<float>>> a;
    for (const char* quantity : kPbM3c2PatchArrays) {
        auto stored = db.series().core_point_array(id, quantity);
        if (!stored && a.size() < kPbM3c2FirstShift)
            throw Error("epoch " + std::to_string(id) + " has no PB-M3C2 patches");
        a.push_back(stored ? std::optional(std::move(stored->values)) : std::nullopt);
    }
    const auto product = stored_product<PbM3c2Reference>(db);
    const std::size_t n = product.patches.size();
    for (auto& values : a) {
        if (!values) values.emplace(n, 0.0f);
        if (values->size() != n) {
            throw Error("epoch " + std::to_string(id) + " has " + std::to_string(values->size()) +
                        " PB-M3C2 values, the stored reference " + std::to_string(n) +
                        " patches: it was measured with other [pbm3c2] parameters or zones");
        }
    }
    const auto at = [&](std::size_t array, std::size_t k) { return double((*a[array])[k]); };
    LasPoints out;
    Columns c(out);
    const NormalDistanceColumns nd(c, "pbm3c2", "reference points compared",
                                   "epoch points compared");
    for (std::size_t k = 0; k < n; ++k) {
        const std::size_t s = kPbM3c2FirstShift;
        const Eigen::Vector3d shift(at(s, k), at(s + 1, k), at(s + 2, k));
        out.xyz.push_back(product.from_frame(k, product.measured_in_frame(k) + shift));
        nd.set(c, at(0, k), at(1, k), product.patches[k].frame.normal, at(2, k), at(3, k));
    }
    return out;
}

// Every area of the reference (its position from the stored product, not the float32 copy
// the arrays keep), with NaN where the epoch measured no vector.
LasPoints vector_points(const EpochDatabase& db, EpochId id) {
    std::array<std::vector<float>, 9> arrays;
    for (std::size_t c = 0; c < arrays.size(); ++c) {
        auto a = db.series().core_point_array(id, kAreaVectorArrays[c]);
        if (!a) throw Error("epoch " + std::to_string(id) + " has no 3-D vectors");
        arrays[c] = std::move(a->values);
    }
    const auto product = stored_product<VectorReference>(db);
    for (const auto& a : arrays) {
        if (a.size() != product.areas()) {
            throw Error("epoch " + std::to_string(id) + " has " + std::to_string(a.size()) +
                        " vector areas, the stored reference " + std::to_string(product.areas()) +
                        ": it was measured with other [vectors] parameters or zones");
        }
    }
    LasPoints out;
    Columns c(out);
    std::array<std::size_t, 3> d{}, s{};
    for (int k = 0; k < 3; ++k) {
        const std::string axis(1, "xyz"[k]);
        d[k] = c.add("vector_d" + axis + "_m", "displacement along " + axis + ", m", Type::f32);
    }
    for (int k = 0; k < 3; ++k) {
        const std::string axis(1, "xyz"[k]);
        s[k] =
            c.add("vector_sigma_" + axis + "_m", "sigma of the displacement, " + axis, Type::f32);
    }
    const auto length = c.add("vector_length_m", "length of the displacement, m", Type::f64);
    for (std::size_t a = 0; a < product.areas(); ++a) {
        out.xyz.push_back(product.frames[a].origin);
        // An area without a vector has no σ (vector_area_arrays).
        const bool measured = std::isfinite(arrays[6][a]);
        Eigen::Vector3d v;
        for (int k = 0; k < 3; ++k) {
            v[k] = measured ? double(arrays[std::size_t(3 + k)][a]) : kNaN;
            c.set(d[std::size_t(k)], v[k]);
            c.set(s[std::size_t(k)], arrays[std::size_t(6 + k)][a]);
        }
        c.set(length, measured ? v.norm() : kNaN);
    }
    return out;
}

}  // namespace

std::string_view to_string(ResultMap m) {
    switch (m) {
        case ResultMap::m3c2:
            return "m3c2";
        case ResultMap::pbm3c2:
            return "pbm3c2";
        case ResultMap::vectors:
            return "vectors";
    }
    return "?";
}

ResultMap parse_result_map(std::string_view name) {
    for (auto m : {ResultMap::m3c2, ResultMap::pbm3c2, ResultMap::vectors})
        if (to_string(m) == name) return m;
    throw Error("unknown result map '" + std::string(name) + "' (m3c2, pbm3c2, vectors)");
}

LasPoints epoch_result_points(const EpochDatabase& db, EpochId epoch, ResultMap map) {
    const auto when = acquired(db, epoch);
    LasPoints out;
    switch (map) {
        case ResultMap::m3c2:
            out = m3c2_points(db, epoch);
            break;
        case ResultMap::pbm3c2:
            out = pbm3c2_points(db, epoch);
            break;
        case ResultMap::vectors:
            out = vector_points(db, epoch);
            break;
    }
    out.acquired_utc = when;
    return out;
}

LasPoints campaign_result_points(const EpochDatabase& db, CampaignId campaign) {
    const auto row = db.campaigns().get(campaign);
    if (!row) throw Error("no campaign " + std::to_string(campaign) + " in " + db.path().string());
    const auto points = db.campaigns().points(campaign);
    if (!points) {
        throw Error("campaign " + std::to_string(campaign) +
                    " kept no points (stored before they were kept)");
    }
    const auto a = points->columns();
    LasPoints out;
    out.acquired_utc = static_cast<double>(row->acquired);
    Columns c(out);
    const auto segment = c.add("segment", "the point's segment; -1: none", Type::i32);
    std::array<std::size_t, 3> d{};
    for (int k = 0; k < 3; ++k) {
        const std::string axis(1, "xyz"[k]);
        d[k] = c.add("c2c_d" + axis + "_m", "C2C vector to the reference, " + axis, Type::f32);
    }
    const auto length = c.add("c2c_m", "C2C distance to the reference, m", Type::f64);
    const auto& o = points->origin;
    for (std::size_t i = 0; i < points->size(); ++i) {
        out.xyz.emplace_back(o[0] + double((*a[0])[i]), o[1] + double((*a[1])[i]),
                             o[2] + double((*a[2])[i]));
        c.set(segment, (*a[3])[i]);
        const Eigen::Vector3d v((*a[4])[i], (*a[5])[i], (*a[6])[i]);
        for (int k = 0; k < 3; ++k) c.set(d[k], v[k]);
        c.set(length, v.allFinite() ? v.norm() : kNaN);
    }
    return out;
}

}  // namespace tlsmon
