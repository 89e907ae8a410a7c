/* SPDX-License-Identifier: MIT */
/* Every command's options through getopt_long (cli.h, cli_options). */
#include "cli.h"

#include <getopt.h>
#include <stdlib.h>
#include <string.h>

/* Levenshtein distance of a and b, or 3 when over 2 (all that matters). */
static int distance(const char *a, const char *b)
{
    size_t la = strlen(a), lb = strlen(b);
    if (la > 64 || lb > 64 || (la > lb ? la - lb : lb - la) > 2)
        return 3;
    int row[65];
    for (size_t j = 0; j <= lb; j++)
        row[j] = (int)j;
    for (size_t i = 1; i <= la; i++) {
        int diag = row[0];
        row[0] = (int)i;
        for (size_t j = 1; j <= lb; j++) {
            int up = row[j];
            int best = diag + (a[i - 1] != b[j - 1]);
            if (up + 1 < best)
                best = up + 1;
            if (row[j - 1] + 1 < best)
                best = row[j - 1] + 1;
            row[j] = best;
            diag = up;
        }
    }
    return row[lb] > 2 ? 3 : row[lb];
}

/* "unknown option 'ARG'", with "; did you mean --X?" for the nearest long
   option at edit distance 2 or less (the first of equals). */
static int unknown(const char *cmd, const char *arg, const struct option *longopts)
{
    char name[128];
    const char *p = arg;
    while (*p == '-')
        p++;
    snprintf(name, sizeof name, "%.*s", (int)strcspn(p, "="), p);
    int dashes = arg[0] == '-' && arg[1] == '-';
    char list[512] = "";
    int prefixes = 0;
    for (const struct option *o = longopts; dashes && name[0] && o->name; o++) {
        if (strncmp(o->name, name, strlen(name)) == 0) {
            size_t len = strlen(list);
            snprintf(list + len, sizeof list - len, "%s--%s", prefixes ? ", " : "", o->name);
            prefixes++;
        }
    }
    if (prefixes > 1)
        return cli_usage_error(cmd, "option '%s' is ambiguous: %s", arg, list);
    const char *best = NULL;
    int best_d = 3;
    for (const struct option *o = longopts; dashes && o->name; o++) {
        int d = distance(name, o->name);
        if (d < best_d) {
            best_d = d;
            best = o->name;
        }
    }
    if (best)
        return cli_usage_error(cmd, "unknown option '%s'; did you mean --%s?", arg, best);
    return cli_usage_error(cmd, "unknown option '%s'", arg);
}

/* The normalised arguments being built: out[0..k), their spelled options
   in store (80 bytes an argument at most). */
typedef struct normal {
    char **out;
    char *store;
    size_t used;
    int k;
} normal;

/* "--NAME" or "-C" in the next 80 bytes of store. */
static char *spell(normal *nm, const char *name, int c)
{
    char *p = nm->store + nm->used;
    if (name)
        snprintf(p, 80, "--%.76s", name);
    else
        snprintf(p, 80, "-%c", c);
    nm->used += strlen(p) + 1;
    return p;
}

/* A copy of longopts (count entries) whose options return 256 + their
   index, so that a short one never collides; NULL when out of memory. */
static struct option *numbered(const struct option *longopts, int count)
{
    struct option *lo = calloc((size_t)count + 1, sizeof *lo);
    for (int i = 0; lo && i < count; i++) {
        lo[i] = longopts[i];
        lo[i].flag = NULL;
        lo[i].val = 256 + i;
    }
    return lo;
}

/* One getopt_long result c into nm; 0 or an exit status. */
static int take(const char *cmd, int c, char **in, const struct option *lo,
                const struct option *longopts, normal *nm)
{
    if (c == 1) {
        nm->out[nm->k++] = optarg;
    } else if (c >= 256) {
        /* "--name=value" and "--name value" (and an unambiguous prefix of
           name) all become "--name" "value" for the command's parser */
        nm->out[nm->k++] = spell(nm, lo[c - 256].name, 0);
        if (optarg)
            nm->out[nm->k++] = optarg;
    } else if (c == ':') {
        /* the command's parser says "OPT needs a value" */
        nm->out[nm->k++] = optopt >= 256 ? spell(nm, lo[optopt - 256].name, 0)
                                         : spell(nm, NULL, optopt);
    } else if (c == '?') {
        const char *arg = in[optind - 1];
        if (optopt >= 256)
            return cli_usage_error(cmd, "--%s takes no value ('%s')", lo[optopt - 256].name, arg);
        return unknown(cmd, optopt ? spell(nm, NULL, optopt) : arg, longopts);
    } else {
        nm->out[nm->k++] = spell(nm, NULL, c);
        if (optarg)
            nm->out[nm->k++] = optarg;
    }
    return 0;
}

int cli_options(const char *cmd, const struct option *longopts, const char *shortopts, int *argc,
                char ***argv)
{
    static char **normal_out; /* the previous call's arrays (one command a process) */
    static char *normal_store;
    cli_set_command(cmd);
    int n = *argc;
    char **in = *argv;
    char optstring[64];
    /* '-': arguments in their order (non-options returned as 1); ':': a
       missing value is reported as ':' and left to the command's message */
    snprintf(optstring, sizeof optstring, "-:%s", shortopts);
    int count = 0;
    while (longopts[count].name)
        count++;
    struct option *lo = numbered(longopts, count);
    normal nm = {calloc(2 * (size_t)n + 2, sizeof(char *)), malloc((size_t)n * 80 + 1), 0, 0};
    if (!lo || !nm.out || !nm.store) {
        free(lo);
        free(nm.out);
        free(nm.store);
        fprintf(stderr, "limn %s: error: out of memory\n", cmd);
        return EXIT_FAILURE_RUN;
    }
    int c, idx, rc = 0, before = 1;
    nm.out[nm.k++] = in[0];
    opterr = 0;
    optind = 0; /* glibc: start afresh */
    while (!rc && (before = optind > 0 ? optind : 1,
                   (c = getopt_long(n, in, optstring, lo, &idx)) != -1))
        rc = take(cmd, c, in, lo, longopts, &nm);
    /* a "--" that ended the options is kept (the commands refuse it, as before) */
    if (!rc && optind == before + 1 && optind <= n && strcmp(in[before], "--") == 0)
        nm.out[nm.k++] = in[before];
    for (int i = optind; !rc && i < n; i++)
        nm.out[nm.k++] = in[i];
    nm.out[nm.k] = NULL;
    free(lo);
    if (rc) {
        free(nm.out);
        free(nm.store);
        return rc;
    }
    free(normal_out);
    free(normal_store);
    normal_out = nm.out;
    normal_store = nm.store;
    *argc = nm.k;
    *argv = nm.out;
    return 0;
}
