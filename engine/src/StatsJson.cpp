#include <sstream>

#include "WorldImpl.h"

namespace cc::detail {
namespace {

const char* solverName(SolverKind s) {
    switch (s) {
    case SolverKind::SubstepNewton: return "substep-newton";
    case SolverKind::SubstepLocalGlobal: return "substep-local-global";
    }
    return "unknown";
}

const char* collisionName(CollisionKind c) {
    switch (c) {
    case CollisionKind::None: return "none";
    case CollisionKind::Proxies: return "proxies";
    case CollisionKind::Mesh: return "mesh";
    case CollisionKind::MeshContinuous: return "mesh-continuous";
    }
    return "unknown";
}

} // namespace

std::string WorldImpl::statsJson() const {
    const FrameStats& f = mFrameStats;
    std::ostringstream out;
    out.precision(6);
    out << "{\"frame\":" << f.frame << ",\"threads\":" << f.threads << ",\"ms\":{\"schedule\":" << f.scheduleMs
        << ",\"simulate\":" << f.simulateMs
        << ",\"total\":" << f.totalMs << "},\"cpuMs\":{\"predicted\":" << f.predictedCpuMs
        << ",\"measured\":" << f.measuredCpuMs << ",\"budget\":" << f.budgetCpuMs << "},\"garments\":" << f.garments
        << ",\"updated\":" << f.updated << ",\"asleep\":" << f.asleep << ",\"visible\":" << f.visible
        << ",\"failed\":" << f.failed << ",\"levelSwitches\":" << f.levelSwitches << ",\"batches\":" << f.batches
        << ",\"perLevel\":[";
    for (int l = 0; l < 16; ++l) out << (l ? "," : "") << f.garmentsPerLevel[l];
    out << "],\"garmentStats\":[";
    bool first = true;
    mGarments.forEach([&](auto h, const GarmentInstance& g) {
        const GarmentStats& s = g.stats;
        out << (first ? "" : ",") << "{\"id\":" << h.index1 << ",\"level\":" << s.level << ",\"vertices\":"
            << s.vertexCount << ",\"solver\":\"" << solverName(s.solver) << "\",\"substeps\":" << s.substeps
            << ",\"interval\":" << s.updateInterval << ",\"updated\":" << (s.updated ? "true" : "false")
            << ",\"collision\":\"" << collisionName(s.collision) << "\",\"selfCollision\":"
            << (s.selfCollision ? "true" : "false") << ",\"contacts\":" << s.contacts << ",\"failSafes\":" << s.failSafes
            << ",\"failed\":" << (s.failed ? "true" : "false") << ",\"screenRadiusPx\":" << s.screenRadiusPx
            << ",\"errorPx\":" << s.predictedErrorPx << ",\"predictedMs\":" << s.predictedMs
            << ",\"measuredMs\":" << s.measuredMs << ",\"collisionMs\":" << s.collisionMs << ",\"selfCollisionMs\":" << s.selfCollisionMs
            << ",\"maxStrain\":" << s.maxStrain << ",\"maxAttachmentError\":" << s.maxAttachmentError
            << ",\"restarted\":" << (s.restarted ? "true" : "false") << "}";
        first = false;
    });
    out << "]}";
    return out.str();
}

} // namespace cc::detail
