#include <cstdio>
#include <string>

#include <gtest/gtest.h>

#include "crowdcloth/Version.h"
#include "crowdcloth/crowdcloth.h"

// The header is generated from project(VERSION); the library reports the version it was built as.
TEST(Version, HeaderMacroIsTheProjectVersion) {
    EXPECT_STREQ(CC_VERSION_STRING, CC_PROJECT_VERSION);
    char dotted[32];
    std::snprintf(dotted, sizeof dotted, "%d.%d.%d", CC_VERSION_MAJOR, CC_VERSION_MINOR,
                  CC_VERSION_PATCH);
    EXPECT_EQ(std::string(dotted), CC_PROJECT_VERSION);
}

TEST(Version, LibraryAgreesWithTheHeaders) {
    EXPECT_EQ(cc_get_version(), uint32_t(CC_VERSION));
    EXPECT_EQ(cc::getVersion(), cc::kVersion);
    EXPECT_EQ(cc::kVersion,
              (cc::kVersionMajor << 16) | (cc::kVersionMinor << 8) | cc::kVersionPatch);
}
