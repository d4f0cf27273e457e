/*
 * Counts the guest instructions a QEMU (7.2) TCG run executes, and prints at exit
 *
 *     insns_executed: N
 *     insns_in_ranges: M        (only with ranges=...)
 *
 * on standard error, or appended to the file given as `-plugin insn_count.so,out=PATH`.
 * `N` counts every instruction; `M` only those whose guest virtual address lies in one of the
 * address ranges given as `ranges=START-END[:START-END...]` (hexadecimal, `0x` optional, END
 * exclusive; colon-separated because QEMU splits plugin arguments at commas), e.g.
 *
 *     -plugin insn_count.so,out=insns.log,ranges=0x5abc-0x5f4c:0x57fc-0x5914
 *
 * Each translation block, when translated, gets an inline counter increment of its number of
 * instructions and, with ranges, a second one of the number of its instructions in a range;
 * the emulator adds them every time the block runs (mps2-an386 and microbit have one vCPU,
 * so single counters are exact). A block left early by an exception counts whole: the
 * firmware test takes the difference of two runs of different lengths, in which such events
 * cancel.
 */
#include <ctype.h>
#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "qemu-plugin-api.h"

/*
 * Two more functions of QEMU 7.2's plugin API (include/qemu/qemu-plugin.h, same signatures),
 * declared here because qemu-plugin-api.h has only those of the total count: the
 * instruction `idx` of a block being translated, and its guest virtual address.
 */
struct qemu_plugin_insn;
struct qemu_plugin_insn *qemu_plugin_tb_get_insn(const struct qemu_plugin_tb *tb, size_t idx);
uint64_t qemu_plugin_insn_vaddr(const struct qemu_plugin_insn *insn);

QEMU_PLUGIN_EXPORT int qemu_plugin_version = QEMU_PLUGIN_VERSION;

/* The most address ranges `ranges=` accepts. */
#define MAX_RANGES 256

/* A guest address range [start, end). */
struct range {
    uint64_t start;
    uint64_t end;
};

static uint64_t insns_executed;
static uint64_t insns_in_ranges;
static struct range ranges[MAX_RANGES];
static size_t n_ranges;
static int have_ranges;
static char out_path[4096];

/* Whether guest address `vaddr` lies in one of the ranges. */
static int in_ranges(uint64_t vaddr)
{
    for (size_t i = 0; i < n_ranges; i++) {
        if (vaddr >= ranges[i].start && vaddr < ranges[i].end) {
            return 1;
        }
    }
    return 0;
}

static void on_tb_translate(qemu_plugin_id_t id, struct qemu_plugin_tb *tb)
{
    (void)id;
    size_t n = qemu_plugin_tb_n_insns(tb);
    qemu_plugin_register_vcpu_tb_exec_inline(tb, QEMU_PLUGIN_INLINE_ADD_U64, &insns_executed, n);
    if (!have_ranges) {
        return;
    }
    uint64_t inside = 0;
    for (size_t i = 0; i < n; i++) {
        inside += (uint64_t)in_ranges(qemu_plugin_insn_vaddr(qemu_plugin_tb_get_insn(tb, i)));
    }
    if (inside > 0) {
        qemu_plugin_register_vcpu_tb_exec_inline(tb, QEMU_PLUGIN_INLINE_ADD_U64,
                                                 &insns_in_ranges, inside);
    }
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
    if (have_ranges) {
        fprintf(out, "insns_in_ranges: %llu\n", (unsigned long long)insns_in_ranges);
    }
    if (out != stderr) {
        fclose(out);
    }
}

/*
 * Parses one hexadecimal address at `*p` (`0x` optional, no sign or space), advancing `*p`
 * past it. Returns 0 on success, -1 if there are no hex digits or the value overflows.
 */
static int parse_address(const char **p, uint64_t *value)
{
    const char *s = *p;
    if (s[0] == '0' && (s[1] == 'x' || s[1] == 'X')) {
        s += 2;
    }
    if (!isxdigit((unsigned char)*s)) {
        return -1;
    }
    char *end;
    errno = 0;
    unsigned long long v = strtoull(s, &end, 16);
    if (errno != 0) {
        return -1;
    }
    *value = v;
    *p = end;
    return 0;
}

/* Parses the value of `ranges=` into `ranges`. Returns 0, or -1 after printing why not. */
static int parse_ranges(const char *spec)
{
    const char *p = spec;
    for (;;) {
        struct range r;
        const char *at = p;
        if (parse_address(&p, &r.start) != 0 || *p++ != '-' || parse_address(&p, &r.end) != 0 ||
            (*p != ':' && *p != '\0')) {
            fprintf(stderr,
                    "insn_count: malformed range at '%s' in ranges=%s "
                    "(expected START-END[:START-END...], hexadecimal, END exclusive)\n",
                    at, spec);
            return -1;
        }
        if (r.end <= r.start) {
            fprintf(stderr, "insn_count: empty range 0x%llx-0x%llx in ranges=%s (END is exclusive)\n",
                    (unsigned long long)r.start, (unsigned long long)r.end, spec);
            return -1;
        }
        if (n_ranges == MAX_RANGES) {
            fprintf(stderr, "insn_count: more than %d ranges in ranges=%s\n", MAX_RANGES, spec);
            return -1;
        }
        ranges[n_ranges++] = r;
        if (*p == '\0') {
            return 0;
        }
        p++;
    }
}

QEMU_PLUGIN_EXPORT int qemu_plugin_install(qemu_plugin_id_t id, const qemu_info_t *info,
                                           int argc, char **argv)
{
    (void)info;
    for (int i = 0; i < argc; i++) {
        if (strncmp(argv[i], "out=", 4) == 0 && strlen(argv[i] + 4) < sizeof out_path) {
            strcpy(out_path, argv[i] + 4);
        } else if (strncmp(argv[i], "ranges=", 7) == 0) {
            if (have_ranges) {
                fprintf(stderr, "insn_count: ranges= given twice (separate ranges with ':')\n");
                return -1;
            }
            if (parse_ranges(argv[i] + 7) != 0) {
                return -1;
            }
            have_ranges = 1;
        } else {
            fprintf(stderr,
                    "insn_count: unknown argument '%s' (expected out=PATH or "
                    "ranges=START-END[:START-END...]; QEMU splits arguments at commas)\n",
                    argv[i]);
            return -1;
        }
    }
    qemu_plugin_register_vcpu_tb_trans_cb(id, on_tb_translate);
    qemu_plugin_register_atexit_cb(id, report_at_exit, NULL);
    return 0;
}
