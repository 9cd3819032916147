#pragma once
// The main job's command line (CLI11): the scene (built-in or --scene FILE, overridden by options),
// what to write, and the studies.

#include <string>

#include "SceneFile.h"

namespace crowd {

/// How garments are coloured in the frames: their own colours, or an overlay from their stats.
enum class ColorBy { None, Lod, Solver, Error };
/// What --export writes per rendered frame.
enum class ExportFormat { None, Obj, Glb };

struct RunOptions {
    Scene scene;
    std::string sceneFile;   ///< empty = the built-in scene
    std::string writeScene;  ///< write the scene here and exit
    std::string out = "crowd_out";
    int renderEvery = 4;
    bool render = true;
    bool video = true;
    bool frameStats = false;
    ExportFormat exportFormat = ExportFormat::None;
    ColorBy colorBy = ColorBy::None;
    int supersample = 1;
    int threads = 0;
    bool fullResolution = false;  ///< every garment at its finest level, every frame (no budget)
    bool fixedCosts = false;      ///< WorldDesc::fixedCostModel: the schedule repeats, whatever the timing
    std::string errorTables;      ///< cache of measured error tables (PlazaSettings::errorTables); empty = none
    int preset = -1;              ///< a cc::QualityPreset for the World; -1 = the default WorldDesc
    bool garmentSelfCollision = false;  ///< WorldDesc::selfCollision: on for garments seen large
    double churn = 0.0;           ///< [1/s] share of the crowd replaced per second (a soak's joins and leaves)
    bool scaling = false, tradeoff = false, batch = false, snapshot = false, selfCollision = false;
    int shadow = 8;               ///< --scaling: garments the shadow check follows at once (0 = off)
    double shadowWindow = 0.25;   ///< [s] --scaling: the shadow check's window
};

/// Parses argv into `options`. Returns -1 to go on, else the exit code: 0 after --help, non-zero
/// after an error (printed naming the option or the scene file and key).
int parseCommandLine(int argc, char** argv, RunOptions& options);

const char* colorByName(ColorBy c);

} // namespace crowd
