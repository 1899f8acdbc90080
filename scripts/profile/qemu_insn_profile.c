// A QEMU TCG plugin: how many times each guest instruction ran, written at exit as "address count" lines (hex,
// decimal) to the file named by the plugin's argument out=FILE. Every instruction of a translated block is counted
// with the block (an inline add per block execution), so a block left early by an exception counts its tail once
// more; on the firmware's images there are none in the loops measured. Debian's qemu ships no qemu-plugin.h: the
// few functions used are declared here from QEMU's plugin API (version 1, QEMU 7.2).
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

typedef uint64_t qemu_plugin_id_t;
struct qemu_plugin_tb;
struct qemu_plugin_insn;
typedef struct qemu_info_t qemu_info_t;
enum qemu_plugin_op { QEMU_PLUGIN_INLINE_ADD_U64 };

void qemu_plugin_register_vcpu_tb_trans_cb(qemu_plugin_id_t id,
                                           void (*cb)(qemu_plugin_id_t, struct qemu_plugin_tb*));
size_t qemu_plugin_tb_n_insns(const struct qemu_plugin_tb* tb);
struct qemu_plugin_insn* qemu_plugin_tb_get_insn(const struct qemu_plugin_tb* tb, size_t idx);
uint64_t qemu_plugin_insn_vaddr(const struct qemu_plugin_insn* insn);
void qemu_plugin_register_vcpu_tb_exec_inline(struct qemu_plugin_tb* tb, enum qemu_plugin_op op, void* ptr,
                                              uint64_t imm);
void qemu_plugin_register_atexit_cb(qemu_plugin_id_t id, void (*cb)(qemu_plugin_id_t, void*), void* userdata);

__attribute__((visibility("default"))) int qemu_plugin_version = 1;

// One translated block: its instructions' addresses and how many times it ran. A block translated again (after a
// flush) is a new record; the script adds records of the same address.
typedef struct Block {
  uint64_t runs;
  size_t n;
  uint64_t* addr;
  struct Block* next;
} Block;
static Block* blocks;
static char out_path[4096] = "insn-profile.txt";

static void on_translate(qemu_plugin_id_t id, struct qemu_plugin_tb* tb) {
  (void)id;
  Block* b = calloc(1, sizeof *b);
  if (b == NULL) return;
  b->n = qemu_plugin_tb_n_insns(tb);
  b->addr = calloc(b->n ? b->n : 1, sizeof *b->addr);
  if (b->addr == NULL) return;
  for (size_t i = 0; i < b->n; ++i) b->addr[i] = qemu_plugin_insn_vaddr(qemu_plugin_tb_get_insn(tb, i));
  b->next = blocks;
  blocks = b;
  qemu_plugin_register_vcpu_tb_exec_inline(tb, QEMU_PLUGIN_INLINE_ADD_U64, &b->runs, 1);
}

static void write_counts(qemu_plugin_id_t id, void* p) {
  (void)id;
  (void)p;
  FILE* f = fopen(out_path, "w");
  if (f == NULL) return;
  for (const Block* b = blocks; b != NULL; b = b->next)
    for (size_t i = 0; i < b->n && b->runs != 0; ++i)
      fprintf(f, "%llx %llu\n", (unsigned long long)b->addr[i], (unsigned long long)b->runs);
  fclose(f);
}

__attribute__((visibility("default"))) int qemu_plugin_install(qemu_plugin_id_t id, const qemu_info_t* info,
                                                               int argc, char** argv) {
  (void)info;
  for (int i = 0; i < argc; ++i)
    if (strncmp(argv[i], "out=", 4) == 0) snprintf(out_path, sizeof out_path, "%s", argv[i] + 4);
  qemu_plugin_register_vcpu_tb_trans_cb(id, on_translate);
  qemu_plugin_register_atexit_cb(id, write_counts, NULL);
  return 0;
}
