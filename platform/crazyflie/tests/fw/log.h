/* log.h - LOG_GROUP_START .. LOG_GROUP_STOP as a table the test reads:
 * cf_test_log_<group>[], ended by a NULL name. */
#ifndef CF_TEST_LOG_H
#define CF_TEST_LOG_H

#include <stdint.h>

#define LOG_UINT8 1
#define LOG_UINT16 2
#define LOG_UINT32 3
#define LOG_INT8 4
#define LOG_INT16 5
#define LOG_INT32 6
#define LOG_FLOAT 7

typedef struct cf_test_var {
    const char *name;
    int type;
    void *address;
} cf_test_var;

extern const cf_test_var cf_test_log_fcssc[];

#define LOG_GROUP_START(group) const cf_test_var cf_test_log_##group[] = {
#define LOG_ADD(type, name, address) {#name, (type), (void *)(address)},
#define LOG_GROUP_STOP(group) {0, 0, 0}};

#endif
