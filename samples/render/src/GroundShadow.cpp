#include "GroundShadow.h"

namespace cc::render {

void groundShadowMatrix(const Rgb& towardsLight, float out[16]) {
    for (int k = 0; k < 16; ++k) out[k] = (k % 5 == 0) ? 1.0f : 0.0f;
    // Only the y column changes: height is traded for a slide along the light, y becomes 0.
    out[4] = -towardsLight[0] / towardsLight[1];
    out[5] = 0.0f;
    out[6] = -towardsLight[2] / towardsLight[1];
}

} // namespace cc::render
