/* A host's own skeleton: arbor_tree_from_branches() copies and validates it, and every
 * mesh function takes the result. */
#include "arbor.h"
#include "check.h"

#include <math.h>
#include <string.h>

static ArborBranch branch(float x0, float y0, float x1, float y1, float r, uint32_t parent) {
  ArborBranch b;
  memset(&b, 0, sizeof b);
  b.start[0] = x0;
  b.start[1] = y0;
  b.end[0] = x1;
  b.end[1] = y1;
  b.start_radius = r;
  b.end_radius = r;
  b.parent = parent;
  return b;
}

static void expect_invalid(const ArborBranch *b, size_t n, const char *needle) {
  ArborTree *t = NULL;
  char msg[512];
  CHECK_STATUS(arbor_tree_from_branches(b, n, &t), ARBOR_STATUS_INVALID_ARGUMENT);
  CHECK(t == NULL, "no tree on error");
  arbor_last_error_message(msg, sizeof msg);
  CHECK(strstr(msg, needle) != NULL, "message '%s' lacks '%s'", msg, needle);
}

int main(void) {
  ArborBranch b[4];
  ArborTree *t = NULL;
  b[0] = branch(0, 0, 0, 10, 1, ARBOR_NO_PARENT);
  b[1] = branch(0, 10, 0, 20, 0.8f, 0);
  b[2] = branch(0, 10, 5, 15, 0.5f, 0);
  b[3] = branch(0, 20, 0, 25, 0.4f, 1);
  b[1].depth = 1;
  b[1].order = 0;
  b[2].order = 1;
  CHECK_STATUS(arbor_tree_from_branches(b, 4, &t), ARBOR_STATUS_OK);
  CHECK(arbor_tree_branch_count(t) == 4, "4 branches");
  {
    ArborBranch back[4];
    CHECK_STATUS(arbor_tree_copy_branches(t, back, 4), ARBOR_STATUS_OK);
    CHECK(memcmp(back, b, sizeof back) == 0, "branches copied as given");
  }
  {
    ArborMeshOptions o = arbor_mesh_options_default();
    size_t nv = 0, ni = 0;
    CHECK_STATUS(arbor_mesh_size(t, &o, &nv, &ni), ARBOR_STATUS_OK);
    CHECK(nv > 0 && ni == 4 * 8 * 6, "mesh of 4 branches: %zu indices", ni);
    ArborVertex *v = malloc(nv * sizeof *v);
    uint32_t *ix = malloc(ni * sizeof *ix);
    CHECK_STATUS(arbor_mesh_write(t, &o, v, nv, ix, ni), ARBOR_STATUS_OK);
    for (size_t k = 0; k < ni; k++) CHECK(ix[k] < nv, "index %zu in range", k);
    free(v);
    free(ix);
  }
  arbor_tree_free(t);

  /* An empty skeleton is a tree with no branches. */
  t = NULL;
  CHECK_STATUS(arbor_tree_from_branches(NULL, 0, &t), ARBOR_STATUS_OK);
  CHECK(t != NULL && arbor_tree_branch_count(t) == 0, "empty tree");
  arbor_tree_free(t);

  /* Bad skeletons are refused by name. */
  {
    ArborBranch bad[2];
    bad[0] = b[0];
    bad[1] = b[1];
    bad[1].parent = 1;
    expect_invalid(bad, 2, "branch 1 has parent 1");
    bad[1] = b[1];
    bad[1].end[2] = NAN;
    expect_invalid(bad, 2, "non-finite");
    bad[1] = b[1];
    bad[1].start_radius = -1;
    expect_invalid(bad, 2, "start_radius");
  }
  t = NULL;
  CHECK_STATUS(arbor_tree_from_branches(NULL, 3, &t), ARBOR_STATUS_NULL_ARGUMENT);
  CHECK_STATUS(arbor_tree_from_branches(b, 4, NULL), ARBOR_STATUS_NULL_ARGUMENT);
  return check_report("skeleton");
}
