/* Self-organizing growth through the C ABI: worlds, species, planting, stepping,
 * snapshots that mesh like any tree, obstacles, the growing-struct rule for the two new
 * option structs, and bad input. */
#include "arbor.h"
#include "check.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static ArborWorld *forest(uint64_t seed, uint32_t parallel) {
  ArborWorldOptions o = arbor_world_options_default();
  ArborWorld *w = NULL;
  o.seed = seed;
  o.parallel = parallel;
  CHECK_STATUS(arbor_world_create(&o, &w), ARBOR_STATUS_OK);
  for (uint32_t s = 0; s < 5; s++) {
    ArborGrowthParams p;
    float at[3] = {3.0f * cosf(1.2566f * (float)s), 0.0f, 3.0f * sinf(1.2566f * (float)s)};
    uint32_t id = 99;
    CHECK_STATUS(arbor_growth_params_preset(s, &p, sizeof p), ARBOR_STATUS_OK);
    CHECK_STATUS(arbor_world_plant(w, &p, at, s, &id), ARBOR_STATUS_OK);
    CHECK(id == s, "tree id %u", id);
  }
  CHECK_STATUS(arbor_world_step(w, 8), ARBOR_STATUS_OK);
  return w;
}

static ArborBranch *branches_of(const ArborWorld *w, size_t index, size_t *n) {
  ArborTree *t = NULL;
  CHECK_STATUS(arbor_world_tree(w, index, &t), ARBOR_STATUS_OK);
  *n = arbor_tree_branch_count(t);
  ArborBranch *b = malloc(*n * sizeof *b);
  CHECK_STATUS(arbor_tree_copy_branches(t, b, *n), ARBOR_STATUS_OK);
  arbor_tree_free(t);
  return b;
}

static int32_t stop_at_cycle_three(void *user, uint32_t stage, float fraction) {
  int *calls = user;
  (*calls)++;
  CHECK(stage == ARBOR_STAGE_GROWTH && fraction >= 0.0f && fraction <= 1.0f, "stage %u at %g", stage,
        fraction);
  return *calls >= 3;
}

/* arbor_world_step stops before the cycle the callback refuses; the world keeps what
   the whole cycles grew, and stepping on (without a callback) works. */
static void cancelled_growth(void) {
  int calls = 0;
  ArborWorldOptions o = arbor_world_options_default();
  o.progress = stop_at_cycle_three;
  o.progress_user_data = &calls;
  ArborWorld *w = NULL, *plain = NULL;
  CHECK_STATUS(arbor_world_create(&o, &w), ARBOR_STATUS_OK);
  ArborWorldOptions p = arbor_world_options_default();
  CHECK_STATUS(arbor_world_create(&p, &plain), ARBOR_STATUS_OK);
  float at[3] = {0, 0, 0};
  CHECK_STATUS(arbor_world_plant(w, NULL, at, 1, NULL), ARBOR_STATUS_OK);
  CHECK_STATUS(arbor_world_plant(plain, NULL, at, 1, NULL), ARBOR_STATUS_OK);
  CHECK_STATUS(arbor_world_step(w, 10), ARBOR_STATUS_CANCELLED);
  CHECK(calls == 3, "%d calls", calls);
  CHECK_STATUS(arbor_world_step(plain, 2), ARBOR_STATUS_OK);
  CHECK(arbor_world_branch_count(w) == arbor_world_branch_count(plain), "%zu vs %zu branches after 2 cycles",
        arbor_world_branch_count(w), arbor_world_branch_count(plain));
  arbor_world_free(w);
  arbor_world_free(plain);
}

static int32_t stop_second(void *user, uint32_t stage, float fraction) {
  int *calls = user;
  (void)stage;
  (void)fraction;
  return ++*calls >= 2;
}

/* An obstacle reports per layer through the world's callback: stopped, the world is as it
   was (a tree grown on equals one grown without the obstacle); added, it shades the tree. */
static void cancelled_obstacle(void) {
  int calls = 0;
  ArborWorldOptions o = arbor_world_options_default();
  o.progress = stop_second;
  o.progress_user_data = &calls;
  ArborWorld *w = NULL, *plain = NULL, *shaded = NULL;
  CHECK_STATUS(arbor_world_create(&o, &w), ARBOR_STATUS_OK);
  ArborWorldOptions p = arbor_world_options_default();
  CHECK_STATUS(arbor_world_create(&p, &plain), ARBOR_STATUS_OK);
  CHECK_STATUS(arbor_world_create(&p, &shaded), ARBOR_STATUS_OK);
  float at[3] = {0, 0, 0};
  /* A slab over the tree, as wide as the world. */
  float lo[3] = {o.min[0], 3.0f, o.min[2]}, hi[3] = {o.max[0], 4.0f, o.max[2]};
  CHECK_STATUS(arbor_world_add_box(w, lo, hi), ARBOR_STATUS_CANCELLED);
  CHECK(calls == 2, "%d calls", calls);
  CHECK_STATUS(arbor_world_add_box(shaded, lo, hi), ARBOR_STATUS_OK);
  ArborWorld *all[3] = {w, plain, shaded};
  for (int k = 0; k < 3; k++) {
    CHECK_STATUS(arbor_world_plant(all[k], NULL, at, 1, NULL), ARBOR_STATUS_OK);
  }
  calls = -1000000; /* the first world keeps its callback: let it run */
  for (int k = 0; k < 3; k++) CHECK_STATUS(arbor_world_step(all[k], 8), ARBOR_STATUS_OK);
  size_t n[3];
  for (int k = 0; k < 3; k++) n[k] = arbor_world_branch_count(all[k]);
  ArborTree *a = NULL, *b = NULL;
  CHECK_STATUS(arbor_world_tree(w, 0, &a), ARBOR_STATUS_OK);
  CHECK_STATUS(arbor_world_tree(plain, 0, &b), ARBOR_STATUS_OK);
  ArborBranch *ba = malloc(n[0] * sizeof *ba), *bb = malloc(n[1] * sizeof *bb);
  CHECK(n[0] == n[1], "a cancelled obstacle changed growth: %zu vs %zu branches", n[0], n[1]);
  if (n[0] == n[1] && ba && bb) {
    CHECK_STATUS(arbor_tree_copy_branches(a, ba, n[0]), ARBOR_STATUS_OK);
    CHECK_STATUS(arbor_tree_copy_branches(b, bb, n[1]), ARBOR_STATUS_OK);
    CHECK(memcmp(ba, bb, n[0] * sizeof *ba) == 0, "the same branches");
  }
  CHECK(n[2] != n[1], "the slab shades the tree: %zu vs %zu branches", n[2], n[1]);
  free(ba);
  free(bb);
  arbor_tree_free(a);
  arbor_tree_free(b);
  for (int k = 0; k < 3; k++) arbor_world_free(all[k]);
}


static const char *last_error(void) {
  static char m[1024];
  arbor_last_error_message(m, sizeof m);
  return m;
}

/* Worlds on a terrain: a height field, trees planted on it and from a species map (two
   halves, two slots), a preview copy whose slider change leaves the original alone, the
   world as one glTF file, and bad ground refused by name before anything is read. */
static void terrain(const char *dir) {
  ArborWorldOptions o = arbor_world_options_default();
  o.min[0] = o.min[2] = -8.0f;
  o.max[0] = o.max[2] = 8.0f;
  ArborWorld *w = NULL;
  CHECK_STATUS(arbor_world_create(&o, &w), ARBOR_STATUS_OK);
  enum { N = 17 };
  float h[N * N];
  for (int j = 0; j < N; j++)
    for (int i = 0; i < N; i++) h[j * N + i] = 1.0f + 0.1f * (float)i; /* a slope up +x */
  /* Bad ground first: too many samples (checked before the pointer is read), too few, NaN. */
  CHECK_STATUS(arbor_world_set_ground(w, NULL, 5000, 5000, 1.0f, 0, 0), ARBOR_STATUS_LIMIT_EXCEEDED);
  CHECK(strstr(last_error(), "MAX_GROUND_SAMPLES") != NULL, "%s",
        last_error());
  CHECK_STATUS(arbor_world_set_ground(w, h, 1, 4, 1.0f, 0, 0), ARBOR_STATUS_INVALID_ARGUMENT);
  float nan_h[4] = {0, 0, NAN, 0};
  CHECK_STATUS(arbor_world_set_ground(w, nan_h, 2, 2, 1.0f, 0, 0), ARBOR_STATUS_INVALID_ARGUMENT);
  const uint8_t not_png[8] = {'G', 'I', 'F', '8', '9', 'a', 0, 0};
  CHECK_STATUS(arbor_world_set_ground_png(w, not_png, sizeof not_png, 1, 0, 1, 0, 0),
               ARBOR_STATUS_INVALID_ARGUMENT);
  CHECK(strstr(last_error(), "height map") != NULL, "%s", last_error());
  CHECK_STATUS(arbor_world_set_ground(w, h, N, N, 1.0f, -8.0f, -8.0f), ARBOR_STATUS_OK);
  float y = 0;
  CHECK_STATUS(arbor_world_ground_height(w, 2.5f, 0.0f, &y), ARBOR_STATUS_OK);
  CHECK(fabsf(y - 2.05f) < 1e-5f, "ground at x 2.5: %g", y);
  /* Two halves: slot 0 (x < 0) and slot 1 (x > 0), one tree a 4 square units. */
  enum { M = 8 };
  uint32_t slots[M * M];
  float density[M * M];
  for (int k = 0; k < M * M; k++) {
    slots[k] = (k % M) < M / 2 ? 0u : 1u;
    density[k] = 0.25f;
  }
  ArborGrowthParams a, b;
  CHECK_STATUS(arbor_growth_params_preset(ARBOR_SPECIES_DECURRENT, &a, sizeof a), ARBOR_STATUS_OK);
  CHECK_STATUS(arbor_growth_params_preset(ARBOR_SPECIES_EXCURRENT, &b, sizeof b), ARBOR_STATUS_OK);
  const ArborGrowthParams *species[2] = {&a, &b};
  size_t planted = 0;
  slots[3] = 2; /* a slot past the two species: refused, nothing planted */
  CHECK_STATUS(arbor_world_plant_map(w, slots, density, M, M, 2.0f, -8.0f, -8.0f, species, 2, 5, &planted),
               ARBOR_STATUS_INVALID_ARGUMENT);
  CHECK(arbor_world_tree_count(w) == 0, "nothing planted");
  slots[3] = 0;
  CHECK_STATUS(arbor_world_plant_map(w, slots, density, M, M, 2.0f, -8.0f, -8.0f, species, 2, 5, &planted),
               ARBOR_STATUS_OK);
  CHECK(planted > 20 && planted == arbor_world_tree_count(w), "%zu planted", planted);
  CHECK_STATUS(arbor_world_step(w, 6), ARBOR_STATUS_OK);
  for (size_t k = 0; k < planted; k++) {
    size_t n = 0;
    ArborBranch *br = branches_of(w, k, &n);
    uint32_t slot = 9;
    CHECK_STATUS(arbor_world_tree_slot(w, k, &slot), ARBOR_STATUS_OK);
    if (n > 0) {
      float g = 0;
      CHECK_STATUS(arbor_world_ground_height(w, br[0].start[0], br[0].start[2], &g), ARBOR_STATUS_OK);
      CHECK(fabsf(br[0].start[1] - g) < 1e-4f, "tree %zu at %g, ground %g", k, br[0].start[1], g);
      CHECK((slot == 0) == (br[0].start[0] < 0.0f), "tree %zu slot %u at x %g", k, slot, br[0].start[0]);
    }
    free(br);
  }
  /* The preview: a copy, slot 1's apical control changed, both stepped. */
  ArborWorld *preview = NULL;
  CHECK_STATUS(arbor_world_clone(w, &preview), ARBOR_STATUS_OK);
  b.apical_control = 0.75f;
  size_t changed = 0;
  CHECK_STATUS(arbor_world_set_species(preview, 1, &b, &changed), ARBOR_STATUS_OK);
  CHECK(changed > 5 && changed < planted, "%zu changed", changed);
  CHECK_STATUS(arbor_world_step(preview, 6), ARBOR_STATUS_OK);
  CHECK_STATUS(arbor_world_step(w, 6), ARBOR_STATUS_OK);
  size_t same = 0, differ = 0;
  for (size_t k = 0; k < planted; k++) {
    size_t n1 = 0, n2 = 0;
    ArborBranch *x = branches_of(w, k, &n1), *z = branches_of(preview, k, &n2);
    uint32_t slot = 0;
    CHECK_STATUS(arbor_world_tree_slot(w, k, &slot), ARBOR_STATUS_OK);
    int equal = n1 == n2 && memcmp(x, z, n1 * sizeof *x) == 0;
    if (slot == 1) differ += !equal;
    else same += equal;
    free(x);
    free(z);
  }
  CHECK(differ > 0 && same > 0, "slot 1 changed in %zu trees, slot 0 kept in %zu", differ, same);
  /* A forest tree shaped as its species shapes its own: twigs grafted, so more branches. */
  {
    ArborTree *grown = NULL, *oak = NULL;
    CHECK_STATUS(arbor_world_tree(w, 0, &grown), ARBOR_STATUS_OK);
    CHECK_STATUS(arbor_species_finish(ARBOR_SPECIES_OAK, grown, &oak), ARBOR_STATUS_OK);
    CHECK(oak != NULL && arbor_tree_branch_count(oak) != arbor_tree_branch_count(grown), "%zu and %zu branches",
          arbor_tree_branch_count(oak), arbor_tree_branch_count(grown));
    arbor_tree_free(oak);
    oak = NULL;
    CHECK_STATUS(arbor_species_finish(ARBOR_SPECIES_BUSH, grown, &oak), ARBOR_STATUS_INVALID_ARGUMENT);
    CHECK_STATUS(arbor_species_finish(ARBOR_SPECIES_OAK, NULL, &oak), ARBOR_STATUS_NULL_ARGUMENT);
    CHECK(oak == NULL, "nothing written");
    arbor_tree_free(grown);
  }
  /* The world as glTF: a node a tree, and the ground. */
  char path[4096];
  snprintf(path, sizeof path, "%s/terrain_world.glb", dir);
  const char *names[2] = {"oak", "pine"};
  ArborLeafOptions leaves = arbor_leaf_options_default();
  CHECK_STATUS(arbor_world_export_gltf(w, names, 2, NULL, &leaves, 64, 1, path), ARBOR_STATUS_OK);
  FILE *f = fopen(path, "rb");
  CHECK(f != NULL, "%s written", path);
  if (f) {
    fseek(f, 0, SEEK_END);
    long size = ftell(f);
    fseek(f, 0, SEEK_SET);
    char *glb = malloc((size_t)size + 1);
    size_t got = fread(glb, 1, (size_t)size, f);
    fclose(f);
    CHECK(got == (size_t)size && got > 1000 && memcmp(glb, "glTF", 4) == 0, "a GLB of %zu bytes", got);
    /* The JSON chunk names the nodes. */
    uint32_t json = 0;
    memcpy(&json, glb + 12, 4);
    CHECK(json + 20 <= got, "JSON chunk %u", json);
    if (json + 20 <= got) {
      char saved = glb[20 + json];
      glb[20 + json] = 0;
      CHECK(strstr(glb + 20, "\"oak_0\"") != NULL && strstr(glb + 20, "\"ground\"") != NULL,
            "oak_0 and ground");
      CHECK(strstr(glb + 20, "\"pine_") != NULL, "pine trees");
      glb[20 + json] = saved;
    }
    free(glb);
  }
  CHECK_STATUS(arbor_world_export_gltf(w, NULL, 1, NULL, NULL, 0, 0, path), ARBOR_STATUS_NULL_ARGUMENT);
  /* A species map from a PNG: a 2 x 2 picture, red (oak, slot 0) left, blue (slot 1)
     right, each pixel an 8 m cell at 4 trees per 100 square metres. */
  {
    static const uint8_t map_png[73] = {
        0x89, 0x50, 0x4e, 0x47, 0x0d, 0x0a, 0x1a, 0x0a, 0x00, 0x00, 0x00, 0x0d, 0x49, 0x48, 0x44,
        0x52, 0x00, 0x00, 0x00, 0x02, 0x00, 0x00, 0x00, 0x02, 0x08, 0x02, 0x00, 0x00, 0x00, 0xfd,
        0xd4, 0x9a, 0x73, 0x00, 0x00, 0x00, 0x10, 0x49, 0x44, 0x41, 0x54, 0x78, 0x9c, 0x63, 0xf8,
        0xcf, 0x00, 0x04, 0xff, 0x19, 0x20, 0x14, 0x00, 0x1b, 0xf2, 0x03, 0xfd, 0xd6, 0x96, 0xf2,
        0x2b, 0x00, 0x00, 0x00, 0x00, 0x49, 0x45, 0x4e, 0x44, 0xae, 0x42, 0x60, 0x82};
    const uint32_t colours[2] = {0xff0000u, 0x0000ffu};
    ArborWorld *m = NULL;
    CHECK_STATUS(arbor_world_create(&o, &m), ARBOR_STATUS_OK);
    CHECK_STATUS(arbor_world_set_ground(m, h, N, N, 1.0f, -8.0f, -8.0f), ARBOR_STATUS_OK);
    size_t n = 0;
    CHECK_STATUS(arbor_world_plant_map_png(m, map_png, sizeof map_png, colours, species, 2, 0.04f, 8.0f, -8.0f,
                                           -8.0f, 3, &n),
                 ARBOR_STATUS_OK);
    CHECK(n > 2 && n == arbor_world_tree_count(m), "%zu planted from the PNG", n);
    for (size_t k = 0; k < n; k++) {
      size_t nb = 0;
      ArborBranch *br = branches_of(m, k, &nb);
      uint32_t slot = 9;
      CHECK_STATUS(arbor_world_tree_slot(m, k, &slot), ARBOR_STATUS_OK);
      CHECK(nb == 1 && (slot == 0) == (br[0].start[0] < 0.0f), "tree %zu slot %u at x %g", k, slot,
            nb ? br[0].start[0] : 0.0f);
      free(br);
    }
    CHECK_STATUS(arbor_world_plant_map_png(m, map_png, 20, colours, species, 2, 0.04f, 8.0f, -8.0f, -8.0f, 3, &n),
                 ARBOR_STATUS_INVALID_ARGUMENT);
    arbor_world_free(m);
  }
  /* The ground goes down first: a planted world refuses it. */
  CHECK_STATUS(arbor_world_set_ground(w, h, N, N, 1.0f, -8.0f, -8.0f), ARBOR_STATUS_INVALID_ARGUMENT);
  CHECK_STATUS(arbor_world_clone(NULL, &preview), ARBOR_STATUS_NULL_ARGUMENT);
  arbor_world_free(preview);
  arbor_world_free(w);
}

int main(int argc, char **argv) {
  terrain(argc > 1 ? argv[1] : ".");
  cancelled_growth();
  cancelled_obstacle();
  ArborWorld *w = forest(7, 1);
  CHECK(arbor_world_tree_count(w) == 5, "5 trees");
  CHECK(arbor_world_branch_count(w) > 500, "%zu branches", arbor_world_branch_count(w));
  /* A snapshot is an ordinary tree: connected, meshable, with leaf sites. */
  {
    ArborTree *t = NULL;
    size_t nv = 0, ni = 0;
    CHECK_STATUS(arbor_world_tree(w, 0, &t), ARBOR_STATUS_OK);
    size_t n = arbor_tree_branch_count(t);
    ArborBranch *b = malloc(n * sizeof *b);
    CHECK_STATUS(arbor_tree_copy_branches(t, b, n), ARBOR_STATUS_OK);
    CHECK(b[0].parent == ARBOR_NO_PARENT, "root first");
    for (size_t i = 1; i < n; i++) {
      CHECK(b[i].parent < i, "branch %zu parent before child", i);
      CHECK(memcmp(b[i].start, b[b[i].parent].end, sizeof b[i].start) == 0, "branch %zu connected", i);
      CHECK(b[i].depth >= b[b[i].parent].depth, "birth cycle never before the parent's");
    }
    free(b);
    CHECK(arbor_tree_leaf_site_count(t) > 0, "living buds are leaf sites");
    ArborMeshOptions mo = arbor_mesh_options_default();
    CHECK_STATUS(arbor_mesh_size(t, &mo, &nv, &ni), ARBOR_STATUS_OK);
    ArborVertex *v = malloc(nv * sizeof *v);
    uint32_t *ix = malloc(ni * sizeof *ix);
    CHECK_STATUS(arbor_mesh_write(t, &mo, v, nv, ix, ni), ARBOR_STATUS_OK);
    free(v);
    free(ix);
    arbor_tree_free(t);
  }
  /* The same world seed and plantings grow the same forest, serial or parallel. */
  {
    ArborWorld *again = forest(7, 0);
    for (size_t k = 0; k < 5; k++) {
      size_t na, nb;
      ArborBranch *a = branches_of(w, k, &na), *b = branches_of(again, k, &nb);
      CHECK(na == nb && memcmp(a, b, na * sizeof *a) == 0, "tree %zu identical", k);
      free(a);
      free(b);
    }
    arbor_world_free(again);
  }
  {
    ArborTree *t = (ArborTree *)1;
    CHECK_STATUS(arbor_world_tree(w, 5, &t), ARBOR_STATUS_INVALID_ARGUMENT);
    CHECK(t == (ArborTree *)1, "out untouched on error");
  }
  arbor_world_free(w);
  arbor_world_free(NULL);

  /* Obstacles, and space colonization. */
  {
    ArborWorldOptions o = arbor_world_options_default();
    ArborWorld *c = NULL;
    float lo[3] = {-1, 3, -1}, hi[3] = {1, 3.5f, 1}, center[3] = {2, 2, 0}, base[3] = {0, 0, 0};
    o.environment = ARBOR_ENVIRONMENT_SPACE_COLONIZATION;
    CHECK_STATUS(arbor_world_create(&o, &c), ARBOR_STATUS_OK);
    CHECK_STATUS(arbor_world_add_box(c, lo, hi), ARBOR_STATUS_OK);
    CHECK_STATUS(arbor_world_add_sphere(c, center, 0.5f), ARBOR_STATUS_OK);
    CHECK_STATUS(arbor_world_add_sphere(c, center, -1.0f), ARBOR_STATUS_INVALID_ARGUMENT);
    CHECK_STATUS(arbor_world_add_box(c, hi, lo), ARBOR_STATUS_INVALID_ARGUMENT);
    CHECK_STATUS(arbor_world_plant(c, NULL, base, 1, NULL), ARBOR_STATUS_OK);
    CHECK_STATUS(arbor_world_step(c, 6), ARBOR_STATUS_OK);
    CHECK(arbor_world_branch_count(c) > 20, "colonization grows: %zu", arbor_world_branch_count(c));
    arbor_world_free(c);
  }

  /* Growing structs: larger zero-tailed accepted, non-zero tail refused by offset, 0. */
  {
    char msg[512];
    size_t big = sizeof(ArborGrowthParams) + 8;
    unsigned char *p = malloc(big);
    ArborWorld *g = NULL;
    float at[3] = {0, 0, 0};
    CHECK_STATUS(arbor_world_create(NULL, &g), ARBOR_STATUS_OK);
    CHECK_STATUS(arbor_growth_params_preset(ARBOR_SPECIES_BUSH, (ArborGrowthParams *)(void *)p, big),
                 ARBOR_STATUS_OK);
    CHECK(((ArborGrowthParams *)(void *)p)->struct_size == big, "preset kept the host's size");
    CHECK_STATUS(arbor_world_plant(g, (const ArborGrowthParams *)(void *)p, at, 1, NULL), ARBOR_STATUS_OK);
    p[big - 2] = 3;
    CHECK_STATUS(arbor_world_plant(g, (const ArborGrowthParams *)(void *)p, at, 1, NULL),
                 ARBOR_STATUS_INVALID_ARGUMENT);
    arbor_last_error_message(msg, sizeof msg);
    CHECK(strstr(msg, "offset") != NULL, "%s", msg);
    free(p);
    {
      ArborGrowthParams z = arbor_growth_params_default();
      z.struct_size = 0;
      CHECK_STATUS(arbor_world_plant(g, &z, at, 1, NULL), ARBOR_STATUS_INVALID_ARGUMENT);
    }
    {
      ArborWorldOptions *exact = malloc(sizeof *exact);
      ArborWorld *e = NULL;
      arbor_world_options_init(exact, sizeof *exact);
      CHECK_STATUS(arbor_world_create(exact, &e), ARBOR_STATUS_OK);
      arbor_world_free(e);
      free(exact);
    }
    arbor_world_free(g);
  }

  /* Bad input, by name. */
  {
    char msg[512];
    ArborWorld *g = NULL;
    ArborWorldOptions o = arbor_world_options_default();
    ArborGrowthParams p = arbor_growth_params_default();
    float at[3] = {0, 0, 0}, far[3] = {100, 0, 0};
    o.cell_size = 0.0005f;
    CHECK_STATUS(arbor_world_create(&o, &g), ARBOR_STATUS_LIMIT_EXCEEDED);
    arbor_last_error_message(msg, sizeof msg);
    CHECK(strstr(msg, "max_cells") != NULL, "%s", msg);
    o = arbor_world_options_default();
    o.environment = 7;
    CHECK_STATUS(arbor_world_create(&o, &g), ARBOR_STATUS_INVALID_ARGUMENT);
    o = arbor_world_options_default();
    o.cell_size = NAN;
    CHECK_STATUS(arbor_world_create(&o, &g), ARBOR_STATUS_INVALID_ARGUMENT);
    o = arbor_world_options_default();
    o.max_branches = 300;
    CHECK_STATUS(arbor_world_create(&o, &g), ARBOR_STATUS_OK);
    p.apical_control = NAN;
    CHECK_STATUS(arbor_world_plant(g, &p, at, 1, NULL), ARBOR_STATUS_INVALID_ARGUMENT);
    arbor_last_error_message(msg, sizeof msg);
    CHECK(strstr(msg, "apical_control") != NULL, "%s", msg);
    p = arbor_growth_params_default();
    CHECK_STATUS(arbor_world_plant(g, &p, far, 1, NULL), ARBOR_STATUS_INVALID_ARGUMENT);
    CHECK_STATUS(arbor_world_plant(g, &p, NULL, 1, NULL), ARBOR_STATUS_NULL_ARGUMENT);
    CHECK_STATUS(arbor_world_plant(g, &p, at, 1, NULL), ARBOR_STATUS_OK);
    CHECK_STATUS(arbor_world_step(g, 40), ARBOR_STATUS_LIMIT_EXCEEDED);
    arbor_last_error_message(msg, sizeof msg);
    CHECK(strstr(msg, "max_branches") != NULL, "%s", msg);
    CHECK(arbor_world_branch_count(g) <= 300, "limit kept");
    CHECK_STATUS(arbor_growth_params_preset(99, &p, sizeof p), ARBOR_STATUS_INVALID_ARGUMENT);
    /* Species are listed by name, counting up until NULL: every named one has a preset. */
    uint32_t species = 0;
    while (arbor_species_name(species) != NULL) {
      CHECK_STATUS(arbor_growth_params_preset(species, &p, sizeof p), ARBOR_STATUS_OK);
      species++;
    }
    CHECK(species == ARBOR_SPECIES_SHRUB + 1, "%u species named", species);
    CHECK(strcmp(arbor_species_name(ARBOR_SPECIES_BUSH), "bush") == 0, "bush");
    CHECK(strcmp(arbor_species_name(ARBOR_SPECIES_OAK), "oak") == 0, "oak");
    CHECK_STATUS(arbor_growth_params_preset(species, &p, sizeof p), ARBOR_STATUS_INVALID_ARGUMENT);
    CHECK_STATUS(arbor_world_step(NULL, 1), ARBOR_STATUS_NULL_ARGUMENT);
    CHECK(arbor_world_tree_count(NULL) == 0 && arbor_world_branch_count(NULL) == 0, "NULL counts");
    arbor_world_free(g);
  }
  return check_report("growth");
}
