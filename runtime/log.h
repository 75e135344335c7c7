// Log lines to stderr, filtered by level: wire/log.h, the one logger of the
// node, the drivers and the client tools.
#pragma once

#include "wire/log.h"
