#include "JsonText.h"

#include <regex>

namespace crowd {

std::string prettyJson(const nlohmann::ordered_json& value) {
    // An array holding only numbers, as dump(2) spreads it over one line per element.
    static const std::regex numberArray(R"(\[\s*(-?[0-9.eE+-]+(?:,\s*-?[0-9.eE+-]+)*)\s*\])");
    static const std::regex separator(R"(,\s+)");
    const std::string text = value.dump(2);
    std::string out;
    auto last = text.cbegin();
    for (std::sregex_iterator m(text.begin(), text.end(), numberArray), end; m != end; ++m) {
        out.append(last, (*m)[0].first);
        out += "[" + std::regex_replace((*m)[1].str(), separator, ", ") + "]";
        last = (*m)[0].second;
    }
    out.append(last, text.cend());
    return out + "\n";
}

} // namespace crowd
