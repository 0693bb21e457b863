/* Output through the debugger (ARM semihosting): QEMU's -semihosting, or OpenOCD/pyOCD with
 * "arm semihosting enable". Without a debugger attached, a semihosting call stops the core:
 * replace these two functions by a UART driver on a board that runs alone. */
#ifndef SEMIHOST_H
#define SEMIHOST_H

void semihost_write(const char *text);
void semihost_exit(int status) __attribute__((noreturn));

#endif
