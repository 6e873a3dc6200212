/* Bad input through the C ABI: NULLs, unknown names and enums, NaN, and every too-small
 * buffer. Each gives its status and a message; nothing is written past a buffer (each
 * buffer is a fresh allocation of exactly the capacity given, so valgrind or ASan sees any
 * overrun). */
#include "arbor.h"
#include "check.h"

#include <math.h>
#include <string.h>

static void message_contains(const char *needle) {
  char m[512];
  size_t n = arbor_last_error_message(m, sizeof m);
  CHECK(n > 0 && strstr(m, needle) != NULL, "message '%s' lacks '%s'", m, needle);
}

static ArborTree *small_tree(void) {
  ArborHondaParams p;
  ArborTree *t = NULL;
  arbor_honda_preset('g', &p);
  p.steps = 3; /* 7 branches */
  CHECK_STATUS(arbor_tree_from_honda(&p, &t), ARBOR_STATUS_OK);
  return t;
}

static void nulls(void) {
  ArborHondaParams p;
  ArborTree *t = (ArborTree *)&p; /* must stay untouched on failure */
  CHECK_STATUS(arbor_honda_preset('a', NULL), ARBOR_STATUS_NULL_ARGUMENT);
  message_contains("out");
  CHECK_STATUS(arbor_tree_from_honda(NULL, &t), ARBOR_STATUS_NULL_ARGUMENT);
  message_contains("params");
  CHECK(t == (ArborTree *)&p, "out written on failure");
  arbor_honda_preset('a', &p);
  CHECK_STATUS(arbor_tree_from_honda(&p, NULL), ARBOR_STATUS_NULL_ARGUMENT);
  CHECK(arbor_tree_branch_count(NULL) == 0, "count of NULL");
  arbor_tree_free(NULL);

  ArborTree *tree = small_tree();
  size_t nv = 0, ni = 0;
  ArborBranch b[7];
  CHECK_STATUS(arbor_tree_copy_branches(NULL, b, 7), ARBOR_STATUS_NULL_ARGUMENT);
  CHECK_STATUS(arbor_tree_copy_branches(tree, NULL, 7), ARBOR_STATUS_NULL_ARGUMENT);
  CHECK_STATUS(arbor_mesh_size(NULL, NULL, &nv, &ni), ARBOR_STATUS_NULL_ARGUMENT);
  CHECK_STATUS(arbor_mesh_size(tree, NULL, NULL, &ni), ARBOR_STATUS_NULL_ARGUMENT);
  message_contains("vertex_count");
  CHECK_STATUS(arbor_mesh_size(tree, NULL, &nv, NULL), ARBOR_STATUS_NULL_ARGUMENT);
  message_contains("index_count");
  /* NULL options mean the defaults. */
  CHECK_STATUS(arbor_mesh_size(tree, NULL, &nv, &ni), ARBOR_STATUS_OK);
  /* 7 branches in 4 axes (tree g, n = 3), 9 vertices a ring. */
  CHECK(nv == (7 + 4) * 9 && ni == 7 * 48, "default sizes %zu %zu", nv, ni);
  ArborVertex *v = malloc(nv * sizeof *v);
  uint32_t *i = malloc(ni * sizeof *i);
  CHECK_STATUS(arbor_mesh_write(NULL, NULL, v, nv, i, ni), ARBOR_STATUS_NULL_ARGUMENT);
  CHECK_STATUS(arbor_mesh_write(tree, NULL, NULL, nv, i, ni), ARBOR_STATUS_NULL_ARGUMENT);
  message_contains("vertices");
  CHECK_STATUS(arbor_mesh_write(tree, NULL, v, nv, NULL, ni), ARBOR_STATUS_NULL_ARGUMENT);
  message_contains("indices");
  CHECK_STATUS(arbor_mesh_write(tree, NULL, v, nv, i, ni), ARBOR_STATUS_OK);
  free(v);
  free(i);
  arbor_tree_free(tree);
}

static void bad_values(void) {
  ArborHondaParams p;
  CHECK_STATUS(arbor_honda_preset('z', &p), ARBOR_STATUS_INVALID_ARGUMENT);
  message_contains("preset");
  CHECK_STATUS(arbor_honda_preset(0, &p), ARBOR_STATUS_INVALID_ARGUMENT);
  CHECK_STATUS(arbor_honda_preset(0xFFFFFFFFu, &p), ARBOR_STATUS_INVALID_ARGUMENT);

  float bad[4] = {NAN, INFINITY, -INFINITY, -1.0f};
  for (int k = 0; k < 4; k++) {
    ArborTree *t = NULL;
    arbor_honda_preset('b', &p);
    p.r1 = bad[k];
    CHECK_STATUS(arbor_tree_from_honda(&p, &t), ARBOR_STATUS_INVALID_ARGUMENT);
    message_contains("r1");
    CHECK(t == NULL, "tree written on failure");
    arbor_honda_preset('b', &p);
    p.trunk_width = bad[k];
    CHECK_STATUS(arbor_tree_from_honda(&p, &t), ARBOR_STATUS_INVALID_ARGUMENT);
    message_contains("trunk_width");
  }
  ArborTree *t = NULL;
  arbor_honda_preset('a', &p);
  p.steps = 60; /* 2^60 - 1 branches */
  CHECK_STATUS(arbor_tree_from_honda(&p, &t), ARBOR_STATUS_LIMIT_EXCEEDED);
  message_contains("max_branches");
  p.steps = 100000;
  CHECK_STATUS(arbor_tree_from_honda(&p, &t), ARBOR_STATUS_INVALID_ARGUMENT);
  message_contains("steps");

  ArborTree *tree = small_tree();
  ArborMeshOptions o = arbor_mesh_options_default();
  size_t nv = 0, ni = 0;
  o.topology = 3;
  CHECK_STATUS(arbor_mesh_size(tree, &o, &nv, &ni), ARBOR_STATUS_INVALID_ARGUMENT);
  message_contains("topology");
  CHECK(nv == 0 && ni == 0, "counts written on failure");
  o = arbor_mesh_options_default();
  uint32_t segs[4] = {0, 2, 65, 0xFFFFFFFFu};
  for (int k = 0; k < 4; k++) {
    o.radial_segments = segs[k];
    CHECK_STATUS(arbor_mesh_size(tree, &o, &nv, &ni), ARBOR_STATUS_INVALID_ARGUMENT);
    message_contains("radial_segments");
  }
  arbor_tree_free(tree);
  /* Success clears the message. */
  CHECK_STATUS(arbor_honda_preset('a', &p), ARBOR_STATUS_OK);
  CHECK(arbor_last_error_message(NULL, 0) == 0, "message not cleared");
}

/* Every capacity from 0 to the exact size, each buffer a fresh allocation of exactly that
 * many elements (plus a guard element checked afterwards). */
static void every_capacity(void) {
  ArborTree *tree = small_tree();
  size_t nb = arbor_tree_branch_count(tree);
  for (size_t cap = 0; cap <= nb; cap++) {
    ArborBranch *b = malloc((cap + 1) * sizeof *b);
    memset(b, 0x5A, (cap + 1) * sizeof *b);
    ArborStatus s = arbor_tree_copy_branches(tree, cap ? b : NULL, cap);
    CHECK(s == (cap == nb ? ARBOR_STATUS_OK : ARBOR_STATUS_BUFFER_TOO_SMALL), "cap %zu: %d",
          cap, (int)s);
    const unsigned char *bytes = (const unsigned char *)b;
    size_t untouched_from = cap == nb ? cap * sizeof *b : 0;
    for (size_t k = untouched_from; k < (cap + 1) * sizeof *b; k++) {
      if (bytes[k] != 0x5A) {
        CHECK(0, "branch cap %zu: byte %zu written", cap, k);
        break;
      }
    }
    free(b);
  }
  for (uint32_t topology = 0; topology < 3; topology++) {
    ArborMeshOptions o = arbor_mesh_options_default();
    o.topology = topology;
    o.radial_segments = 3;
    size_t nv = 0, ni = 0;
    CHECK_STATUS(arbor_mesh_size(tree, &o, &nv, &ni), ARBOR_STATUS_OK);
    for (size_t vc = 0; vc <= nv; vc++) {
      for (size_t ic = 0; ic <= ni; ic += (vc == nv ? 1 : ni)) {
        ArborVertex *v = malloc((vc + 1) * sizeof *v);
        uint32_t *idx = malloc((ic + 1) * sizeof *idx);
        memset(v, 0x5A, (vc + 1) * sizeof *v);
        memset(idx, 0x5A, (ic + 1) * sizeof *idx);
        ArborStatus s = arbor_mesh_write(tree, &o, v, vc, idx, ic);
        int exact = vc == nv && ic == ni;
        CHECK(s == (exact ? ARBOR_STATUS_OK : ARBOR_STATUS_BUFFER_TOO_SMALL),
              "topology %u caps %zu/%zu: %d", topology, vc, ic, (int)s);
        if (!exact) {
          const unsigned char *bv = (const unsigned char *)v, *bi = (const unsigned char *)idx;
          int clean = 1;
          for (size_t k = 0; k < (vc + 1) * sizeof *v; k++) clean &= bv[k] == 0x5A;
          for (size_t k = 0; k < (ic + 1) * sizeof *idx; k++) clean &= bi[k] == 0x5A;
          CHECK(clean, "topology %u caps %zu/%zu wrote into a too-small buffer", topology, vc,
                ic);
        } else {
          const unsigned char *gv = (const unsigned char *)(v + nv), *gi =
                                                                   (const unsigned char *)(idx + ni);
          int clean = 1;
          for (size_t k = 0; k < sizeof *v; k++) clean &= gv[k] == 0x5A;
          for (size_t k = 0; k < sizeof *idx; k++) clean &= gi[k] == 0x5A;
          CHECK(clean, "topology %u wrote past the exact size", topology);
        }
        free(v);
        free(idx);
        if (ni == 0) break;
      }
    }
  }
  arbor_tree_free(tree);
}

static void status_strings(void) {
  CHECK(strcmp(arbor_status_str(ARBOR_STATUS_OK), "ok") == 0, "ok string");
  CHECK(strcmp(arbor_status_str(ARBOR_STATUS_BUFFER_TOO_SMALL), "buffer too small") == 0,
        "buffer string");
  CHECK(strcmp(arbor_status_str(999), "unknown status") == 0, "unknown string");
}

/* The outside fuzzer's third round: a leaf size whose product with a denormal scale is
   small but which overflows on its own, and a parse-error column counted in the file's
   own text (not the macro-expanded one). */
static void round_three(void) {
  const char *g = "Lsystem: 1\nAxiom: F(1)~\nendlsystem\n";
  ArborTree *t = NULL;
  CHECK_STATUS(arbor_tree_from_lsystem(g, strlen(g), NULL, &t), ARBOR_STATUS_OK);
  ArborLeafOptions lo = arbor_leaf_options_default();
  lo.size = 3.4e38f;
  ArborMeshOptions mo = arbor_mesh_options_default();
  mo.scale = 1e-40f;
  size_t n = 0;
  CHECK_STATUS(arbor_leaf_instance_count(t, &lo, &mo, &n), ARBOR_STATUS_INVALID_ARGUMENT);
  message_contains("`size`");
  arbor_tree_free(t);
  const char *m = "#define LONG 1+1+1+1+1+1+1+1+1+1+1+1+1+1+1\nAxiom: F(LONG) ) $$\n";
  CHECK_STATUS(arbor_tree_from_lsystem(m, strlen(m), NULL, &t), ARBOR_STATUS_PARSE_ERROR);
  message_contains("line 2, column 16");
}

int main(void) {
  round_three();
  nulls();
  bad_values();
  every_capacity();
  status_strings();
  return check_report("errors");
}
