/*
 * hal_uart.h - USART0 (Arduino Mega pins 0 RX / 1 TX, the USB-serial bridge):
 * 115200 baud 8N1 (U2X, UBRR 16: 117647 baud, +2.1 %).
 *
 * TX is non-blocking: hal_uart_write copies a whole frame into a 128-byte
 * ring and the UDRE interrupt sends it; a frame that does not fit is dropped
 * whole (never a partial frame, never a wait), so telemetry cannot break the
 * loop's deadline. RX runs in its interrupt and only matches the four-byte
 * commands of telemetry.h ("ARM1" arm, "ARM0" disarm).
 */
#ifndef FC_ATMEGA_HAL_UART_H
#define FC_ATMEGA_HAL_UART_H

#include <stdbool.h>
#include <stdint.h>

#define HAL_UART_BAUD 115200UL
#define HAL_UART_TX_BUFFER 128u /* power of two */

typedef enum hal_uart_command {
    HAL_UART_CMD_NONE = 0,
    HAL_UART_CMD_ARM,
    HAL_UART_CMD_DISARM
} hal_uart_command;

void hal_uart_init(void);

/* Queue n bytes; false (and nothing queued) if they do not all fit. */
bool hal_uart_write(const uint8_t *data, uint8_t n);

/* The last command received since the previous call, or HAL_UART_CMD_NONE. */
hal_uart_command hal_uart_take_command(void);

/* Blocking write of a string, for the boot banner only (before the loop). */
void hal_uart_write_string_blocking(const char *s);

#endif /* FC_ATMEGA_HAL_UART_H */
