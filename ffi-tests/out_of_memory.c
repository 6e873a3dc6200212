/* Allocation failures are statuses, never an abort: run under `ulimit -v` (tests/ffi.rs
   runs it with 1 GiB of address space, natively: valgrind and ASan need more). */
#include "arbor.h"
#include "check.h"

#include <string.h>

int main(void) {
  /* A world at the max_cells ceiling. Its shadow grid grows with what is shaded, so the
     world is made; an obstacle filling the box would need 8 GiB of shadow, which cannot
     be had, and the world stays as it was. */
  ArborWorldOptions wo = arbor_world_options_default();
  for (int k = 0; k < 3; k++) {
    wo.min[k] = 0.0f;
    wo.max[k] = 1280.0f;
  }
  wo.cell_size = 1.0f;
  wo.max_cells = (uint64_t)1 << 31;
  ArborWorld *w = NULL;
  CHECK_STATUS(arbor_world_create(&wo, &w), ARBOR_STATUS_OK);
  const float lo[3] = {0.0f, 0.0f, 0.0f}, hi[3] = {1279.0f, 1279.0f, 1279.0f};
  CHECK_STATUS(arbor_world_add_box(w, lo, hi), ARBOR_STATUS_OUT_OF_MEMORY);
  char m[512];
  arbor_last_error_message(m, sizeof m);
  CHECK(strstr(m, "shadow") != NULL, "message '%s' names the shadow", m);
  const float at[3] = {640.0f, 0.0f, 640.0f};
  CHECK_STATUS(arbor_world_plant(w, NULL, at, 1, NULL), ARBOR_STATUS_OK);
  CHECK_STATUS(arbor_world_step(w, 3), ARBOR_STATUS_OK);
  arbor_world_free(w);
  w = NULL;
  /* The same for markers. */
  wo.environment = ARBOR_ENVIRONMENT_SPACE_COLONIZATION;
  CHECK_STATUS(arbor_world_create(&wo, &w), ARBOR_STATUS_OUT_OF_MEMORY);
  arbor_last_error_message(m, sizeof m);
  CHECK(strstr(m, "markers") != NULL, "message '%s' names the markers", m);

  /* The 1996 model at n = 24: 16,777,215 branches (within max_branches), 1.1 GB of them. */
  ArborHondaParams big;
  CHECK_STATUS(arbor_honda_preset('a', &big), ARBOR_STATUS_OK);
  big.steps = 24;
  ArborTree *bt = NULL;
  CHECK_STATUS(arbor_tree_from_honda(&big, &bt), ARBOR_STATUS_OUT_OF_MEMORY);
  CHECK(bt == NULL, "out written on failure");
  arbor_last_error_message(m, sizeof m);
  CHECK(strstr(m, "branches") != NULL, "message '%s' names the branches", m);

  /* A grammar whose string fits (16 M modules, within max_modules) and whose skeleton,
     16 M branches, does not. */
  const char *g = "derivation length: 24\nAxiom: F(1)\nF(x) --> F(x)F(x)\n";
  CHECK_STATUS(arbor_tree_from_lsystem(g, strlen(g), NULL, &bt), ARBOR_STATUS_OUT_OF_MEMORY);
  CHECK(bt == NULL, "out written on failure");
  arbor_last_error_message(m, sizeof m);
  CHECK(strstr(m, "out of memory") != NULL, "message '%s'", m);

  /* A mesh arbor owns, larger than the address space left: tree a at n = 20 (610 MiB as
     a list of 8-sided tubes, more with 32 sides). */
  ArborHondaParams p;
  CHECK_STATUS(arbor_honda_preset('a', &p), ARBOR_STATUS_OK);
  p.steps = 20;
  ArborTree *t = NULL;
  CHECK_STATUS(arbor_tree_from_honda(&p, &t), ARBOR_STATUS_OK);
  ArborMeshOptions o = arbor_mesh_options_default();
  o.radial_segments = 32;
  ArborMesh *mesh = NULL;
  CHECK_STATUS(arbor_mesh_create(t, &o, &mesh), ARBOR_STATUS_OUT_OF_MEMORY);
  CHECK(mesh == NULL, "out written on failure");
  arbor_last_error_message(m, sizeof m);
  CHECK(strstr(m, "vertices") != NULL, "message '%s' names the vertices", m);
  /* The library goes on: a small mesh still works. */
  o.radial_segments = 3;
  p.steps = 6;
  arbor_tree_free(t);
  t = NULL;
  CHECK_STATUS(arbor_tree_from_honda(&p, &t), ARBOR_STATUS_OK);
  CHECK_STATUS(arbor_mesh_create(t, &o, &mesh), ARBOR_STATUS_OK);
  arbor_mesh_free(mesh);
  arbor_tree_free(t);
  return check_report("out_of_memory");
}
