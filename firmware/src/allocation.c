#include "fc/allocation.h"
typedef int fc_allocation_placeholder;
