#include "ImportFormats.h"

#include <algorithm>
#include <cctype>
#include <cstdint>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <regex>
#include <sstream>
#include <vector>

#include "AssimpConvert.h"

namespace cc::detail {
namespace {

constexpr double kInch = 0.0254;

// Conventions of files that state no unit: id Software's and Valve's tools model in inches
// (a 72-unit human), MikuMikuDance in units of about 8 cm (a 20-unit character); the rest are
// taken as metres. Up axis: Doom 3 and the Source engine are Z up (assimp turns MD5 itself, not
// SMD). Key rates: SMD files have none (assimp assumes 25 ticks/s; Source compiles them at 30
// frames/s); MD5's is in the .md5anim, which assimp 5.2.5 does not read (it keeps 24).
const ImportFormat kFormats[] = {
    {"glTF 2", "gltf glb", FormatContent::Skinned, 1.0, false, true},
    {"FBX", "fbx", FormatContent::Skinned, 1.0, false, true},
    {"Collada", "dae zae", FormatContent::Skinned, 1.0, false, true},
    {"DirectX", "x", FormatContent::Skinned, 1.0, false, false},
    {"Blitz3D", "b3d", FormatContent::Skinned, 1.0, false, false},
    {"Doom 3 MD5", "md5mesh", FormatContent::Skinned, kInch, false, false},
    {"Valve SMD", "smd vta", FormatContent::Skinned, kInch, true, false, 30.0},
    {"Ogre XML", "mesh.xml", FormatContent::Skinned, 1.0, false, false},
    {"Milkshape 3D", "ms3d", FormatContent::Skinned, 1.0, false, false},
    {"3ds Max ASE", "ase ask", FormatContent::Skinned, 1.0, false, false},
    {"MikuMikuDance PMX", "pmx", FormatContent::Skinned, 0.08, false, false},
    {"assimp binary", "assbin", FormatContent::Skinned, 1.0, false, true},
    {"OpenGEX", "ogex", FormatContent::Static, 1.0, false, true},
    {"Wavefront OBJ", "obj", FormatContent::Static, 1.0, false, false},
    {"STL", "stl", FormatContent::Static, 1.0, false, false},
    {"Stanford PLY", "ply", FormatContent::Static, 1.0, false, false},
    {"3D Studio", "3ds prj", FormatContent::Static, 1.0, false, false},
    {"Object File Format", "off", FormatContent::Static, 1.0, false, false},
    {"AC3D", "ac acc ac3d", FormatContent::Static, 1.0, false, false},
    {"LightWave", "lwo lxo", FormatContent::Static, 1.0, false, false},
    {"X3D", "x3d x3db", FormatContent::Static, 1.0, false, false},
    {"AMF", "amf", FormatContent::Static, 1.0, false, false},
    {"3MF", "3mf", FormatContent::Static, 1.0, false, false},
    {"Inter-Quake Model", "iqm", FormatContent::Static, 1.0, false, false},
    {"Quake II MD2", "md2", FormatContent::Static, kInch, false, false},
    {"Quake III MD3", "md3", FormatContent::Static, kInch, false, false},
    {"Quake MDL", "mdl", FormatContent::Static, kInch, false, false},
    {"Blender", "blend", FormatContent::Static, 1.0, false, false},
    {"Biovision BVH", "bvh", FormatContent::Animation, 1.0, false, false},
    {"CharacterStudio Motion", "csm", FormatContent::Animation, 1.0, false, false},
};

bool startsWith(const std::string& s, const char* prefix, std::size_t at = 0) {
    const std::size_t n = std::strlen(prefix);
    return s.size() >= at + n && s.compare(at, n, prefix) == 0;
}

bool contains(const std::string& s, const char* token) { return s.find(token) != std::string::npos; }

std::string lower(std::string s) {
    std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return char(std::tolower(c)); });
    return s;
}

/// Mostly printable text (a text format fed binary garbage is refused before parsing).
bool looksLikeText(const std::string& head) {
    std::size_t bad = 0;
    for (unsigned char c : head)
        if (c == 0 || (c < 32 && c != '\n' && c != '\r' && c != '\t')) ++bad;
    return bad * 100 <= head.size();
}

uint32_t readU32(const std::string& s, std::size_t at) {
    uint32_t v = 0;
    std::memcpy(&v, s.data() + at, 4);
    return v;
}

uint16_t readU16(const std::string& s, std::size_t at) {
    uint16_t v = 0;
    std::memcpy(&v, s.data() + at, 2);
    return v;
}

/// Blitz3D files are nested chunks (4-byte tag, 4-byte length): every chunk must lie inside its
/// parent, and the file must hold the whole top chunk.
Status checkB3dChunks(const std::string& bytes, const std::string& path) {
    const auto fail = [&](const std::string& why) { return Status::invalidArgument(path + ": not a valid Blitz3D file: " + why); };
    if (bytes.size() < 12 || !startsWith(bytes, "BB3D")) return fail("no BB3D chunk");
    const uint32_t top = readU32(bytes, 4);
    if (8ull + top > bytes.size())
        return fail("truncated: the BB3D chunk declares " + std::to_string(top) + " bytes, the file holds " +
                    std::to_string(bytes.size() - 8));
    // Walk the chunk tree: chunks that hold other chunks (a node's children, a mesh's arrays).
    struct Span {
        std::size_t begin, end;
    };
    std::vector<Span> stack{{12, 8 + std::size_t(top)}};
    std::size_t chunks = 0;
    while (!stack.empty()) {
        const Span span = stack.back();
        stack.pop_back();
        std::size_t at = span.begin;
        while (at < span.end) {
            if (++chunks > (1u << 22)) return fail("too many chunks");
            if (at + 8 > span.end) return fail("a chunk header runs past its parent at byte " + std::to_string(at));
            const std::string tag = bytes.substr(at, 4);
            for (unsigned char c : tag)
                if (!std::isupper(c) && !std::isdigit(c)) return fail("bad chunk tag at byte " + std::to_string(at));
            const uint32_t length = readU32(bytes, at + 4);
            const std::size_t body = at + 8;
            if (body + length > span.end)
                return fail("chunk " + tag + " at byte " + std::to_string(at) + " declares " + std::to_string(length) +
                            " bytes, past the end of its parent");
            if (tag == "NODE") {
                // name (NUL-terminated), position, scale, rotation; then child chunks
                std::size_t p = body;
                while (p < body + length && bytes[p] != '\0') ++p;
                p += 1 + 40;
                if (p > body + length) return fail("NODE chunk at byte " + std::to_string(at) + " is too short");
                stack.push_back({p, body + length});
            } else if (tag == "MESH") {
                if (length < 4) return fail("MESH chunk at byte " + std::to_string(at) + " is too short");
                stack.push_back({body + 4, body + length});
            } else if (tag == "VRTS") {
                if (length < 12) return fail("VRTS chunk at byte " + std::to_string(at) + " is too short");
                const uint32_t flags = readU32(bytes, body), sets = readU32(bytes, body + 4), setSize = readU32(bytes, body + 8);
                if (sets > 4 || setSize > 4) return fail("VRTS chunk at byte " + std::to_string(at) + " has bad texture coordinates");
                const std::size_t stride = 12 + ((flags & 1) ? 12 : 0) + ((flags & 2) ? 16 : 0) + 4 * sets * setSize;
                if ((length - 12) % stride != 0) return fail("VRTS chunk at byte " + std::to_string(at) + " ends inside a vertex");
            } else if (tag == "TRIS") {
                if (length < 4 || (length - 4) % 12 != 0) return fail("TRIS chunk at byte " + std::to_string(at) + " ends inside a triangle");
            } else if (tag == "BONE") {
                if (length % 8 != 0) return fail("BONE chunk at byte " + std::to_string(at) + " ends inside a weight");
            } else if (tag == "KEYS") {
                if (length < 4) return fail("KEYS chunk at byte " + std::to_string(at) + " is too short");
                const uint32_t flags = readU32(bytes, body);
                const std::size_t stride = 4 + ((flags & 1) ? 12 : 0) + ((flags & 2) ? 12 : 0) + ((flags & 4) ? 16 : 0);
                if ((length - 4) % stride != 0) return fail("KEYS chunk at byte " + std::to_string(at) + " ends inside a key");
            } else if (tag == "ANIM") {
                if (length != 12) return fail("ANIM chunk at byte " + std::to_string(at) + " is not 12 bytes");
            }
            at = body + length;
        }
    }
    return Status::ok();
}

/// Milkshape 3D: a header and arrays whose counts must fit the file.
Status checkMs3dLayout(const std::string& bytes, const std::string& path) {
    const auto fail = [&](const std::string& why) { return Status::invalidArgument(path + ": not a valid Milkshape 3D file: " + why); };
    std::size_t at = 14;
    const auto need = [&](std::size_t n, const char* what) -> Status {
        if (at + n > bytes.size())
            return fail(std::string("truncated in its ") + what + " (byte " + std::to_string(at) + " of " + std::to_string(bytes.size()) + ")");
        return Status::ok();
    };
    const auto array = [&](std::size_t elementSize, const char* what) -> Status {
        if (Status s = need(2, what); !s) return s;
        const std::size_t count = readU16(bytes, at);
        at += 2;
        if (Status s = need(count * elementSize, what); !s) return s;
        at += count * elementSize;
        return Status::ok();
    };
    if (bytes.size() < 14 || !startsWith(bytes, "MS3D000000")) return fail("no MS3D000000 header");
    const uint32_t version = readU32(bytes, 10);
    if (version != 3 && version != 4) return fail("version " + std::to_string(version) + " (need 3 or 4)");
    if (Status s = array(15, "vertices"); !s) return s;
    if (Status s = array(70, "triangles"); !s) return s;
    // Groups: flags, name[32], triangle count and indices, material.
    if (Status s = need(2, "groups"); !s) return s;
    const std::size_t groups = readU16(bytes, at);
    at += 2;
    for (std::size_t g = 0; g < groups; ++g) {
        if (Status s = need(33, "groups"); !s) return s;
        at += 33;
        if (Status s = array(2, "groups"); !s) return s;
        if (Status s = need(1, "groups"); !s) return s;
        at += 1;
    }
    if (Status s = array(361, "materials"); !s) return s;
    if (Status s = need(12, "animation header"); !s) return s;
    at += 12;
    if (Status s = need(2, "joints"); !s) return s;
    const std::size_t joints = readU16(bytes, at);
    at += 2;
    for (std::size_t j = 0; j < joints; ++j) {
        if (Status s = need(93, "joints"); !s) return s;
        const std::size_t rotations = readU16(bytes, at + 89), translations = readU16(bytes, at + 91);
        at += 93;
        if (Status s = need(16 * (rotations + translations), "joint keys"); !s) return s;
        at += 16 * (rotations + translations);
    }
    return Status::ok();
}

/// The lines of a text, trimmed, empty ones dropped.
std::vector<std::string> lines(const std::string& text) {
    std::vector<std::string> out;
    std::istringstream in(text);
    std::string line;
    while (std::getline(in, line)) {
        const auto b = line.find_first_not_of(" \t\r");
        if (b == std::string::npos) continue;
        const auto e = line.find_last_not_of(" \t\r");
        out.push_back(line.substr(b, e - b + 1));
    }
    return out;
}

/// Doom 3 meshes declare their counts: a file cut short has fewer verts, tris or weights than it
/// says (assimp 5.2.5 reads what is there), or unbalanced braces.
Status checkMd5Complete(const std::string& text, const std::string& path) {
    const auto fail = [&](const std::string& why) { return Status::invalidArgument(path + ": truncated or malformed MD5 mesh: " + why); };
    if (std::count(text.begin(), text.end(), '{') != std::count(text.begin(), text.end(), '}')) return fail("unbalanced braces");
    long declared[3] = {0, 0, 0}, found[3] = {0, 0, 0};
    const char* keys[3] = {"numverts", "numtris", "numweights"};
    const char* items[3] = {"vert", "tri", "weight"};
    for (const std::string& l : lines(text)) {
        std::istringstream words(l);
        std::string first;
        words >> first;
        for (int k = 0; k < 3; ++k) {
            if (first == keys[k]) {
                long n = 0;
                words >> n;
                declared[k] += n;
            } else if (first == items[k]) {
                ++found[k];
            }
        }
    }
    for (int k = 0; k < 3; ++k)
        if (declared[k] != found[k])
            return fail(std::string(keys[k]) + " says " + std::to_string(declared[k]) + ", the file has " + std::to_string(found[k]));
    return Status::ok();
}

/// Valve SMD sections (nodes, skeleton, triangles) each close with "end"; a triangle is a material
/// line and three vertex lines.
Status checkSmdComplete(const std::string& text, const std::string& path) {
    const auto fail = [&](const std::string& why) { return Status::invalidArgument(path + ": truncated or malformed SMD: " + why); };
    const std::vector<std::string> all = lines(text);
    std::string open;
    std::size_t triangleLines = 0;
    for (const std::string& l : all) {
        if (open.empty()) {
            if (l == "nodes" || l == "skeleton" || l == "triangles" || l == "vertexanimation") open = l;
            continue;
        }
        if (l == "end") {
            if (open == "triangles" && triangleLines % 4 != 0) return fail("the triangles section ends inside a triangle");
            open.clear();
            continue;
        }
        if (open == "triangles") ++triangleLines;
    }
    if (!open.empty()) return fail("the " + open + " section has no closing 'end'");
    return Status::ok();
}

} // namespace

const ImportFormat* formatOf(const std::string& path) {
    const std::size_t slash = path.find_last_of("/\\");
    const std::string name = lower(path.substr(slash == std::string::npos ? 0 : slash + 1));
    for (const ImportFormat& f : kFormats) {
        std::istringstream extensions(f.extensions);
        std::string ext;
        while (extensions >> ext) {
            const std::string suffix = "." + ext;
            if (name.size() > suffix.size() && name.compare(name.size() - suffix.size(), suffix.size(), suffix) == 0) return &f;
        }
    }
    return nullptr;
}

std::string supportedExtensions() {
    std::string out;
    for (const ImportFormat& f : kFormats) {
        std::istringstream extensions(f.extensions);
        std::string ext;
        while (extensions >> ext) out += (out.empty() ? "." : ", .") + ext;
    }
    return out;
}

Status checkSignature(const ImportFormat& format, const std::string& head, const std::string& path, std::size_t size) {
    const std::string name = format.name;
    const auto notA = [&](const std::string& why) { return Status::invalidArgument(path + ": not a " + name + " file (" + why + ")"); };
    const std::string ext = lowerExtension(path);
    const bool text = looksLikeText(head.substr(0, std::min<std::size_t>(head.size(), 4096)));
    if (ext == "glb") {
        if (size < 12 || !startsWith(head, "glTF")) return notA("no 'glTF' magic");
        const uint32_t version = readU32(head, 4), length = readU32(head, 8);
        if (version != 2) return Status::invalidArgument(path + ": unsupported binary glTF version " + std::to_string(version) + " (need 2)");
        if (length != size)
            return Status::invalidArgument(path + ": " + (length > size ? "truncated" : "malformed") + ": GLB header declares " +
                                           std::to_string(length) + " bytes, the file has " + std::to_string(size));
    } else if (ext == "gltf") {
        const auto first = head.find_first_not_of(" \t\r\n\xef\xbb\xbf");
        if (first == std::string::npos || head[first] != '{') return notA("does not start with '{'");
    } else if (ext == "dae") {
        if (!contains(head, "<COLLADA")) return notA("no <COLLADA> element");
    } else if (ext == "zae" || ext == "3mf") {
        if (!startsWith(head, "PK\x03\x04")) return notA("not a zip archive");
    } else if (ext == "fbx") {
        if (!startsWith(head, "Kaydara FBX Binary") && !contains(head, "FBXHeaderExtension"))
            return notA("neither the binary signature nor an ASCII FBXHeaderExtension");
    } else if (ext == "x") {
        if (!startsWith(head, "xof ")) return notA("no 'xof ' header");
        if (size < 16) return notA("truncated header");
        const std::string kind = head.substr(8, 4);
        if (kind != "txt " && kind != "bin " && kind != "tzip" && kind != "bzip") return notA("unknown encoding '" + kind + "'");
    } else if (ext == "b3d") {
        return checkB3dChunks(head, path);
    } else if (ext == "ms3d") {
        return checkMs3dLayout(head, path);
    } else if (ext == "md5mesh") {
        if (!text || !contains(head, "MD5Version")) return notA("no MD5Version");
        return checkMd5Complete(head, path);
    } else if (ext == "smd" || ext == "vta") {
        if (!text || !contains(head, "version") || !contains(head, "nodes")) return notA("no 'version' and 'nodes' sections");
        return checkSmdComplete(head, path);
    } else if (ext == "xml") {
        if (!text || !contains(head, "<mesh")) return notA("no <mesh> element");
    } else if (ext == "ase" || ext == "ask") {
        if (!text || !contains(head, "*3DSMAX_ASCIIEXPORT")) return notA("no *3DSMAX_ASCIIEXPORT");
    } else if (ext == "pmx") {
        if (!startsWith(head, "PMX ")) return notA("no 'PMX ' magic");
    } else if (ext == "assbin") {
        if (!startsWith(head, "ASSIMP.binary-dump.")) return notA("no assimp binary dump header");
    } else if (ext == "ogex") {
        if (!text || (!contains(head, "Metric") && !contains(head, "GeometryNode"))) return notA("no Metric or GeometryNode structure");
    } else if (ext == "obj") {
        if (!text) return notA("not text");
    } else if (ext == "stl") {
        const bool ascii = startsWith(head, "solid") && text;
        if (!ascii) {
            if (size < 84) return notA("shorter than a binary STL header");
            const uint64_t triangles = readU32(head, 80);
            if (84 + 50 * triangles != size)
                return Status::invalidArgument(path + ": " + (84 + 50 * triangles > size ? "truncated" : "malformed") +
                                               " binary STL: " + std::to_string(triangles) + " triangles need " +
                                               std::to_string(84 + 50 * triangles) + " bytes, the file has " + std::to_string(size));
        }
    } else if (ext == "ply") {
        if (!startsWith(head, "ply")) return notA("no 'ply' magic");
        if (!contains(head, "end_header")) return notA("no end_header");
    } else if (ext == "3ds" || ext == "prj") {
        if (size < 6 || readU16(head, 0) != 0x4D4D) return notA("no main chunk");
        if (readU32(head, 2) > size) return Status::invalidArgument(path + ": truncated 3D Studio file: the main chunk runs past the end");
    } else if (ext == "off") {
        if (!text || !contains(head.substr(0, 16), "OFF")) return notA("no OFF header");
    } else if (ext == "iqm") {
        if (!startsWith(head, "INTERQUAKEMODEL")) return notA("no INTERQUAKEMODEL magic");
        if (size < 124 || readU32(head, 20) > size) return Status::invalidArgument(path + ": truncated Inter-Quake Model file");
    } else if (ext == "md2") {
        if (!startsWith(head, "IDP2")) return notA("no IDP2 magic");
    } else if (ext == "md3") {
        if (!startsWith(head, "IDP3")) return notA("no IDP3 magic");
    } else if (ext == "blend") {
        if (!startsWith(head, "BLENDER")) return notA("no BLENDER header");
    } else if (ext == "bvh") {
        if (!text || !contains(head, "HIERARCHY")) return notA("no HIERARCHY section");
    } else if (ext == "x3d") {
        if (!contains(head, "<X3D")) return notA("no <X3D> element");
    } else if (ext == "amf") {
        if (!contains(head, "<amf")) return notA("no <amf> element");
    } else if (ext == "lwo" || ext == "lxo") {
        if (!startsWith(head, "FORM")) return notA("no FORM chunk");
    } else if (!text && (ext == "ac" || ext == "acc" || ext == "ac3d" || ext == "csm")) {
        return notA("not text");
    }
    return Status::ok();
}

double md5FrameRate(const std::string& animText) {
    static const std::regex rate(R"re(frameRate\s+([0-9.eE+]+))re");
    std::smatch m;
    if (!std::regex_search(animText, m, rate)) return 0.0;
    const double fps = std::strtod(m[1].str().c_str(), nullptr);
    return std::isfinite(fps) && fps > 0.0 && fps <= 1000.0 ? fps : 0.0;
}

bool openGexMetrics(const std::string& text, double& outMetresPerUnit, bool& outZUp) {
    bool found = false;
    // Metric (key = "distance") {float {0.01}}    Metric (key = "up") {string {"z"}}
    static const std::regex distance(R"re(Metric\s*\(\s*key\s*=\s*"distance"\s*\)\s*\{\s*float\s*\{\s*([-+0-9.eE]+)\s*\})re");
    static const std::regex up(R"re(Metric\s*\(\s*key\s*=\s*"up"\s*\)\s*\{\s*string\s*\{\s*"([xyzXYZ])"\s*\})re");
    std::smatch m;
    if (std::regex_search(text, m, distance)) {
        // A named copy: `end` points into it (into a temporary it dangled, ASan: stack-use-after-scope).
        const std::string number = m[1].str();
        char* end = nullptr;
        const double value = std::strtod(number.c_str(), &end);
        if (end && *end == '\0' && std::isfinite(value) && value > 0.0) outMetresPerUnit = value, found = true;
    }
    if (std::regex_search(text, m, up)) {
        outZUp = std::tolower(static_cast<unsigned char>(m[1].str()[0])) == 'z';
        found = true;
    }
    return found;
}

} // namespace cc::detail
