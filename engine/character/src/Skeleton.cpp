#include "crowdcloth/character/Skeleton.h"

#include <string>

namespace cc {

int32_t Skeleton::findJoint(const std::string& name) const {
    for (std::size_t i = 0; i < joints.size(); ++i) {
        if (joints[i].name == name) return static_cast<int32_t>(i);
    }
    return -1;
}

Status Skeleton::validate() const {
    if (joints.empty()) return Status::invalidArgument("skeleton has no joints");
    if (joints.size() > kMaxJoints) {
        return Status::invalidArgument("skeleton has " + std::to_string(joints.size()) +
                                       " joints, more than the cap " + std::to_string(kMaxJoints));
    }
    for (std::size_t i = 0; i < joints.size(); ++i) {
        const Joint& j = joints[i];
        const std::string where = "joint " + std::to_string(i) + " '" + j.name + "'";
        if (j.parent < -1 || j.parent >= static_cast<int32_t>(i)) {
            return Status::invalidArgument(where + ": parent " + std::to_string(j.parent) +
                                           " does not precede it (topological order required)");
        }
        if (!j.restLocal.isFinite()) return Status::invalidArgument(where + ": non-finite rest transform");
        if (!(j.restLocal.scale.minCoeff() > 0.0)) {
            return Status::invalidArgument(where + ": rest scale must be positive");
        }
        const double qn = j.restLocal.rotation.norm();
        if (std::abs(qn - 1.0) > 1e-6) {
            return Status::invalidArgument(where + ": rest rotation is not a unit quaternion (norm " +
                                           std::to_string(qn) + ")");
        }
    }
    return Status::ok();
}

void Skeleton::restPose(Span<Transform> outLocal) const {
    for (std::size_t i = 0; i < joints.size() && i < outLocal.size(); ++i) outLocal[i] = joints[i].restLocal;
}

void Skeleton::computeGlobalTransforms(Span<const Transform> local, Span<Mat4> outGlobal) const {
    for (std::size_t i = 0; i < joints.size(); ++i) {
        const int32_t p = joints[i].parent;
        if (p < 0) {
            outGlobal[i] = local[i].matrix();
        } else {
            outGlobal[i] = outGlobal[static_cast<std::size_t>(p)] * local[i].matrix();
        }
    }
}

} // namespace cc
