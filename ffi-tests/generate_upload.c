/* The generate-then-upload path for all nine 1996 presets, as a host would walk it. */
#include "arbor.h"
#include "check.h"

#include <math.h>
#include <string.h>

_Static_assert(sizeof(ArborVertex) == 32, "ArborVertex is 32 bytes");
_Static_assert(offsetof(ArborVertex, normal) == 12, "normal at 12");
_Static_assert(offsetof(ArborVertex, uv) == 24, "uv at 24");
_Static_assert(sizeof(ArborBranch) == 48, "ArborBranch is 48 bytes");
_Static_assert(sizeof(ArborHondaParams) == 48, "ArborHondaParams is 48 bytes");

static const size_t expected_branches[9] = {1023, 2223, 510, 1023, 1990, 5027, 1023, 919, 1586};

static void upload_one(char name, size_t expected) {
  ArborHondaParams p;
  ArborTree *tree = NULL;
  CHECK_STATUS(arbor_honda_preset((uint32_t)name, &p), ARBOR_STATUS_OK);
  CHECK(p.trunk_length == 100.0f, "tree %c trunk %f", name, p.trunk_length);
  CHECK_STATUS(arbor_tree_from_honda(&p, &tree), ARBOR_STATUS_OK);
  if (!tree) return;

  size_t nb = arbor_tree_branch_count(tree);
  CHECK(nb == expected, "tree %c has %zu branches, expected %zu", name, nb, expected);
  ArborBranch *branches = malloc(nb * sizeof *branches);
  CHECK_STATUS(arbor_tree_copy_branches(tree, branches, nb), ARBOR_STATUS_OK);
  CHECK(branches[0].parent == ARBOR_NO_PARENT && branches[0].depth == 1, "trunk of %c", name);
  CHECK(branches[0].end[1] == 100.0f && branches[0].start_radius == p.trunk_width / 2,
        "trunk of %c", name);
  for (size_t i = 1; i < nb; i++) {
    const ArborBranch *b = &branches[i];
    CHECK(b->parent < i, "tree %c branch %zu parent %u", name, i, b->parent);
    if (b->parent >= i) break;
    CHECK(memcmp(b->start, branches[b->parent].end, sizeof b->start) == 0,
          "tree %c branch %zu starts off its parent", name, i);
  }

  for (uint32_t topology = 0; topology < 3; topology++) {
    ArborMeshOptions o = arbor_mesh_options_default();
    o.topology = topology;
    size_t nv = 0, ni = 0;
    CHECK_STATUS(arbor_mesh_size(tree, &o, &nv, &ni), ARBOR_STATUS_OK);
    /* Mitred joints: one ring per branch plus one where each axis starts. */
    size_t axes = 0;
    for (size_t i = 0; i < nb; i++)
      axes += branches[i].parent == ARBOR_NO_PARENT || branches[branches[i].parent].order != branches[i].order;
    CHECK(nv == (nb + axes) * (o.radial_segments + 1), "tree %c: %zu vertices", name, nv);
    /* What glMapBufferRange would hand back: uninitialised memory of exactly that size. */
    ArborVertex *vertices = malloc(nv * sizeof *vertices);
    uint32_t *indices = malloc(ni * sizeof *indices);
    CHECK_STATUS(arbor_mesh_write(tree, &o, vertices, nv, indices, ni), ARBOR_STATUS_OK);
    size_t restarts = 0;
    for (size_t i = 0; i < ni; i++) {
      if (indices[i] == ARBOR_RESTART_INDEX) {
        restarts++;
        continue;
      }
      if (indices[i] >= nv) {
        CHECK(0, "tree %c topology %u index %zu = %u out of range", name, topology, i, indices[i]);
        break;
      }
    }
    /* A restart between branches, and one inside each axis start's tube (two strips). */
    CHECK(restarts == (topology == ARBOR_TOPOLOGY_TRIANGLE_STRIP_RESTART ? nb - 1 + axes : 0),
          "tree %c topology %u: %zu restarts", name, topology, restarts);
    for (size_t i = 0; i < nv; i++) {
      const float *n = vertices[i].normal;
      float len = sqrtf(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
      if (!(fabsf(len - 1.0f) < 1e-4f) || isnan(vertices[i].position[0])) {
        CHECK(0, "tree %c vertex %zu normal length %f", name, i, len);
        break;
      }
    }
    free(vertices);
    free(indices);
  }
  free(branches);
  arbor_tree_free(tree);
}

int main(void) {
  CHECK(arbor_abi_version() >= ARBOR_ABI_VERSION, "library ABI %u older than header %u",
        arbor_abi_version(), ARBOR_ABI_VERSION);
  char header_version[32];
  snprintf(header_version, sizeof header_version, "%d.%d.%d", ARBOR_VERSION_MAJOR,
           ARBOR_VERSION_MINOR, ARBOR_VERSION_PATCH);
  CHECK(strcmp(arbor_version(), header_version) == 0, "version %s vs header %s",
        arbor_version(), header_version);
  /* The sizes the library reports are the header's. */
  const size_t sizes[23] = {sizeof(ArborHondaParams), sizeof(ArborBranch), sizeof(ArborVertex),
                            sizeof(ArborMeshOptions), sizeof(ArborLsystemOptions),
                            sizeof(ArborLeafOptions), sizeof(ArborLeafInstance),
                            sizeof(ArborBranchRange), sizeof(ArborLeafSite),
                            sizeof(ArborAnimationVertex), sizeof(ArborForestTree),
                            sizeof(ArborWorldOptions), sizeof(ArborGrowthParams),
                            sizeof(ArborCurve), sizeof(ArborCurveRecord),
                            sizeof(ArborCurveGrowthRecord), sizeof(ArborOrgan),
                            sizeof(ArborVertexCompact), sizeof(ArborAnimationVertexCompact),
                            sizeof(ArborForestPlant), sizeof(ArborCapsule),
                            sizeof(ArborLodOptions), sizeof(ArborBone)};
  for (uint32_t id = 0; id < 23; id++)
    CHECK(arbor_struct_size(id) == sizes[id], "struct %u: %zu vs %zu", id, arbor_struct_size(id),
          sizes[id]);
  CHECK(arbor_struct_size(23) == 0 && arbor_struct_size(ARBOR_STRUCT_ID_LEAF_SITE) == 44 && arbor_struct_size(ARBOR_STRUCT_ID_ORGAN) == 56,
        "unknown id");
  for (int i = 0; i < 9; i++) upload_one((char)('a' + i), expected_branches[i]);
  /* Upper case names work too. */
  ArborHondaParams lower, upper;
  CHECK_STATUS(arbor_honda_preset('g', &lower), ARBOR_STATUS_OK);
  CHECK_STATUS(arbor_honda_preset('G', &upper), ARBOR_STATUS_OK);
  CHECK(memcmp(&lower, &upper, sizeof lower) == 0, "'G' differs from 'g'");
  return check_report("generate_upload");
}
