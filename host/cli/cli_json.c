/* SPDX-License-Identifier: MIT */
/* The JSON writer of the reports and of limn info --json (cli.h). */
#include "cli.h"

#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

struct json_out {
    char *text;
    size_t len, cap;
    int depth;
    int need_comma;
    int failed;
    int compact;    /* one line (limn info --json) instead of one key per line */
};

static void put(json_out *j, const char *s, size_t n)
{
    if (j->failed)
        return;
    if (j->len + n + 1 > j->cap) {
        size_t cap = (j->cap ? j->cap * 2 : 1024) + n;
        char *t = realloc(j->text, cap);
        if (!t) {
            j->failed = 1;
            return;
        }
        j->text = t;
        j->cap = cap;
    }
    memcpy(j->text + j->len, s, n);
    j->len += n;
    j->text[j->len] = '\0';
}

static void puts_(json_out *j, const char *s) { put(j, s, strlen(s)); }

/* Length of the valid UTF-8 sequence at p (RFC 3629: no overlong forms, no
   surrogates, nothing past U+10FFFF), or 0 when the byte starts none. */
static size_t utf8_length(const unsigned char *p)
{
    unsigned char c = p[0];
    size_t n;
    unsigned char lo = 0x80, hi = 0xBF; /* range of the second byte */
    if (c < 0x80)
        return 1;
    if (c >= 0xC2 && c <= 0xDF)
        n = 2;
    else if (c >= 0xE0 && c <= 0xEF) {
        n = 3;
        lo = c == 0xE0 ? 0xA0 : 0x80;
        hi = c == 0xED ? 0x9F : 0xBF;
    } else if (c >= 0xF0 && c <= 0xF4) {
        n = 4;
        lo = c == 0xF0 ? 0x90 : 0x80;
        hi = c == 0xF4 ? 0x8F : 0xBF;
    } else
        return 0;
    if (p[1] < lo || p[1] > hi)
        return 0;
    for (size_t i = 2; i < n; i++)
        if (p[i] < 0x80 || p[i] > 0xBF)
            return 0;
    return n;
}

/* A JSON string (RFC 8259): quotes, backslashes and control characters
   escaped; a byte that is not valid UTF-8 (a file name from another
   encoding) becomes U+FFFD, so the document always parses. */
static void put_string(json_out *j, const char *v)
{
    puts_(j, "\"");
    for (const unsigned char *p = (const unsigned char *)v; *p;) {
        char esc[8];
        size_t n = utf8_length(p);
        const char *named = *p == '"'    ? "\\\""
                            : *p == '\\' ? "\\\\"
                            : *p == '\n' ? "\\n"
                            : *p == '\t' ? "\\t"
                            : *p == '\r' ? "\\r"
                            : *p == '\b' ? "\\b"
                            : *p == '\f' ? "\\f"
                                         : NULL;
        if (named) {
            puts_(j, named);
        } else if (*p < 0x20) {
            snprintf(esc, sizeof esc, "\\u%04x", *p);
            puts_(j, esc);
        } else if (n == 0) {
            puts_(j, "\\ufffd");
            n = 1;
        } else {
            put(j, (const char *)p, n);
        }
        p += n ? n : 1;
    }
    puts_(j, "\"");
}

/* Comma, then a new line and indentation (or one space when compact). */
static void element(json_out *j)
{
    if (j->need_comma)
        puts_(j, j->compact ? ", " : ",");
    if (!j->compact) {
        puts_(j, "\n");
        for (int i = 0; i < j->depth; i++)
            puts_(j, "  ");
    }
    j->need_comma = 1;
}

static void key(json_out *j, const char *k)
{
    element(j);
    put_string(j, k);
    puts_(j, ": ");
}

/* A closing bracket on its own line (or right after the last value). */
static void close_(json_out *j, const char *bracket)
{
    j->depth--;
    if (!j->compact) {
        puts_(j, "\n");
        for (int i = 0; i < j->depth; i++)
            puts_(j, "  ");
    }
    puts_(j, bracket);
    j->need_comma = 1;
}

static void open_(json_out *j, const char *bracket)
{
    puts_(j, bracket);
    j->depth++;
    j->need_comma = 0;
}

static json_out *begin(int compact)
{
    json_out *j = calloc(1, sizeof *j);
    if (j) {
        j->compact = compact;
        open_(j, "{");
        json_string(j, "limn_version", limn_version());
    }
    return j;
}

json_out *json_begin(void) { return begin(0); }
json_out *json_begin_line(void) { return begin(1); }

void json_string(json_out *j, const char *k, const char *v)
{
    key(j, k);
    put_string(j, v ? v : "");
}

/* The shortest of %.15g / %.17g that reads back to v, with a '.' whatever
   the locale (the C locale for this thread, only here); null if not finite. */
static void put_number(json_out *j, double v)
{
    char buf[64] = "null";
    if (isfinite(v)) {
        cli_locale loc;
        int entered = cli_locale_enter(&loc);
        snprintf(buf, sizeof buf, "%.15g", v);
        if (strtod(buf, NULL) != v)
            snprintf(buf, sizeof buf, "%.17g", v);
        if (entered)
            cli_locale_leave(&loc);
        else if (strchr(buf, ','))
            *strchr(buf, ',') = '.'; /* no C locale object: mend the decimal comma */
    }
    puts_(j, buf);
}

void json_number(json_out *j, const char *k, double v)
{
    key(j, k);
    put_number(j, v);
}

void json_integer(json_out *j, const char *k, long long v)
{
    char buf[32];
    key(j, k);
    snprintf(buf, sizeof buf, "%lld", v);
    puts_(j, buf);
}

void json_bool(json_out *j, const char *k, int v)
{
    key(j, k);
    puts_(j, v ? "true" : "false");
}

void json_object_begin(json_out *j, const char *k)
{
    key(j, k);
    open_(j, "{");
}

void json_object_end(json_out *j) { close_(j, "}"); }

void json_array_begin(json_out *j, const char *k)
{
    key(j, k);
    open_(j, "[");
}

void json_array_end(json_out *j) { close_(j, "]"); }

void json_element_number(json_out *j, double v)
{
    element(j);
    put_number(j, v);
}

void json_element_object_begin(json_out *j)
{
    element(j);
    open_(j, "{");
}

void json_element_array_begin(json_out *j)
{
    element(j);
    open_(j, "[");
}

limn_status json_print(limn_context *ctx, json_out *j, FILE *f)
{
    (void)ctx; /* the messages are the CLI's own (cli_error) */
    limn_status st = LIMN_OK;
    while (j->depth > 0)
        json_object_end(j);
    puts_(j, "\n");
    if (j->failed)
        st = cli_error(LIMN_ERR_MEMORY, "out of memory writing JSON");
    else if (fwrite(j->text, 1, j->len, f) != j->len || fflush(f) != 0)
        st = cli_error(LIMN_ERR_IO, "cannot write JSON: %s", strerror(errno));
    free(j->text);
    free(j);
    return st;
}

limn_status json_stage(limn_context *ctx, json_out *j, const char *path, limn_output_set *set)
{
    limn_status st = LIMN_OK;
    while (j->depth > 0)
        json_object_end(j);
    puts_(j, "\n");
    if (j->failed)
        st = cli_error(LIMN_ERR_MEMORY, "out of memory writing the report %s", path);
    else
        st = limn_output_set_add_bytes(ctx, set, path, j->text, j->len);
    free(j->text);
    free(j);
    return st;
}

limn_status json_commit(limn_context *ctx, json_out *j, const char *path)
{
    limn_output_set *set = NULL;
    limn_status st = limn_output_set_create(ctx, &set);
    if (st) {
        free(j->text);
        free(j);
        return st;
    }
    st = json_stage(ctx, j, path, set);
    if (!st)
        st = limn_output_set_commit(ctx, set);
    limn_output_set_destroy(set);
    return st;
}
