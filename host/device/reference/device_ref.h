/* SPDX-License-Identifier: MIT */
/* Internals of the reference backend shared by device_ref.c,
   device_ref_mixed.c (the float operations of the mixed-precision solve) and
   device_ref_sgs.c (the SGS-preconditioned CG's sweeps). */
#ifndef LIMN_DEVICE_REF_H
#define LIMN_DEVICE_REF_H

#include "device/device.h"

struct device_buffer {
    size_t bytes;
    void *data;
};

limn_status ref_residual_f(struct device *dev, const device_csr *a, device_buffer *m,
                           device_buffer *p, device_buffer *r_f, device_norms *norms);
limn_status ref_step_f(struct device *dev, const device_csr *a, device_buffer *b,
                       device_buffer *d, device_buffer *prev, device_buffer *next, float c1,
                       float c2, device_norms *norms);
limn_status ref_add_f(struct device *dev, size_t rows, device_buffer *p, device_buffer *d);
limn_status ref_to_float(struct device *dev, size_t count, device_buffer *w,
                         device_buffer *w_f);
limn_status ref_sgs_upper(struct device *dev, const device_sgs *a, double beta,
                          const sgs_vectors *v);
limn_status ref_sgs_lower(struct device *dev, const device_sgs *a, int start,
                          const sgs_vectors *v, device_norms *out);
limn_status ref_sgs_update(struct device *dev, const device_sgs *a, double alpha,
                           const sgs_vectors *v, device_norms *norms);

#endif
