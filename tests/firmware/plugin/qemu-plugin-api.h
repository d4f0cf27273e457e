/*
 * The few declarations of QEMU's TCG plugin API (include/qemu/qemu-plugin.h) that
 * insn_count.c uses, written for the ABI of QEMU 7.2 (plugin API version 1), whose Debian
 * package exports the API from the emulator binary but ships neither plugins nor the header.
 * Only functions and types used here are declared; their signatures match QEMU 7.2's.
 */
#ifndef ANGLETRACK_QEMU_PLUGIN_API_H
#define ANGLETRACK_QEMU_PLUGIN_API_H

#include <stddef.h>
#include <stdint.h>

/* The API version this plugin is written against (QEMU_PLUGIN_VERSION of QEMU 7.2). */
#define QEMU_PLUGIN_VERSION 1

#define QEMU_PLUGIN_EXPORT __attribute__((visibility("default")))

/* A plugin's handle, given to qemu_plugin_install. */
typedef uint64_t qemu_plugin_id_t;

/* Information about the emulator (only passed through here: opaque). */
typedef struct qemu_info_t qemu_info_t;

/* A translation block being translated (opaque). */
struct qemu_plugin_tb;

/* Inline operations on a 64-bit counter (enum qemu_plugin_op). */
enum qemu_plugin_op {
    QEMU_PLUGIN_INLINE_ADD_U64,
};

typedef void (*qemu_plugin_vcpu_tb_trans_cb_t)(qemu_plugin_id_t id, struct qemu_plugin_tb *tb);
typedef void (*qemu_plugin_udata_cb_t)(qemu_plugin_id_t id, void *userdata);

void qemu_plugin_register_vcpu_tb_trans_cb(qemu_plugin_id_t id, qemu_plugin_vcpu_tb_trans_cb_t cb);
size_t qemu_plugin_tb_n_insns(const struct qemu_plugin_tb *tb);
void qemu_plugin_register_vcpu_tb_exec_inline(struct qemu_plugin_tb *tb, enum qemu_plugin_op op,
                                              void *ptr, uint64_t imm);
void qemu_plugin_register_atexit_cb(qemu_plugin_id_t id, qemu_plugin_udata_cb_t cb,
                                    void *userdata);

#endif
