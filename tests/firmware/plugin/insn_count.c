/*
 * Counts the guest instructions a QEMU (7.2) TCG run executes, and prints the total at exit:
 *
 *     insns_executed: N
 *
 * on standard error, or appended to the file given as `-plugin insn_count.so,out=PATH`.
 *
 * Each translation block, when translated, gets an inline counter increment of its number of
 * instructions; the emulator adds it every time the block runs (mps2-an386 has one vCPU, so a
 * single counter is exact). A block left early by an exception counts whole: the firmware
 * test takes the difference of two runs of different lengths, in which such events cancel.
 */
#include <stdio.h>
#include <string.h>

#include "qemu-plugin-api.h"

QEMU_PLUGIN_EXPORT int qemu_plugin_version = QEMU_PLUGIN_VERSION;

static uint64_t insns_executed;
static char out_path[4096];

static void on_tb_translate(qemu_plugin_id_t id, struct qemu_plugin_tb *tb)
{
    (void)id;
    qemu_plugin_register_vcpu_tb_exec_inline(tb, QEMU_PLUGIN_INLINE_ADD_U64, &insns_executed,
                                             qemu_plugin_tb_n_insns(tb));
}

static void report_at_exit(qemu_plugin_id_t id, void *userdata)
{
    (void)id;
    (void)userdata;
    FILE *out = out_path[0] ? fopen(out_path, "a") : stderr;
    if (out == NULL) {
        perror(out_path);
        out = stderr;
    }
    fprintf(out, "insns_executed: %llu\n", (unsigned long long)insns_executed);
    if (out != stderr) {
        fclose(out);
    }
}

QEMU_PLUGIN_EXPORT int qemu_plugin_install(qemu_plugin_id_t id, const qemu_info_t *info,
                                           int argc, char **argv)
{
    (void)info;
    for (int i = 0; i < argc; i++) {
        if (strncmp(argv[i], "out=", 4) == 0 && strlen(argv[i] + 4) < sizeof out_path) {
            strcpy(out_path, argv[i] + 4);
        } else {
            fprintf(stderr, "insn_count: unknown argument '%s' (expected out=PATH)\n", argv[i]);
            return -1;
        }
    }
    qemu_plugin_register_vcpu_tb_trans_cb(id, on_tb_translate);
    qemu_plugin_register_atexit_cb(id, report_at_exit, NULL);
    return 0;
}
