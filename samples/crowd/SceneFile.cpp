#include "SceneFile.h"

#include <cmath>
#include <filesystem>
#include <fstream>
#include <functional>
#include <map>
#include <stdexcept>

#include <nlohmann/json.hpp>

#include "JsonText.h"

namespace crowd {
namespace {

using Json = nlohmann::json;

/// A problem at one key; readScene turns it into a Status naming the file.
struct SceneError : std::runtime_error {
    using std::runtime_error::runtime_error;
};

double number(const Json& j, const std::string& key, double lo, double hi) {
    if (!j.is_number()) throw SceneError("'" + key + "' must be a number, not " + j.type_name());
    const double v = j.get<double>();
    if (!std::isfinite(v) || v < lo || v > hi)
        throw SceneError("'" + key + "' is " + j.dump() + ", must be in [" + Json(lo).dump() + ", " + Json(hi).dump() + "]");
    return v;
}

int integer(const Json& j, const std::string& key, int lo, int hi) {
    if (!j.is_number_integer()) throw SceneError("'" + key + "' must be an integer, not " + j.dump());
    return int(number(j, key, lo, hi));
}

std::string text(const Json& j, const std::string& key) {
    if (!j.is_string()) throw SceneError("'" + key + "' must be a string, not " + j.type_name());
    return j.get<std::string>();
}

std::array<double, 3> vec3(const Json& j, const std::string& key) {
    if (!j.is_array() || j.size() != 3) throw SceneError("'" + key + "' must be an array of 3 numbers");
    std::array<double, 3> v{};
    for (int k = 0; k < 3; ++k) v[k] = number(j[k], key + "[" + std::to_string(k) + "]", -1e6, 1e6);
    return v;
}

/// Calls the handler of each key of an object; a key without one is an error.
void forEachKey(const Json& j, const std::string& where,
                const std::map<std::string, std::function<void(const Json&, const std::string&)>>& handlers) {
    if (!j.is_object()) throw SceneError("'" + where + "' must be an object, not " + j.type_name());
    for (const auto& [key, value] : j.items()) {
        const std::string path = where.empty() ? key : where + "." + key;
        const auto h = handlers.find(key);
        if (h == handlers.end()) {
            std::string known;
            for (const auto& [name, unused] : handlers) known += (known.empty() ? "" : ", ") + name;
            throw SceneError("unknown key '" + path + "' (known here: " + known + ")");
        }
        h->second(value, path);
    }
}

CameraKey cameraKey(const Json& j, const std::string& where) {
    CameraKey k;
    forEachKey(j, where,
               {{"time", [&](const Json& v, const std::string& p) { k.time = number(v, p, 0.0, 1e6); }},
                {"eye", [&](const Json& v, const std::string& p) { k.eye = vec3(v, p); }},
                {"target", [&](const Json& v, const std::string& p) { k.target = vec3(v, p); }},
                {"follow", [&](const Json& v, const std::string& p) {
                     k.follow = integer(v, p, -1, SceneLimits::kMaxCharacters - 1);
                 }}});
    return k;
}

Scene parse(const Json& root, const std::filesystem::path& directory) {
    Scene s = defaultScene();
    PlazaSettings& c = s.plaza;
    forEachKey(
        root, "",
        {{"characters", [&](const Json& v, const std::string& p) { c.characters = integer(v, p, 1, SceneLimits::kMaxCharacters); }},
         {"spacing", [&](const Json& v, const std::string& p) { c.spacing = number(v, p, 0.5, 100.0); }},
         {"runnerFraction", [&](const Json& v, const std::string& p) { c.runnerFraction = number(v, p, 0.0, 1.0); }},
         {"idleFraction", [&](const Json& v, const std::string& p) { c.idleFraction = number(v, p, 0.0, 1.0); }},
         {"stopStartFraction", [&](const Json& v, const std::string& p) { c.stopStartFraction = number(v, p, 0.0, 1.0); }},
         {"seed",
          [&](const Json& v, const std::string& p) {
              if (!v.is_number_integer()) throw SceneError("'" + p + "' must be an integer, not " + v.dump());
              c.seed = uint32_t(number(v, p, 0.0, 4294967295.0));
          }},
         {"garments",
          [&](const Json& v, const std::string& p) {
              forEachKey(v, p,
                         {{"cape", [&](const Json& x, const std::string& q) { c.garments.cape = number(x, q, 0.0, 1e6); }},
                          {"skirt", [&](const Json& x, const std::string& q) { c.garments.skirt = number(x, q, 0.0, 1e6); }},
                          {"dress", [&](const Json& x, const std::string& q) { c.garments.dress = number(x, q, 0.0, 1e6); }},
                          {"poncho", [&](const Json& x, const std::string& q) { c.garments.poncho = number(x, q, 0.0, 1e6); }}});
          }},
         {"velocityDamping", [&](const Json& v, const std::string& p) { c.velocityDamping = number(v, p, 0.0, 1000.0); }},
         {"stiffnessDamping", [&](const Json& v, const std::string& p) { c.stiffnessDamping = number(v, p, 0.0, 10.0); }},
         {"inertiaScale", [&](const Json& v, const std::string& p) { c.inertiaScale = number(v, p, 0.0, 1.0); }},
         {"walkSpeed", [&](const Json& v, const std::string& p) { c.walkSpeed = number(v, p, 0.0, 20.0); }},
         {"camera",
          [&](const Json& v, const std::string& p) {
              if (!v.is_array()) throw SceneError("'" + p + "' must be an array of camera keys");
              c.camera.clear();
              for (std::size_t i = 0; i < v.size(); ++i) c.camera.push_back(cameraKey(v[i], p + "[" + std::to_string(i) + "]"));
          }},
         {"budgetMs", [&](const Json& v, const std::string& p) { s.budgetMs = number(v, p, 0.01, SceneLimits::kMaxBudgetMs); }},
         {"seconds", [&](const Json& v, const std::string& p) { s.seconds = number(v, p, 1.0 / 60.0, SceneLimits::kMaxSeconds); }},
         {"viewport",
          [&](const Json& v, const std::string& p) {
              const auto side = [&](int& out) {
                  return [&out](const Json& x, const std::string& q) {
                      out = integer(x, q, SceneLimits::kMinViewport, SceneLimits::kMaxViewport);
                  };
              };
              forEachKey(v, p, {{"width", side(s.width)}, {"height", side(s.height)}});
          }},
         {"assets",
          [&](const Json& v, const std::string& p) {
              if (!v.is_array()) throw SceneError("'" + p + "' must be an array of file names");
              s.assets.clear();
              for (std::size_t i = 0; i < v.size(); ++i) {
                  const std::filesystem::path file(text(v[i], p + "[" + std::to_string(i) + "]"));
                  s.assets.push_back((file.is_relative() ? directory / file : file).lexically_normal().string());
              }
          }},
         {"clip", [&](const Json& v, const std::string& p) { s.clip = text(v, p); }},
         {"assetHeight", [&](const Json& v, const std::string& p) { s.assetHeight = number(v, p, 0.0, 100.0); }}});
    return s;
}

nlohmann::ordered_json cameraJson(const std::vector<CameraKey>& path) {
    nlohmann::ordered_json keys = nlohmann::ordered_json::array();
    for (const CameraKey& k : path) keys.push_back({{"time", k.time}, {"eye", k.eye}, {"target", k.target}, {"follow", k.follow}});
    return keys;
}

/// Asset paths as the file stores them: relative to its directory, where readScene resolves them.
std::vector<std::string> relativeTo(const std::filesystem::path& directory, const std::vector<std::string>& assets) {
    std::vector<std::string> out;
    out.reserve(assets.size());
    for (const std::string& a : assets)
        out.push_back(std::filesystem::proximate(std::filesystem::absolute(a), std::filesystem::absolute(directory)).string());
    return out;
}

} // namespace

Scene defaultScene() { return Scene{}; }

cc::Result<Scene> readScene(const std::string& path) {
    std::ifstream in(path);
    if (!in) return cc::Status::invalidArgument("scene " + path + ": cannot be opened");
    Json root;
    try {
        root = Json::parse(in);
    } catch (const Json::parse_error& e) {
        return cc::Status::invalidArgument("scene " + path + ": not valid JSON: " + e.what());
    }
    try {
        return parse(root, std::filesystem::path(path).parent_path());
    } catch (const SceneError& e) {
        return cc::Status::invalidArgument("scene " + path + ": " + e.what());
    }
}

cc::Status writeScene(const Scene& s, const std::string& path) {
    const PlazaSettings& c = s.plaza;
    const nlohmann::ordered_json root = {
        {"characters", c.characters},
        {"spacing", c.spacing},
        {"runnerFraction", c.runnerFraction},
        {"idleFraction", c.idleFraction},
        {"stopStartFraction", c.stopStartFraction},
        {"seed", c.seed},
        {"garments", {{"cape", c.garments.cape}, {"skirt", c.garments.skirt}, {"dress", c.garments.dress}, {"poncho", c.garments.poncho}}},
        {"velocityDamping", c.velocityDamping},
        {"stiffnessDamping", c.stiffnessDamping},
        {"inertiaScale", c.inertiaScale},
        {"walkSpeed", c.walkSpeed},
        {"camera", cameraJson(c.camera.empty() ? Plaza::defaultCameraPath(c) : c.camera)},
        {"budgetMs", s.budgetMs},
        {"seconds", s.seconds},
        {"viewport", {{"width", s.width}, {"height", s.height}}},
        {"assets", relativeTo(std::filesystem::path(path).parent_path(), s.assets)},
        {"clip", s.clip},
        {"assetHeight", s.assetHeight}};
    std::ofstream out(path);
    out << prettyJson(root);
    if (!out) return cc::Status::invalidArgument("scene " + path + ": cannot be written");
    return cc::Status::ok();
}

} // namespace crowd
