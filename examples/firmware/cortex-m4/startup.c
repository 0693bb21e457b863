/*
 * Reset and the vector table for a Cortex-M4, without a vendor library: copy .data from flash,
 * zero .bss, give the FPU full access (CPACR: CP10 and CP11) before any float instruction, call
 * main, and report its status to the debugger (semihosting).  A vendor's CMSIS startup file
 * does the same; keep it and drop this file when porting to an STM32, nRF52 or Teensy.
 */

#include <stdint.h>

#include "semihost.h"

extern uint32_t _data_load, _data_start, _data_end, _bss_start, _bss_end, _stack_top;
extern int main(void);

void Reset_Handler(void);
void Default_Handler(void);

#define CPACR (*(volatile uint32_t *)0xE000ED88u)

void Reset_Handler(void)
{
    const uint32_t *from = &_data_load;
    uint32_t *to = &_data_start;
    while (to < &_data_end) {
        *to++ = *from++;
    }
    for (to = &_bss_start; to < &_bss_end; ++to) {
        *to = 0u;
    }
    CPACR |= (0xFu << 20);  /* CP10, CP11: full access to the single-precision FPU */
    __asm__ volatile ("dsb\n\tisb" ::: "memory");
    semihost_exit(main());
}

void Default_Handler(void)
{
    semihost_write("fault: an exception without a handler\n");
    semihost_exit(99);
}

/* initial stack pointer, reset, then the 14 system exceptions (NMI .. SysTick) */
__attribute__((section(".vectors"), used))
static void (*const vectors[16])(void) = {
    (void (*)(void))(uintptr_t)&_stack_top, Reset_Handler,
    Default_Handler, Default_Handler, Default_Handler, Default_Handler, Default_Handler,
    0, 0, 0, 0,
    Default_Handler, Default_Handler, 0, Default_Handler, Default_Handler,
};
