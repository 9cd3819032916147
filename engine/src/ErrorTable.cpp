// Error tables (crowdcloth/ErrorTable.h): checks, the key, the text form and the on-disk cache.
// The cook itself (measuring) is ErrorTableCook.cpp.
#include "crowdcloth/ErrorTable.h"

#include <cinttypes>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "CookedAsset.h"
#include "crowdcloth/World.h"
#include "crowdcloth/core/Hash.h"

namespace cc {
namespace {

/// Bumped whenever the measuring method changes what a table holds: old caches then miss.
constexpr uint64_t kMethodVersion = 1;

constexpr const char* kMagic = "crowdcloth-error-table";

template <typename T>
uint64_t mix(uint64_t h, const T& value) {
    return hashBytes(&value, sizeof value, h);
}

std::string hexDouble(double v) {
    char text[64];
    std::snprintf(text, sizeof text, "%a", v);
    return text;
}

/// Reads the words of one line that must start with `name`, as doubles (hexadecimal floats or
/// decimals); fails naming the line.
Result<std::vector<double>> numbersAfter(std::istream& in, const char* name, std::size_t count) {
    std::string line;
    if (!std::getline(in, line)) return Status::invalidArgument(std::string("error table: missing line '") + name + "'");
    std::istringstream words(line);
    std::string word;
    words >> word;
    if (word != name)
        return Status::invalidArgument(std::string("error table: expected '") + name + "', found '" + word + "'");
    std::vector<double> values;
    while (words >> word) {
        char* end = nullptr;
        const double v = std::strtod(word.c_str(), &end);
        if (end == word.c_str() || *end != '\0')
            return Status::invalidArgument(std::string("error table: '") + name + "': not a number: " + word);
        values.push_back(v);
    }
    if (values.size() != count)
        return Status::invalidArgument(std::string("error table: '") + name + "' needs " + std::to_string(count) +
                                       " numbers, has " + std::to_string(values.size()));
    return values;
}

bool finiteAtLeastZero(const std::vector<double>& values) {
    for (double v : values)
        if (!std::isfinite(v) || v < 0.0) return false;
    return true;
}

} // namespace

Status ErrorCookDesc::validate() const {
    if (!(seconds >= 1.0 && seconds <= 60.0)) return Status::invalidArgument("ErrorCookDesc.seconds must be in [1, 60]");
    if (!(windowSeconds >= 0.05 && windowSeconds <= 2.0))
        return Status::invalidArgument("ErrorCookDesc.windowSeconds must be in [0.05, 2]");
    if (seconds < 0.5 + windowSeconds)
        return Status::invalidArgument("ErrorCookDesc.seconds must leave room for a window after the first 0.5 s");
    if (referenceSubsteps < 2 || referenceSubsteps > 64)
        return Status::invalidArgument("ErrorCookDesc.referenceSubsteps must be in [2, 64]");
    if (referenceIterations < 1 || referenceIterations > 100)
        return Status::invalidArgument("ErrorCookDesc.referenceIterations must be in [1, 100]");
    return Status::ok();
}

Status ErrorTable::validate() const {
    if (Status s = cook.validate(); !s) return Status::invalidArgument("ErrorTable.cook: " + s.message());
    if (errorPerRadius.empty() || errorPerRadius.size() % kMotions != 0)
        return Status::invalidArgument("ErrorTable.errorPerRadius must hold levels x " + std::to_string(kMotions) + " values");
    if (medianErrorPerRadius.size() != errorPerRadius.size())
        return Status::invalidArgument("ErrorTable.medianErrorPerRadius must be as long as errorPerRadius");
    if (!finiteAtLeastZero(errorPerRadius) || !finiteAtLeastZero(medianErrorPerRadius))
        return Status::invalidArgument("ErrorTable: errors must be finite and >= 0");
    for (uint32_t m = 0; m < kMotions; ++m)
        if (!std::isfinite(speeds[m]) || speeds[m] < 0.0 || (m > 0 && !(speeds[m] > speeds[m - 1])))
            return Status::invalidArgument("ErrorTable.speeds must be finite, >= 0 and ascending");
    if (windows == 0) return Status::invalidArgument("ErrorTable.windows must be > 0");
    return Status::ok();
}

std::string ErrorTable::toText() const {
    std::ostringstream out;
    out << kMagic << ' ' << kFormatVersion << '\n';
    char key16[32];
    std::snprintf(key16, sizeof key16, "%016" PRIx64, key);
    out << "key " << key16 << '\n';
    out << "cook " << hexDouble(cook.seconds) << ' ' << hexDouble(cook.windowSeconds) << ' ' << cook.referenceSubsteps
        << ' ' << cook.referenceIterations << '\n';
    out << "speeds";
    for (double s : speeds) out << ' ' << hexDouble(s);
    out << "\nwindows " << windows << "\nlevels " << levelCount() << '\n';
    out << "# level: error / radius, 95th percentile per motion, then the median per motion\n";
    for (uint32_t l = 0; l < levelCount(); ++l) {
        out << "level";
        for (const std::vector<double>* column : {&errorPerRadius, &medianErrorPerRadius})
            for (uint32_t m = 0; m < kMotions; ++m) out << ' ' << hexDouble((*column)[l * kMotions + m]);
        out << '\n';
    }
    out << "end\n";  // a file cut anywhere, even inside a number, lacks it
    return out.str();
}

Result<ErrorTable> ErrorTable::fromText(const std::string& text) {
    std::istringstream in(text);
    std::string magic;
    uint32_t version = 0;
    in >> magic >> version;
    if (magic != kMagic) return Status::invalidArgument("error table: not an error table (no '" + std::string(kMagic) + "')");
    if (version != kFormatVersion)
        return Status::invalidArgument("error table: format version " + std::to_string(version) + ", this build reads " +
                                       std::to_string(kFormatVersion));
    in.ignore(1);
    ErrorTable t;
    std::string word, keyText;
    in >> word >> keyText;
    if (word != "key" || keyText.size() != 16) return Status::invalidArgument("error table: expected 'key' and 16 hex digits");
    char* end = nullptr;
    t.key = std::strtoull(keyText.c_str(), &end, 16);
    if (*end != '\0') return Status::invalidArgument("error table: key is not hexadecimal: " + keyText);
    in.ignore(1);
    auto cook = numbersAfter(in, "cook", 4);
    if (!cook.isOk()) return cook.status();
    const std::vector<double>& c = cook.value();
    if (!(c[2] >= 0.0 && c[2] <= 1e6 && c[3] >= 0.0 && c[3] <= 1e6))  // before the casts (validate names them)
        return Status::invalidArgument("error table: the cook's substeps and iterations must be counts");
    t.cook.seconds = c[0];
    t.cook.windowSeconds = c[1];
    t.cook.referenceSubsteps = uint32_t(c[2]);
    t.cook.referenceIterations = uint32_t(c[3]);
    auto speeds = numbersAfter(in, "speeds", kMotions);
    if (!speeds.isOk()) return speeds.status();
    for (uint32_t m = 0; m < kMotions; ++m) t.speeds[m] = speeds.value()[m];
    auto windows = numbersAfter(in, "windows", 1);
    auto levels = windows.isOk() ? numbersAfter(in, "levels", 1) : windows;
    if (!levels.isOk()) return levels.status();
    if (!(windows.value()[0] >= 1.0 && windows.value()[0] <= 1e6 && levels.value()[0] >= 1.0 && levels.value()[0] <= 64.0))
        return Status::invalidArgument("error table: windows must be in [1, 1e6] and levels in [1, 64]");
    t.windows = uint32_t(windows.value()[0]);
    const uint32_t levelCount = uint32_t(levels.value()[0]);
    std::string comment;
    std::getline(in, comment);
    for (uint32_t l = 0; l < levelCount; ++l) {
        auto row = numbersAfter(in, "level", 2 * kMotions);
        if (!row.isOk()) return Status::invalidArgument(row.status().message() + " (level " + std::to_string(l) + ")");
        for (uint32_t m = 0; m < kMotions; ++m) {
            t.errorPerRadius.push_back(row.value()[m]);
            t.medianErrorPerRadius.push_back(row.value()[kMotions + m]);
        }
    }
    std::string last;
    std::getline(in, last);
    if (last != "end") return Status::invalidArgument("error table: truncated (no 'end' after the levels)");
    if (Status s = t.validate(); !s) return s;
    return t;
}

// Pool adjacent violators: the least-squares non-increasing fit of each motion's column.
ErrorTable ErrorTable::nonIncreasingInLevel() const {
    ErrorTable table = *this;
    const uint32_t n = table.levelCount();
    for (std::vector<double>* column : {&table.errorPerRadius, &table.medianErrorPerRadius})
        for (uint32_t m = 0; m < ErrorTable::kMotions; ++m) {
            // Blocks of pooled levels: their mean and size; a block above its predecessor merges.
            std::vector<std::pair<double, uint32_t>> blocks;
            for (uint32_t l = 0; l < n; ++l) {
                blocks.push_back({(*column)[l * ErrorTable::kMotions + m], 1});
                while (blocks.size() > 1 && blocks.back().first > blocks[blocks.size() - 2].first) {
                    const auto [mean, size] = blocks.back();
                    blocks.pop_back();
                    auto& into = blocks.back();
                    into.first = (into.first * into.second + mean * size) / (into.second + size);
                    into.second += size;
                }
            }
            uint32_t l = 0;
            for (const auto& [mean, size] : blocks)
                for (uint32_t k = 0; k < size; ++k, ++l) (*column)[l * ErrorTable::kMotions + m] = mean;
        }
    return table;
}

uint64_t errorTableKey(const ClothAssetDesc& design, const WorldDesc& world, const ErrorCookDesc& cook) {
    uint64_t h = mix(kHashSeed, kMethodVersion);
    h = mix(h, detail::designFingerprint(design));
    // The effort every level runs under (WorldDesc::effortAt) and the forces.
    h = mix(h, world.substeps);
    h = mix(h, world.solverIterations);
    h = mix(h, world.strainLimit);
    for (double g : world.gravity) h = mix(h, g);
    h = mix(h, cook.seconds);
    h = mix(h, cook.windowSeconds);
    h = mix(h, cook.referenceSubsteps);
    return mix(h, cook.referenceIterations);
}

Result<ErrorTable> loadOrCookErrorTable(const std::string& directory, const ClothAssetDesc& design,
                                        const WorldDesc& world, const ErrorCookDesc& cook) {
    namespace fs = std::filesystem;
    const uint64_t key = errorTableKey(design, world, cook);
    char name[40];
    std::snprintf(name, sizeof name, "%016" PRIx64 ".errors", key);
    const fs::path path = fs::path(directory) / name;
    if (std::ifstream file{path}) {
        std::stringstream text;
        text << file.rdbuf();
        auto cached = ErrorTable::fromText(text.str());
        if (cached.isOk() && cached.value().key == key) return cached;
    }
    auto cooked = cookErrorTable(design, world, cook);
    if (!cooked.isOk()) return cooked;
    std::error_code ec;
    fs::create_directories(directory, ec);
    // Written whole, then renamed: a reader never sees half a table, and two cooks racing agree.
    const fs::path temporary = path.string() + ".partial";
    {
        std::ofstream out(temporary, std::ios::trunc);
        out << cooked.value().toText();
        if (!out) return Status::invalidArgument("loadOrCookErrorTable: cannot write " + temporary.string());
    }
    fs::rename(temporary, path, ec);
    if (ec) return Status::invalidArgument("loadOrCookErrorTable: cannot rename to " + path.string() + ": " + ec.message());
    return cooked;
}

} // namespace cc
