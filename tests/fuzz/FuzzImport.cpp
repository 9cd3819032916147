// Fuzz target: the import gate (importCharacter: size cap, format sniffing, assimp's parse, the
// conversion to a Character, its way back from the parsing process and its validation) on any
// bytes under any extension it knows. The gate must hand back a character that passes
// Character::validate() or an error whose message starts with the file's path; never a crash, a
// hang, a huge allocation or a leak in the caller. The parse runs isolated in a child process, as
// shipped: in this process assimp 5.2.5 itself crashes within the first few dozen mutations
// (a SEGV in its parsers, found by this fuzzer at once), which is why the gate isolates it.
// Built for libFuzzer with -DCC_BUILD_FUZZERS=ON (clang; scripts/run-fuzz.sh), and always as
// cc_fuzz_import_replay, which runs the committed corpus (tests/fuzz/import_corpus) in CTest.
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <system_error>
#include <filesystem>
#include <fstream>
#include <string>

#include <unistd.h>

#include "ImportInput.h"
#include "crowdcloth/import/CharacterIO.h"

namespace {

namespace fs = std::filesystem;

/// This process's folder for the file under test; removed when the process exits.
struct WorkDir {
    fs::path path = fs::temp_directory_path() / ("cc_fuzz_import_" + std::to_string(::getpid()));
    WorkDir() { fs::create_directories(path); }
    ~WorkDir() {
        std::error_code ignored;
        fs::remove_all(path, ignored);
    }
};

const fs::path& workDir() {
    static const WorkDir dir;
    return dir.path;
}

[[noreturn]] void broken(const std::string& what) {
    std::fprintf(stderr, "import gate broke its promise: %s\n", what.c_str());
    std::abort();
}

} // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, std::size_t size) {
    const cc::fuzz::ImportInput in = cc::fuzz::decodeImportInput(data, size);
    const std::string path = (workDir() / (std::string("input.") + in.extension)).string();
    {
        std::ofstream file(path, std::ios::binary | std::ios::trunc);
        file.write(reinterpret_cast<const char*>(in.bytes), std::streamsize(in.size));
    }
    cc::ImportSettings settings;
    settings.timeoutSeconds = 10.0;                // a parse that hangs is an error, not the fuzzer's timeout
    settings.maxFileBytes = std::size_t(1) << 20;  // the fuzzer's inputs are small; the cap is part of the gate
    const cc::Result<cc::Character> character = cc::importCharacter(path, settings);
    if (character.isOk()) {
        if (cc::Status s = character.value().validate(); !s) broken(path + " read as an invalid character: " + s.message());
    } else if (character.status().message().rfind(path, 0) != 0) {
        broken("the error does not start with the file's path: " + character.status().message());
    }
    std::error_code ignored;
    fs::remove(path, ignored);
    return 0;
}
