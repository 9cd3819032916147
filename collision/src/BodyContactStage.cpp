#include "crowdcloth/collision/BodyContactStage.h"

#include <string>

namespace cc::collision {

Status BodyContactStage::gather(Span<const Collider* const> colliders, Span<const Vec3> start, Span<const Vec3> end,
                                const BodyContactSettings& settings, std::vector<Contact>& outContacts) {
    outContacts.clear();
    if (Status s = settings.validate(); !s) return s;
    for (std::size_t k = 0; k < colliders.size(); ++k) {
        if (!colliders[k]) return Status::invalidArgument("BodyContactStage: collider " + std::to_string(k) + " is null");
        // Parts of different colliders are different parts.
        const uint32_t partOffset = uint32_t(k) << 24;
        if (Status s = colliders[k]->queryProximity(end, settings.query, mScratch); !s) return s;
        for (Contact& c : mScratch) c.part += partOffset;
        outContacts.insert(outContacts.end(), mScratch.begin(), mScratch.end());
        if (!settings.continuous) continue;
        if (Status s = colliders[k]->queryContinuous(start, end, settings.query, mScratch); !s) return s;
        for (Contact& c : mScratch) c.part += partOffset;
        outContacts.insert(outContacts.end(), mScratch.begin(), mScratch.end());
    }
    reduceContactsPerVertex(outContacts);
    return Status::ok();
}

} // namespace cc::collision
