/* Curves through the C ABI: copy, smooth (joints kept, C1 along axes), edit one branch
 * (its subtree follows; bad edits change nothing), GPU records with growth bounds, and a
 * mesh written after an edit. */
#include "arbor.h"
#include "check.h"

#include <math.h>
#include <pthread.h>
#include <string.h>

static float dist(const float a[3], const float b[3]) {
  float dx = a[0] - b[0], dy = a[1] - b[1], dz = a[2] - b[2];
  return sqrtf(dx * dx + dy * dy + dz * dz);
}

/* A host's copy of the mesh: written in full once, then only rewritten. */
typedef struct Copy {
  const ArborTree *tree;
  const ArborMeshOptions *mo;
  ArborVertex *v;
  uint32_t *ix;
  size_t nv, ni, branch;
  ArborStatus status;
} Copy;

static void *rewrite_copy(void *arg) {
  Copy *c = arg;
  c->status = arbor_mesh_rewrite_branch(c->tree, c->mo, c->branch, c->v, c->nv, c->ix, c->ni);
  return NULL;
}

/* Two buffers (A and B, as a double-buffered upload keeps them), both written in full
   before an edit, then rewritten one after the other, and then on two threads at once:
   each equals a full write. */
static void rewrites_of_several_buffers(void) {
  ArborHondaParams g;
  arbor_honda_preset('g', &g);
  g.steps = 10;
  ArborTree *tree = NULL;
  CHECK_STATUS(arbor_tree_from_honda(&g, &tree), ARBOR_STATUS_OK);
  ArborMeshOptions mo = arbor_mesh_options_default();
  mo.curve_rings = 1;
  size_t nv = 0, ni = 0, nb = arbor_tree_branch_count(tree);
  CHECK_STATUS(arbor_mesh_size(tree, &mo, &nv, &ni), ARBOR_STATUS_OK);
  Copy c[2];
  for (int k = 0; k < 2; k++) {
    c[k].tree = tree;
    c[k].mo = &mo;
    c[k].nv = nv;
    c[k].ni = ni;
    c[k].v = malloc(nv * sizeof(ArborVertex));
    c[k].ix = malloc(ni * sizeof(uint32_t));
    CHECK_STATUS(arbor_mesh_write(tree, &mo, c[k].v, nv, c[k].ix, ni), ARBOR_STATUS_OK);
  }
  ArborVertex *fresh_v = malloc(nv * sizeof *fresh_v);
  uint32_t *fresh_i = malloc(ni * sizeof *fresh_i);
  ArborCurve *cs = malloc(nb * sizeof *cs);
  size_t edits[3] = {nb - 1, 7, nb / 2};
  for (int round = 0; round < 3; round++) {
    CHECK_STATUS(arbor_tree_copy_curves(tree, cs, nb), ARBOR_STATUS_OK);
    ArborCurve e = cs[edits[round]];
    e.p3[0] += 0.4f;
    e.p1[1] += 0.2f;
    CHECK_STATUS(arbor_tree_set_curve(tree, edits[round], &e), ARBOR_STATUS_OK);
    for (int k = 0; k < 2; k++) c[k].branch = edits[round];
    if (round < 2) {
      /* One after the other (the second round: B first). */
      for (int j = 0; j < 2; j++) rewrite_copy(&c[round == 0 ? j : 1 - j]);
    } else {
      pthread_t th[2];
      for (int k = 0; k < 2; k++) pthread_create(&th[k], NULL, rewrite_copy, &c[k]);
      for (int k = 0; k < 2; k++) pthread_join(th[k], NULL);
    }
    CHECK_STATUS(arbor_mesh_write(tree, &mo, fresh_v, nv, fresh_i, ni), ARBOR_STATUS_OK);
    for (int k = 0; k < 2; k++) {
      CHECK(c[k].status == ARBOR_STATUS_OK, "round %d buffer %d: status %d", round, k, (int)c[k].status);
      CHECK(memcmp(c[k].v, fresh_v, nv * sizeof *fresh_v) == 0,
            "round %d buffer %c: vertices equal a full write", round, 'A' + k);
      CHECK(memcmp(c[k].ix, fresh_i, ni * sizeof *fresh_i) == 0, "round %d buffer %c: indices",
            round, 'A' + k);
    }
  }
  for (int k = 0; k < 2; k++) {
    free(c[k].v);
    free(c[k].ix);
  }
  free(fresh_v);
  free(fresh_i);
  free(cs);
  arbor_tree_free(tree);
}

int main(void) {
  ArborHondaParams p;
  ArborTree *t = NULL;
  arbor_honda_preset('c', &p);
  CHECK_STATUS(arbor_tree_from_honda(&p, &t), ARBOR_STATUS_OK);
  size_t n = arbor_tree_branch_count(t);
  ArborBranch *b = malloc(n * sizeof *b);
  ArborCurve *c = malloc(n * sizeof *c);
  CHECK_STATUS(arbor_tree_copy_branches(t, b, n), ARBOR_STATUS_OK);
  CHECK_STATUS(arbor_tree_copy_curves(t, c, n - 1), ARBOR_STATUS_BUFFER_TOO_SMALL);
  CHECK_STATUS(arbor_tree_copy_curves(t, c, n), ARBOR_STATUS_OK);
  for (size_t i = 0; i < n; i++) {
    CHECK(memcmp(c[i].p0, b[i].start, 12) == 0 && memcmp(c[i].p3, b[i].end, 12) == 0, "ends %zu", i);
    float third[3] = {b[i].start[0] + (b[i].end[0] - b[i].start[0]) / 3,
                      b[i].start[1] + (b[i].end[1] - b[i].start[1]) / 3,
                      b[i].start[2] + (b[i].end[2] - b[i].start[2]) / 3};
    CHECK(dist(c[i].p1, third) < 1e-4f, "straight: p1 at the third, branch %zu", i);
  }
  /* Smoothing: no joint moves; along an axis the tangents meet. */
  CHECK_STATUS(arbor_tree_smooth(t, 1.0f), ARBOR_STATUS_OK);
  CHECK_STATUS(arbor_tree_smooth(t, NAN), ARBOR_STATUS_INVALID_ARGUMENT);
  {
    ArborBranch *after = malloc(n * sizeof *after);
    CHECK_STATUS(arbor_tree_copy_branches(t, after, n), ARBOR_STATUS_OK);
    CHECK(memcmp(after, b, n * sizeof *b) == 0, "smoothing moves no joint");
    free(after);
  }
  CHECK_STATUS(arbor_tree_copy_curves(t, c, n), ARBOR_STATUS_OK);
  CHECK(dist(c[1].p1, c[1].p0) > 1e-3f, "a smoothed branch has handles");

  /* Edit branch 1: its end moves, the subtree follows. */
  ArborCurve e = c[1];
  float moved[3] = {4, -1, 2};
  for (int k = 0; k < 3; k++) {
    e.p3[k] += moved[k];
    e.p2[k] += moved[k];
  }
  e.r0 = 5;
  e.r1 = 4;
  size_t nv = 0, ni = 0;
  ArborMeshOptions o = arbor_mesh_options_default();
  CHECK_STATUS(arbor_mesh_size(t, &o, &nv, &ni), ARBOR_STATUS_OK); /* a plan is kept */
  CHECK_STATUS(arbor_tree_set_curve(t, 1, &e), ARBOR_STATUS_OK);
  {
    ArborBranch *after = malloc(n * sizeof *after);
    CHECK_STATUS(arbor_tree_copy_branches(t, after, n), ARBOR_STATUS_OK);
    for (size_t i = 1; i < n; i++)
      CHECK(memcmp(after[i].start, after[after[i].parent].end, 12) == 0, "connected %zu", i);
    CHECK(after[1].start_radius == 5 && after[1].end_radius == 4, "radii set");
    CHECK(fabsf(after[n - 1].end[0] - b[n - 1].end[0] - moved[0]) < 1e-3f ||
              after[n - 1].end[0] == b[n - 1].end[0],
          "the last branch moved with the edit or lies outside the subtree");
    CHECK(memcmp(&after[0], &b[0], sizeof b[0]) == 0, "the trunk did not move");
    free(after);
  }
  /* A bad edit is refused by name and changes nothing. */
  {
    char msg[256];
    ArborCurve bad = e;
    bad.p0[1] += 1;
    CHECK_STATUS(arbor_tree_set_curve(t, 1, &bad), ARBOR_STATUS_INVALID_ARGUMENT);
    arbor_last_error_message(msg, sizeof msg);
    CHECK(strstr(msg, "start") != NULL, "%s", msg);
    CHECK_STATUS(arbor_tree_set_curve(t, n, &e), ARBOR_STATUS_INVALID_ARGUMENT);
    bad = e;
    bad.r0 = NAN;
    CHECK_STATUS(arbor_tree_set_curve(t, 1, &bad), ARBOR_STATUS_INVALID_ARGUMENT);
    CHECK_STATUS(arbor_tree_set_curve(t, 1, NULL), ARBOR_STATUS_NULL_ARGUMENT);
    ArborCurve now;
    ArborCurve *all = malloc(n * sizeof *all);
    CHECK_STATUS(arbor_tree_copy_curves(t, all, n), ARBOR_STATUS_OK);
    now = all[1];
    CHECK(memcmp(&now, &e, sizeof e) == 0, "unchanged by the bad edits");
    free(all);
  }
  /* The mesh after the edit (the kept plan was dropped). */
  {
    CHECK_STATUS(arbor_mesh_size(t, &o, &nv, &ni), ARBOR_STATUS_OK);
    ArborVertex *v = malloc(nv * sizeof *v);
    uint32_t *ix = malloc(ni * sizeof *ix);
    CHECK_STATUS(arbor_mesh_write(t, &o, v, nv, ix, ni), ARBOR_STATUS_OK);
    free(v);
    free(ix);
  }
  /* GPU records. */
  {
    ArborCurveRecord *r = malloc(n * sizeof *r);
    ArborCurveGrowthRecord *g = malloc(n * sizeof *g);
    ArborCurve *all = malloc(n * sizeof *all);
    CHECK_STATUS(arbor_tree_curve_records_write(t, r, n - 1), ARBOR_STATUS_BUFFER_TOO_SMALL);
    CHECK_STATUS(arbor_tree_curve_records_write(t, r, n), ARBOR_STATUS_OK);
    CHECK_STATUS(arbor_tree_curve_growth_records_write(t, g, n), ARBOR_STATUS_OK);
    CHECK_STATUS(arbor_tree_copy_curves(t, all, n), ARBOR_STATUS_OK);
    for (size_t i = 0; i < n; i++) {
      CHECK(memcmp(r[i].p0, all[i].p0, 12) == 0 && memcmp(r[i].p3, all[i].p3, 12) == 0, "record %zu", i);
      CHECK(r[i].length >= dist(all[i].p0, all[i].p3) * 0.999f, "arc at least the chord, %zu", i);
      if (r[i].parent != ARBOR_NO_PARENT) {
        const ArborCurveRecord *q = &r[r[i].parent];
        CHECK(fabsf(r[i].v0 - (q->v0 + q->length)) < 1e-3f * (1 + r[i].v0), "v continues %zu", i);
      }
      CHECK(g[i].grow_start >= 0 && g[i].grow_start < g[i].grow_end && g[i].grow_end <= 1,
            "growth bounds %zu", i);
      CHECK(memcmp(&g[i].curve, &r[i], sizeof r[i]) == 0, "growth record %zu", i);
    }
    CHECK(sizeof(ArborCurveRecord) == 80 && sizeof(ArborCurveGrowthRecord) == 96, "std430 sizes");
    free(r);
    free(g);
    free(all);
  }
  free(b);
  free(c);
  arbor_tree_free(t);
  CHECK_STATUS(arbor_tree_smooth(NULL, 1), ARBOR_STATUS_NULL_ARGUMENT);

  /* One-branch rewrites inside the host's buffers equal full writes, in every topology. */
  for (uint32_t topo = 0; topo < 3; topo++) {
    ArborHondaParams g;
    ArborTree *tree = NULL;
    arbor_honda_preset('g', &g);
    g.steps = 12;
    CHECK_STATUS(arbor_tree_from_honda(&g, &tree), ARBOR_STATUS_OK);
    ArborMeshOptions mo = arbor_mesh_options_default();
    mo.topology = topo;
    mo.curve_rings = 2;
    size_t nv = 0, ni = 0, nb = arbor_tree_branch_count(tree);
    CHECK_STATUS(arbor_mesh_size(tree, &mo, &nv, &ni), ARBOR_STATUS_OK);
    ArborVertex *v = malloc(nv * sizeof *v), *fresh_v = malloc(nv * sizeof *v);
    uint32_t *ix = malloc(ni * sizeof *ix), *fresh_i = malloc(ni * sizeof *ix);
    CHECK_STATUS(arbor_mesh_write(tree, &mo, v, nv, ix, ni), ARBOR_STATUS_OK);
    ArborCurve *cs = malloc(nb * sizeof *cs);
    size_t edits[2] = {nb - 1, 5};
    for (int k = 0; k < 2; k++) {
      CHECK_STATUS(arbor_tree_copy_curves(tree, cs, nb), ARBOR_STATUS_OK);
      ArborCurve e2 = cs[edits[k]];
      e2.p3[0] += 0.5f;
      e2.p2[2] -= 0.3f;
      e2.r1 *= 0.9f;
      CHECK_STATUS(arbor_tree_set_curve(tree, edits[k], &e2), ARBOR_STATUS_OK);
      CHECK_STATUS(arbor_mesh_rewrite_branch(tree, &mo, edits[k], v, nv, ix, ni), ARBOR_STATUS_OK);
      CHECK_STATUS(arbor_mesh_write(tree, &mo, fresh_v, nv, fresh_i, ni), ARBOR_STATUS_OK);
      CHECK(memcmp(v, fresh_v, nv * sizeof *v) == 0, "topology %u edit %d: vertices equal a full write", topo, k);
      CHECK(memcmp(ix, fresh_i, ni * sizeof *ix) == 0, "topology %u edit %d: indices", topo, k);
    }
    CHECK_STATUS(arbor_mesh_rewrite_branch(tree, &mo, nb, v, nv, ix, ni), ARBOR_STATUS_INVALID_ARGUMENT);
    CHECK_STATUS(arbor_mesh_rewrite_branch(tree, &mo, 0, v, nv - 1, ix, ni), ARBOR_STATUS_INVALID_ARGUMENT);
    free(v);
    free(fresh_v);
    free(ix);
    free(fresh_i);
    free(cs);
    arbor_tree_free(tree);
  }
  rewrites_of_several_buffers();
  return check_report("curves");
}
