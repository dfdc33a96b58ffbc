/* fc/attitude_estimator.h - placeholder, being written */
#ifndef FC_ATTITUDE_ESTIMATOR_H
#define FC_ATTITUDE_ESTIMATOR_H
#include "fc/status.h"
#endif
