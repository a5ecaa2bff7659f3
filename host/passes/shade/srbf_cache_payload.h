/* srbf_cache_payload.h: the disk-cache payloads of the SRBF tables (srbf_tables.c) and of Ren's
 * table (srbf_ren.c), and decoding one from memory. The decoders are pure (no I/O, no OpenCL)
 * and kept apart from the builders so that test/fuzz/fuzz_cache.c links only this file; the
 * entry around a payload (key, length, hash) is base/disk_cache.h's. */
#ifndef SL_SRBF_CACHE_PAYLOAD_H
#define SL_SRBF_CACHE_PAYLOAD_H

#include "passes/shade/srbf_tables.h"
#include "srbf_ren_c.h"

#include <stddef.h>
#include <stdint.h>

/* SRBF tables: this, then C, H and D as floats. */
typedef struct sl_srbf_tables_meta {
    double build_s_C, build_s_H, err_C, err_H, build_s_W, err_W, err_D, err_Ch_x, err_Ch_s;
} sl_srbf_tables_meta;

/* The tables' payload size (meta + C + H + D). */
size_t sl_srbf_tables_payload_bytes(void);
/* A payload of n bytes into t (C, H, D allocated; the meta fields; from_cache = 1). Returns 0,
 * or -1 when n is not sl_srbf_tables_payload_bytes() (t untouched). */
int sl_srbf_tables_from_payload(sl_srbf_tables *t, const void *data, size_t n);

/* Ren's table: this, then n_floats floats. */
typedef struct sl_srbf_ren_meta {
    uint64_t n_floats;
    sl_srbf_ren_dims dims;
    double build_s, err_median, err_p95, err_max;
    char built_on[256];
} sl_srbf_ren_meta;

/* A payload of n bytes into t, whose n_floats and dims say what the caller expects: the meta
 * must record the same n_floats and dims and n must be exactly the meta plus n_floats floats.
 * Returns 0 (T allocated, the measured fields, built_on NUL-terminated, from_cache = 1), or -1
 * (t untouched). */
int sl_srbf_ren_from_payload(sl_srbf_ren *t, const void *data, size_t n);

#endif
