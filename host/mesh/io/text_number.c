/* SPDX-License-Identifier: MIT */
/*
 * Decimal to double without strtod (text_number.h). A mantissa m < 10^19 and
 * a power of ten 10^q, |q| <= 22:
 * - m <= 2^53: m and 10^|q| are exact doubles, so one multiplication or
 *   division rounds once, correctly (Clinger's fast path);
 * - else, q <= 0 (the 17-digit "%.17g" case): a first guess m / 10^-q is at
 *   most a few units in the last place off; it is moved to the nearest
 *   double by comparing m / 10^-q exactly, in 128-bit integers, with the
 *   midpoints to its neighbours (ties to even, as strtod rounds).
 * Everything else returns 0 and the caller's strtod decides.
 */
#include "mesh/io/text_number.h"

#include <float.h>
#include <math.h>
#include <stdint.h>
#include <string.h>

static const double tn_pow10[23] = {1e0,  1e1,  1e2,  1e3,  1e4,  1e5,  1e6,  1e7,
                                    1e8,  1e9,  1e10, 1e11, 1e12, 1e13, 1e14, 1e15,
                                    1e16, 1e17, 1e18, 1e19, 1e20, 1e21, 1e22};

#if FLT_EVAL_METHOD == 0 /* double arithmetic rounds once to double */
#define TN_EXACT 1
#endif
#if defined(TN_EXACT) && defined(__SIZEOF_INT128__)
#define TN_WIDE 1
__extension__ typedef unsigned __int128 tn_u128;

static const uint64_t tn_pow5[23] = {
    1ull, 5ull, 25ull, 125ull, 625ull, 3125ull, 15625ull, 78125ull, 390625ull, 1953125ull,
    9765625ull, 48828125ull, 244140625ull, 1220703125ull, 6103515625ull, 30517578125ull,
    152587890625ull, 762939453125ull, 3814697265625ull, 19073486328125ull, 95367431640625ull,
    476837158203125ull, 2384185791015625ull};

/* The sign of m / 10^k - n * 2^f, exactly; 2 when it does not fit. */
static int tn_compare(uint64_t m, int k, uint64_t n, int f)
{
    tn_u128 rhs = (tn_u128)n * tn_pow5[k]; /* n < 2^56, 5^22 < 2^52 */
    tn_u128 lhs = m;
    int t = f + k; /* m vs n * 5^k * 2^t */
    if (t >= 0) {
        if (t > 126 || rhs >> (127 - t))
            return -1; /* rhs >= 2^127 > m */
        rhs <<= t;
    } else {
        if (-t > 63)
            return 2;
        lhs <<= -t;
    }
    return lhs < rhs ? -1 : lhs > rhs;
}

/* The double nearest to m / 10^k (2^53 < m < 10^19, 0 < k <= 22) in *out;
   0 when the comparison cannot decide. The guess is a normal double. */
static int tn_nearest(uint64_t m, int k, double *out)
{
    double d = (double)m / tn_pow10[k];
    for (int step = 0; step < 8; step++) {
        uint64_t u;
        memcpy(&u, &d, 8);
        uint64_t mm = (u & (((uint64_t)1 << 52) - 1)) | (uint64_t)1 << 52; /* d = mm * 2^e */
        int e = (int)(u >> 52) - 1075;
        int up = tn_compare(m, k, 2 * mm + 1, e - 1);
        if (up == 2)
            return 0;
        if (up > 0 || (up == 0 && (mm & 1))) {
            d = nextafter(d, INFINITY);
            if (up == 0) /* a tie goes to the even neighbour */
                break;
            continue;
        }
        int down = mm == (uint64_t)1 << 52 ? tn_compare(m, k, 4 * mm - 1, e - 2)
                                           : tn_compare(m, k, 2 * mm - 1, e - 1);
        if (down == 2)
            return 0;
        if (up == 0 || down > 0 || (down == 0 && !(mm & 1)))
            break;
        d = nextafter(d, 0.0);
        if (down == 0)
            break;
    }
    *out = d;
    return 1;
}
#endif

/* Eight ASCII digits at s (little-endian SWAR, as in simdjson and
   fast_float): whether they are all digits, and their value. */
static int tn_eight(const char *s, uint32_t *out)
{
    uint64_t v;
    memcpy(&v, s, 8);
#if defined(__BYTE_ORDER__) && __BYTE_ORDER__ == __ORDER_BIG_ENDIAN__
    v = __builtin_bswap64(v);
#endif
    if (((v + 0x4646464646464646ull) | (v - 0x3030303030303030ull)) & 0x8080808080808080ull)
        return 0;
    v -= 0x3030303030303030ull;
    v = v * 10 + (v >> 8);
    v = (((v & 0x000000FF000000FFull) * (100 + (1000000ull << 32))) +
         (((v >> 16) & 0x000000FF000000FFull) * (1 + (10000ull << 32)))) >> 32;
    *out = (uint32_t)v;
    return 1;
}

/* Digits from s into *m (*digits counts them); NULL past 19. */
static const char *tn_run(const char *s, const char *e, uint64_t *m, int *digits)
{
    uint32_t eight;
    while (e - s >= 8 && tn_eight(s, &eight)) {
        if ((*digits += 8) > 19)
            return NULL;
        *m = *m * 100000000u + eight;
        s += 8;
    }
    for (; s < e && (unsigned)(*s - '0') < 10; s++) {
        if (++*digits > 19)
            return NULL;
        *m = *m * 10 + (uint64_t)(*s - '0');
    }
    return s;
}

/* The mantissa's digits from s: *m, and in *frac how many of them (and the
   zeros before them) follow the point. Zeros before the first nonzero digit
   are not counted against the 19 digits. Returns where it stopped, or NULL
   when there are more or no digits. */
static const char *tn_digits(const char *s, const char *e, uint64_t *m, int *frac)
{
    const char *start = s, *mark;
    int digits = 0;
    *m = 0;
    *frac = 0;
    while (s < e && *s == '0')
        s++;
    if (!(s = tn_run(s, e, m, &digits)))
        return NULL;
    int any = s > start;
    if (s < e && *s == '.') {
        mark = ++s;
        if (!digits)
            while (s < e && *s == '0')
                s++;
        if (!(s = tn_run(s, e, m, &digits)))
            return NULL;
        *frac = (int)(s - mark);
        any |= s > mark;
    }
    return any ? s : NULL;
}

const char *tn_double(const char *s, const char *e, double *out)
{
#ifndef TN_EXACT
    (void)s, (void)e, (void)out;
    return NULL;
#else
    int neg = 0, frac, ex = 0;
    uint64_t m;
    if (s < e && (*s == '+' || *s == '-'))
        neg = *s++ == '-';
    if (!(s = tn_digits(s, e, &m, &frac)))
        return NULL;
    if (s < e && (*s == 'e' || *s == 'E')) {
        int eneg = 0;
        s++;
        if (s < e && (*s == '+' || *s == '-'))
            eneg = *s++ == '-';
        if (s == e || (unsigned)(*s - '0') >= 10)
            return NULL;
        for (; s < e && (unsigned)(*s - '0') < 10; s++)
            if (ex < 100000)
                ex = ex * 10 + (*s - '0');
        ex = eneg ? -ex : ex;
    }
    int q = ex - frac;
    double v;
    if (m == 0)
        v = 0.0;
    else if (q < -22 || q > 22)
        return NULL;
    else if (m <= (uint64_t)1 << 53)
        v = q < 0 ? (double)m / tn_pow10[-q] : (double)m * tn_pow10[q];
#ifdef TN_WIDE
    else if (q == 0)
        v = (double)m; /* the conversion rounds to nearest, ties to even */
    else if (q < 0 && tn_nearest(m, -q, &v))
        ;
#endif
    else
        return NULL;
    *out = neg ? -v : v;
    return s;
#endif
}
