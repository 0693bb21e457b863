#include "report.h"

#include <string.h>

#include "semihost.h"

void report_text(const char *text)
{
    semihost_write(text);
}

static char *append_unsigned(char *at, uint32_t value)
{
    char digits[10];
    int count = 0;
    do {
        digits[count++] = (char)('0' + value % 10u);
        value /= 10u;
    } while (value != 0u);
    while (count > 0) {
        *at++ = digits[--count];
    }
    return at;
}

void report_int(int value)
{
    char line[16], *at = line;
    if (value < 0) {
        *at++ = '-';
    }
    at = append_unsigned(at, value < 0 ? 0u - (uint32_t)value : (uint32_t)value);
    *at = '\0';
    semihost_write(line);
}

/* d.ddddddde+XX with 7 significant digits, computed in float (good to about 1e-6 relative) */
static char *append_decimal(char *at, float value)
{
    uint32_t bits, mantissa;
    int exponent = 0, k;
    memcpy(&bits, &value, sizeof bits);
    if ((bits & 0x7F800000u) == 0x7F800000u) {
        const char *text = (bits & 0x007FFFFFu) ? "nan" : ((bits >> 31) ? "-inf" : "inf");
        while (*text) {
            *at++ = *text++;
        }
        return at;
    }
    if (bits >> 31) {
        *at++ = '-';
        value = -value;
    }
    if (value != 0.0F) {
        while (value >= 10.0F) {
            value /= 10.0F;
            ++exponent;
        }
        while (value < 1.0F) {
            value *= 10.0F;
            --exponent;
        }
    }
    mantissa = (uint32_t)(value * 1000000.0F + 0.5F);
    if (mantissa >= 10000000u) {
        mantissa /= 10u;
        ++exponent;
    }
    *at++ = (char)('0' + mantissa / 1000000u);
    *at++ = '.';
    for (k = 100000; k >= 1; k /= 10) {
        *at++ = (char)('0' + (mantissa / (uint32_t)k) % 10u);
    }
    *at++ = 'e';
    *at++ = exponent < 0 ? '-' : '+';
    k = exponent < 0 ? -exponent : exponent;
    *at++ = (char)('0' + k / 10);
    *at++ = (char)('0' + k % 10);
    return at;
}

void report_float(const char *tag, int index, float value)
{
    static const char hex[] = "0123456789abcdef";
    char line[96], *at = line;
    uint32_t bits;
    int shift;
    size_t length = strlen(tag);
    if (length > 48) {
        length = 48;
    }
    memcpy(at, tag, length);
    at += length;
    *at++ = ' ';
    at = append_unsigned(at, (uint32_t)index);
    *at++ = ' ';
    memcpy(&bits, &value, sizeof bits);
    for (shift = 28; shift >= 0; shift -= 4) {
        *at++ = hex[(bits >> shift) & 0xFu];
    }
    *at++ = ' ';
    at = append_decimal(at, value);
    *at++ = '\n';
    *at = '\0';
    semihost_write(line);
}
