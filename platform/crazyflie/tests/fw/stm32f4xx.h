/* stm32f4xx.h - the core debug and DWT registers the glue touches. Every
 * access to DWT advances its cycle counter by cf_test_dwt_step cycles, so a
 * test sees the glue measure a step of known length. */
#ifndef CF_TEST_STM32F4XX_H
#define CF_TEST_STM32F4XX_H

#include <stdint.h>

typedef struct {
    volatile uint32_t DEMCR;
} CoreDebug_Type;

typedef struct {
    volatile uint32_t CTRL;
    volatile uint32_t CYCCNT;
} DWT_Type;

#define CoreDebug_DEMCR_TRCENA_Msk (1UL << 24)
#define DWT_CTRL_CYCCNTENA_Msk (1UL << 0)

extern CoreDebug_Type cf_test_core_debug;
extern uint32_t cf_test_dwt_step;
DWT_Type *cf_test_dwt(void);

#define CoreDebug (&cf_test_core_debug)
#define DWT (cf_test_dwt())

#endif
