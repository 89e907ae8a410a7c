/* SPDX-License-Identifier: MIT */
/* How the backend choice (device/choice/choice.c) opens the reference backend. */
#ifndef LIMN_DEVICE_REF_OPEN_H
#define LIMN_DEVICE_REF_OPEN_H

#include "limn.h"

struct device;

limn_status device_open_reference(limn_context *ctx, struct device **out);

#endif
