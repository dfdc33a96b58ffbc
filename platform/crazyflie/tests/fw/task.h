/* task.h - the task calls of the glue, defined by the test: the app task's
 * loop (appMain) returns to the test from its wait (test_cf_glue.c). */
#ifndef CF_TEST_TASK_H
#define CF_TEST_TASK_H

#include "FreeRTOS.h"

TaskHandle_t xTaskGetCurrentTaskHandle(void);
BaseType_t xTaskNotifyGive(TaskHandle_t task);
uint32_t ulTaskNotifyTake(BaseType_t clear_on_exit, TickType_t ticks_to_wait);
void vTaskDelay(TickType_t ticks);

#endif
