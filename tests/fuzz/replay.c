/* SPDX-License-Identifier: MIT */
/*
 * Replays files through the fuzz harness (fuzz_common.h) in the normal test
 * suite, without libFuzzer: every committed seed of tests/fuzz/corpus and
 * every crash ever found (tests/fuzz/regressions). The target of a file is
 * the name of the directory holding it (corpus/obj/..., regressions/ply_le/...).
 *
 *   replay DIR...   (each DIR holds one subdirectory per target)
 *
 * A broken contract aborts (and the sanitizers report, in the LIMN_SANITIZE
 * build); the exit status is 0 when every file ran through.
 */
#include "fuzz_common.h"
#include "slurp.h"

#include <dirent.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

static int cmp_str(const void *a, const void *b)
{
    return strcmp(*(char *const *)a, *(char *const *)b);
}

static int replay_file(const char *target, const char *path)
{
    FILE *f = fopen(path, "rb");
    if (!f) {
        fprintf(stderr, "replay: cannot open %s\n", path);
        return 1;
    }
    size_t n;
    unsigned char *buf = (unsigned char *)test_read_stream(f, &n);
    fclose(f);
    if (!buf) {
        fprintf(stderr, "replay: out of memory reading %s\n", path);
        return 1;
    }
    int rc = limn_fuzz_run(target, buf, n);
    free(buf);
    if (rc) {
        fprintf(stderr, "replay: %s: unknown target '%s'\n", path, target);
        return 1;
    }
    return 0;
}

/* Every regular file under dir/target (sorted, one level). */
static int replay_target(const char *dir, const char *target, size_t *count)
{
    char sub[4096];
    snprintf(sub, sizeof sub, "%s/%s", dir, target);
    DIR *d = opendir(sub);
    if (!d)
        return 0;
    char **names = NULL;
    size_t n = 0, cap = 0;
    struct dirent *e;
    while ((e = readdir(d))) {
        if (e->d_name[0] == '.' || strcmp(e->d_name, "README.md") == 0)
            continue;
        if (n == cap) {
            cap = cap ? 2 * cap : 64;
            char **grown = realloc(names, cap * sizeof *names);
            if (!grown)
                break;
            names = grown;
        }
        names[n++] = strdup(e->d_name);
    }
    closedir(d);
    if (n)
        qsort(names, n, sizeof *names, cmp_str);
    int failed = 0;
    for (size_t i = 0; i < n; i++) {
        char path[8192];
        snprintf(path, sizeof path, "%s/%s", sub, names[i]);
        struct stat st;
        if (stat(path, &st) == 0 && S_ISREG(st.st_mode)) {
            failed |= replay_file(target, path);
            (*count)++;
        }
        free(names[i]);
    }
    free(names);
    return failed;
}

int main(int argc, char **argv)
{
    static const char *const targets[] = {"obj", "off", "stl", "ply", "ply_le", "ply_be"};
    int failed = 0;
    for (int a = 1; a < argc; a++) {
        for (size_t t = 0; t < sizeof targets / sizeof *targets; t++) {
            size_t count = 0;
            failed |= replay_target(argv[a], targets[t], &count);
            if (count)
                printf("%-40s %-7s %4zu files replayed\n", argv[a], targets[t], count);
        }
    }
    return failed;
}
