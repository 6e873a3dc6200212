/* Owned mesh handles, leaf sites, const handles read from several threads at once,
 * thread-local error messages, every float of ArborHondaParams as NaN and infinity, and
 * arbor_last_error_message with every capacity. */
#include "arbor.h"
#include "check.h"

#include <math.h>
#include <pthread.h>
#include <stddef.h>
#include <string.h>

_Static_assert(sizeof(ArborLeafSite) == 44, "ArborLeafSite is 44 bytes");

static ArborTree *shared_tree;
static ArborVertex *ref_vertices;
static uint32_t *ref_indices;
static size_t ref_nv, ref_ni;

static void *worker(void *arg) {
  long id = (long)arg;
  int *failures = malloc(sizeof *failures);
  *failures = 0;
  for (int round = 0; round < 3; round++) {
    ArborMesh *m = NULL;
    if (arbor_mesh_create(shared_tree, NULL, &m) != ARBOR_STATUS_OK) (*failures)++;
    size_t nv = 0, ni = 0;
    const ArborVertex *v = arbor_mesh_vertices(m, &nv);
    const uint32_t *i = arbor_mesh_indices(m, &ni);
    if (nv != ref_nv || ni != ref_ni || memcmp(v, ref_vertices, nv * sizeof *v) != 0 ||
        memcmp(i, ref_indices, ni * sizeof *i) != 0)
      (*failures)++;
    arbor_mesh_free(m);
    /* Each thread's last error is its own. */
    ArborHondaParams p;
    arbor_honda_preset('a', &p);
    p.steps = 2000 + (uint32_t)id;
    ArborTree *t = NULL;
    if (arbor_tree_from_honda(&p, &t) != ARBOR_STATUS_INVALID_ARGUMENT) (*failures)++;
    char want[32], msg[256];
    snprintf(want, sizeof want, "%u", 2000 + (unsigned)id);
    arbor_last_error_message(msg, sizeof msg);
    if (strstr(msg, want) == NULL) (*failures)++;
  }
  return failures;
}

static void threads(void) {
  ArborHondaParams p;
  arbor_honda_preset('f', &p);
  CHECK_STATUS(arbor_tree_from_honda(&p, &shared_tree), ARBOR_STATUS_OK);
  CHECK_STATUS(arbor_mesh_size(shared_tree, NULL, &ref_nv, &ref_ni), ARBOR_STATUS_OK);
  ref_vertices = malloc(ref_nv * sizeof *ref_vertices);
  ref_indices = malloc(ref_ni * sizeof *ref_indices);
  CHECK_STATUS(arbor_mesh_write(shared_tree, NULL, ref_vertices, ref_nv, ref_indices, ref_ni),
               ARBOR_STATUS_OK);
  pthread_t th[4];
  for (long k = 0; k < 4; k++) pthread_create(&th[k], NULL, worker, (void *)k);
  for (int k = 0; k < 4; k++) {
    void *r = NULL;
    pthread_join(th[k], &r);
    CHECK(*(int *)r == 0, "thread %d saw %d failures", k, *(int *)r);
    free(r);
  }
  free(ref_vertices);
  free(ref_indices);
  arbor_tree_free(shared_tree);
}

static void owned_meshes(void) {
  ArborHondaParams p;
  ArborTree *t = NULL;
  arbor_honda_preset('c', &p);
  arbor_tree_from_honda(&p, &t);
  ArborMeshOptions o = arbor_mesh_options_default();
  o.topology = ARBOR_TOPOLOGY_TRIANGLE_STRIP_RESTART;
  ArborMesh *m = NULL;
  CHECK_STATUS(arbor_mesh_create(t, &o, &m), ARBOR_STATUS_OK);
  size_t nv = 0, ni = 0, sv = 0, si = 0;
  CHECK(arbor_mesh_vertices(m, &nv) != NULL && arbor_mesh_indices(m, &ni) != NULL, "buffers");
  arbor_mesh_size(t, &o, &sv, &si);
  CHECK(nv == sv && ni == si, "owned %zu/%zu vs sized %zu/%zu", nv, ni, sv, si);
  CHECK(arbor_mesh_topology(m) == ARBOR_TOPOLOGY_TRIANGLE_STRIP_RESTART, "topology");
  CHECK(arbor_mesh_vertices(m, NULL) != NULL, "count may be NULL");
  arbor_mesh_free(m);
  size_t c = 7;
  CHECK(arbor_mesh_vertices(NULL, &c) == NULL && c == 0, "NULL mesh");
  c = 7;
  CHECK(arbor_mesh_indices(NULL, &c) == NULL && c == 0, "NULL mesh");
  CHECK(arbor_mesh_topology(NULL) == 0, "NULL mesh topology");
  arbor_mesh_free(NULL);
  CHECK_STATUS(arbor_mesh_create(t, NULL, NULL), ARBOR_STATUS_NULL_ARGUMENT);
  CHECK_STATUS(arbor_mesh_create(NULL, NULL, &m), ARBOR_STATUS_NULL_ARGUMENT);
  o.tip = 9;
  m = NULL;
  CHECK_STATUS(arbor_mesh_create(t, &o, &m), ARBOR_STATUS_INVALID_ARGUMENT);
  CHECK(m == NULL, "out written on failure");
  ArborLeafOptions lo = arbor_leaf_options_default();
  lo.tips = 1;
  CHECK_STATUS(arbor_leaf_mesh_create(t, &lo, NULL, &m), ARBOR_STATUS_OK);
  CHECK(arbor_mesh_vertices(m, &nv) != NULL && nv > 0, "leaf mesh");
  arbor_mesh_free(m);
  arbor_tree_free(t);
}

static void leaf_sites(void) {
  const char *g = "angle increment: 45\nAxiom: F[+F~][-F~]F~\n";
  ArborTree *t = NULL;
  CHECK_STATUS(arbor_tree_from_lsystem(g, strlen(g), NULL, &t), ARBOR_STATUS_OK);
  size_t n = arbor_tree_leaf_site_count(t);
  CHECK(n == 3, "%zu sites", n);
  for (size_t cap = 0; cap <= n; cap++) {
    ArborLeafSite *s = malloc((cap + 1) * sizeof *s);
    memset(s, 0x5A, (cap + 1) * sizeof *s);
    ArborStatus st = arbor_tree_copy_leaf_sites(t, cap ? s : NULL, cap);
    CHECK(st == (cap == n ? ARBOR_STATUS_OK : ARBOR_STATUS_BUFFER_TOO_SMALL), "cap %zu", cap);
    if (cap == n) {
      CHECK(s[2].position[1] == 2.0f && s[2].branch == 3, "last site on the last F");
      CHECK(fabsf(s[0].heading[0] + sqrtf(0.5f)) < 1e-5f, "first site's heading");
    }
    free(s);
  }
  CHECK(arbor_tree_leaf_site_count(NULL) == 0, "NULL tree");
  arbor_tree_free(t);
}

static void every_float_field(void) {
  static const struct { const char *name; size_t offset; } fields[] = {
      {"trunk_length", offsetof(ArborHondaParams, trunk_length)},
      {"trunk_width", offsetof(ArborHondaParams, trunk_width)},
      {"r1", offsetof(ArborHondaParams, r1)},
      {"r2", offsetof(ArborHondaParams, r2)},
      {"alpha1", offsetof(ArborHondaParams, alpha1)},
      {"alpha2", offsetof(ArborHondaParams, alpha2)},
      {"phi1", offsetof(ArborHondaParams, phi1)},
      {"phi2", offsetof(ArborHondaParams, phi2)},
      {"q", offsetof(ArborHondaParams, q)},
      {"e", offsetof(ArborHondaParams, e)},
      {"min_length", offsetof(ArborHondaParams, min_length)},
  };
  const float bad[3] = {NAN, INFINITY, -INFINITY};
  for (size_t f = 0; f < sizeof fields / sizeof fields[0]; f++) {
    for (int k = 0; k < 3; k++) {
      ArborHondaParams p;
      arbor_honda_preset('b', &p);
      memcpy((char *)&p + fields[f].offset, &bad[k], sizeof(float));
      ArborTree *t = NULL;
      CHECK_STATUS(arbor_tree_from_honda(&p, &t), ARBOR_STATUS_INVALID_ARGUMENT);
      char msg[256];
      arbor_last_error_message(msg, sizeof msg);
      char want[64];
      snprintf(want, sizeof want, "`%s`", fields[f].name);
      CHECK(strstr(msg, want) != NULL, "%s: message '%s'", fields[f].name, msg);
      CHECK(t == NULL, "tree made from a bad %s", fields[f].name);
    }
  }
}

static void message_every_capacity(void) {
  ArborHondaParams p;
  arbor_honda_preset('a', &p);
  p.q = 3.0f;
  ArborTree *t = NULL;
  arbor_tree_from_honda(&p, &t);
  size_t len = arbor_last_error_message(NULL, 0);
  CHECK(len > 10, "message length %zu", len);
  char *full = malloc(len + 1);
  arbor_last_error_message(full, len + 1);
  for (size_t cap = 0; cap <= len + 1; cap++) {
    char *buf = malloc(cap + 1);
    memset(buf, 0x5A, cap + 1);
    size_t n = arbor_last_error_message(cap ? buf : NULL, cap);
    CHECK(n == len, "cap %zu returned %zu", cap, n);
    if (cap > 0) {
      size_t kept = cap - 1 < len ? cap - 1 : len;
      CHECK(memcmp(buf, full, kept) == 0 && buf[kept] == '\0', "cap %zu contents", cap);
    }
    CHECK((unsigned char)buf[cap] == 0x5A, "cap %zu wrote past", cap);
    free(buf);
  }
  free(full);
}

int main(void) {
  threads();
  owned_meshes();
  leaf_sites();
  every_float_field();
  message_every_capacity();
  return check_report("handles_threads");
}
