/* FreeRTOS.h - the kernel's types and macros the glue uses. */
#ifndef CF_TEST_FREERTOS_H
#define CF_TEST_FREERTOS_H

#include <stdint.h>

typedef long BaseType_t;
typedef uint32_t TickType_t;
typedef void *TaskHandle_t;

#define pdTRUE ((BaseType_t)1)
#define pdFALSE ((BaseType_t)0)
/* ms to ticks at the firmware's 1 kHz tick */
#define M2T(ms) ((TickType_t)(ms))

#endif
