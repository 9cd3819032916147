#include "ExternalTools.h"

#include <filesystem>

#include <spawn.h>
#include <sys/wait.h>

extern char** environ;

namespace crowd {
namespace {

// Debian's interpreter, not whatever `python3` is first on PATH (a pyenv shim may lack matplotlib).
const char* kPython = "/usr/bin/python3";
constexpr int kPlotNeedsMatplotlib = 3;  // scripts/plot-summary.py's exit code without matplotlib

} // namespace

int runProgram(const std::vector<std::string>& argv) {
    std::vector<char*> args;
    args.reserve(argv.size() + 1);
    for (const std::string& a : argv) args.push_back(const_cast<char*>(a.c_str()));
    args.push_back(nullptr);
    pid_t pid = 0;
    if (posix_spawnp(&pid, args[0], nullptr, nullptr, args.data(), environ) != 0) return 127;
    int status = 0;
    if (waitpid(pid, &status, 0) < 0) return 127;
    return WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
}

cc::Status encodeVideo(const std::string& frameDir, int renderEvery, const std::string& mp4Path) {
    const int code = runProgram({"ffmpeg", "-loglevel", "error", "-y", "-framerate", "60/" + std::to_string(renderEvery),
                                 "-i", (std::filesystem::path(frameDir) / "frame_%05d.png").string(), "-vf",
                                 "pad=ceil(iw/2)*2:ceil(ih/2)*2", "-c:v", "libx264", "-pix_fmt", "yuv420p", mp4Path});
    if (code == 127) return cc::Status::invalidArgument("ffmpeg not found (apt-get install ffmpeg)");
    if (code != 0) return cc::Status::invalidArgument("ffmpeg failed with exit code " + std::to_string(code));
    return cc::Status::ok();
}

namespace {

cc::Status runPlotScript(const char* script, const std::string& csvPath, const std::string& pngPath) {
    if (!std::filesystem::exists(kPython))
        return cc::Status::invalidArgument(std::string(kPython) + " not found (apt-get install python3-matplotlib)");
    const int code = runProgram({kPython, script, csvPath, pngPath});
    if (code == kPlotNeedsMatplotlib)
        return cc::Status::invalidArgument(std::string(kPython) + " has no matplotlib (apt-get install python3-matplotlib)");
    if (code != 0)
        return cc::Status::invalidArgument(std::string(script) + " failed with exit code " + std::to_string(code));
    return cc::Status::ok();
}

} // namespace

cc::Status plotSummary(const std::string& csvPath, const std::string& pngPath) {
    return runPlotScript(CC_CROWD_PLOT_SCRIPT, csvPath, pngPath);
}

cc::Status plotTradeoff(const std::string& csvPath, const std::string& pngPath) {
    return runPlotScript(CC_CROWD_TRADEOFF_SCRIPT, csvPath, pngPath);
}

} // namespace crowd
