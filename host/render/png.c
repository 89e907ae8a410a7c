/* SPDX-License-Identifier: MIT */
/*
 * A small PNG writer (8-bit RGB) with its own deflate encoder (RFC 1951):
 * LZ77 with hash chains over a 32 KiB window, then dynamic Huffman blocks
 * (code lengths limited to 15/7 bits by halving frequencies until they fit).
 * Rows are filtered with the filter of smallest absolute sum, as libpng does
 * by default. No dependency: the pictures limn renders compress to about the
 * size zlib gives them, and nothing needs to be installed for it.
 */
#include "base/atomic_file.h"
#include "base/context.h"

#include <stdlib.h>
#include <string.h>

/* ---------------------------------------------------------- bit writer */

typedef struct bytes {
    uint8_t *data;
    size_t len, cap;
    int failed;
} bytes;

static void put_byte(bytes *b, uint8_t v)
{
    if (b->failed)
        return;
    if (b->len == b->cap) {
        size_t cap = b->cap ? 2 * b->cap : 4096;
        uint8_t *d = realloc(b->data, cap);
        if (!d) {
            b->failed = 1;
            return;
        }
        b->data = d;
        b->cap = cap;
    }
    b->data[b->len++] = v;
}

typedef struct bitw {
    bytes *out;
    uint32_t acc;
    int nbits;
} bitw;

static void put_bits(bitw *w, uint32_t value, int n)
{
    w->acc |= value << w->nbits;
    w->nbits += n;
    while (w->nbits >= 8) {
        put_byte(w->out, (uint8_t)w->acc);
        w->acc >>= 8;
        w->nbits -= 8;
    }
}

static void flush_bits(bitw *w)
{
    if (w->nbits > 0)
        put_byte(w->out, (uint8_t)w->acc);
    w->acc = 0;
    w->nbits = 0;
}

/* ------------------------------------------------------------- Huffman */

/* Code lengths for freq[0..n) with no code longer than limit. */
static void huffman_lengths(const uint32_t *freq, int n, int limit, uint8_t *len)
{
    uint32_t f[320];
    int parent[640];
    uint64_t weight[640];
    for (int i = 0; i < n; i++)
        f[i] = freq[i];
    for (;;) {
        memset(len, 0, (size_t)n);
        int leaves = 0, last = 0;
        for (int i = 0; i < n; i++)
            if (f[i]) {
                leaves++;
                last = i;
            }
        if (leaves == 0)
            return;
        if (leaves == 1) {
            len[last] = 1;
            return;
        }
        int nodes = n;
        int active[640], na = 0;
        for (int i = 0; i < n; i++) {
            parent[i] = -1;
            weight[i] = f[i];
            if (f[i])
                active[na++] = i;
        }
        while (na > 1) {
            /* the two lightest (ties by index, for determinism) */
            int a = -1, b = -1;
            for (int k = 0; k < na; k++) {
                int x = active[k];
                if (a < 0 || weight[x] < weight[active[a]])
                    b = a, a = k;
                else if (b < 0 || weight[x] < weight[active[b]])
                    b = k;
            }
            int na_ = active[a], nb_ = active[b];
            weight[nodes] = weight[na_] + weight[nb_];
            parent[nodes] = -1;
            parent[na_] = parent[nb_] = nodes;
            /* replace a by the new node, drop b */
            active[a] = nodes++;
            active[b] = active[--na];
        }
        int longest = 0;
        for (int i = 0; i < n; i++)
            if (f[i]) {
                int d = 0;
                for (int p = parent[i]; p >= 0; p = parent[p])
                    d++;
                len[i] = (uint8_t)d;
                longest = d > longest ? d : longest;
            }
        if (longest <= limit)
            return;
        for (int i = 0; i < n; i++)
            if (f[i])
                f[i] = (f[i] >> 1) | 1;
    }
}

/* Canonical codes, bit-reversed for the LSB-first writer. */
static void huffman_codes(const uint8_t *len, int n, uint16_t *code)
{
    int count[16] = {0}, next[16];
    for (int i = 0; i < n; i++)
        count[len[i]]++;
    count[0] = 0;
    int c = 0;
    for (int bits = 1; bits < 16; bits++) {
        c = (c + count[bits - 1]) << 1;
        next[bits] = c;
    }
    for (int i = 0; i < n; i++) {
        if (!len[i]) {
            code[i] = 0;
            continue;
        }
        int v = next[len[i]]++, r = 0;
        for (int k = 0; k < len[i]; k++)
            r |= ((v >> k) & 1) << (len[i] - 1 - k);
        code[i] = (uint16_t)r;
    }
}

/* --------------------------------------------------------------- deflate */

static const uint16_t len_base[29] = {3,  4,  5,  6,  7,  8,  9,  10, 11,  13,
                                      15, 17, 19, 23, 27, 31, 35, 43, 51,  59,
                                      67, 83, 99, 115, 131, 163, 195, 227, 258};
static const uint8_t len_extra[29] = {0, 0, 0, 0, 0, 0, 0, 0, 1, 1, 1, 1, 2, 2, 2,
                                      2, 3, 3, 3, 3, 4, 4, 4, 4, 5, 5, 5, 5, 0};
static const uint16_t dist_base[30] = {1,    2,    3,    4,    5,    7,     9,     13,
                                       17,   25,   33,   49,   65,   97,    129,   193,
                                       257,  385,  513,  769,  1025, 1537,  2049,  3073,
                                       4097, 6145, 8193, 12289, 16385, 24577};
static const uint8_t dist_extra[30] = {0, 0, 0, 0, 1, 1, 2, 2,  3,  3,  4,  4,  5,  5,  6,
                                       6, 7, 7, 8, 8, 9, 9, 10, 10, 11, 11, 12, 12, 13, 13};

static int len_code(int length)
{
    int k = 28;
    while (len_base[k] > length)
        k--;
    return k;
}

static int dist_code(int d)
{
    int k = 29;
    while (dist_base[k] > d)
        k--;
    return k;
}

typedef struct token {
    uint16_t lit;   /* literal byte, or match length */
    uint16_t dist;  /* 0 for a literal */
} token;

#define WINDOW 32768
#define HASH_BITS 15
#define MAX_CHAIN 96
#define BLOCK_TOKENS 65536

/* Symbol frequencies of the tokens, the end of block included. */
static void count_symbols(const token *t, size_t nt, uint32_t lf[286], uint32_t df[30])
{
    for (size_t i = 0; i < nt; i++) {
        if (t[i].dist == 0) {
            lf[t[i].lit]++;
        } else {
            lf[257 + len_code(t[i].lit)]++;
            df[dist_code(t[i].dist)]++;
        }
    }
    lf[256] = 1;
    /* at least two codes per alphabet keeps every decoder happy */
    if (lf[0] == 0)
        lf[0] = 1;
    int used = 0;
    for (int i = 0; i < 30; i++)
        used += df[i] != 0;
    if (used < 2) {
        if (!df[0])
            df[0] = 1;
        if (!df[1])
            df[1] = 1;
    }
}

/* Run-length code of the code lengths (symbols 16, 17, 18, each with its
   extra bits); returns the number of symbols. */
static int rle_lengths(const uint8_t *lens, int total, uint8_t *sym, uint8_t *extra)
{
    int ns = 0;
    for (int i = 0; i < total;) {
        int v = lens[i], run = 1;
        while (i + run < total && lens[i + run] == v)
            run++;
        i += run;
        if (v == 0) {
            while (run >= 11) {
                int r = run > 138 ? 138 : run;
                sym[ns] = 18, extra[ns++] = (uint8_t)(r - 11);
                run -= r;
            }
            if (run >= 3) {
                sym[ns] = 17, extra[ns++] = (uint8_t)(run - 3);
                run = 0;
            }
        } else {
            sym[ns] = (uint8_t)v, extra[ns++] = 0;
            run--;
            while (run >= 3) {
                int r = run > 6 ? 6 : run;
                sym[ns] = 16, extra[ns++] = (uint8_t)(r - 3);
                run -= r;
            }
        }
        while (run-- > 0)
            sym[ns] = (uint8_t)v, extra[ns++] = 0;
    }
    return ns;
}

/* A dynamic block's header: the first hlit literal/length and hdist
   distance code lengths, run-length coded in the code length code. */
static void write_header(bitw *w, int final, const uint8_t *ll, int hlit, const uint8_t *dl,
                         int hdist)
{
    uint8_t lens[316], sym[316], extra[316];
    memcpy(lens, ll, (size_t)hlit);
    memcpy(lens + hlit, dl, (size_t)hdist);
    int ns = rle_lengths(lens, hlit + hdist, sym, extra);
    uint32_t cf[19] = {0};
    for (int i = 0; i < ns; i++)
        cf[sym[i]]++;
    uint8_t cl[19];
    uint16_t cc[19];
    huffman_lengths(cf, 19, 7, cl);
    huffman_codes(cl, 19, cc);
    static const uint8_t order[19] = {16, 17, 18, 0, 8, 7, 9, 6, 10, 5,
                                      11, 4, 12, 3, 13, 2, 14, 1, 15};
    int hclen = 19;
    while (hclen > 4 && cl[order[hclen - 1]] == 0)
        hclen--;

    put_bits(w, final ? 1u : 0u, 1);
    put_bits(w, 2, 2);
    put_bits(w, (uint32_t)(hlit - 257), 5);
    put_bits(w, (uint32_t)(hdist - 1), 5);
    put_bits(w, (uint32_t)(hclen - 4), 4);
    for (int i = 0; i < hclen; i++)
        put_bits(w, cl[order[i]], 3);
    for (int i = 0; i < ns; i++) {
        put_bits(w, cc[sym[i]], cl[sym[i]]);
        if (sym[i] == 16)
            put_bits(w, extra[i], 2);
        else if (sym[i] == 17)
            put_bits(w, extra[i], 3);
        else if (sym[i] == 18)
            put_bits(w, extra[i], 7);
    }
}

static void write_block(bitw *w, const token *t, size_t nt, int final)
{
    uint32_t lf[286] = {0}, df[30] = {0};
    count_symbols(t, nt, lf, df);
    uint8_t ll[286], dl[30];
    uint16_t lc[286], dc[30];
    huffman_lengths(lf, 286, 15, ll);
    huffman_lengths(df, 30, 15, dl);
    huffman_codes(ll, 286, lc);
    huffman_codes(dl, 30, dc);
    int hlit = 286, hdist = 30;
    while (hlit > 257 && ll[hlit - 1] == 0)
        hlit--;
    while (hdist > 1 && dl[hdist - 1] == 0)
        hdist--;
    write_header(w, final, ll, hlit, dl, hdist);
    for (size_t i = 0; i < nt; i++) {
        if (t[i].dist == 0) {
            put_bits(w, lc[t[i].lit], ll[t[i].lit]);
        } else {
            int k = len_code(t[i].lit), d = dist_code(t[i].dist);
            put_bits(w, lc[257 + k], ll[257 + k]);
            put_bits(w, (uint32_t)(t[i].lit - len_base[k]), len_extra[k]);
            put_bits(w, dc[d], dl[d]);
            put_bits(w, (uint32_t)(t[i].dist - dist_base[d]), dist_extra[d]);
        }
    }
    put_bits(w, lc[256], ll[256]);
}

static int deflate_bytes(const uint8_t *in, size_t n, bytes *out)
{
    int32_t *head = malloc((1u << HASH_BITS) * sizeof *head);
    int32_t *prev = malloc(WINDOW * sizeof *prev);
    token *tok = malloc(BLOCK_TOKENS * sizeof *tok);
    if (!head || !prev || !tok) {
        free(head);
        free(prev);
        free(tok);
        return 0;
    }
    for (size_t i = 0; i < (1u << HASH_BITS); i++)
        head[i] = -1;
    bitw w = {.out = out};
    size_t nt = 0, i = 0;
#define HASH(p) ((((uint32_t)in[p] << 10) ^ ((uint32_t)in[(p) + 1] << 5) ^ in[(p) + 2]) & ((1u << HASH_BITS) - 1))
    while (i < n) {
        int best = 0, best_dist = 0;
        if (i + 2 < n) {
            uint32_t h = HASH(i);
            int32_t cand = head[h];
            int chain = MAX_CHAIN;
            size_t max_len = n - i < 258 ? n - i : 258;
            while (cand >= 0 && i - (size_t)cand <= WINDOW - 1 && chain-- > 0) {
                const uint8_t *a = in + cand, *b = in + i;
                size_t l = 0;
                while (l < max_len && a[l] == b[l])
                    l++;
                if ((int)l > best) {
                    best = (int)l;
                    best_dist = (int)(i - (size_t)cand);
                    if (l == max_len)
                        break;
                }
                int32_t p = prev[cand & (WINDOW - 1)];
                if (p >= cand)
                    break;
                cand = p;
            }
        }
        size_t advance = best >= 3 ? (size_t)best : 1;
        if (best >= 3)
            tok[nt++] = (token){(uint16_t)best, (uint16_t)best_dist};
        else
            tok[nt++] = (token){in[i], 0};
        for (size_t k = 0; k < advance; k++, i++)
            if (i + 2 < n) {
                uint32_t h = HASH(i);
                prev[i & (WINDOW - 1)] = head[h];
                head[h] = (int32_t)i;
            }
        if (nt == BLOCK_TOKENS) {
            write_block(&w, tok, nt, i >= n);
            nt = 0;
        }
    }
#undef HASH
    if (nt > 0 || n == 0)
        write_block(&w, tok, nt, 1);
    flush_bits(&w);
    free(head);
    free(prev);
    free(tok);
    return !out->failed;
}

/* ------------------------------------------------------------------- PNG */

/* CRC-32 bit by bit: pictures are small, and no table (no global state). */
static uint32_t crc32_update(uint32_t crc, const uint8_t *p, size_t n)
{
    crc = ~crc;
    for (size_t i = 0; i < n; i++) {
        crc ^= p[i];
        for (int j = 0; j < 8; j++)
            crc = (crc >> 1) ^ (0xEDB88320u & (0u - (crc & 1u)));
    }
    return ~crc;
}

static void put_u32(bytes *b, uint32_t v)
{
    put_byte(b, (uint8_t)(v >> 24));
    put_byte(b, (uint8_t)(v >> 16));
    put_byte(b, (uint8_t)(v >> 8));
    put_byte(b, (uint8_t)v);
}

static void chunk(bytes *b, const char *type, const uint8_t *data, size_t n)
{
    put_u32(b, (uint32_t)n);
    size_t start = b->len;
    for (int i = 0; i < 4; i++)
        put_byte(b, (uint8_t)type[i]);
    for (size_t i = 0; i < n; i++)
        put_byte(b, data[i]);
    put_u32(b, b->failed ? 0 : crc32_update(0, b->data + start, n + 4));
}

static int paeth(int a, int b, int c)
{
    int p = a + b - c, pa = abs(p - a), pb = abs(p - b), pc = abs(p - c);
    return pa <= pb && pa <= pc ? a : pb <= pc ? b : c;
}

/* Each row with the filter of smallest absolute sum (its type byte first)
   into raw; trial: room for 5 rows. */
static void filter_rows(const uint8_t *rgb, int height, size_t stride, uint8_t *raw,
                        uint8_t *trial)
{
    for (int y = 0; y < height; y++) {
        const uint8_t *row = rgb + (size_t)y * stride, *up = y ? row - stride : NULL;
        long best_sum = -1;
        int best = 0;
        for (int f = 0; f < 5; f++) {
            uint8_t *o = trial + (size_t)f * stride;
            long sum = 0;
            for (size_t i = 0; i < stride; i++) {
                int a = i >= 3 ? row[i - 3] : 0, b = up ? up[i] : 0,
                    c = (up && i >= 3) ? up[i - 3] : 0, pred = 0;
                switch (f) {
                case 1: pred = a; break;
                case 2: pred = b; break;
                case 3: pred = (a + b) / 2; break;
                case 4: pred = paeth(a, b, c); break;
                default: pred = 0; break;
                }
                o[i] = (uint8_t)(row[i] - pred);
                sum += o[i] < 128 ? o[i] : 256 - o[i];
            }
            if (best_sum < 0 || sum < best_sum)
                best_sum = sum, best = f;
        }
        uint8_t *dst = raw + (size_t)y * (stride + 1);
        dst[0] = (uint8_t)best;
        memcpy(dst + 1, trial + (size_t)best * stride, stride);
    }
}

/* The zlib stream of raw into z: header, deflate, Adler-32; 0 when out of
   memory in deflate. */
static int zlib_stream(const uint8_t *raw, size_t raw_len, bytes *z)
{
    put_byte(z, 0x78);
    put_byte(z, 0x9C);
    if (!deflate_bytes(raw, raw_len, z))
        return 0;
    uint32_t s1 = 1, s2 = 0;
    for (size_t i = 0; i < raw_len; i++) {
        s1 = (s1 + raw[i]) % 65521u;
        s2 = (s2 + s1) % 65521u;
    }
    put_u32(z, (s2 << 16) | s1);
    return 1;
}

/* The PNG file: signature, IHDR (8-bit RGB), the one IDAT, IEND. */
static void png_file(bytes *png, int width, int height, const bytes *z)
{
    static const uint8_t signature[8] = {0x89, 'P', 'N', 'G', 0x0D, 0x0A, 0x1A, 0x0A};
    for (int i = 0; i < 8; i++)
        put_byte(png, signature[i]);
    uint8_t ihdr[13] = {(uint8_t)(width >> 24), (uint8_t)(width >> 16), (uint8_t)(width >> 8),
                        (uint8_t)width, (uint8_t)(height >> 24), (uint8_t)(height >> 16),
                        (uint8_t)(height >> 8), (uint8_t)height, 8, 2, 0, 0, 0};
    chunk(png, "IHDR", ihdr, sizeof ihdr);
    chunk(png, "IDAT", z->data, z->len);
    chunk(png, "IEND", NULL, 0);
}

/* png's bytes to path, whole or not at all. */
static limn_status write_whole(limn_context *ctx, const char *path, const bytes *png)
{
    atomic_file af;
    limn_status st = atomic_file_open(ctx, path, &af);
    if (st)
        return st;
    if (fwrite(png->data, 1, png->len, af.f) != png->len) {
        atomic_file_abort(&af);
        return ctx_fail(ctx, LIMN_ERR_IO, "%s: write failed", path);
    }
    return atomic_file_commit(ctx, &af);
}

/* limn_png_write and limn_output_set_add_png (set not NULL): the picture
   encoded, then written whole or staged in set. */
static limn_status png_out(limn_context *ctx, const char *fn, limn_output_set *set,
                           const char *path, int width, int height, const uint8_t *rgb)
{
    if (!ctx)
        return LIMN_ERR_ARGUMENT;
    ctx_clear(ctx);
    if (!path || !*path || !rgb)
        return ctx_fail(ctx, LIMN_ERR_ARGUMENT, "%s: %s", fn,
                         !rgb ? "rgb is NULL" : "no file name");
    if (width < 1 || height < 1 || width > 65535 || height > 65535)
        return ctx_fail(ctx, LIMN_ERR_ARGUMENT, "%s: picture size %dx%d is outside 1..65535",
                         fn, width, height);
    size_t stride = 3 * (size_t)width, raw_len = (stride + 1) * (size_t)height;
    uint8_t *raw = malloc(raw_len), *trial = malloc(5 * stride);
    bytes z = {0}, png = {0};
    limn_status st = LIMN_OK;
    if (!raw || !trial)
        st = ctx_fail(ctx, LIMN_ERR_MEMORY, "out of memory for a %dx%d picture", width, height);
    else
        filter_rows(rgb, height, stride, raw, trial);
    if (!st && !zlib_stream(raw, raw_len, &z))
        st = ctx_fail(ctx, LIMN_ERR_MEMORY, "out of memory compressing the picture");
    if (!st)
        png_file(&png, width, height, &z);
    if (!st && (png.failed || z.failed))
        st = ctx_fail(ctx, LIMN_ERR_MEMORY, "out of memory writing the picture");
    if (!st && set)
        st = limn_output_set_add_bytes(ctx, set, path, png.data, png.len);
    else if (!st)
        st = write_whole(ctx, path, &png);
    free(raw);
    free(trial);
    free(z.data);
    free(png.data);
    return st;
}

limn_status limn_png_write(limn_context *ctx, const char *path, int width, int height,
                           const uint8_t *rgb)
{
    return png_out(ctx, "limn_png_write", NULL, path, width, height, rgb);
}

limn_status limn_output_set_add_png(limn_context *ctx, limn_output_set *set, const char *path,
                                    int width, int height, const uint8_t *rgb)
{
    if (ctx && !set)
        return ctx_fail(ctx, LIMN_ERR_ARGUMENT, "limn_output_set_add_png: set is NULL");
    return png_out(ctx, "limn_output_set_add_png", set, path, width, height, rgb);
}
