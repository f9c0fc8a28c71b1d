#include "algorithms/keypoints/spherical_image.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <string>

#include "core/error.hpp"
#include "core/statistics.hpp"

namespace tlsmon::keypoints {

namespace {

constexpr double two_pi = 2.0 * std::numbers::pi;

// The azimuth at which the scan is cut open: the middle of the widest angular gap between
// returns (the gap across ±π included), so that no return lies near the cut. Azimuths below
// the cut are then taken + 2π; a cut at −π leaves them as they are. The gap is found on a
// histogram of 0.1° bins (a sort of millions of azimuths costs more than the rest of the
// images); only a scan without any empty bin falls back to the sorted azimuths.
double unwrap_cut(const std::vector<double>& azimuths) {
    constexpr int bins = 3600;
    const double width = two_pi / bins;
    std::vector<std::uint32_t> count(bins, 0);
    for (double a : azimuths) {
        const int k = std::clamp(static_cast<int>((a + std::numbers::pi) / width), 0, bins - 1);
        ++count[static_cast<std::size_t>(k)];
    }
    // The longest circular run of empty bins: start from an occupied bin.
    int first_occupied = -1;
    for (int k = 0; k < bins && first_occupied < 0; ++k)
        if (count[static_cast<std::size_t>(k)] > 0) first_occupied = k;
    if (first_occupied < 0) return -std::numbers::pi;
    int best_length = 0, best_start = 0, length = 0, start = 0;
    for (int i = 1; i <= bins; ++i) {
        const int k = (first_occupied + i) % bins;
        if (count[static_cast<std::size_t>(k)] == 0) {
            if (length == 0) start = k;
            if (++length > best_length) {
                best_length = length;
                best_start = start;
            }
        } else {
            length = 0;
        }
    }
    if (best_length > 0) {
        const int end = best_start + best_length;  // one past the run, may exceed `bins`
        if (end > bins) return -std::numbers::pi;  // the run spans ±π: no cut needed
        return -std::numbers::pi + width * 0.5 * (best_start + end);
    }
    std::vector<double> sorted = azimuths;
    std::sort(sorted.begin(), sorted.end());
    double widest = two_pi - (sorted.back() - sorted.front());  // across ±π
    double cut = -std::numbers::pi;
    for (std::size_t i = 1; i < sorted.size(); ++i) {
        const double gap = sorted[i] - sorted[i - 1];
        if (gap > widest) {
            widest = gap;
            cut = 0.5 * (sorted[i] + sorted[i - 1]);
        }
    }
    return cut;
}

double unwrapped(double azimuth, double cut) {
    return azimuth < cut ? azimuth + two_pi : azimuth;
}

// Nominal angles of a lattice's lines from the medians of the lines that have returns (NaN
// for the others): the missing ones continued at the median step. Throws when fewer than
// two lines have returns.
Eigen::ArrayXd complete_lattice(const std::vector<double>& medians, const std::string& source,
                                const char* what) {
    std::vector<std::size_t> known;
    for (std::size_t i = 0; i < medians.size(); ++i)
        if (!std::isnan(medians[i])) known.push_back(i);
    if (known.size() < 2) {
        throw Error(source + ": spherical images need returns in at least two " + what +
                    " of the grid, to know its angular step");
    }
    std::vector<double> steps;
    for (std::size_t j = 1; j < known.size(); ++j)
        steps.push_back((medians[known[j]] - medians[known[j - 1]]) /
                        static_cast<double>(known[j] - known[j - 1]));
    const double step = median(steps);
    Eigen::ArrayXd lattice(static_cast<Eigen::Index>(medians.size()));
    for (std::size_t i = 0; i < medians.size(); ++i) {
        if (!std::isnan(medians[i])) {
            lattice(static_cast<Eigen::Index>(i)) = medians[i];
            continue;
        }
        // The nearest line with returns, continued at the step.
        const auto after = std::lower_bound(known.begin(), known.end(), i);
        std::size_t nearest = after == known.end() ? known.back() : *after;
        if (after != known.begin() && (after == known.end() || i - *(after - 1) < *after - i))
            nearest = *(after - 1);
        lattice(static_cast<Eigen::Index>(i)) =
            medians[nearest] + step * (static_cast<double>(i) - static_cast<double>(nearest));
    }
    return lattice;
}

double lattice_at(const Eigen::ArrayXd& lattice, double position) {
    const Eigen::Index n = lattice.size();
    if (n == 1) return lattice(0);
    const auto i0 =
        std::clamp<Eigen::Index>(static_cast<Eigen::Index>(std::floor(position)), 0, n - 2);
    const double t = position - static_cast<double>(i0);
    return lattice(i0) + t * (lattice(i0 + 1) - lattice(i0));
}

void check_intensity(const Scan& scan) {
    if (scan.intensity.size() != scan.xyz.size()) {
        throw Error(scan.source + ": spherical images need an intensity for every point (" +
                    std::to_string(scan.intensity.size()) + " intensities, " +
                    std::to_string(scan.xyz.size()) + " points)");
    }
    if (scan.xyz.empty()) throw Error(scan.source + ": no returns for spherical images");
}

SphericalImages empty_images(Eigen::Index rows, Eigen::Index columns, const Scan& scan) {
    SphericalImages im;
    im.rows = rows;
    im.columns = columns;
    im.valid = ImageMask::Constant(rows, columns, false);
    im.intensity = Eigen::ArrayXXd::Zero(rows, columns);
    im.range = Eigen::ArrayXXd::Zero(rows, columns);
    im.azimuth = Eigen::ArrayXXd::Zero(rows, columns);
    im.elevation = Eigen::ArrayXXd::Zero(rows, columns);
    im.pose = scan.pose;
    return im;
}

}  // namespace

Polar polar_of(const Eigen::Vector3d& p) {
    const double horizontal = std::hypot(p.x(), p.y());
    return {p.norm(), std::atan2(p.y(), p.x()), std::atan2(p.z(), horizontal)};
}

Eigen::Vector3d cartesian_of(const Polar& q) {
    const double ce = std::cos(q.elevation);
    return q.range * Eigen::Vector3d(ce * std::cos(q.azimuth), ce * std::sin(q.azimuth),
                                     std::sin(q.elevation));
}

double wrapped_difference(double a, double b) {
    double d = std::remainder(a - b, two_pi);  // in [−π, π]
    if (d <= -std::numbers::pi) d += two_pi;
    return d;
}

double SphericalImages::azimuth_at(double column) const {
    return lattice_at(column_azimuth, column);
}
double SphericalImages::elevation_at(double row) const {
    return lattice_at(row_elevation, row);
}

SphericalImages spherical_images_from_grid(const Scan& scan) {
    if (!scan.grid) throw Error(scan.source + ": the scan has no grid (not a structured scan)");
    check_intensity(scan);
    const ScanGrid& grid = *scan.grid;
    if (grid.row.size() != scan.size() || grid.column.size() != scan.size())
        throw Error(scan.source + ": the grid's indices do not match the points in number");
    const Eigen::Affine3d to_scanner = scan.pose.inverse();

    std::vector<Polar> polar(scan.size());
    std::vector<double> azimuths(scan.size());
    for (std::size_t i = 0; i < scan.size(); ++i) {
        if (grid.row[i] >= grid.rows || grid.column[i] >= grid.columns)
            throw Error(scan.source + ": point " + std::to_string(i) + " lies outside the grid");
        polar[i] = polar_of(to_scanner * scan.xyz[i]);
        azimuths[i] = polar[i].azimuth;
    }
    const double cut = unwrap_cut(azimuths);
    for (auto& q : polar) q.azimuth = unwrapped(q.azimuth, cut);

    // Median angle of each grid column and row, for the orientation and the lattice.
    std::vector<std::vector<double>> by_column(grid.columns), by_row(grid.rows);
    for (std::size_t i = 0; i < scan.size(); ++i) {
        by_column[grid.column[i]].push_back(polar[i].azimuth);
        by_row[grid.row[i]].push_back(polar[i].elevation);
    }
    const double nan = std::numeric_limits<double>::quiet_NaN();
    std::vector<double> column_median(grid.columns, nan), row_median(grid.rows, nan);
    for (std::size_t c = 0; c < grid.columns; ++c)
        if (!by_column[c].empty()) column_median[c] = median(std::move(by_column[c]));
    for (std::size_t r = 0; r < grid.rows; ++r)
        if (!by_row[r].empty()) row_median[r] = median(std::move(by_row[r]));
    Eigen::ArrayXd column_lattice = complete_lattice(column_median, scan.source, "columns");
    Eigen::ArrayXd row_lattice = complete_lattice(row_median, scan.source, "rows");
    // Photograph orientation: azimuth decreasing with the column, elevation with the row.
    const bool flip_columns = column_lattice(column_lattice.size() - 1) > column_lattice(0);
    const bool flip_rows = row_lattice(row_lattice.size() - 1) > row_lattice(0);
    if (flip_columns) column_lattice.reverseInPlace();
    if (flip_rows) row_lattice.reverseInPlace();

    SphericalImages im = empty_images(grid.rows, grid.columns, scan);
    for (std::size_t i = 0; i < scan.size(); ++i) {
        const Eigen::Index r = flip_rows ? grid.rows - 1 - grid.row[i] : grid.row[i];
        const Eigen::Index c = flip_columns ? grid.columns - 1 - grid.column[i] : grid.column[i];
        im.valid(r, c) = true;
        im.intensity(r, c) = scan.intensity[i];
        im.range(r, c) = polar[i].range;
        // Within π of its column's nominal azimuth: a full panorama's cut may pass through a
        // column whose returns straddle it.
        im.azimuth(r, c) =
            column_lattice(c) + wrapped_difference(polar[i].azimuth, column_lattice(c));
        im.elevation(r, c) = polar[i].elevation;
    }
    im.column_azimuth = std::move(column_lattice);
    im.row_elevation = std::move(row_lattice);
    im.azimuth_step = std::abs(im.azimuth_at(1.0) - im.azimuth_at(0.0));
    im.elevation_step = std::abs(im.elevation_at(1.0) - im.elevation_at(0.0));
    {
        std::vector<double> steps;
        for (Eigen::Index c = 1; c < im.columns; ++c)
            steps.push_back(im.column_azimuth(c - 1) - im.column_azimuth(c));
        if (!steps.empty()) im.azimuth_step = std::abs(median(steps));
        steps.clear();
        for (Eigen::Index r = 1; r < im.rows; ++r)
            steps.push_back(im.row_elevation(r - 1) - im.row_elevation(r));
        if (!steps.empty()) im.elevation_step = std::abs(median(steps));
    }
    return im;
}

SphericalImages spherical_images_binned(const Scan& scan, const Binning& binning) {
    if (!(binning.azimuth_step > 0.0) || !(binning.elevation_step > 0.0))
        throw Error(scan.source + ": binning steps must be > 0");
    check_intensity(scan);
    const Eigen::Affine3d to_scanner = scan.pose.inverse();
    std::vector<Polar> polar(scan.size());
    std::vector<double> azimuths(scan.size());
    for (std::size_t i = 0; i < scan.size(); ++i) {
        polar[i] = polar_of(to_scanner * scan.xyz[i]);
        azimuths[i] = polar[i].azimuth;
    }
    const double cut = unwrap_cut(azimuths);
    std::vector<long long> k(scan.size()), m(scan.size());
    long long k_min = std::numeric_limits<long long>::max(),
              k_max = std::numeric_limits<long long>::min();
    long long m_min = k_min, m_max = k_max;
    for (std::size_t i = 0; i < scan.size(); ++i) {
        polar[i].azimuth = unwrapped(polar[i].azimuth, cut);
        k[i] = std::llround(polar[i].azimuth / binning.azimuth_step);
        m[i] = std::llround(polar[i].elevation / binning.elevation_step);
        k_min = std::min(k_min, k[i]);
        k_max = std::max(k_max, k[i]);
        m_min = std::min(m_min, m[i]);
        m_max = std::max(m_max, m[i]);
    }
    const auto columns = static_cast<std::uint64_t>(k_max - k_min + 1);
    const auto rows = static_cast<std::uint64_t>(m_max - m_min + 1);
    if (rows * columns > binning.max_pixels) {
        throw Error(scan.source + ": binning at these steps gives " + std::to_string(rows) + " × " +
                    std::to_string(columns) + " pixels, more than " +
                    std::to_string(binning.max_pixels));
    }
    SphericalImages im =
        empty_images(static_cast<Eigen::Index>(rows), static_cast<Eigen::Index>(columns), scan);
    Eigen::ArrayXXd best = Eigen::ArrayXXd::Constant(im.rows, im.columns, 1e300);
    for (std::size_t i = 0; i < scan.size(); ++i) {
        const auto c = static_cast<Eigen::Index>(k_max - k[i]);
        const auto r = static_cast<Eigen::Index>(m_max - m[i]);
        // Off-centre distance in steps (the pixel's own units, both axes alike).
        const double du = polar[i].azimuth / binning.azimuth_step - static_cast<double>(k[i]);
        const double dv = polar[i].elevation / binning.elevation_step - static_cast<double>(m[i]);
        const double d2 = du * du + dv * dv;
        if (d2 >= best(r, c)) continue;
        best(r, c) = d2;
        im.valid(r, c) = true;
        im.intensity(r, c) = scan.intensity[i];
        im.range(r, c) = polar[i].range;
        im.azimuth(r, c) = polar[i].azimuth;
        im.elevation(r, c) = polar[i].elevation;
    }
    im.column_azimuth.resize(im.columns);
    for (Eigen::Index c = 0; c < im.columns; ++c)
        im.column_azimuth(c) = static_cast<double>(k_max - c) * binning.azimuth_step;
    im.row_elevation.resize(im.rows);
    for (Eigen::Index r = 0; r < im.rows; ++r)
        im.row_elevation(r) = static_cast<double>(m_max - r) * binning.elevation_step;
    im.azimuth_step = binning.azimuth_step;
    im.elevation_step = binning.elevation_step;
    return im;
}

Raster8 intensity_to_8bit(const SphericalImages& images, double low_quantile,
                          double high_quantile) {
    if (!(low_quantile >= 0.0 && low_quantile < high_quantile && high_quantile <= 1.0))
        throw Error("intensity_to_8bit: quantiles must satisfy 0 <= low < high <= 1");
    std::vector<double> values;
    values.reserve(static_cast<std::size_t>(images.valid.count()));
    for (Eigen::Index c = 0; c < images.columns; ++c)
        for (Eigen::Index r = 0; r < images.rows; ++r)
            if (images.valid(r, c)) values.push_back(images.intensity(r, c));
    Raster8 out;
    out.rows = static_cast<int>(images.rows);
    out.columns = static_cast<int>(images.columns);
    out.pixels.assign(static_cast<std::size_t>(images.rows * images.columns), 0);
    if (values.empty()) return out;
    auto quantile = [&](double q) {
        const auto k =
            static_cast<std::ptrdiff_t>(std::floor(q * static_cast<double>(values.size() - 1)));
        std::nth_element(values.begin(), values.begin() + k, values.end());
        return values[static_cast<std::size_t>(k)];
    };
    const double low = quantile(low_quantile);
    const double high = quantile(high_quantile);
    const double middle = quantile(0.5);
    const double scale = high > low ? 255.0 / (high - low) : 0.0;
    auto grey = [&](double v) {
        return static_cast<std::uint8_t>(std::lround(std::clamp((v - low) * scale, 0.0, 255.0)));
    };
    for (Eigen::Index r = 0; r < images.rows; ++r)
        for (Eigen::Index c = 0; c < images.columns; ++c)
            out.pixels[static_cast<std::size_t>(r * images.columns + c)] =
                grey(images.valid(r, c) ? images.intensity(r, c) : middle);
    return out;
}

Raster8 detection_mask(const SphericalImages& images, int margin) {
    if (margin < 0) throw Error("detection_mask: the margin must be >= 0");
    const Eigen::Index rows = images.rows, columns = images.columns;
    // Erosion by a (2·margin + 1)² square, separably: a pixel survives a pass when its whole
    // window along that axis lies inside the image and is valid (prefix sums of the valid).
    auto erode = [margin](const ImageMask& in, bool along_rows) {
        ImageMask out = ImageMask::Constant(in.rows(), in.cols(), false);
        const Eigen::Index lines = along_rows ? in.rows() : in.cols();
        const Eigen::Index length = along_rows ? in.cols() : in.rows();
        std::vector<Eigen::Index> prefix(static_cast<std::size_t>(length) + 1);
        for (Eigen::Index l = 0; l < lines; ++l) {
            prefix[0] = 0;
            for (Eigen::Index i = 0; i < length; ++i)
                prefix[static_cast<std::size_t>(i) + 1] =
                    prefix[static_cast<std::size_t>(i)] + (along_rows ? in(l, i) : in(i, l));
            for (Eigen::Index i = margin; i + margin < length; ++i) {
                const Eigen::Index n = prefix[static_cast<std::size_t>(i + margin + 1)] -
                                       prefix[static_cast<std::size_t>(i - margin)];
                if (n == 2 * margin + 1) (along_rows ? out(l, i) : out(i, l)) = true;
            }
        }
        return out;
    };
    const ImageMask kept = erode(erode(images.valid, true), false);
    Raster8 out;
    out.rows = static_cast<int>(rows);
    out.columns = static_cast<int>(columns);
    out.pixels.assign(static_cast<std::size_t>(rows * columns), 0);
    for (Eigen::Index r = 0; r < rows; ++r)
        for (Eigen::Index c = 0; c < columns; ++c)
            if (kept(r, c)) out.pixels[static_cast<std::size_t>(r * columns + c)] = 255;
    return out;
}

ImageMask pixels_in_boxes(const SphericalImages& images,
                          const std::vector<Eigen::AlignedBox3d>& project_boxes) {
    ImageMask inside = ImageMask::Constant(images.rows, images.columns, false);
    for (Eigen::Index r = 0; r < images.rows; ++r)
        for (Eigen::Index c = 0; c < images.columns; ++c) {
            if (!images.valid(r, c)) continue;
            const Eigen::Vector3d p =
                images.pose *
                cartesian_of({images.range(r, c), images.azimuth(r, c), images.elevation(r, c)});
            for (const auto& box : project_boxes)
                if (box.contains(p)) {
                    inside(r, c) = true;
                    break;
                }
        }
    return inside;
}

void restrict_mask(Raster8& mask, const ImageMask& region) {
    if (region.rows() != mask.rows || region.cols() != mask.columns)
        throw Error("restrict_mask: the region's size differs from the mask's");
    for (int r = 0; r < mask.rows; ++r)
        for (int c = 0; c < mask.columns; ++c)
            if (!region(r, c))
                mask.pixels[static_cast<std::size_t>(r) * static_cast<std::size_t>(mask.columns) +
                            static_cast<std::size_t>(c)] = 0;
}

}  // namespace tlsmon::keypoints
