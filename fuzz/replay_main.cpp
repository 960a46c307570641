// Replays files (or every file under directories) through LLVMFuzzerTestOneInput, so ordinary
// builds compile every fuzz target and ctest runs the corpus as plain tests. `--shard=i/n` replays
// only the i-th of n shares of the sorted file list (every n-th file from the i-th), so that a slow
// corpus can run as n tests in parallel.
#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size);

int main(int argc, char** argv) {
    namespace fs = std::filesystem;
    std::vector<fs::path> files;
    unsigned long shard = 0, shards = 1;
    for (int i = 1; i < argc; ++i) {
        const std::string arg = argv[i];
        if (arg.rfind("--shard=", 0) == 0) {
            if (std::sscanf(arg.c_str(), "--shard=%lu/%lu", &shard, &shards) != 2 || shards == 0 || shard >= shards) {
                std::fprintf(stderr, "bad %s: expected --shard=i/n with i < n\n", arg.c_str());
                return 2;
            }
            continue;
        }
        const fs::path p(arg);
        if (fs::is_directory(p)) {
            for (const auto& e : fs::recursive_directory_iterator(p))
                if (e.is_regular_file() && e.path().filename().string()[0] != '.' && e.path().extension() != ".md")
                    files.push_back(e.path());
        } else {
            files.push_back(p);
        }
    }
    std::sort(files.begin(), files.end());
    std::vector<fs::path> mine;
    for (std::size_t i = shard; i < files.size(); i += shards) mine.push_back(files[i]);
    files.swap(mine);
    for (const auto& f : files) {
        std::ifstream in(f, std::ios::binary);
        const std::vector<char> bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
        LLVMFuzzerTestOneInput(reinterpret_cast<const std::uint8_t*>(bytes.data()), bytes.size());
    }
    std::printf("replayed %zu inputs\n", files.size());
    return 0;
}
