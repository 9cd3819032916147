// Runs a fuzz target on files (or every file of directories) given on the command line: the
// corpus as a regression test, with no fuzzer needed (gcc, CTest).
#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <vector>

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, std::size_t size);

int main(int argc, char** argv) {
    int files = 0;
    for (int a = 1; a < argc; ++a) {
        std::vector<std::filesystem::path> paths;
        if (std::filesystem::is_directory(argv[a])) {
            for (const auto& e : std::filesystem::directory_iterator(argv[a])) paths.push_back(e.path());
        } else {
            paths.push_back(argv[a]);
        }
        std::sort(paths.begin(), paths.end());
        for (const auto& p : paths) {
            std::ifstream f(p, std::ios::binary);
            if (!f) {
                std::fprintf(stderr, "replay: cannot read %s\n", p.string().c_str());
                return 2;
            }
            const std::vector<uint8_t> bytes((std::istreambuf_iterator<char>(f)), std::istreambuf_iterator<char>());
            LLVMFuzzerTestOneInput(bytes.data(), bytes.size());
            ++files;
        }
    }
    std::printf("replay: %d inputs ran clean\n", files);
    return files > 0 ? 0 : 2;
}
