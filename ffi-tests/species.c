/* Named species through the C ABI: the adult tree, the options that draw it in metres,
 * its textures into the host's memory and the leaf atlas' cells. */
#include "arbor.h"
#include "check.h"

#include <string.h>

int main(void) {
  ArborTree *oak = NULL;
  CHECK_STATUS(arbor_tree_from_species(ARBOR_SPECIES_OAK, 1, &oak), ARBOR_STATUS_OK);
  CHECK(arbor_tree_branch_count(oak) > 1000, "%zu branches", arbor_tree_branch_count(oak));
  ArborTree *none = NULL;
  CHECK_STATUS(arbor_tree_from_species(ARBOR_SPECIES_BUSH, 1, &none), ARBOR_STATUS_INVALID_ARGUMENT);
  CHECK_STATUS(arbor_tree_from_species(99, 1, &none), ARBOR_STATUS_INVALID_ARGUMENT);
  CHECK(none == NULL, "nothing written on failure");

  /* The options that draw it 18 m tall with the species' leaves. */
  ArborMeshOptions mo = arbor_mesh_options_default();
  mo.threads = 1;
  ArborLeafOptions lo = arbor_leaf_options_default();
  CHECK_STATUS(arbor_species_options(ARBOR_SPECIES_OAK, oak, &mo, &lo), ARBOR_STATUS_OK);
  CHECK(mo.even_texels == 1 && mo.scale > 0.0f && mo.threads == 1, "mesh options");
  /* The oak carries its leaves on twigs: on tips, not buds. */
  CHECK(lo.atlas_columns * lo.atlas_rows == 8 && lo.sites == 0 && lo.tips == 1, "leaf options");
  size_t nv = 0, ni = 0;
  CHECK_STATUS(arbor_mesh_size(oak, &mo, &nv, &ni), ARBOR_STATUS_OK);
  ArborVertex *v = malloc(nv * sizeof *v);
  uint32_t *ix = malloc(ni * sizeof *ix);
  CHECK_STATUS(arbor_mesh_write(oak, &mo, v, nv, ix, ni), ARBOR_STATUS_OK);
  float lo_y = 1e30f, hi_y = -1e30f;
  for (size_t k = 0; k < nv; k++) {
    lo_y = v[k].position[1] < lo_y ? v[k].position[1] : lo_y;
    hi_y = v[k].position[1] > hi_y ? v[k].position[1] : hi_y;
  }
  CHECK(hi_y - lo_y > 16.0f && hi_y - lo_y < 20.0f, "%.2f m tall", (double)(hi_y - lo_y));
  free(v);
  free(ix);
  size_t lv = 0, li = 0;
  CHECK_STATUS(arbor_leaf_mesh_size(oak, &lo, &mo, &lv, &li), ARBOR_STATUS_OK);
  CHECK(lv >= 4 * 1000, "%zu leaf vertices", lv);

  /* Instanced twigs: the bare tree, one prototype per variant meshed once, and the
   * transforms; the stems they place are the twigs the tree above has baked in. */
  ArborTree *bare = NULL;
  CHECK_STATUS(arbor_tree_from_species_bare(ARBOR_SPECIES_OAK, 1, &bare), ARBOR_STATUS_OK);
  size_t twigs = 0;
  CHECK_STATUS(arbor_species_twig_instances_write(ARBOR_SPECIES_OAK, bare, &mo, NULL, 0, &twigs), ARBOR_STATUS_OK);
  CHECK(twigs > 500, "%zu twigs", twigs);
  ArborLeafInstance *ti = malloc(twigs * sizeof *ti);
  ti[0].scale = -1.0f;
  CHECK_STATUS(arbor_species_twig_instances_write(ARBOR_SPECIES_OAK, bare, &mo, ti, twigs - 1, NULL),
               ARBOR_STATUS_BUFFER_TOO_SMALL);
  CHECK(ti[0].scale == -1.0f, "nothing written on failure");
  CHECK_STATUS(arbor_species_twig_instances_write(ARBOR_SPECIES_OAK, bare, &mo, ti, twigs, NULL), ARBOR_STATUS_OK);
  size_t stems[ARBOR_TWIG_VARIANTS], placed = 0;
  ArborMeshOptions tmo = arbor_mesh_options_default();
  ArborLeafOptions tlo = arbor_leaf_options_default();
  tmo.threads = 1;
  CHECK_STATUS(arbor_species_twig_options(ARBOR_SPECIES_OAK, &tmo, &tlo), ARBOR_STATUS_OK);
  CHECK(tlo.sites == 1 && tlo.tips == 0 && tmo.even_texels == 1 && tmo.radial_segments <= 4, "twig options");
  for (uint32_t k = 0; k < ARBOR_TWIG_VARIANTS; k++) {
    ArborTree *twig = NULL;
    CHECK_STATUS(arbor_species_twig_create(ARBOR_SPECIES_OAK, k, &twig), ARBOR_STATUS_OK);
    stems[k] = arbor_tree_branch_count(twig);
    size_t tv = 0, tl = 0, unused = 0;
    CHECK_STATUS(arbor_mesh_size(twig, &tmo, &tv, &unused), ARBOR_STATUS_OK);
    CHECK_STATUS(arbor_leaf_instance_count(twig, &tlo, &tmo, &tl), ARBOR_STATUS_OK);
    CHECK(tv > 0 && tl >= stems[k], "twig %u: %zu vertices, %zu leaves on %zu stems", k, tv, tl, stems[k]);
    arbor_tree_free(twig);
  }
  for (size_t k = 0; k < twigs; k++) {
    const float *q = ti[k].rotation;
    float n = q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3];
    CHECK(n > 0.999f && n < 1.001f && ti[k].scale > 0.8f && ti[k].scale < 1.2f, "twig %zu", k);
    CHECK(ti[k].position[1] > -1.0f && ti[k].position[1] < 20.0f, "twig %zu at %g m", k, (double)ti[k].position[1]);
    placed += stems[k % ARBOR_TWIG_VARIANTS];
  }
  CHECK(arbor_tree_branch_count(bare) + placed == arbor_tree_branch_count(oak), "%zu + %zu stems vs %zu",
        arbor_tree_branch_count(bare), placed, arbor_tree_branch_count(oak));
  CHECK_STATUS(arbor_species_twig_create(ARBOR_SPECIES_BUSH, 0, &none), ARBOR_STATUS_INVALID_ARGUMENT);
  free(ti);
  arbor_tree_free(bare);

  /* Collision capsules for the oak's trunk and limbs, in its metres. */
  size_t nc = 0;
  CHECK_STATUS(arbor_tree_capsules_write(oak, &mo, 24, 0.0f, NULL, 0, &nc), ARBOR_STATUS_OK);
  CHECK(nc > 3 && nc <= 24, "%zu capsules", nc);
  ArborCapsule *caps = malloc(nc * sizeof *caps);
  caps[0].radius = -1.0f;
  CHECK_STATUS(arbor_tree_capsules_write(oak, &mo, 24, 0.0f, caps, nc - 1, NULL), ARBOR_STATUS_BUFFER_TOO_SMALL);
  CHECK(caps[0].radius == -1.0f, "nothing written on failure");
  CHECK_STATUS(arbor_tree_capsules_write(oak, &mo, 24, 0.0f, caps, nc, NULL), ARBOR_STATUS_OK);
  CHECK(caps[0].a[1] < 0.5f && caps[0].radius > 0.1f && caps[0].radius < 1.5f, "the trunk: r %g m",
        (double)caps[0].radius);
  for (size_t k = 1; k < nc; k++) CHECK(caps[k].radius <= caps[0].radius + 1e-4f, "capsule %zu", k);
  CHECK_STATUS(arbor_tree_capsules_write(oak, &mo, 0, 0.0f, caps, nc, NULL), ARBOR_STATUS_INVALID_ARGUMENT);
  CHECK(arbor_struct_size(ARBOR_STRUCT_ID_CAPSULE) == sizeof(ArborCapsule), "capsule size");
  free(caps);

  /* Wind as a skin: bones with inverse bind matrices, four weights a vertex of the mesh
     arbor_mesh_write() writes, and the clip's keys. */
  size_t nb = 0, sv = 0, mv = 0, mi = 0;
  CHECK_STATUS(arbor_tree_bones_write(oak, &mo, 32, NULL, NULL, 0, &nb), ARBOR_STATUS_OK);
  CHECK(nb > 4 && nb <= 32, "%zu bones", nb);
  ArborBone *bones = malloc(nb * sizeof *bones);
  float *ibm = malloc(nb * 16 * sizeof *ibm);
  bones[0].radius = -1.0f;
  CHECK_STATUS(arbor_tree_bones_write(oak, &mo, 32, bones, ibm, nb - 1, NULL), ARBOR_STATUS_BUFFER_TOO_SMALL);
  CHECK(bones[0].radius == -1.0f, "nothing written on failure");
  CHECK_STATUS(arbor_tree_bones_write(oak, &mo, 32, bones, ibm, nb, NULL), ARBOR_STATUS_OK);
  CHECK(bones[0].parent == ARBOR_NO_PARENT && bones[0].radius > 0.0f, "the root bone");
  for (size_t k = 1; k < nb; k++) CHECK(bones[k].parent < k, "bone %zu: parent %u", k, bones[k].parent);
  for (size_t k = 0; k < nb; k++)
    CHECK(ibm[16 * k + 12] == -bones[k].head[0] && ibm[16 * k + 13] == -bones[k].head[1] && ibm[16 * k + 15] == 1.0f,
          "inverse bind %zu", k);
  CHECK_STATUS(arbor_mesh_size(oak, &mo, &mv, &mi), ARBOR_STATUS_OK);
  CHECK_STATUS(arbor_mesh_skin_write(oak, &mo, 32, NULL, NULL, 0, &sv), ARBOR_STATUS_OK);
  CHECK(sv == mv, "skin %zu vertices, mesh %zu", sv, mv);
  uint16_t *joints = malloc(sv * 4 * sizeof *joints);
  float *weights = malloc(sv * 4 * sizeof *weights);
  memset(weights, 0x7f, sv * 4 * sizeof *weights); /* prefaulted, and not a weight */
  CHECK_STATUS(arbor_mesh_skin_write(oak, &mo, 32, joints, weights, sv - 1, NULL), ARBOR_STATUS_BUFFER_TOO_SMALL);
  CHECK_STATUS(arbor_mesh_skin_write(oak, &mo, 32, joints, weights, sv, NULL), ARBOR_STATUS_OK);
  size_t *used = calloc(nb, sizeof *used);
  for (size_t v = 0; v < sv; v++) {
    float sum = 0.0f;
    for (int i = 0; i < 4; i++) {
      sum += weights[4 * v + i];
      CHECK(joints[4 * v + i] < nb, "vertex %zu: joint %u", v, joints[4 * v + i]);
      if (weights[4 * v + i] > 0.0f) used[joints[4 * v + i]]++;
    }
    CHECK(sum > 0.9999f && sum < 1.0001f, "vertex %zu: weights sum to %g", v, (double)sum);
  }
  for (size_t k = 0; k < nb; k++) CHECK(used[k] > 0, "bone %zu moves no vertex", k);
  size_t keys = 0, clip_bones = 0;
  CHECK_STATUS(arbor_tree_wind_clip_write(oak, &mo, 32, NULL, 2.0f, 4.0f, 30, 7, NULL, 0, NULL, 0, &keys, &clip_bones),
               ARBOR_STATUS_OK);
  CHECK(keys == 121 && clip_bones == nb, "%zu keys, %zu bones", keys, clip_bones);
  float *key_times = malloc(keys * sizeof *key_times);
  float *rot = malloc(keys * nb * 4 * sizeof *rot);
  const float wind[3] = {0.0f, 0.0f, 1.0f};
  CHECK_STATUS(arbor_tree_wind_clip_write(oak, &mo, 32, wind, 2.0f, 4.0f, 30, 7, key_times, keys, rot, nb - 1, NULL, NULL),
               ARBOR_STATUS_BUFFER_TOO_SMALL);
  CHECK_STATUS(arbor_tree_wind_clip_write(oak, &mo, 32, wind, 2.0f, 4.0f, 30, 7, key_times, keys, rot, nb, NULL, NULL),
               ARBOR_STATUS_OK);
  CHECK(key_times[0] == 0.0f && key_times[keys - 1] == 4.0f, "times %g..%g", (double)key_times[0],
        (double)key_times[keys - 1]);
  for (size_t b = 0; b < nb; b++) {
    const float *first = rot + 4 * (b * keys), *last = rot + 4 * (b * keys + keys - 1);
    float dot = 0.0f, norm = 0.0f;
    for (int i = 0; i < 4; i++) {
      dot += first[i] * last[i];
      norm += first[i] * first[i];
    }
    CHECK(norm > 0.999f && norm < 1.001f && (dot > 0.99999f || dot < -0.99999f), "bone %zu loops", b);
  }
  CHECK_STATUS(arbor_tree_wind_clip_write(oak, &mo, 32, NULL, 2.0f, 0.1f, 30, 7, NULL, 0, NULL, 0, &keys, NULL),
               ARBOR_STATUS_INVALID_ARGUMENT);
  CHECK(arbor_struct_size(ARBOR_STRUCT_ID_BONE) == sizeof(ArborBone), "bone size");
  free(bones), free(ibm), free(joints), free(weights), free(used), free(key_times), free(rot);

  /* Textures: size, then fill; a short buffer is refused with nothing written. */
  const uint32_t size = 64;
  size_t bytes = (size_t)size * size * 4;
  uint8_t *px = malloc(bytes);
  memset(px, 7, bytes);
  CHECK_STATUS(arbor_species_texture_write(ARBOR_SPECIES_OAK, ARBOR_TEXTURE_LEAF_ATLAS, size, 1, 1, px, bytes - 1),
               ARBOR_STATUS_BUFFER_TOO_SMALL);
  CHECK(px[0] == 7, "nothing written on failure");
  CHECK_STATUS(arbor_species_texture_write(ARBOR_SPECIES_OAK, ARBOR_TEXTURE_LEAF_ATLAS, size, 1, 1, px, bytes),
               ARBOR_STATUS_OK);
  size_t clear = 0, solid = 0;
  for (size_t k = 0; k < bytes; k += 4) {
    clear += px[k + 3] == 0;
    solid += px[k + 3] == 255;
  }
  CHECK(clear > 0 && solid > 0, "alpha-cut atlas: %zu clear, %zu solid", clear, solid);
  CHECK_STATUS(arbor_species_texture_write(ARBOR_SPECIES_PINE, ARBOR_TEXTURE_BARK_NORMAL, size, 1, 1, px, bytes),
               ARBOR_STATUS_OK);
  size_t out = 0;
  for (size_t k = 0; k < bytes; k += 4) out += px[k + 2] > 128 && px[k + 3] == 255;
  CHECK(out == bytes / 4, "normals face out: %zu of %zu", out, bytes / 4);
  /* Roughness in glTF's layout: green varies, blue (metalness) 0. */
  CHECK_STATUS(arbor_species_texture_write(ARBOR_SPECIES_OAK, ARBOR_TEXTURE_BARK_ROUGHNESS, size, 1, 1, px, bytes),
               ARBOR_STATUS_OK);
  uint8_t g_lo = 255, g_hi = 0;
  for (size_t k = 0; k < bytes; k += 4) {
    CHECK(px[k + 2] == 0 && px[k + 3] == 255, "roughness pixel %zu", k / 4);
    g_lo = px[k + 1] < g_lo ? px[k + 1] : g_lo;
    g_hi = px[k + 1] > g_hi ? px[k + 1] : g_hi;
  }
  CHECK(g_hi > g_lo + 20, "roughness %u..%u", g_lo, g_hi);
  CHECK_STATUS(arbor_species_texture_write(ARBOR_SPECIES_OAK, 4, size, 1, 1, px, bytes), ARBOR_STATUS_INVALID_ARGUMENT);
  CHECK_STATUS(arbor_species_texture_write(ARBOR_SPECIES_OAK, 1, 8, 1, 0, px, bytes), ARBOR_STATUS_INVALID_ARGUMENT);
  CHECK_STATUS(arbor_species_texture_write(ARBOR_SPECIES_OAK, 1, size, 1, 0, NULL, bytes), ARBOR_STATUS_NULL_ARGUMENT);
  free(px);
  /* A larger image on the calling thread only (threads 1: no thread of arbor's, as a host
   * under valgrind asks), the same bytes each time (the Rust tests check that any thread
   * count draws the same pixels). */
  size_t big = (size_t)256 * 256 * 4;
  uint8_t *one = malloc(big), *all = malloc(big);
  memset(one, 7, big);
  memset(all, 9, big);
  CHECK_STATUS(arbor_species_texture_write(ARBOR_SPECIES_BIRCH, ARBOR_TEXTURE_BARK_COLOR, 256, 2, 1, one, big),
               ARBOR_STATUS_OK);
  CHECK_STATUS(arbor_species_texture_write(ARBOR_SPECIES_BIRCH, ARBOR_TEXTURE_BARK_COLOR, 256, 2, 1, all, big),
               ARBOR_STATUS_OK);
  CHECK(memcmp(one, all, big) == 0, "the same pixels twice");
  free(one);
  free(all);

  /* The atlas' cells and each leaf's. */
  float rect[4];
  uint32_t cells = 0;
  CHECK_STATUS(arbor_leaf_atlas_rect(5, rect, &cells), ARBOR_STATUS_OK);
  CHECK(cells == 8 && rect[0] == 0.25f && rect[1] == 0.5f && rect[2] == 0.5f && rect[3] == 1.0f,
        "cell 5: %g %g %g %g of %u", (double)rect[0], (double)rect[1], (double)rect[2], (double)rect[3], cells);
  CHECK_STATUS(arbor_leaf_atlas_rect(0, NULL, NULL), ARBOR_STATUS_NULL_ARGUMENT);
  uint32_t seen = 0;
  for (size_t k = 0; k < 64; k++) {
    uint32_t c = arbor_leaf_cell(&lo, k);
    CHECK(c < 8, "cell %u", c);
    seen |= 1u << c;
  }
  CHECK(seen == 0xff, "every cell used: %x", seen);
  CHECK(arbor_leaf_cell(NULL, 3) == 0, "one cell by default");

  arbor_tree_free(oak);
  return check_report("species");
}
