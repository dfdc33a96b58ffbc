/* Configure-time probe: the simavr and libelf headers and libraries are
 * usable by the host compiler (platform/atmega/CMakeLists.txt). */
#include <gelf.h>
#include <libelf.h>
#include <stddef.h>

#include "avr_uart.h"
#include "sim_avr.h"
#include "sim_elf.h"

int main(void)
{
    (void)elf_version(EV_CURRENT);
    avr_t *avr = avr_make_mcu_by_name("atmega2560");
    return avr != NULL ? 0 : 1;
}
