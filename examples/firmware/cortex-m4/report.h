/* Printing floats without double arithmetic: each number as its IEEE-754 bits in hex (exact,
 * what a test reads back) and as a decimal computed in float (for people). printf("%f") would
 * promote to double and pull newlib's double-precision routines into a float-only build. */
#ifndef REPORT_H
#define REPORT_H

#include <stdint.h>

void report_text(const char *text);
void report_int(int value);
/* "<tag> <index> <hex bits> <decimal>\n" */
void report_float(const char *tag, int index, float value);

#endif
