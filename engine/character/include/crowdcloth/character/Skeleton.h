#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "crowdcloth/character/Transform.h"
#include "crowdcloth/core/Span.h"
#include "crowdcloth/core/Status.h"

namespace cc {

/// Sane caps on imported or generated data, checked before anything is allocated from a count.
constexpr std::size_t kMaxJoints = 4096;

/// One joint: a name, its parent (earlier in the array, or -1 for a root) and its rest transform
/// relative to the parent (the pose used for joints a clip does not animate).
struct Joint {
    std::string name;
    int32_t parent = -1;
    Transform restLocal;
};

/// A joint hierarchy in topological order (every parent precedes its children), so global
/// transforms are one forward pass. Plain data; copy freely.
///
///     std::vector<Mat4> global(skeleton.jointCount());
///     skeleton.computeGlobalTransforms(localPose, global);
struct Skeleton {
    std::vector<Joint> joints;

    std::size_t jointCount() const { return joints.size(); }
    /// Index of the first joint with that name, or -1.
    int32_t findJoint(const std::string& name) const;
    /// Checks the count cap, parent order (parent < index) and finite rest transforms with
    /// positive scale. The message names the joint.
    Status validate() const;
    /// Writes every joint's rest local transform (outLocal.size() == jointCount()).
    void restPose(Span<Transform> outLocal) const;
    /// Global (model-space) matrices from local transforms. Sizes must equal jointCount().
    void computeGlobalTransforms(Span<const Transform> local, Span<Mat4> outGlobal) const;
};

} // namespace cc
