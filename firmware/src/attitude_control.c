#include "fc/attitude_control.h"
typedef int fc_attitude_control_placeholder;
