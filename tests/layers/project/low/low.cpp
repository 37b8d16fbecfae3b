#include "low/low.h"

int low_value() { return 1; }
