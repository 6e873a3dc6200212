/* Structs that grow: a host built against an older header (smaller struct, malloc'd at its
 * exact size, so valgrind and ASan catch any read past it), a newer header (larger struct,
 * zero tail), a newer header with a field this library does not know (non-zero tail), and
 * sizes below the first layout. Also: init writes nothing past the size it is given, and
 * every shared struct's field offsets are as the header says. */
#include "arbor.h"
#include "check.h"

#include <stddef.h>
#include <string.h>

/* ArborMeshOptions as its first layout declared it (before threads and max_vertices). */
typedef struct OldMeshOptions {
  uint32_t struct_size, radial_segments, topology, min_radial_segments;
  float cull_radius;
  uint32_t joints, smooth_taper, base_cap, tip;
  float texture_scale;
  uint32_t winding, up_axis;
  float scale;
} OldMeshOptions;

/* ArborLeafOptions as its first layout declared it (before max_leaves). */
typedef struct OldLeafOptions {
  uint32_t struct_size, sites, polygons, tips, min_depth;
  float density, size, size_jitter, rotation_jitter, tilt;
  uint64_t seed;
  const char *prefab_obj_path;
} OldLeafOptions;

/* ArborLsystemOptions as its first layout declared it (before variation_seed). */
typedef struct OldLsystemOptions {
  uint32_t struct_size;
  int32_t steps;
  uint64_t seed, max_modules, max_params, max_branches;
  uint32_t override_flags;
  float angle_increment, initial_width, width_increment, turn_jitter;
} OldLsystemOptions;

_Static_assert(sizeof(OldLsystemOptions) == ARBOR_LSYSTEM_OPTIONS_MIN_SIZE, "first lsystem layout");
_Static_assert(sizeof(OldMeshOptions) == ARBOR_MESH_OPTIONS_MIN_SIZE, "first mesh layout");
_Static_assert(sizeof(OldLeafOptions) == ARBOR_LEAF_OPTIONS_MIN_SIZE, "first leaf layout");
_Static_assert(offsetof(ArborMeshOptions, struct_size) == 0, "struct_size first");
_Static_assert(offsetof(ArborMeshOptions, scale) == offsetof(OldMeshOptions, scale), "append only");
_Static_assert(offsetof(ArborLeafOptions, prefab_obj_path) == offsetof(OldLeafOptions, prefab_obj_path),
               "append only");
_Static_assert(offsetof(ArborLsystemOptions, struct_size) == 0, "struct_size first");
_Static_assert(sizeof(ArborLsystemOptions) >= ARBOR_LSYSTEM_OPTIONS_MIN_SIZE, "lsystem layout");

static ArborTree *tree_g(void) {
  ArborHondaParams p;
  ArborTree *t = NULL;
  arbor_honda_preset('g', &p);
  p.steps = 8;
  CHECK_STATUS(arbor_tree_from_honda(&p, &t), ARBOR_STATUS_OK);
  return t;
}

static void last_message(char *buf, size_t cap) { arbor_last_error_message(buf, cap); }

static void mesh_options_of_every_size(const ArborTree *t) {
  size_t nv_new = 0, ni_new = 0, nv = 0, ni = 0;
  char msg[512];
  ArborMeshOptions cur = arbor_mesh_options_default();
  CHECK(cur.struct_size == sizeof(ArborMeshOptions), "default struct_size %u", cur.struct_size);
  CHECK_STATUS(arbor_mesh_size(t, &cur, &nv_new, &ni_new), ARBOR_STATUS_OK);

  /* An older host: exactly the first layout's bytes, in a heap block of that size. */
  OldMeshOptions *old = malloc(sizeof *old);
  memset(old, 0xAB, sizeof *old);
  arbor_mesh_options_init((ArborMeshOptions *)(void *)old, sizeof *old);
  CHECK(old->struct_size == sizeof *old, "init set struct_size %u", old->struct_size);
  CHECK(old->radial_segments == cur.radial_segments && old->scale == cur.scale,
        "init wrote the defaults of the old fields");
  CHECK_STATUS(arbor_mesh_size(t, (const ArborMeshOptions *)(void *)old, &nv, &ni), ARBOR_STATUS_OK);
  CHECK(nv == nv_new && ni == ni_new, "old struct gets the defaults: %zu/%zu vs %zu/%zu", nv, ni,
        nv_new, ni_new);
  old->radial_segments = 5;
  CHECK_STATUS(arbor_mesh_size(t, (const ArborMeshOptions *)(void *)old, &nv, &ni), ARBOR_STATUS_OK);
  CHECK(nv != nv_new, "old struct's own fields are read");
  {
    ArborVertex *v = malloc(nv * sizeof *v);
    uint32_t *ix = malloc(ni * sizeof *ix);
    CHECK_STATUS(arbor_mesh_write(t, (const ArborMeshOptions *)(void *)old, v, nv, ix, ni),
                 ARBOR_STATUS_OK);
    free(v);
    free(ix);
  }
  free(old);

  /* A newer host: a larger struct with a zero tail is accepted. */
  {
    size_t big = sizeof(ArborMeshOptions) + 24;
    unsigned char *p = malloc(big);
    memset(p, 0xCD, big);
    arbor_mesh_options_init((ArborMeshOptions *)(void *)p, big);
    CHECK(((ArborMeshOptions *)(void *)p)->struct_size == big, "larger struct_size kept");
    for (size_t k = sizeof(ArborMeshOptions); k < big; k++) CHECK(p[k] == 0, "init zeroed byte %zu", k);
    CHECK_STATUS(arbor_mesh_size(t, (const ArborMeshOptions *)(void *)p, &nv, &ni), ARBOR_STATUS_OK);
    CHECK(nv == nv_new, "zero tail: same mesh");
    /* ... and one that sets a field this library does not know is refused, by offset. */
    p[sizeof(ArborMeshOptions) + 5] = 1;
    CHECK_STATUS(arbor_mesh_size(t, (const ArborMeshOptions *)(void *)p, &nv, &ni),
                 ARBOR_STATUS_INVALID_ARGUMENT);
    last_message(msg, sizeof msg);
    {
      char want[64];
      snprintf(want, sizeof want, "offset %zu", sizeof(ArborMeshOptions) + 5);
      CHECK(strstr(msg, want) != NULL, "message names the offset: %s", msg);
    }
    free(p);
  }

  /* Below the first layout, and 0. */
  {
    ArborMeshOptions small = arbor_mesh_options_default();
    small.struct_size = ARBOR_MESH_OPTIONS_MIN_SIZE - 4;
    CHECK_STATUS(arbor_mesh_size(t, &small, &nv, &ni), ARBOR_STATUS_INVALID_ARGUMENT);
    last_message(msg, sizeof msg);
    CHECK(strstr(msg, "struct_size") != NULL, "message names struct_size: %s", msg);
    small.struct_size = 0;
    CHECK_STATUS(arbor_mesh_size(t, &small, &nv, &ni), ARBOR_STATUS_INVALID_ARGUMENT);
    nv = 12345;
    CHECK(nv == 12345, "out-parameters untouched on error");
  }

  /* init writes nothing past the size it is given. */
  {
    unsigned char buf[sizeof(ArborMeshOptions) + 16];
    memset(buf, 0x5A, sizeof buf);
    arbor_mesh_options_init((ArborMeshOptions *)(void *)buf, ARBOR_MESH_OPTIONS_MIN_SIZE);
    for (size_t k = ARBOR_MESH_OPTIONS_MIN_SIZE; k < sizeof buf; k++)
      CHECK(buf[k] == 0x5A, "init wrote byte %zu past its size", k);
    arbor_mesh_options_init(NULL, sizeof(ArborMeshOptions)); /* does nothing */
  }

  /* The limit added after the first layout works. */
  {
    ArborMeshOptions lim = arbor_mesh_options_default();
    lim.max_vertices = 10;
    CHECK_STATUS(arbor_mesh_size(t, &lim, &nv, &ni), ARBOR_STATUS_LIMIT_EXCEEDED);
    last_message(msg, sizeof msg);
    CHECK(strstr(msg, "max_vertices") != NULL, "message names max_vertices: %s", msg);
  }

  /* Levels of detail read an array of the host's (old) size. */
  {
    OldMeshOptions *levels = malloc(2 * sizeof *levels);
    size_t vc[2], ic[2];
    arbor_mesh_options_init((ArborMeshOptions *)(void *)&levels[0], sizeof *levels);
    arbor_mesh_options_init((ArborMeshOptions *)(void *)&levels[1], sizeof *levels);
    levels[1].radial_segments = 4;
    CHECK_STATUS(arbor_mesh_lod_size(t, (const ArborMeshOptions *)(void *)levels, 2, vc, ic),
                 ARBOR_STATUS_OK);
    CHECK(vc[0] == nv_new && vc[1] < vc[0], "old-size LOD array: %zu %zu", vc[0], vc[1]);
    free(levels);
  }
}

static void leaf_options_of_every_size(const ArborTree *t) {
  size_t n_new = 0, n = 0;
  char msg[512];
  ArborLeafOptions cur = arbor_leaf_options_default();
  cur.tips = 1;
  CHECK_STATUS(arbor_leaf_instance_count(t, &cur, NULL, &n_new), ARBOR_STATUS_OK);
  CHECK(n_new > 0, "tips get leaves");

  OldLeafOptions *old = malloc(sizeof *old);
  arbor_leaf_options_init((ArborLeafOptions *)(void *)old, sizeof *old);
  old->tips = 1;
  CHECK_STATUS(arbor_leaf_instance_count(t, (const ArborLeafOptions *)(void *)old, NULL, &n),
               ARBOR_STATUS_OK);
  CHECK(n == n_new, "old leaf struct: %zu vs %zu", n, n_new);
  free(old);

  cur.max_leaves = n_new - 1;
  CHECK_STATUS(arbor_leaf_instance_count(t, &cur, NULL, &n), ARBOR_STATUS_LIMIT_EXCEEDED);
  last_message(msg, sizeof msg);
  CHECK(strstr(msg, "max_leaves") != NULL, "message names max_leaves: %s", msg);
  cur.max_leaves = n_new;
  CHECK_STATUS(arbor_leaf_instance_count(t, &cur, NULL, &n), ARBOR_STATUS_OK);

  {
    size_t big = sizeof(ArborLeafOptions) + 8;
    unsigned char *p = malloc(big);
    arbor_leaf_options_init((ArborLeafOptions *)(void *)p, big);
    CHECK_STATUS(arbor_leaf_instance_count(t, (const ArborLeafOptions *)(void *)p, NULL, &n),
                 ARBOR_STATUS_OK);
    p[big - 1] = 7;
    CHECK_STATUS(arbor_leaf_instance_count(t, (const ArborLeafOptions *)(void *)p, NULL, &n),
                 ARBOR_STATUS_INVALID_ARGUMENT);
    free(p);
  }
  {
    ArborLeafOptions zero = arbor_leaf_options_default();
    zero.struct_size = 0;
    CHECK_STATUS(arbor_leaf_instance_count(t, &zero, NULL, &n), ARBOR_STATUS_INVALID_ARGUMENT);
  }
}

static void lsystem_options_of_every_size(void) {
  const char *src = "Lsystem: 1\nderivation length: 3\nAxiom: F\nF --> F[+F]F\nendlsystem\n";
  ArborTree *t = NULL;
  char msg[512];
  /* Exactly the library's size, in a heap block of that size. */
  ArborLsystemOptions *o = malloc(sizeof *o);
  arbor_lsystem_options_init(o, sizeof *o);
  CHECK_STATUS(arbor_tree_from_lsystem(src, strlen(src), o, &t), ARBOR_STATUS_OK);
  CHECK(arbor_tree_branch_count(t) == 27, "27 branches, got %zu", arbor_tree_branch_count(t));
  arbor_tree_free(t);
  free(o);
  /* An older host's struct, at its exact size: variation_seed gets its default (0). */
  {
    const char *stoch = "Lsystem: 1\nseed: 4\nderivation length: 6\nAxiom: A\n"
                        "A --> F[+A]A : 0.5\nA --> F[-A] : 0.5\nendlsystem\n";
    ArborTree *a = NULL, *b = NULL, *c = NULL;
    OldLsystemOptions *old = malloc(sizeof *old);
    ArborLsystemOptions varied = arbor_lsystem_options_default();
    arbor_lsystem_options_init((ArborLsystemOptions *)(void *)old, sizeof *old);
    CHECK(old->struct_size == sizeof *old && old->steps == -1, "old lsystem init");
    CHECK_STATUS(arbor_tree_from_lsystem(stoch, strlen(stoch), (const ArborLsystemOptions *)(void *)old, &a),
                 ARBOR_STATUS_OK);
    CHECK_STATUS(arbor_tree_from_lsystem(stoch, strlen(stoch), NULL, &b), ARBOR_STATUS_OK);
    varied.variation_seed = 99;
    CHECK_STATUS(arbor_tree_from_lsystem(stoch, strlen(stoch), &varied, &c), ARBOR_STATUS_OK);
    {
      size_t na = arbor_tree_branch_count(a), nb = arbor_tree_branch_count(b), nc = arbor_tree_branch_count(c);
      ArborBranch *ba = malloc(na * sizeof *ba), *bb = malloc(nb * sizeof *bb), *bc = malloc(nc * sizeof *bc);
      arbor_tree_copy_branches(a, ba, na);
      arbor_tree_copy_branches(b, bb, nb);
      arbor_tree_copy_branches(c, bc, nc);
      CHECK(na == nb && memcmp(ba, bb, na * sizeof *ba) == 0, "old struct = defaults");
      CHECK(nc != na || memcmp(ba, bc, na * sizeof *ba) != 0, "variation_seed varies a seeded file");
      free(ba);
      free(bb);
      free(bc);
    }
    arbor_tree_free(a);
    arbor_tree_free(b);
    arbor_tree_free(c);
    free(old);
  }
  {
    size_t big = sizeof(ArborLsystemOptions) + 16;
    unsigned char *p = malloc(big);
    arbor_lsystem_options_init((ArborLsystemOptions *)(void *)p, big);
    t = NULL;
    CHECK_STATUS(arbor_tree_from_lsystem(src, strlen(src), (const ArborLsystemOptions *)(void *)p, &t),
                 ARBOR_STATUS_OK);
    arbor_tree_free(t);
    p[sizeof(ArborLsystemOptions)] = 1;
    t = NULL;
    CHECK_STATUS(arbor_tree_from_lsystem(src, strlen(src), (const ArborLsystemOptions *)(void *)p, &t),
                 ARBOR_STATUS_INVALID_ARGUMENT);
    CHECK(t == NULL, "no tree on error");
    last_message(msg, sizeof msg);
    CHECK(strstr(msg, "offset") != NULL, "message names the offset: %s", msg);
    free(p);
  }
  {
    ArborLsystemOptions z = arbor_lsystem_options_default();
    z.struct_size = 0;
    CHECK_STATUS(arbor_tree_from_lsystem(src, strlen(src), &z, &t), ARBOR_STATUS_INVALID_ARGUMENT);
  }
}

int main(void) {
  ArborTree *t = tree_g();
  mesh_options_of_every_size(t);
  leaf_options_of_every_size(t);
  lsystem_options_of_every_size();
  arbor_tree_free(t);
  CHECK(arbor_abi_version() == ARBOR_ABI_VERSION, "abi %u", arbor_abi_version());
  return check_report("growing");
}
