/* SPDX-License-Identifier: MIT */
/* The clock of every timing in reports: monotonic seconds. */
#ifndef LIMN_CLOCK_H
#define LIMN_CLOCK_H

double clock_seconds(void);

#endif
