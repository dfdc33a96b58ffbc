/* fc/allocation.h - placeholder, being written */
#ifndef FC_ALLOCATION_H
#define FC_ALLOCATION_H
#include "fc/status.h"
#endif
