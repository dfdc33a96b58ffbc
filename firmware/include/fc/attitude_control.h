/* fc/attitude_control.h - placeholder, being written */
#ifndef FC_ATTITUDE_CONTROL_H
#define FC_ATTITUDE_CONTROL_H
#include "fc/status.h"
#endif
