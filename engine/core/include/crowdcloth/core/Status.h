#pragma once

// Status and Result are part of the public API (World.h returns them); the internals keep
// including them under this name.
#include "crowdcloth/Status.h"
