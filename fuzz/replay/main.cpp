// A main for the fuzz targets without libFuzzer (gcc): runs LLVMFuzzerTestOneInput once on
// each file given, or on each file in each folder given, and exits. Built with the
// sanitizers, this replays the seed corpora in CI without fuzzing. Options (-runs=0 and
// the like, which libFuzzer would take) are ignored, so fuzz/run.sh --replay calls both
// kinds of binary the same way. A crash or sanitizer report ends the process; the last
// "Running:" line names the input.
#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <vector>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size);

namespace {

namespace fs = std::filesystem;

void run_one(const fs::path& file) {
    std::fprintf(stderr, "Running: %s\n", file.c_str());
    std::ifstream in(file, std::ios::binary);
    const std::vector<std::uint8_t> bytes{std::istreambuf_iterator<char>(in), {}};
    if (!in.eof() && in.fail()) {
        std::fprintf(stderr, "cannot read %s\n", file.c_str());
        std::exit(2);
    }
    LLVMFuzzerTestOneInput(bytes.data(), bytes.size());
}

}  // namespace

int main(int argc, char** argv) {
    std::vector<fs::path> inputs;
    for (int i = 1; i < argc; ++i) {
        if (argv[i][0] == '-') continue;
        const fs::path p = argv[i];
        if (fs::is_directory(p)) {
            std::vector<fs::path> files;
            for (const auto& e : fs::directory_iterator(p)) {
                if (e.is_regular_file()) files.push_back(e.path());
            }
            std::sort(files.begin(), files.end());  // the same order in every run
            inputs.insert(inputs.end(), files.begin(), files.end());
        } else {
            inputs.push_back(p);
        }
    }
    for (const auto& file : inputs) run_one(file);
    std::fprintf(stderr, "replayed %zu inputs\n", inputs.size());
    return 0;
}
