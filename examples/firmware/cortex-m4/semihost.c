#include "semihost.h"

#include <stdint.h>

static uintptr_t semihost_call(uintptr_t operation, const void *argument)
{
    register uintptr_t r0 __asm__("r0") = operation;
    register const void *r1 __asm__("r1") = argument;
    __asm__ volatile ("bkpt 0xAB" : "+r"(r0) : "r"(r1) : "memory");
    return r0;
}

void semihost_write(const char *text)
{
    (void)semihost_call(0x04u, text);  /* SYS_WRITE0: a NUL-terminated string to the console */
}

void semihost_exit(int status)
{
    /* SYS_EXIT_EXTENDED: ADP_Stopped_ApplicationExit with the status (QEMU exits with it) */
    const uintptr_t block[2] = {0x20026u, (uintptr_t)status};
    for (;;) {
        (void)semihost_call(0x20u, block);
    }
}
