#include "pipeline/primitive_reference.hpp"

#include "core/error.hpp"
#include "core/payload.hpp"

namespace tlsmon {

namespace {

void put_text(PayloadWriter& w, const std::string& s) {
    w.put_array(std::vector<char>(s.begin(), s.end()));
}

std::string get_text(PayloadReader& in) {
    const auto c = in.get_array<char>();
    return {c.begin(), c.end()};
}

}  // namespace

std::string PrimitiveReference::encode() const {
    PayloadWriter w;
    w.put<std::uint32_t>(kFormatVersion);
    for (int k = 0; k < 3; ++k) w.put<double>(scanner(k));
    w.put<std::uint64_t>(entries.size());
    for (const Entry& e : entries) {
        const primitives::Fit& f = e.fit;
        const primitives::Frame& fr = f.primitive.frame;
        put_text(w, e.zone);
        put_text(w, e.refused);
        w.put<std::uint8_t>(static_cast<std::uint8_t>(f.primitive.kind));
        w.put<std::uint8_t>(static_cast<std::uint8_t>(f.status));
        std::vector<double> frame;
        for (const auto* v : {&fr.origin, &fr.a, &fr.b1, &fr.b2})
            for (int k = 0; k < 3; ++k) frame.push_back((*v)(k));
        w.put_array(frame);
        w.put_array(
            std::vector<double>(f.primitive.x.data(), f.primitive.x.data() + f.primitive.x.size()));
        w.put_array(
            std::vector<double>(f.covariance.data(), f.covariance.data() + f.covariance.size()));
        for (const double v : {f.s0, f.rms, e.far_end}) w.put<double>(v);
        for (const std::uint64_t v : {std::uint64_t(f.candidates), std::uint64_t(f.used),
                                      e.seed_inliers, std::uint64_t(f.iterations)})
            w.put<std::uint64_t>(v);
    }
    return w.take();
}

PrimitiveReference PrimitiveReference::decode(std::string_view payload) {
    PayloadReader in(payload);
    if (const auto version = in.get<std::uint32_t>(); version != kFormatVersion) {
        throw Error("primitives stage payload: format " + std::to_string(version) + ", expected " +
                    std::to_string(kFormatVersion));
    }
    PrimitiveReference r;
    for (int k = 0; k < 3; ++k) r.scanner(k) = in.get<double>();
    const auto n = in.get<std::uint64_t>();
    for (std::uint64_t i = 0; i < n; ++i) {
        Entry e;
        e.zone = get_text(in);
        e.refused = get_text(in);
        const auto kind = in.get<std::uint8_t>(), status = in.get<std::uint8_t>();
        if (kind > 2 || status > 3) throw Error("primitives stage payload: a malformed entry");
        primitives::Fit& f = e.fit;
        f.primitive.kind = static_cast<primitives::Kind>(kind);
        f.status = static_cast<primitives::FitStatus>(status);
        const auto frame = in.get_array<double>();
        const auto x = in.get_array<double>();
        const auto cov = in.get_array<double>();
        const auto u = static_cast<std::size_t>(primitives::parameter_count(f.primitive.kind));
        if (frame.size() != 12 || x.size() != u || (cov.size() != u * u && !cov.empty()))
            throw Error("primitives stage payload: an entry of inconsistent sizes");
        primitives::Frame& fr = f.primitive.frame;
        fr.origin = {frame[0], frame[1], frame[2]};
        fr.a = {frame[3], frame[4], frame[5]};
        fr.b1 = {frame[6], frame[7], frame[8]};
        fr.b2 = {frame[9], frame[10], frame[11]};
        f.primitive.x = Eigen::Map<const Eigen::VectorXd>(x.data(), Eigen::Index(u));
        if (!cov.empty())
            f.covariance =
                Eigen::Map<const Eigen::MatrixXd>(cov.data(), Eigen::Index(u), Eigen::Index(u));
        f.s0 = in.get<double>();
        f.rms = in.get<double>();
        e.far_end = in.get<double>();
        f.candidates = in.get<std::uint64_t>();
        f.used = in.get<std::uint64_t>();
        e.seed_inliers = in.get<std::uint64_t>();
        f.iterations = static_cast<int>(in.get<std::uint64_t>());
        r.entries.push_back(std::move(e));
    }
    return r;
}

}  // namespace tlsmon
