#include "sim/symmetry.h"
