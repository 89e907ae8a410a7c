/* SPDX-License-Identifier: MIT */
/* Test-only minimal OBJ reader; see obj_mini.h. */
#include "obj_mini.h"
#include "oracle_fail.h"

#include <ctype.h>
#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* growable arrays */
static int om_grow(void **p, size_t *cap, size_t need, size_t elem) {
    if (need <= *cap) return 0;
    size_t nc = *cap ? *cap : 64;
    while (nc < need) nc *= 2;
    void *q = realloc(*p, nc * elem);
    if (!q) return 1;
    *p = q;
    *cap = nc;
    return 0;
}

void obj_mini_free(obj_mini_mesh *m) {
    if (!m) return;
    free(m->pos);
    free(m->face_sizes);
    free(m->face_indices);
    memset(m, 0, sizeof *m);
}

int obj_mini_read(const char *path, obj_mini_mesh *m, char *err, size_t errlen) {
    memset(m, 0, sizeof *m);
    FILE *fp = fopen(path, "r");
    if (!fp) return oracle_fail(err, errlen, "%s: %s", path, strerror(errno));

    size_t pcap = 0, scap = 0, icap = 0, nidx = 0;
    char line[65536];
    long lineno = 0;
    int rc = 0;
    while (fgets(line, sizeof line, fp)) {
        ++lineno;
        if (!strchr(line, '\n') && !feof(fp)) {
            rc = oracle_fail(err, errlen, "%s:%ld: line too long", path, lineno);
            break;
        }
        char *s = line;
        while (*s == ' ' || *s == '\t') ++s;
        if (s[0] == 'v' && (s[1] == ' ' || s[1] == '\t')) {
            double xyz[3];
            char *p = s + 1, *end;
            for (int c = 0; c < 3; ++c) {
                xyz[c] = strtod(p, &end);
                if (end == p) {
                    rc = oracle_fail(err, errlen, "%s:%ld: bad vertex line", path, lineno);
                    goto done;
                }
                p = end;
            }
            if (om_grow((void **)&m->pos, &pcap, 3 * (size_t)(m->nverts + 1), sizeof(double))) {
                rc = oracle_fail(err, errlen, "out of memory");
                goto done;
            }
            memcpy(m->pos + 3 * (size_t)m->nverts, xyz, sizeof xyz);
            m->nverts++;
        } else if (s[0] == 'f' && (s[1] == ' ' || s[1] == '\t')) {
            char *p = s + 1;
            int count = 0;
            for (;;) {
                while (*p == ' ' || *p == '\t' || *p == '\r' || *p == '\n') ++p;
                if (!*p) break;
                char *end;
                long idx = strtol(p, &end, 10);
                if (end == p || idx == 0) {
                    rc = oracle_fail(err, errlen, "%s:%ld: bad face index", path, lineno);
                    goto done;
                }
                long v = idx > 0 ? idx - 1 : (long)m->nverts + idx;
                if (v < 0 || v >= m->nverts) {
                    rc = oracle_fail(err, errlen, "%s:%ld: face index %ld out of range", path,
                                 lineno, idx);
                    goto done;
                }
                p = end;
                while (*p && !isspace((unsigned char)*p)) ++p; /* skip /vt/vn */
                if (om_grow((void **)&m->face_indices, &icap, nidx + 1, sizeof(int))) {
                    rc = oracle_fail(err, errlen, "out of memory");
                    goto done;
                }
                m->face_indices[nidx++] = (int)v;
                ++count;
            }
            if (count < 3) {
                rc = oracle_fail(err, errlen, "%s:%ld: face with %d vertices", path, lineno, count);
                goto done;
            }
            if (om_grow((void **)&m->face_sizes, &scap, (size_t)m->nfaces + 1, sizeof(int))) {
                rc = oracle_fail(err, errlen, "out of memory");
                goto done;
            }
            m->face_sizes[m->nfaces++] = count;
        }
    }
    if (!rc && ferror(fp)) rc = oracle_fail(err, errlen, "%s: read error", path);
done:
    fclose(fp);
    if (rc) obj_mini_free(m);
    return rc;
}
