/*
 * hal_esc.h - ESC outputs as hardware PWM: 400 Hz, pulses 1000-2000 us with
 * 0.5 us resolution (Timer4 and Timer5, mode 14 fast PWM, TOP = ICR = 4999,
 * clk/8). Channel i drives:
 *
 *   0 OC4A PH3 (Arduino Mega D6)     3 OC5A PL3 (D46)
 *   1 OC4B PH4 (D7)                  4 OC5B PL4 (D45)
 *   2 OC4C PH5 (D8)                  5 OC5C PL5 (D44)
 *
 * 1000 us is motors off; hal_esc_init starts every channel there, so the
 * ESCs see "off" from the first pulse on. A new pulse width takes effect at
 * the start of the next PWM period (OCR double buffering): no runt pulses.
 */
#ifndef FC_ATMEGA_HAL_ESC_H
#define FC_ATMEGA_HAL_ESC_H

#include <stdint.h>

#define HAL_ESC_CHANNELS 6u
#define HAL_ESC_RATE_HZ 400u
#define HAL_ESC_US_OFF 1000u
#define HAL_ESC_US_MAX 2000u

void hal_esc_init(void);

/* Pulse width of channel ch in us, clamped to [1000, 2000]. */
void hal_esc_write_us(uint8_t ch, uint16_t us);

/* Every channel to 1000 us. */
void hal_esc_all_off(void);

#endif /* FC_ATMEGA_HAL_ESC_H */
