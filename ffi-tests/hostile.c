/* Hostile inputs an outside fuzzer found (round 4), replayed through the C ABI with every
 * option the finding names: the files are in ffi-tests/hostile/, beside this program's
 * source. */
#include "arbor.h"
#include "check.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* The text of ffi-tests/hostile/NAME (NUL-terminated), its length in *len. */
static char *read_finding(const char *name, size_t *len) {
  char path[4096];
  const char *here = __FILE__;
  const char *slash = strrchr(here, '/');
  int dir = slash ? (int)(slash - here) : 1;
  snprintf(path, sizeof path, "%.*s/hostile/%s", dir, slash ? here : ".", name);
  FILE *f = fopen(path, "rb");
  CHECK(f != NULL, "cannot open %s", path);
  if (!f) exit(1);
  fseek(f, 0, SEEK_END);
  long n = ftell(f);
  fseek(f, 0, SEEK_SET);
  char *text = malloc((size_t)n + 1);
  size_t got = fread(text, 1, (size_t)n, f);
  fclose(f);
  text[got] = '\0';
  *len = got;
  return text;
}

/* leaf_normal_z_up.l: every normal of the baked leaf mesh is unit length with Z up (and
 * with Y up, and wound clockwise), with the options of the finding. */
static void leaf_normals_are_unit_under_every_up_axis(void) {
  size_t n;
  char *text = read_finding("leaf_normal_z_up.l", &n);
  ArborLsystemOptions lo = arbor_lsystem_options_default();
  lo.steps = -1;
  lo.seed = 7;
  lo.override_flags = 7;
  lo.angle_increment = 360;
  lo.initial_width = 1;
  lo.width_increment = 0;
  ArborTree *tree = NULL;
  CHECK_STATUS(arbor_tree_from_lsystem(text, n, &lo, &tree), ARBOR_STATUS_OK);
  ArborLeafOptions leaves = arbor_leaf_options_default();
  for (uint32_t up = 0; up < 2; up++) {
    for (uint32_t winding = 0; winding < 2; winding++) {
      ArborMeshOptions mo = arbor_mesh_options_default();
      mo.radial_segments = 9;
      mo.topology = 1;
      mo.joints = 1;
      mo.up_axis = up;
      mo.winding = winding;
      size_t nv = 0, ni = 0;
      CHECK_STATUS(arbor_leaf_mesh_size(tree, &leaves, &mo, &nv, &ni), ARBOR_STATUS_OK);
      /* The mesh the finding was made with. */
      CHECK(nv == 22029, "%zu vertices", nv);
      ArborVertex *v = malloc(nv * sizeof *v);
      uint32_t *ix = malloc(ni * sizeof *ix);
      CHECK_STATUS(arbor_leaf_mesh_write(tree, &leaves, &mo, v, nv, ix, ni), ARBOR_STATUS_OK);
      size_t bad = 0, first = 0;
      for (size_t k = 0; k < nv; k++) {
        const float *q = v[k].normal;
        float l = sqrtf(q[0] * q[0] + q[1] * q[1] + q[2] * q[2]);
        if (!(fabsf(l - 1.0f) < 1e-3f)) {
          if (bad++ == 0) first = k;
        }
      }
      CHECK(bad == 0, "up axis %u, winding %u: %zu normals not unit, the first vertex %zu",
            up, winding, bad, first);
      free(v);
      free(ix);
    }
  }
  arbor_tree_free(tree);
  free(text);
}

/* error_column_after_continuation.l: line 2 ends in `\`; the error is told where the `:`
 * stands in the file, on line 3 ("angle increment: -30"), column 16. */
static void error_position_is_in_the_files_own_text(void) {
  size_t n;
  char *text = read_finding("error_column_after_continuation.l", &n);
  ArborTree *tree = NULL;
  CHECK_STATUS(arbor_tree_from_lsystem(text, n, NULL, &tree), ARBOR_STATUS_PARSE_ERROR);
  char m[512];
  arbor_last_error_message(m, sizeof m);
  CHECK(strstr(m, "line 3, column 16") != NULL, "message '%s'", m);
  CHECK(tree == NULL, "tree written on failure");
  free(text);
}

static int32_t stop_at_third(void *user, uint32_t stage, float fraction) {
  (void)stage;
  (void)fraction;
  int *calls = user;
  return ++*calls >= 3;
}

/* derivation_runs_past_20s.l: steps = 65,535 with the default limits stops with
 * ARBOR_STATUS_LIMIT_EXCEEDED naming max_work (within the limits' time bound; the
 * finding ran past 20 s), and a progress callback that asks to stop is heard. */
static void a_long_derivation_stops_within_its_limits(void) {
  size_t n;
  char *text = read_finding("derivation_runs_past_20s.l", &n);
  ArborLsystemOptions lo = arbor_lsystem_options_default();
  lo.steps = 65535;
  ArborTree *tree = NULL;
  CHECK_STATUS(arbor_tree_from_lsystem(text, n, &lo, &tree), ARBOR_STATUS_LIMIT_EXCEEDED);
  char m[512];
  arbor_last_error_message(m, sizeof m);
  CHECK(strstr(m, "max_work") != NULL, "message '%s'", m);
  CHECK(tree == NULL, "tree written on failure");
  int calls = 0;
  lo.progress = stop_at_third;
  lo.progress_user_data = &calls;
  CHECK_STATUS(arbor_tree_from_lsystem(text, n, &lo, &tree), ARBOR_STATUS_CANCELLED);
  CHECK(calls == 3, "%d calls", calls);
  CHECK(tree == NULL, "tree written on failure");
  free(text);
}

int main(void) {
  leaf_normals_are_unit_under_every_up_axis();
  error_position_is_in_the_files_own_text();
  a_long_derivation_stops_within_its_limits();
  return check_report("hostile");
}
