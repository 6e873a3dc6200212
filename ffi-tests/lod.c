/* Levels of detail and impostors through the C ABI: the chain of a tree with leaves, each
 * level's bark and leaves size then fill, and an octahedral impostor's atlases into the
 * host's memory. */
#include "arbor.h"
#include "check.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

int main(void) {
  ArborHondaParams p;
  CHECK_STATUS(arbor_honda_preset('b', &p), ARBOR_STATUS_OK);
  ArborTree *tree = NULL;
  CHECK_STATUS(arbor_tree_from_honda(&p, &tree), ARBOR_STATUS_OK);
  ArborLeafOptions lo = arbor_leaf_options_default();
  lo.sites = 0;
  lo.tips = 1;
  lo.density = 3.0f;
  lo.size = 8.0f;
  ArborLodOptions od = arbor_lod_options_default();
  CHECK(od.levels == 4 && od.budget == 0.4f && od.struct_size == sizeof od, "defaults");

  /* On the calling thread (the test runs under valgrind). */
  ArborMeshOptions mo = arbor_mesh_options_default();
  mo.threads = 1;
  ArborLods *lods = NULL;
  CHECK_STATUS(arbor_tree_lods_create(tree, &mo, &lo, NULL, 0, 0, &od, &lods), ARBOR_STATUS_OK);
  CHECK(arbor_lods_count(lods) == 4, "%zu levels", arbor_lods_count(lods));
  size_t full = 0;
  float previous = 2.0f;
  for (size_t k = 0; k < 4; k++) {
    float coverage = 0.0f, iou = 0.0f;
    size_t triangles = 0;
    CHECK_STATUS(arbor_lods_level_info(lods, k, &coverage, &iou, &triangles), ARBOR_STATUS_OK);
    CHECK(coverage <= previous && coverage > 0.0f, "level %zu coverage %f", k, (double)coverage);
    previous = coverage;
    if (k == 0) full = triangles;
    CHECK(k == 0 || (double)triangles <= 0.4 * (double)full * 1.0001, "level %zu: %zu of %zu", k,
          triangles, full);
    /* Bark and leaves, size then fill: their indices make the level's triangles. */
    size_t sum = 0;
    for (uint32_t part = 0; part < 2; part++) {
      size_t nv = 0, ni = 0;
      CHECK_STATUS(arbor_lods_mesh_write(lods, k, part, NULL, 0, NULL, 0, &nv, &ni), ARBOR_STATUS_OK);
      CHECK(nv > 0 && ni > 0, "level %zu part %u empty", k, part);
      ArborVertex *v = malloc(nv * sizeof *v);
      uint32_t *ix = malloc(ni * sizeof *ix);
      CHECK_STATUS(arbor_lods_mesh_write(lods, k, part, v, nv - 1, ix, ni, NULL, NULL),
                   ARBOR_STATUS_BUFFER_TOO_SMALL);
      CHECK_STATUS(arbor_lods_mesh_write(lods, k, part, v, nv, ix, ni, NULL, NULL), ARBOR_STATUS_OK);
      for (size_t i = 0; i < ni; i++) CHECK(ix[i] < nv, "index %zu out of range", i);
      sum += ni / 3;
      free(v);
      free(ix);
    }
    CHECK(sum == triangles, "level %zu: %zu indexed vs %zu", k, sum, triangles);
  }
  CHECK_STATUS(arbor_lods_level_info(lods, 4, NULL, NULL, NULL), ARBOR_STATUS_INVALID_ARGUMENT);
  /* Every level's bark and leaves skinned on the tree's bones: a skin vertex a mesh
   * vertex, four weights summing to one on bones the tree has; level 0's bark the skin of
   * the tree's own mesh; a part past the leaves refused. */
  size_t bone_count = 0;
  CHECK_STATUS(arbor_tree_bones_write(tree, &mo, 16, NULL, NULL, 0, &bone_count), ARBOR_STATUS_OK);
  CHECK(bone_count > 4 && bone_count <= 16, "%zu bones", bone_count);
  for (size_t k = 0; k < 4; k++) {
    for (uint32_t part = 0; part < 2; part++) {
      size_t nv = 0, ni = 0, ns = 0;
      CHECK_STATUS(arbor_lods_mesh_write(lods, k, part, NULL, 0, NULL, 0, &nv, &ni), ARBOR_STATUS_OK);
      CHECK_STATUS(arbor_lods_skin_write(lods, k, part, 16, NULL, NULL, 0, &ns), ARBOR_STATUS_OK);
      CHECK(ns == nv && ns > 0, "level %zu part %u: %zu skin vertices, %zu mesh vertices", k, part, ns, nv);
      uint16_t *joints = malloc(4 * ns * sizeof *joints);
      float *weights = malloc(4 * ns * sizeof *weights);
      weights[0] = 7.0f;
      CHECK_STATUS(arbor_lods_skin_write(lods, k, part, 16, joints, weights, ns - 1, NULL),
                   ARBOR_STATUS_BUFFER_TOO_SMALL);
      CHECK(weights[0] == 7.0f, "nothing written when too small");
      CHECK_STATUS(arbor_lods_skin_write(lods, k, part, 16, joints, weights, ns, NULL), ARBOR_STATUS_OK);
      int summed = 1, joined = 1;
      for (size_t v = 0; v < ns; v++) {
        float w = weights[4 * v] + weights[4 * v + 1] + weights[4 * v + 2] + weights[4 * v + 3];
        summed = summed && w > 0.9999f && w < 1.0001f;
        for (int j = 0; j < 4; j++) joined = joined && joints[4 * v + j] < bone_count;
      }
      CHECK(summed && joined, "level %zu part %u: weights and joints", k, part);
      if (k == 0 && part == 0) {
        size_t tn = 0;
        CHECK_STATUS(arbor_mesh_skin_write(tree, &mo, 16, NULL, NULL, 0, &tn), ARBOR_STATUS_OK);
        CHECK(tn == ns, "level 0's bark is the tree's mesh: %zu vs %zu", tn, ns);
        uint16_t *tj = malloc(4 * tn * sizeof *tj);
        float *tw = malloc(4 * tn * sizeof *tw);
        CHECK_STATUS(arbor_mesh_skin_write(tree, &mo, 16, tj, tw, tn, NULL), ARBOR_STATUS_OK);
        CHECK(memcmp(tj, joints, 4 * tn * sizeof *tj) == 0 && memcmp(tw, weights, 4 * tn * sizeof *tw) == 0,
              "level 0's bark skin is the tree's");
        free(tj);
        free(tw);
      }
      free(joints);
      free(weights);
    }
  }
  CHECK_STATUS(arbor_lods_skin_write(lods, 0, 2, 16, NULL, NULL, 0, NULL), ARBOR_STATUS_INVALID_ARGUMENT);
  {
    uint16_t j[4];
    CHECK_STATUS(arbor_lods_skin_write(lods, 0, 0, 16, j, NULL, SIZE_MAX, NULL), ARBOR_STATUS_INVALID_ARGUMENT);
  }
  CHECK_STATUS(arbor_lods_skin_write(lods, 4, 0, 16, NULL, NULL, 0, NULL), ARBOR_STATUS_INVALID_ARGUMENT);
  CHECK_STATUS(arbor_lods_skin_write(lods, 0, 0, 0, NULL, NULL, 0, NULL), ARBOR_STATUS_INVALID_ARGUMENT);
  /* Each branch's pivot for a Pivot-Painter-style shader: a row a branch, its axis unit,
   * its parent before it, and each branch starting where its parent ends. */
  size_t pivot_count = 0;
  CHECK_STATUS(arbor_tree_pivots_write(tree, &mo, NULL, 0, &pivot_count), ARBOR_STATUS_OK);
  CHECK(pivot_count == arbor_tree_branch_count(tree), "%zu pivots", pivot_count);
  float *pivots = malloc(8 * pivot_count * sizeof *pivots);
  pivots[0] = 1234.0f;
  CHECK_STATUS(arbor_tree_pivots_write(tree, &mo, pivots, pivot_count - 1, NULL), ARBOR_STATUS_BUFFER_TOO_SMALL);
  CHECK(pivots[0] == 1234.0f, "nothing written when too small");
  CHECK_STATUS(arbor_tree_pivots_write(tree, &mo, pivots, pivot_count, NULL), ARBOR_STATUS_OK);
  CHECK(pivots[7] == -1.0f, "the trunk is a root: %f", (double)pivots[7]);
  int pivots_hold = 1;
  for (size_t k = 0; k < pivot_count; k++) {
    const float *r = &pivots[8 * k];
    float axis = r[4] * r[4] + r[5] * r[5] + r[6] * r[6];
    pivots_hold = pivots_hold && r[3] > 0.0f && axis > 0.9999f && axis < 1.0001f && r[7] < (float)k;
    if (r[7] >= 0.0f) {
      const float *p = &pivots[8 * (size_t)r[7]];
      for (int c = 0; c < 3; c++)
        pivots_hold = pivots_hold && fabsf(p[c] + p[3] * p[4 + c] - r[c]) <= 1e-4f * (1.0f + p[3]);
    }
  }
  CHECK(pivots_hold, "pivots: lengths, unit axes, parents first, joined ends");
  /* A capacity whose floats overflow size_t is refused, not trusted. */
  CHECK_STATUS(arbor_tree_pivots_write(tree, &mo, pivots, SIZE_MAX, NULL), ARBOR_STATUS_INVALID_ARGUMENT);
  free(pivots);
  /* The level to bake an impostor from: every level is first drawn at least 8 pixels
   * across (the last is), none that many (the full tree), and 0 for NULL. */
  CHECK(arbor_lods_impostor_level(lods, 8) == 3, "%zu", arbor_lods_impostor_level(lods, 8));
  CHECK(arbor_lods_impostor_level(lods, UINT32_MAX) == 0, "%zu", arbor_lods_impostor_level(lods, UINT32_MAX));
  CHECK(arbor_lods_impostor_level(lods, 128) < 4, "%zu", arbor_lods_impostor_level(lods, 128));
  CHECK(arbor_lods_impostor_level(NULL, 128) == 0, "NULL");
  CHECK_STATUS(arbor_lods_mesh_write(lods, 0, 2, NULL, 0, NULL, 0, NULL, NULL), ARBOR_STATUS_INVALID_ARGUMENT);

  /* The impostor of level 2: 4 x 4 views of 32 pixels. */
  ArborImpostor *imp = NULL;
  CHECK_STATUS(arbor_lods_impostor_create(lods, 2, 4, 32, 1, NULL, 0, 0, &imp), ARBOR_STATUS_OK);
  uint32_t side = 0;
  float centre[3], radius = 0.0f, up[3];
  CHECK_STATUS(arbor_impostor_info(imp, &side, centre, &radius, up), ARBOR_STATUS_OK);
  CHECK(side == 128 && radius > 0.0f && up[1] == 1.0f, "side %u radius %f", side, (double)radius);
  size_t bytes = 0;
  CHECK_STATUS(arbor_impostor_atlas_write(imp, 0, NULL, 0, &bytes), ARBOR_STATUS_OK);
  CHECK(bytes == (size_t)side * side * 4, "%zu bytes", bytes);
  uint8_t *albedo = malloc(bytes);
  memset(albedo, 7, bytes);
  CHECK_STATUS(arbor_impostor_atlas_write(imp, 0, albedo, bytes - 1, NULL), ARBOR_STATUS_BUFFER_TOO_SMALL);
  CHECK(albedo[0] == 7, "nothing written when too small");
  CHECK_STATUS(arbor_impostor_atlas_write(imp, 0, albedo, bytes, NULL), ARBOR_STATUS_OK);
  /* Each view has the tree in it, and its corner is clear. */
  for (uint32_t cell = 0; cell < 16; cell++) {
    uint32_t x0 = (cell % 4) * 32, y0 = (cell / 4) * 32, covered = 0;
    for (uint32_t y = 0; y < 32; y++)
      for (uint32_t x = 0; x < 32; x++) covered += albedo[((y0 + y) * side + x0 + x) * 4 + 3] > 0;
    CHECK(covered > 20, "view %u: %u pixels", cell, covered);
    CHECK(albedo[(y0 * side + x0) * 4 + 3] == 0, "view %u corner", cell);
  }
  CHECK_STATUS(arbor_impostor_atlas_write(imp, 2, albedo, bytes, NULL), ARBOR_STATUS_INVALID_ARGUMENT);
  ArborImpostor *none = NULL;
  CHECK_STATUS(arbor_lods_impostor_create(lods, 0, 0, 32, 1, NULL, 0, 0, &none), ARBOR_STATUS_INVALID_ARGUMENT);
  CHECK(none == NULL, "nothing on failure");
  arbor_impostor_free(imp);
  free(albedo);
  /* The billboard of the last level: three crossed quads, both sides, and their atlas. */
  ArborBillboard *bb = NULL;
  size_t last = arbor_lods_count(lods) - 1;
  CHECK_STATUS(arbor_lods_billboard_create(lods, last, 3, 32, NULL, 0, 0, &bb), ARBOR_STATUS_OK);
  size_t bv = 0, bi = 0;
  CHECK_STATUS(arbor_billboard_mesh_write(bb, 0, NULL, 0, NULL, 0, &bv, &bi), ARBOR_STATUS_OK);
  CHECK(bv == 12 && bi == 18, "one side: %zu vertices, %zu indices", bv, bi);
  CHECK_STATUS(arbor_billboard_mesh_write(bb, 1, NULL, 0, NULL, 0, &bv, &bi), ARBOR_STATUS_OK);
  CHECK(bv == 24 && bi == 36, "two sides: %zu vertices, %zu indices", bv, bi);
  ArborVertex quads[24];
  uint32_t quad_indices[36];
  quads[0].position[0] = 1234.0f;
  CHECK_STATUS(arbor_billboard_mesh_write(bb, 1, quads, 24, quad_indices, 35, NULL, NULL),
               ARBOR_STATUS_BUFFER_TOO_SMALL);
  CHECK(quads[0].position[0] == 1234.0f, "nothing written when too small");
  CHECK_STATUS(arbor_billboard_mesh_write(bb, 1, quads, 24, quad_indices, 36, NULL, NULL), ARBOR_STATUS_OK);
  for (int k = 0; k < 12; k++) {
    CHECK(quads[k + 12].normal[0] == -quads[k].normal[0] && quads[k + 12].position[1] == quads[k].position[1],
          "back vertex %d", k);
    CHECK(quads[k].uv[0] >= 0.0f && quads[k].uv[0] <= 1.0f && quads[k].uv[1] >= 0.0f && quads[k].uv[1] <= 1.0f,
          "uv %d", k);
  }
  for (int k = 0; k < 36; k++) CHECK(quad_indices[k] < 24, "index %d", k);
  CHECK_STATUS(arbor_billboard_mesh_write(bb, 2, NULL, 0, NULL, 0, &bv, &bi), ARBOR_STATUS_INVALID_ARGUMENT);
  uint32_t bw = 0, bh = 0;
  CHECK_STATUS(arbor_billboard_atlas_write(bb, 0, NULL, 0, &bw, &bh), ARBOR_STATUS_OK);
  CHECK(bw == 96 && bh == 32, "atlas %u x %u", bw, bh);
  uint8_t *card = malloc((size_t)bw * bh * 4);
  memset(card, 7, (size_t)bw * bh * 4);
  CHECK_STATUS(arbor_billboard_atlas_write(bb, 0, card, (size_t)bw * bh * 4 - 1, NULL, NULL),
               ARBOR_STATUS_BUFFER_TOO_SMALL);
  CHECK(card[0] == 7, "nothing written when too small");
  CHECK_STATUS(arbor_billboard_atlas_write(bb, 0, card, (size_t)bw * bh * 4, NULL, NULL), ARBOR_STATUS_OK);
  for (uint32_t plane = 0; plane < 3; plane++) {
    uint32_t covered = 0;
    for (uint32_t y = 0; y < 32; y++)
      for (uint32_t x = 0; x < 32; x++) covered += card[(y * bw + plane * 32 + x) * 4 + 3] > 0;
    CHECK(covered > 20, "plane %u: %u pixels", plane, covered);
  }
  CHECK(card[3] == 0, "the atlas' corner is clear");
  free(card);
  arbor_billboard_free(bb);
  arbor_billboard_free(NULL);
  ArborBillboard *no = NULL;
  CHECK_STATUS(arbor_lods_billboard_create(lods, last, 5, 32, NULL, 0, 0, &no), ARBOR_STATUS_INVALID_ARGUMENT);
  CHECK(no == NULL, "nothing on failure");
  /* A bad atlas size is refused before it is read. */
  uint8_t pixel[4] = {0, 0, 0, 255};
  ArborLods *bad = NULL;
  CHECK_STATUS(arbor_tree_lods_create(tree, NULL, &lo, pixel, 0, 1, NULL, &bad), ARBOR_STATUS_INVALID_ARGUMENT);
  CHECK(bad == NULL, "nothing on failure");
  arbor_impostor_free(NULL);
  arbor_lods_free(lods);
  arbor_tree_free(tree);
  return check_report("lod");
}
