#include "core/error.h"
// Out-of-line anchor so the error classes' vtables live in libnephele_core.
