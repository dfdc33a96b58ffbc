/* hal_uart.c - USART0 telemetry and commands (hal_uart.h). */
#include "hal_uart.h"

#include <avr/interrupt.h>
#include <avr/io.h>

#include "telemetry.h"

/* U2X: baud = F_CPU / (8 (UBRR + 1)) */
#define UBRR_VALUE ((uint16_t)((F_CPU + 4UL * HAL_UART_BAUD) / (8UL * HAL_UART_BAUD) - 1UL))

#define TX_MASK ((uint8_t)(HAL_UART_TX_BUFFER - 1u))

static uint8_t s_tx[HAL_UART_TX_BUFFER];
static volatile uint8_t s_tx_head; /* written by the writer */
static volatile uint8_t s_tx_tail; /* written by the ISR */
static volatile uint8_t s_command; /* hal_uart_command, written by the RX ISR */
static uint8_t s_rx_match;         /* bytes of "ARM" matched so far (ISR only) */

ISR(USART0_UDRE_vect)
{
    const uint8_t tail = s_tx_tail;
    if (tail == s_tx_head) {
        UCSR0B &= (uint8_t)~_BV(UDRIE0); /* empty: stop until the next write */
        return;
    }
    UDR0 = s_tx[tail];
    s_tx_tail = (uint8_t)((tail + 1u) & TX_MASK);
}

ISR(USART0_RX_vect)
{
    const uint8_t status = UCSR0A;
    const uint8_t c = UDR0;
    if ((status & (_BV(FE0) | _BV(DOR0))) != 0u) {
        s_rx_match = 0u;
        return;
    }
    static const char prefix[3] = {'A', 'R', 'M'};
    if (s_rx_match < 3u) {
        if (c == (uint8_t)prefix[s_rx_match]) {
            s_rx_match++;
        } else {
            s_rx_match = (c == 'A') ? 1u : 0u;
        }
        return;
    }
    if (c == '1') {
        s_command = HAL_UART_CMD_ARM;
    } else if (c == '0') {
        s_command = HAL_UART_CMD_DISARM;
    }
    s_rx_match = (c == 'A') ? 1u : 0u;
}

void hal_uart_init(void)
{
    UCSR0B = 0u;
    UBRR0 = UBRR_VALUE;
    UCSR0A = _BV(U2X0);
    UCSR0C = _BV(UCSZ01) | _BV(UCSZ00); /* 8N1 */
    s_tx_head = 0u;
    s_tx_tail = 0u;
    s_command = HAL_UART_CMD_NONE;
    s_rx_match = 0u;
    UCSR0B = _BV(RXEN0) | _BV(TXEN0) | _BV(RXCIE0);
}

bool hal_uart_write(const uint8_t *data, uint8_t n)
{
    uint8_t head = s_tx_head;
    const uint8_t used = (uint8_t)((head - s_tx_tail) & TX_MASK);
    if ((uint16_t)used + n > (uint16_t)(HAL_UART_TX_BUFFER - 1u)) {
        return false;
    }
    for (uint8_t i = 0u; i < n; i++) {
        s_tx[head] = data[i];
        head = (uint8_t)((head + 1u) & TX_MASK);
    }
    s_tx_head = head;
    UCSR0B |= _BV(UDRIE0); /* the ISR takes it from here */
    return true;
}

hal_uart_command hal_uart_take_command(void)
{
    const uint8_t sreg = SREG;
    cli();
    const hal_uart_command c = (hal_uart_command)s_command;
    s_command = HAL_UART_CMD_NONE;
    SREG = sreg;
    return c;
}

void hal_uart_write_string_blocking(const char *s)
{
    while (*s != '\0') {
        uint8_t n = 0u;
        while (s[n] != '\0' && n < 32u) {
            n++;
        }
        while (!hal_uart_write((const uint8_t *)s, n)) {
        }
        s += n;
    }
}
