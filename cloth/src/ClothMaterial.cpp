#include "crowdcloth/cloth/ClothMaterial.h"

#include <cmath>
#include <sstream>

namespace cc::cloth {
namespace {

Status checkRange(const char* field, double value, double lo, double hi, bool loInclusive) {
    const bool ok = std::isfinite(value) && (loInclusive ? value >= lo : value > lo) && value <= hi;
    if (ok) return Status::ok();
    std::ostringstream msg;
    msg << "ClothMaterial." << field << " = " << value << " is outside " << (loInclusive ? "[" : "(")
        << lo << ", " << hi << "]";
    return Status::invalidArgument(msg.str());
}

} // namespace

Status ClothMaterial::validate() const {
    if (Status s = checkRange("arealDensity", arealDensity, 0.0, 100.0, false); !s) return s;
    if (Status s = checkRange("stretchStiffness", stretchStiffness, 0.0, 1e9, false); !s) return s;
    if (Status s = checkRange("shearStiffness", shearStiffness, 0.0, 1e9, true); !s) return s;
    if (Status s = checkRange("bendStiffness", bendStiffness, 0.0, 1e3, true); !s) return s;
    return checkRange("damping", damping, 0.0, 10.0, true);
}

} // namespace cc::cloth
