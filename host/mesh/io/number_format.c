/* SPDX-License-Identifier: MIT */
/*
 * "%.17g" without printf. A double is m * 2^e (m < 2^53); its 17 significant
 * digits are round(m * 2^e * 10^k) for k = 16 - X, X the decimal exponent.
 * For k in [0, 27] that is (m * 5^k) * 2^(e + k) with m * 5^k < 2^116:
 * exact in 128-bit integers, rounded to nearest, ties to even, as glibc's
 * printf rounds. That covers |x| in [1e-11, 1e17), every coordinate of a
 * real mesh; anything else (and a compiler without __int128) goes to
 * snprintf itself. test_writers compares both on millions of values.
 */
#include "mesh/io/number_format.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

size_t number_u64(uint64_t v, char *out)
{
    char tmp[20];
    size_t n = 0;
    do {
        tmp[n++] = (char)('0' + v % 10);
        v /= 10;
    } while (v);
    for (size_t i = 0; i < n; i++)
        out[i] = tmp[n - 1 - i];
    return n;
}

static size_t g17_printf(double x, char *out)
{
    char buf[64];
    int n = snprintf(buf, sizeof buf, "%.17g", x);
    memcpy(out, buf, (size_t)n);
    return (size_t)n;
}

#ifdef __SIZEOF_INT128__

#define TEN16 10000000000000000ull

__extension__ typedef unsigned __int128 u128; /* __extension__: no -Wpedantic here */

/* round(m * 2^e * 10^(16 - x10)) or 0 when outside the exact range. */
static uint64_t scaled(uint64_t m, int e, int x10)
{
    static const uint64_t pow5[28] = {1ull,
                                      5ull,
                                      25ull,
                                      125ull,
                                      625ull,
                                      3125ull,
                                      15625ull,
                                      78125ull,
                                      390625ull,
                                      1953125ull,
                                      9765625ull,
                                      48828125ull,
                                      244140625ull,
                                      1220703125ull,
                                      6103515625ull,
                                      30517578125ull,
                                      152587890625ull,
                                      762939453125ull,
                                      3814697265625ull,
                                      19073486328125ull,
                                      95367431640625ull,
                                      476837158203125ull,
                                      2384185791015625ull,
                                      11920928955078125ull,
                                      59604644775390625ull,
                                      298023223876953125ull,
                                      1490116119384765625ull,
                                      7450580596923828125ull};
    int k = 16 - x10;
    if (k < 0 || k > 27)
        return 0;
    u128 p = (u128)m * pow5[k];
    int s = -(e + k); /* the value is p / 2^s */
    if (s <= 0)
        return s < -8 ? 0 : (uint64_t)(p << -s); /* below 10^18 when x10 is near */
    if (s > 120)
        return 0;
    u128 q = p >> s, r = p - (q << s), half = (u128)1 << (s - 1);
    if (r > half || (r == half && (q & 1)))
        q++;
    return q > ~(uint64_t)0 ? 0 : (uint64_t)q;
}

/* The 17 digits d (10^16 <= d < 10^17) and exponent of |x| > 0; 0 outside the range. */
static int digits17(double ax, uint64_t *d, int *x10)
{
    uint64_t bits;
    memcpy(&bits, &ax, sizeof bits);
    int be = (int)(bits >> 52) & 0x7ff;
    if (be == 0 || be == 0x7ff || !(ax >= 1e-11 && ax < 1e17))
        return 0;
    uint64_t m = (bits & ((1ull << 52) - 1)) | (1ull << 52);
    int e = be - 1075;
    int x = (int)floor(log10(ax)); /* off by one at most near a power of ten */
    for (int tries = 0; tries < 3; tries++) {
        uint64_t q = scaled(m, e, x);
        if (!q)
            return 0;
        if (q >= 10 * TEN16)
            x++; /* also when rounding carried into an 18th digit */
        else if (q < TEN16)
            x--;
        else {
            uint64_t below; /* x one too high, rounding reached 10^16: one lower, no carry */
            if (q == TEN16 && (below = scaled(m, e, x - 1)) != 0 && below < 10 * TEN16) {
                q = below;
                x--;
            }
            *d = q;
            *x10 = x;
            return 1;
        }
    }
    return 0;
}

size_t number_g17(double x, char *out)
{
    char *o = out;
    if (x == 0) { /* "0" and "-0" */
        if (signbit(x))
            *o++ = '-';
        *o++ = '0';
        return (size_t)(o - out);
    }
    uint64_t d;
    int x10;
    if (!digits17(fabs(x), &d, &x10))
        return g17_printf(x, out);
    char dig[17];
    for (int i = 16; i >= 0; i--, d /= 10)
        dig[i] = (char)('0' + d % 10);
    int n = 17; /* %g drops trailing zeros */
    while (dig[n - 1] == '0')
        n--;
    if (x < 0)
        *o++ = '-';
    if (x10 < -4) { /* e-style: d.ddde-XX (x10 >= -11 here) */
        *o++ = dig[0];
        if (n > 1) {
            *o++ = '.';
            memcpy(o, dig + 1, (size_t)(n - 1));
            o += n - 1;
        }
        *o++ = 'e';
        *o++ = '-';
        *o++ = (char)('0' + (-x10) / 10);
        *o++ = (char)('0' + (-x10) % 10);
    } else if (x10 < 0) { /* 0.000ddd */
        *o++ = '0';
        *o++ = '.';
        for (int i = 0; i < -x10 - 1; i++)
            *o++ = '0';
        memcpy(o, dig, (size_t)n);
        o += n;
    } else { /* ddd.ddd (x10 <= 16) */
        memcpy(o, dig, (size_t)x10 + 1);
        o += x10 + 1;
        if (n > x10 + 1) {
            *o++ = '.';
            memcpy(o, dig + x10 + 1, (size_t)(n - x10 - 1));
            o += n - x10 - 1;
        }
    }
    return (size_t)(o - out);
}

#else

size_t number_g17(double x, char *out) { return g17_printf(x, out); }

#endif
