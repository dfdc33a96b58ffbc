/* param.h - PARAM_GROUP_START .. PARAM_GROUP_STOP as a table the test reads
 * and writes through: cf_test_param_<group>[], ended by a NULL name. */
#ifndef CF_TEST_PARAM_H
#define CF_TEST_PARAM_H

#include "log.h"

#define PARAM_UINT8 LOG_UINT8
#define PARAM_FLOAT LOG_FLOAT

extern const cf_test_var cf_test_param_fcssc[];

#define PARAM_GROUP_START(group) const cf_test_var cf_test_param_##group[] = {
#define PARAM_ADD(type, name, address) {#name, (type), (void *)(address)},
#define PARAM_GROUP_STOP(group) {0, 0, 0}};

#endif
