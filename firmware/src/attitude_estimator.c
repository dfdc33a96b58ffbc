#include "fc/attitude_estimator.h"
typedef int fc_attitude_estimator_placeholder;
