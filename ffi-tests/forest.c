/* Forests through the C ABI: seeded variation, pruning, the animation stream and a merged
 * forest mesh. */
#include "arbor.h"
#include "check.h"

#include <string.h>

static ArborTree *varied(char name, uint64_t seed) {
  ArborHondaParams p;
  ArborTree *t = NULL;
  arbor_honda_preset((uint32_t)name, &p);
  CHECK_STATUS(arbor_tree_from_honda_varied(&p, seed, &t), ARBOR_STATUS_OK);
  return t;
}

static int same_branches(ArborTree *a, ArborTree *b) {
  size_t n = arbor_tree_branch_count(a);
  if (n != arbor_tree_branch_count(b)) return 0;
  ArborBranch *x = malloc(n * sizeof *x), *y = malloc(n * sizeof *y);
  arbor_tree_copy_branches(a, x, n);
  arbor_tree_copy_branches(b, y, n);
  int same = memcmp(x, y, n * sizeof *x) == 0;
  free(x);
  free(y);
  return same;
}

/* Whether the calling thread's last error names `what`. */
static int last_error_names(const char *what) {
  char m[512];
  arbor_last_error_message(m, sizeof m);
  return strstr(m, what) != NULL;
}

/* Vertices of the mesh of one self-organizing tree grown as a forest plant grows it: alone
 * at the origin of a default world seeded with `seed`. */
static size_t grown_vertices(const ArborGrowthParams *species, uint32_t cycles, uint64_t seed) {
  ArborWorldOptions wo = arbor_world_options_default();
  wo.seed = seed;
  ArborWorld *w = NULL;
  CHECK_STATUS(arbor_world_create(&wo, &w), ARBOR_STATUS_OK);
  const float origin[3] = {0, 0, 0};
  CHECK_STATUS(arbor_world_plant(w, species, origin, seed, NULL), ARBOR_STATUS_OK);
  CHECK_STATUS(arbor_world_step(w, cycles), ARBOR_STATUS_OK);
  ArborTree *t = NULL;
  CHECK_STATUS(arbor_world_tree(w, 0, &t), ARBOR_STATUS_OK);
  size_t v = 0, i = 0;
  arbor_mesh_size(t, NULL, &v, &i);
  arbor_tree_free(t);
  arbor_world_free(w);
  return v;
}

/* Forests of plants of any source: the 1996 model and self-organizing trees in one mesh,
 * read with the host's stride (a newer, larger struct with a zero tail). */
static void plants(void) {
  enum { N = 3, STRIDE = sizeof(ArborForestPlant) + 8 };
  unsigned char *block = calloc(N, STRIDE);
  ArborForestPlant *p[N];
  for (int k = 0; k < N; k++) {
    p[k] = (ArborForestPlant *)(block + k * STRIDE);
    arbor_forest_plant_init(p[k], STRIDE);
    CHECK(p[k]->struct_size == STRIDE && p[k]->scale == 1.0f && p[k]->cycles == 30,
          "defaults of plant %d", k);
  }
  ArborGrowthParams decurrent;
  CHECK_STATUS(arbor_growth_params_preset(ARBOR_SPECIES_DECURRENT, &decurrent, sizeof decurrent),
               ARBOR_STATUS_OK);
  arbor_honda_preset('g', &p[0]->honda);
  p[0]->seed = 1;
  p[1]->source = ARBOR_PLANT_SOURCE_GROWTH;
  p[1]->species = &decurrent;
  p[1]->cycles = 12;
  p[1]->seed = 5;
  p[1]->position[0] = 40.0f;
  p[2]->source = ARBOR_PLANT_SOURCE_GROWTH;
  p[2]->cycles = 8;
  p[2]->seed = 2;
  p[2]->position[2] = -40.0f;
  const ArborForestPlant *plants = p[0];

  ArborTree *g1 = varied('g', 1);
  size_t gv = 0, gi = 0;
  arbor_mesh_size(g1, NULL, &gv, &gi);
  arbor_tree_free(g1);
  size_t expected = gv + grown_vertices(&decurrent, 12, 5) + grown_vertices(NULL, 8, 2);

  ArborMesh *owned = NULL;
  CHECK_STATUS(arbor_forest_plants_mesh_create(plants, N, NULL, &owned), ARBOR_STATUS_OK);
  size_t ov = 0, oi = 0, sv = 0, si = 0;
  const ArborVertex *vv = arbor_mesh_vertices(owned, &ov);
  const uint32_t *ii = arbor_mesh_indices(owned, &oi);
  CHECK(ov == expected && ov > gv, "plants forest: %zu vertices, expected %zu", ov, expected);
  CHECK_STATUS(arbor_forest_plants_mesh_size(plants, N, NULL, &sv, &si), ARBOR_STATUS_OK);
  CHECK(sv == ov && si == oi, "plant sizes %zu/%zu vs %zu/%zu", sv, si, ov, oi);
  ArborVertex *w = malloc(sv * sizeof *w);
  uint32_t *j = malloc(si * sizeof *j);
  CHECK_STATUS(arbor_forest_plants_mesh_write(plants, N, NULL, w, sv - 1, j, si),
               ARBOR_STATUS_BUFFER_TOO_SMALL);
  CHECK_STATUS(arbor_forest_plants_mesh_write(plants, N, NULL, w, sv, j, si), ARBOR_STATUS_OK);
  CHECK(memcmp(w, vv, sv * sizeof *w) == 0 && memcmp(j, ii, si * sizeof *j) == 0,
        "written plants forest differs from the owned one");
  free(w);
  free(j);
  arbor_mesh_free(owned);

  /* Bad plants are refused by name, and nothing is written. */
  ArborMesh *none = NULL;
  p[1]->cycles = 0;
  CHECK_STATUS(arbor_forest_plants_mesh_create(plants, N, NULL, &none), ARBOR_STATUS_INVALID_ARGUMENT);
  CHECK(last_error_names("plants[1].cycles"), "names the cycles");
  p[1]->cycles = 12;
  p[2]->source = 7;
  CHECK_STATUS(arbor_forest_plants_mesh_create(plants, N, NULL, &none), ARBOR_STATUS_INVALID_ARGUMENT);
  CHECK(last_error_names("plants[2].source"), "names the source");
  p[2]->source = ARBOR_PLANT_SOURCE_GROWTH;
  decurrent.apical_control = 2.0f;
  CHECK_STATUS(arbor_forest_plants_mesh_create(plants, N, NULL, &none), ARBOR_STATUS_INVALID_ARGUMENT);
  CHECK(last_error_names("apical_control"), "names the species field");
  block[STRIDE - 1] = 1; /* a field this library does not have */
  CHECK_STATUS(arbor_forest_plants_mesh_create(plants, N, NULL, &none), ARBOR_STATUS_INVALID_ARGUMENT);
  CHECK(none == NULL, "out written on failure");
  CHECK_STATUS(arbor_forest_plants_mesh_create(NULL, 2, NULL, &none), ARBOR_STATUS_NULL_ARGUMENT);
  CHECK_STATUS(arbor_forest_plants_mesh_create(NULL, 0, NULL, &none), ARBOR_STATUS_OK);
  arbor_mesh_free(none);
  free(block);
}

int main(void) {
  ArborHondaParams p;
  ArborTree *paper = NULL;
  arbor_honda_preset('g', &p);
  arbor_tree_from_honda(&p, &paper);
  ArborTree *v0 = varied('g', 0), *v1 = varied('g', 1), *v1b = varied('g', 1), *v2 = varied('g', 2);
  CHECK(same_branches(paper, v0), "seed 0 is the paper's tree");
  CHECK(same_branches(v1, v1b), "same seed, same tree");
  CHECK(!same_branches(v1, v2), "another seed, another tree");
  CHECK_STATUS(arbor_tree_from_honda_varied(NULL, 1, &v0), ARBOR_STATUS_NULL_ARGUMENT);

  /* Pruning tree a removes its overlapping twigs. */
  ArborTree *a = NULL, *pruned = NULL;
  arbor_honda_preset('a', &p);
  arbor_tree_from_honda(&p, &a);
  size_t removed = 0;
  CHECK_STATUS(arbor_tree_prune_collisions(a, &pruned, &removed), ARBOR_STATUS_OK);
  CHECK(removed > 0 && arbor_tree_branch_count(pruned) + removed == 1023, "removed %zu", removed);
  CHECK_STATUS(arbor_tree_prune_collisions(a, NULL, NULL), ARBOR_STATUS_NULL_ARGUMENT);

  /* Animation stream: one element per vertex, every capacity short of it refused. */
  size_t nv = 0, ni = 0;
  arbor_mesh_size(pruned, NULL, &nv, &ni);
  for (size_t cap = nv - 2; cap <= nv; cap++) {
    ArborAnimationVertex *an = malloc((cap + 1) * sizeof *an);
    ArborStatus s = arbor_mesh_animation_write(pruned, NULL, an, cap);
    CHECK(s == (cap == nv ? ARBOR_STATUS_OK : ARBOR_STATUS_BUFFER_TOO_SMALL), "cap %zu", cap);
    if (s == ARBOR_STATUS_OK) {
      int ok = 1;
      for (size_t k = 0; k < nv; k++)
        ok &= an[k].growth >= 0 && an[k].growth <= 1 && an[k].phase >= 0 && an[k].phase < 1;
      CHECK(ok, "animation values in range");
    }
    free(an);
  }

  /* A forest of four trees in one mesh. */
  ArborForestTree trees[4];
  memset(trees, 0, sizeof trees);
  size_t expected = 0;
  for (int k = 0; k < 4; k++) {
    arbor_honda_preset((uint32_t)"agce"[k], &trees[k].params);
    trees[k].seed = (uint64_t)k;
    trees[k].position[0] = 200.0f * (float)k;
    trees[k].rotation = 30.0f * (float)k;
    trees[k].scale = 1.0f;
    ArborTree *one = varied("agce"[k], (uint64_t)k);
    size_t v = 0, i = 0;
    arbor_mesh_size(one, NULL, &v, &i);
    expected += v;
    arbor_tree_free(one);
  }
  ArborMesh *forest = NULL;
  CHECK_STATUS(arbor_forest_mesh_create(trees, 4, NULL, &forest), ARBOR_STATUS_OK);
  size_t fv = 0;
  CHECK(arbor_mesh_vertices(forest, &fv) != NULL && fv == expected, "%zu vs %zu", fv, expected);
  /* Size, then write into caller memory: the same mesh, in every topology. */
  for (uint32_t topology = 0; topology < 3; topology++) {
    ArborMeshOptions o = arbor_mesh_options_default();
    o.topology = topology;
    ArborMesh *owned = NULL;
    CHECK_STATUS(arbor_forest_mesh_create(trees, 4, &o, &owned), ARBOR_STATUS_OK);
    size_t ov = 0, oi = 0, sv = 0, si = 0;
    const ArborVertex *vv = arbor_mesh_vertices(owned, &ov);
    const uint32_t *ii = arbor_mesh_indices(owned, &oi);
    CHECK_STATUS(arbor_forest_mesh_size(trees, 4, &o, &sv, &si), ARBOR_STATUS_OK);
    CHECK(sv == ov && si == oi, "sizes %zu/%zu vs %zu/%zu", sv, si, ov, oi);
    ArborVertex *w = malloc(sv * sizeof *w);
    uint32_t *j = malloc(si * sizeof *j);
    CHECK_STATUS(arbor_forest_mesh_write(trees, 4, &o, w, sv, j, si - 1), ARBOR_STATUS_BUFFER_TOO_SMALL);
    CHECK_STATUS(arbor_forest_mesh_write(trees, 4, &o, w, sv, j, si), ARBOR_STATUS_OK);
    CHECK(memcmp(w, vv, sv * sizeof *w) == 0 && memcmp(j, ii, si * sizeof *j) == 0,
          "topology %u: written forest differs from the owned one", topology);
    free(w);
    free(j);
    arbor_mesh_free(owned);
  }
  arbor_mesh_free(forest);
  trees[2].scale = -1.0f;
  forest = NULL;
  CHECK_STATUS(arbor_forest_mesh_create(trees, 4, NULL, &forest), ARBOR_STATUS_INVALID_ARGUMENT);
  CHECK(forest == NULL, "out written on failure");
  CHECK_STATUS(arbor_forest_mesh_create(NULL, 2, NULL, &forest), ARBOR_STATUS_NULL_ARGUMENT);

  arbor_tree_free(paper);
  arbor_tree_free(v1);
  arbor_tree_free(v1b);
  arbor_tree_free(v2);
  arbor_tree_free(a);
  arbor_tree_free(pruned);
  arbor_tree_free(v0);
  plants();
  return check_report("forest");
}
