// The keypoint stage's work on one epoch (issue 12: < 10 s on 2 cores), with the stage's own
// functions (pipeline/keypoint_stage.hpp) and the zones of the simulated pier (its south
// face, the face's 10 m bands, the west face): step by step — spherical images, detection,
// description, matching, 3-D (with the patch refinement), filtering and segments. The
// reference product is built first and reported apart (the pipeline builds it once and keeps
// it in the reference cache); reading the files is not counted.
//
//   bench_keypoint_stage REFERENCE.ptx EPOCH.ptx [DETECTOR [REFINE(0|1) [bands|zones
//                        [DETECTOR_THRESHOLD]]]]
//
// e.g. two epochs of `tlsmon simulate --preset pier --epochs 2 --out /tmp/pier`. No
// registration: the epochs' drift shows in the vectors, not in the times.
#include "pipeline/keypoint_stage.hpp"

#include <time.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <string>

#include "bench/bench_support.hpp"
#include "formats/scan_file.hpp"
#include "simulator/scene.hpp"

namespace {

using namespace tlsmon;
using Clock = std::chrono::steady_clock;

double since(Clock::time_point t0) {
    return bench::seconds_since(t0);
}
double process_cpu() {
    return bench::process_cpu_seconds();
}

}  // namespace

int main(int argc, char** argv) {
    if (argc < 3) {
        std::fprintf(stderr,
                     "usage: bench_keypoint_stage REFERENCE EPOCH [DETECTOR [REFINE [bands|zones "
                     "[DETECTOR_THRESHOLD]]]]\n");
        return 2;
    }
    KeypointConfig config;
    if (argc > 3) config.detector = argv[3];
    if (argc > 4) config.refine = std::atoi(argv[4]) != 0;
    if (argc > 5 && std::string(argv[5]) == "bands") config.segments = KeypointSegments::bands;
    if (argc > 6) config.detector_threshold = std::atof(argv[6]);
    const auto& p = sim::preset_pier().pier;
    const ZoneShape south =
        box_zone("south", {p.x0 + 0.5, p.y0 - 0.5, 1.0}, {p.x1 - 0.5, p.y0 + 0.5, p.height - 1.0});
    config.zones.push_back(south);
    for (auto& b : bands_of(south, 2, 10.0, 0.0, p.height)) config.zones.push_back(b);
    config.zones.push_back(
        box_zone("west", {p.x0 - 0.5, p.y0 + 0.5, 1.0}, {p.x0 + 0.5, p.y1 - 0.5, p.height - 1.0}));

    auto t0 = Clock::now();
    const auto reference_scans = read_scans(argv[1]);
    const auto epoch_scans = read_scans(argv[2]);
    std::printf("read both files: %.2f s (not counted)\n", since(t0));

    t0 = Clock::now();
    double cpu0 = process_cpu();
    const KeypointReference reference = prepare_keypoint_reference(config, reference_scans);
    std::printf("reference: %zu keypoints detected, %zu kept: %.2f s wall, %.2f s CPU (cached)\n",
                reference.detected(), reference.keypoints(), since(t0), process_cpu() - cpu0);

    t0 = Clock::now();
    cpu0 = process_cpu();
    KeypointEpoch epoch = measure_keypoints(config, reference, epoch_scans, StageOutputs{});
    const std::size_t in_3d = epoch.matches.size();
    const KeypointSegmentsResult segments =
        keypoint_segments(config, reference, std::move(epoch.matches), StageOutputs{});
    const double wall = since(t0), cpu = process_cpu() - cpu0;
    std::size_t defined = 0, kept = 0;
    for (const auto& s : segments.segments) {
        defined += s.displacement.defined();
        kept += s.displacement.count;
    }
    std::printf(
        "%s + %s, refine %d, %s: %zu detected, %zu described, %zu matched, %zu in 3-D "
        "(%zu not found by the patch), %zu kept in %zu of %zu segments\n",
        config.detector.c_str(), config.descriptor.c_str(), config.refine ? 1 : 0,
        config.segments == KeypointSegments::zones ? "zones" : "bands", epoch.detected,
        epoch.described, epoch.pairs, in_3d, epoch.dropped_patch, kept, defined,
        segments.segments.size());
    std::printf(
        "epoch steps, s wall: images %.2f, detection %.2f, description %.2f, matching %.2f, "
        "3-D %.2f, filtering %.2f; total %.2f s wall, %.2f s CPU\n",
        epoch.images_s, epoch.detection_s, epoch.description_s, epoch.matching_s, epoch.to_3d_s,
        segments.filtering_s, wall, cpu);
    return 0;
}
