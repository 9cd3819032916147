#pragma once
// The main job's scene: the crowd's layout, its camera path, the cloth budget, the run's length and
// viewport, and the imported characters; read from and written to JSON.

#include <string>
#include <vector>

#include "Plaza.h"
#include "crowdcloth/core/Status.h"

namespace crowd {

/// Limits shared by the scene file and the command line, so both reject the same values.
struct SceneLimits {
    static constexpr int kMaxCharacters = 100000;
    static constexpr double kMaxSeconds = 3600.0;
    static constexpr int kMinViewport = 16, kMaxViewport = 8192;
    static constexpr double kMaxBudgetMs = 10000.0;
};

struct Scene {
    /// The crowd; its `bodies` are not part of the file (they come from `assets`).
    PlazaSettings plaza;
    double budgetMs = 12.0;   ///< [ms] cloth wall time per frame
    double seconds = 10.0;    ///< [s] simulated at 60 Hz
    int width = 960, height = 540;
    /// Imported characters (paths from the working directory; in the file, relative to the file),
    /// the clip they play, their standing height [m] (0 = as authored).
    std::vector<std::string> assets;
    std::string clip;
    double assetHeight = 0.0;
};

/// The built-in scene: its camera path is empty, i.e. the built-in one for however many characters.
Scene defaultScene();
/// Reads a scene; an error names the file and the key (unknown keys and wrong types are errors).
/// Keys that are absent keep their defaultScene() values.
cc::Result<Scene> readScene(const std::string& path);
/// Writes every key of the scene (an empty camera path is written as the built-in one).
cc::Status writeScene(const Scene& scene, const std::string& path);

} // namespace crowd
