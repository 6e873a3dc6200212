/* Every mesh option, branch ranges, levels of detail, leaves (instances and baked mesh,
 * with a prefab OBJ) and OBJ export through the C ABI. argv[1]: a scratch directory. */
#include "arbor.h"
#include "check.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

_Static_assert(sizeof(ArborLeafInstance) == 32, "ArborLeafInstance is 32 bytes");
_Static_assert(sizeof(ArborBranchRange) == 16, "ArborBranchRange is 16 bytes");

static void message_contains(const char *needle) {
  char m[512];
  arbor_last_error_message(m, sizeof m);
  CHECK(strstr(m, needle) != NULL, "message '%s' lacks '%s'", m, needle);
}

static ArborTree *preset(char name, uint32_t steps) {
  ArborHondaParams p;
  ArborTree *t = NULL;
  arbor_honda_preset((uint32_t)name, &p);
  if (steps) p.steps = steps;
  CHECK_STATUS(arbor_tree_from_honda(&p, &t), ARBOR_STATUS_OK);
  return t;
}

static int all_bytes(const void *p, size_t n, unsigned char b) {
  const unsigned char *c = (const unsigned char *)p;
  for (size_t i = 0; i < n; i++)
    if (c[i] != b) return 0;
  return 1;
}

/* Writes with `o` and checks indices and normals; returns the vertex count. */
static size_t write_and_check(const ArborTree *t, const ArborMeshOptions *o, const char *what) {
  size_t nv = 0, ni = 0;
  CHECK_STATUS(arbor_mesh_size(t, o, &nv, &ni), ARBOR_STATUS_OK);
  ArborVertex *v = malloc(nv * sizeof *v);
  uint32_t *idx = malloc(ni * sizeof *idx);
  CHECK_STATUS(arbor_mesh_write(t, o, v, nv, idx, ni), ARBOR_STATUS_OK);
  for (size_t i = 0; i < ni; i++) {
    if (idx[i] != ARBOR_RESTART_INDEX && idx[i] >= nv) {
      CHECK(0, "%s: index %zu out of range", what, i);
      break;
    }
  }
  for (size_t i = 0; i < nv; i++) {
    const float *n = v[i].normal;
    if (fabsf(sqrtf(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]) - 1.0f) > 1e-3f) {
      CHECK(0, "%s: normal %zu", what, i);
      break;
    }
  }
  free(v);
  free(idx);
  return nv;
}

static void every_mesh_option(void) {
  ArborTree *t = preset('e', 0);
  ArborMeshOptions d = arbor_mesh_options_default();
  CHECK(d.radial_segments == 8 && d.joints == ARBOR_JOINTS_MITRED && d.scale == 1.0f &&
            d.texture_scale == 1.0f && d.tip == ARBOR_TIP_OPEN,
        "defaults");
  size_t base = write_and_check(t, &d, "default");
  ArborMeshOptions o = d;
  o.joints = ARBOR_JOINTS_SEPARATE;
  CHECK(write_and_check(t, &o, "separate") == 2 * arbor_tree_branch_count(t) * 9, "separate");
  o = d;
  o.tip = ARBOR_TIP_POINT;
  o.base_cap = 1;
  o.smooth_taper = 1;
  CHECK(write_and_check(t, &o, "caps") > base, "caps add vertices");
  o = d;
  o.min_radial_segments = 3;
  o.cull_radius = 1.0f;
  CHECK(write_and_check(t, &o, "lod") < base, "lod removes vertices");
  for (uint32_t topology = 0; topology < 3; topology++) {
    o = d;
    o.topology = topology;
    o.winding = ARBOR_WINDING_CLOCKWISE;
    o.up_axis = ARBOR_UP_AXIS_Z;
    o.scale = 0.5f;
    o.texture_scale = 10.0f;
    write_and_check(t, &o, "conventions");
  }
  struct { const char *field; ArborMeshOptions o; } bad[9];
  for (int k = 0; k < 9; k++) bad[k].o = d;
  bad[0].field = "joints"; bad[0].o.joints = 2;
  bad[1].field = "tip"; bad[1].o.tip = 3;
  bad[2].field = "winding"; bad[2].o.winding = 7;
  bad[3].field = "up_axis"; bad[3].o.up_axis = 2;
  bad[4].field = "smooth_taper"; bad[4].o.smooth_taper = 2;
  bad[5].field = "cull_radius"; bad[5].o.cull_radius = NAN;
  bad[6].field = "scale"; bad[6].o.scale = -1.0f;
  bad[7].field = "texture_scale"; bad[7].o.texture_scale = INFINITY;
  bad[8].field = "min_radial_segments"; bad[8].o.min_radial_segments = 99;
  for (int k = 0; k < 9; k++) {
    size_t nv = 0, ni = 0;
    CHECK_STATUS(arbor_mesh_size(t, &bad[k].o, &nv, &ni), ARBOR_STATUS_INVALID_ARGUMENT);
    message_contains(bad[k].field);
  }
  arbor_tree_free(t);
}

static void branch_ranges(void) {
  ArborTree *t = preset('a', 4); /* 15 branches */
  size_t nb = arbor_tree_branch_count(t);
  ArborMeshOptions o = arbor_mesh_options_default();
  o.topology = ARBOR_TOPOLOGY_TRIANGLE_STRIP_DEGENERATE;
  o.tip = ARBOR_TIP_CAP;
  size_t nv = 0, ni = 0;
  arbor_mesh_size(t, &o, &nv, &ni);
  for (size_t cap = 0; cap <= nb; cap++) {
    ArborBranchRange *r = malloc((cap + 1) * sizeof *r);
    memset(r, 0x5A, (cap + 1) * sizeof *r);
    ArborStatus s = arbor_mesh_branch_ranges(t, &o, cap ? r : NULL, cap);
    if (cap < nb) {
      CHECK(s == ARBOR_STATUS_BUFFER_TOO_SMALL, "cap %zu", cap);
      CHECK(all_bytes(r, (cap + 1) * sizeof *r, 0x5A), "cap %zu wrote", cap);
    } else {
      CHECK(s == ARBOR_STATUS_OK, "exact cap");
      uint32_t v = 0, i = 0;
      for (size_t b = 0; b < nb; b++) {
        CHECK(r[b].first_vertex == v && r[b].first_index == i, "range %zu does not tile", b);
        v += r[b].vertex_count;
        i += r[b].index_count;
      }
      CHECK(v == nv && i == ni, "ranges cover %u/%u of %zu/%zu", v, i, nv, ni);
      CHECK(all_bytes(r + nb, sizeof *r, 0x5A), "wrote past");
    }
    free(r);
  }
  arbor_tree_free(t);
}

static void levels_of_detail(void) {
  ArborTree *t = preset('b', 0);
  ArborMeshOptions levels[3];
  for (int k = 0; k < 3; k++) {
    levels[k] = arbor_mesh_options_default();
    levels[k].radial_segments = 16 >> k;
    levels[k].min_radial_segments = 3;
    levels[k].cull_radius = 0.5f * (float)k;
  }
  size_t nv[3], ni[3];
  CHECK_STATUS(arbor_mesh_lod_size(t, levels, 3, nv, ni), ARBOR_STATUS_OK);
  CHECK(nv[0] > nv[1] && nv[1] > nv[2] && ni[0] > ni[1] && ni[1] > ni[2], "levels shrink");
  ArborVertex *v[3];
  uint32_t *i[3];
  size_t vcap[3], icap[3];
  for (int k = 0; k < 3; k++) {
    vcap[k] = nv[k];
    icap[k] = ni[k];
    v[k] = malloc(nv[k] * sizeof(ArborVertex));
    i[k] = malloc(ni[k] * sizeof(uint32_t));
    memset(v[k], 0x5A, nv[k] * sizeof(ArborVertex));
  }
  icap[1] = ni[1] - 1;
  CHECK_STATUS(arbor_mesh_lod_write(t, levels, 3, v, vcap, i, icap),
               ARBOR_STATUS_BUFFER_TOO_SMALL);
  message_contains("level 1");
  CHECK(all_bytes(v[0], nv[0] * sizeof(ArborVertex), 0x5A), "level 0 written on failure");
  icap[1] = ni[1];
  CHECK_STATUS(arbor_mesh_lod_write(t, levels, 3, v, vcap, i, icap), ARBOR_STATUS_OK);
  /* Each level equals the single-level writer's output. */
  for (int k = 0; k < 3; k++) {
    ArborVertex *w = malloc(nv[k] * sizeof *w);
    uint32_t *j = malloc(ni[k] * sizeof *j);
    arbor_mesh_write(t, &levels[k], w, nv[k], j, ni[k]);
    CHECK(memcmp(w, v[k], nv[k] * sizeof *w) == 0 && memcmp(j, i[k], ni[k] * sizeof *j) == 0,
          "level %d differs", k);
    free(w);
    free(j);
    free(v[k]);
    free(i[k]);
  }
  CHECK_STATUS(arbor_mesh_lod_size(t, NULL, 2, nv, ni), ARBOR_STATUS_NULL_ARGUMENT);
  CHECK_STATUS(arbor_mesh_lod_size(t, NULL, 0, NULL, NULL), ARBOR_STATUS_OK);
  arbor_tree_free(t);
}

static void leaves(const char *dir) {
  ArborTree *t = preset('g', 5); /* 31 branches, 16 tips */
  ArborLeafOptions lo = arbor_leaf_options_default();
  CHECK(lo.tips == 0 && lo.sites == 1 && lo.density == 1.0f && lo.prefab_obj_path == NULL,
        "leaf defaults");
  size_t count = 99;
  CHECK_STATUS(arbor_leaf_instance_count(t, &lo, NULL, &count), ARBOR_STATUS_OK);
  CHECK(count == 0, "no sites, no tips: %zu", count);
  lo.tips = 1;
  lo.density = 2.0f;
  lo.size = 4.0f;
  CHECK_STATUS(arbor_leaf_instance_count(t, &lo, NULL, &count), ARBOR_STATUS_OK);
  CHECK(count == 32, "%zu leaves", count);
  for (size_t cap = 0; cap <= count; cap++) {
    ArborLeafInstance *l = malloc((cap + 1) * sizeof *l);
    memset(l, 0x5A, (cap + 1) * sizeof *l);
    ArborStatus s = arbor_leaf_instances_write(t, &lo, NULL, cap ? l : NULL, cap);
    CHECK(s == (cap == count ? ARBOR_STATUS_OK : ARBOR_STATUS_BUFFER_TOO_SMALL), "cap %zu", cap);
    if (cap == count) {
      for (size_t k = 0; k < count; k++) {
        const float *q = l[k].rotation;
        float len = sqrtf(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]);
        CHECK(fabsf(len - 1.0f) < 1e-4f && l[k].scale > 3.0f && l[k].scale < 5.0f, "leaf %zu", k);
      }
      CHECK(all_bytes(l + count, sizeof *l, 0x5A), "wrote past");
    } else {
      CHECK(all_bytes(l, (cap + 1) * sizeof *l, 0x5A), "cap %zu wrote", cap);
    }
    free(l);
  }
  size_t nv = 0, ni = 0;
  CHECK_STATUS(arbor_leaf_mesh_size(t, &lo, NULL, &nv, &ni), ARBOR_STATUS_OK);
  CHECK(nv == count * 4 && ni == count * 6, "quads: %zu %zu", nv, ni);
  for (size_t vc = 0; vc <= nv; vc += (vc + 1 < nv ? nv - 1 : 1)) {
    ArborVertex *v = malloc((vc + 1) * sizeof *v);
    uint32_t *i = malloc((ni + 1) * sizeof *i);
    memset(v, 0x5A, (vc + 1) * sizeof *v);
    ArborStatus s = arbor_leaf_mesh_write(t, &lo, NULL, v, vc, i, ni);
    CHECK(s == (vc == nv ? ARBOR_STATUS_OK : ARBOR_STATUS_BUFFER_TOO_SMALL), "vc %zu", vc);
    CHECK(all_bytes(vc == nv ? (void *)(v + nv) : (void *)v,
                    (vc == nv ? 1 : vc + 1) * sizeof *v, 0x5A),
          "leaf vertices written out of place (vc %zu)", vc);
    free(v);
    free(i);
  }
  /* A prefab: two blades from an OBJ file. */
  char path[1024];
  snprintf(path, sizeof path, "%s/blades.obj", dir);
  FILE *f = fopen(path, "w");
  CHECK(f != NULL, "cannot write %s", path);
  if (f) {
    fputs("v -0.1 0 0\nv 0.1 0 0\nv 0 1 0\nv 0 0 -0.1\nv 0 0 0.1\nv 0.3 0.9 0\n"
          "f 1 2 3\nf 4 5 6\n", f);
    fclose(f);
  }
  lo.prefab_obj_path = path;
  CHECK_STATUS(arbor_leaf_mesh_size(t, &lo, NULL, &nv, &ni), ARBOR_STATUS_OK);
  CHECK(nv == count * 6 && ni == count * 6, "prefab: %zu %zu", nv, ni);
  {
    /* The same shape loaded once into a handle: the same mesh, and the file is not read
       again (it is gone before the calls). */
    ArborVertex *v1 = malloc(nv * sizeof *v1), *v2 = malloc(nv * sizeof *v2);
    uint32_t *i1 = malloc(ni * sizeof *i1), *i2 = malloc(ni * sizeof *i2);
    CHECK_STATUS(arbor_leaf_mesh_write(t, &lo, NULL, v1, nv, i1, ni), ARBOR_STATUS_OK);
    ArborLeafPrefab *prefab = NULL;
    CHECK_STATUS(arbor_leaf_prefab_load(path, NULL, &prefab), ARBOR_STATUS_OK);
    CHECK(arbor_leaf_prefab_triangle_count(prefab) == 2, "two blades");
    CHECK(arbor_leaf_prefab_triangle_count(NULL) == 0, "NULL prefab");
    CHECK_STATUS(arbor_leaf_mesh_size(t, &lo, NULL, &nv, &ni), ARBOR_STATUS_OK);
    lo.prefab = prefab;
    CHECK_STATUS(arbor_leaf_mesh_size(t, &lo, NULL, &nv, &ni), ARBOR_STATUS_INVALID_ARGUMENT);
    message_contains("prefab_obj_path");
    lo.prefab_obj_path = NULL;
    remove(path);
    size_t nv2 = 0, ni2 = 0;
    CHECK_STATUS(arbor_leaf_mesh_size(t, &lo, NULL, &nv2, &ni2), ARBOR_STATUS_OK);
    CHECK(nv2 == nv && ni2 == ni, "handle: %zu %zu", nv2, ni2);
    CHECK_STATUS(arbor_leaf_mesh_write(t, &lo, NULL, v2, nv, i2, ni), ARBOR_STATUS_OK);
    CHECK(memcmp(v1, v2, nv * sizeof *v1) == 0 && memcmp(i1, i2, ni * sizeof *i1) == 0,
          "a handle's mesh equals the file's");
    lo.prefab = NULL;
    arbor_leaf_prefab_free(prefab);
    arbor_leaf_prefab_free(NULL);
    CHECK_STATUS(arbor_leaf_prefab_load("/nonexistent/leaf.obj", NULL, &prefab), ARBOR_STATUS_IO_ERROR);
    CHECK_STATUS(arbor_leaf_prefab_load(NULL, NULL, &prefab), ARBOR_STATUS_NULL_ARGUMENT);
    free(v1);
    free(v2);
    free(i1);
    free(i2);
  }
  lo.prefab_obj_path = "/nonexistent/leaf.obj";
  CHECK_STATUS(arbor_leaf_mesh_size(t, &lo, NULL, &nv, &ni), ARBOR_STATUS_IO_ERROR);
  message_contains("/nonexistent/leaf.obj");
  lo.prefab_obj_path = NULL;
  lo.density = -1.0f;
  CHECK_STATUS(arbor_leaf_instance_count(t, &lo, NULL, &count), ARBOR_STATUS_INVALID_ARGUMENT);
  message_contains("density");
  lo.density = 1.0f;
  lo.tips = 5;
  CHECK_STATUS(arbor_leaf_instance_count(t, &lo, NULL, &count), ARBOR_STATUS_INVALID_ARGUMENT);
  message_contains("tips");
  CHECK_STATUS(arbor_leaf_instance_count(NULL, NULL, NULL, &count), ARBOR_STATUS_NULL_ARGUMENT);
  CHECK_STATUS(arbor_leaf_instance_count(t, NULL, NULL, NULL), ARBOR_STATUS_NULL_ARGUMENT);
  arbor_tree_free(t);
}

static void obj_export(const char *dir) {
  ArborTree *t = preset('c', 0);
  ArborLeafOptions lo = arbor_leaf_options_default();
  lo.tips = 1;
  char path[1024];
  snprintf(path, sizeof path, "%s/tree_c.obj", dir);
  CHECK_STATUS(arbor_export_obj(t, NULL, &lo, path), ARBOR_STATUS_OK);
  FILE *f = fopen(path, "r");
  CHECK(f != NULL, "no file at %s", path);
  if (f) {
    char line[256];
    int groups = 0, faces = 0;
    while (fgets(line, sizeof line, f)) {
      groups += line[0] == 'g';
      faces += line[0] == 'f';
    }
    fclose(f);
    CHECK(groups == 2 && faces > 510 * 16, "%d groups, %d faces", groups, faces);
  }
  CHECK_STATUS(arbor_export_obj(t, NULL, NULL, "/nonexistent/dir/tree.obj"),
               ARBOR_STATUS_IO_ERROR);
  message_contains("/nonexistent/dir/tree.obj");
  CHECK_STATUS(arbor_export_obj(t, NULL, NULL, NULL), ARBOR_STATUS_NULL_ARGUMENT);
  arbor_tree_free(t);
}

/* Compact vertices through arbor_mesh_write_bytes: 20 bytes each, the same indices as the
 * f32 mesh, and decoded (octahedral normal, v over arbor_mesh_v_scale) within the
 * documented precision; the f32 format through the same call equals arbor_mesh_write. */
static void compact_vertices(void) {
  _Static_assert(sizeof(ArborVertexCompact) == 20, "ArborVertexCompact is 20 bytes");
  CHECK(arbor_struct_size(ARBOR_STRUCT_ID_VERTEX_COMPACT) == 20, "struct size");
  ArborTree *t = preset('g', 0);
  ArborMeshOptions o = arbor_mesh_options_default();
  o.topology = ARBOR_TOPOLOGY_TRIANGLE_STRIP_RESTART;
  size_t nv = 0, ni = 0;
  CHECK_STATUS(arbor_mesh_size(t, &o, &nv, &ni), ARBOR_STATUS_OK);
  ArborVertex *v = malloc(nv * sizeof *v);
  ArborVertex *vb = malloc(nv * sizeof *vb);
  uint32_t *idx = malloc(ni * sizeof *idx);
  uint32_t *idx_c = malloc(ni * sizeof *idx_c);
  CHECK_STATUS(arbor_mesh_write(t, &o, v, nv, idx, ni), ARBOR_STATUS_OK);
  CHECK_STATUS(arbor_mesh_write_bytes(t, &o, vb, nv * sizeof *vb, idx_c, ni), ARBOR_STATUS_OK);
  CHECK(memcmp(v, vb, nv * sizeof *v) == 0, "f32 through write_bytes equals arbor_mesh_write");

  o.vertex_format = ARBOR_VERTEX_FORMAT_COMPACT;
  size_t nv_c = 0, ni_c = 0;
  CHECK_STATUS(arbor_mesh_size(t, &o, &nv_c, &ni_c), ARBOR_STATUS_OK);
  CHECK(nv_c == nv && ni_c == ni, "the same counts");
  ArborVertexCompact *c = malloc(nv * sizeof *c);
  /* Too few bytes: refused, nothing written. */
  memset(c, 0xAB, nv * sizeof *c);
  CHECK_STATUS(arbor_mesh_write_bytes(t, &o, c, nv * sizeof *c - 1, idx_c, ni),
               ARBOR_STATUS_BUFFER_TOO_SMALL);
  message_contains("vertex_bytes");
  CHECK(all_bytes(c, nv * sizeof *c, 0xAB), "nothing written");
  /* Misaligned: refused. */
  CHECK_STATUS(arbor_mesh_write_bytes(t, &o, (char *)vb + 2, nv * sizeof *c, idx_c, ni),
               ARBOR_STATUS_INVALID_ARGUMENT);
  message_contains("aligned");
  /* The f32 call with compact options names the field. */
  CHECK_STATUS(arbor_mesh_write(t, &o, vb, nv, idx_c, ni), ARBOR_STATUS_INVALID_ARGUMENT);
  message_contains("vertex_format");
  CHECK_STATUS(arbor_mesh_write_bytes(t, &o, c, nv * sizeof *c, idx_c, ni), ARBOR_STATUS_OK);
  CHECK(memcmp(idx, idx_c, ni * sizeof *idx) == 0, "the same indices");
  float v_scale = 0.0f;
  CHECK_STATUS(arbor_mesh_v_scale(t, &o, &v_scale), ARBOR_STATUS_OK);
  float v_max = 0.0f;
  for (size_t i = 0; i < nv; i++) v_max = v[i].uv[1] > v_max ? v[i].uv[1] : v_max;
  CHECK(v_scale >= v_max && v_scale < 2.0f * (v_max > 1.0f ? v_max : 1.0f), "v_scale %g", v_scale);
  double worst_n = 0.0, worst_v = 0.0;
  for (size_t i = 0; i < nv; i++) {
    float x = c[i].normal[0] / 32767.0f, y = c[i].normal[1] / 32767.0f;
    x = x < -1.0f ? -1.0f : x;
    y = y < -1.0f ? -1.0f : y;
    float z = 1.0f - fabsf(x) - fabsf(y);
    if (z < 0.0f) {
      float ox = x;
      x = copysignf(1.0f - fabsf(y), x);
      y = copysignf(1.0f - fabsf(ox), y);
    }
    float len = sqrtf(x * x + y * y + z * z);
    const float *n = v[i].normal;
    double dot = (n[0] * x + n[1] * y + n[2] * z) / len;
    double cx = (n[1] * z - n[2] * y) / len, cy = (n[2] * x - n[0] * z) / len,
           cz = (n[0] * y - n[1] * x) / len;
    double deg = atan2(sqrt(cx * cx + cy * cy + cz * cz), dot) * 57.29577951308232;
    worst_n = deg > worst_n ? deg : worst_n;
    double dv = fabs(c[i].uv[1] / 65535.0 * v_scale - v[i].uv[1]) / v_max;
    worst_v = dv > worst_v ? dv : worst_v;
    CHECK(memcmp(c[i].position, v[i].position, sizeof c[i].position) == 0, "position %zu", i);
  }
  CHECK(worst_n < 0.1, "normal error %g degrees", worst_n);
  /* The animation stream in both forms through one call: 16 and 8 bytes a vertex. */
  ArborAnimationVertex *anim = malloc(nv * sizeof *anim);
  ArborAnimationVertexCompact *anim_c = malloc(nv * sizeof *anim_c);
  ArborMeshOptions o32 = o;
  o32.vertex_format = ARBOR_VERTEX_FORMAT_F32;
  CHECK_STATUS(arbor_mesh_animation_write_bytes(t, &o32, anim, nv * sizeof *anim), ARBOR_STATUS_OK);
  CHECK_STATUS(arbor_mesh_animation_write_bytes(t, &o, anim_c, nv * sizeof *anim_c - 1),
               ARBOR_STATUS_BUFFER_TOO_SMALL);
  CHECK_STATUS(arbor_mesh_animation_write_bytes(t, &o, anim_c, nv * sizeof *anim_c), ARBOR_STATUS_OK);
  CHECK(sizeof(ArborAnimationVertexCompact) == 8, "8 bytes");
  for (size_t i = 0; i < nv; i++) {
    if (fabs(anim_c[i].growth / 65535.0 - anim[i].growth) > 1e-4 || anim_c[i].order != (uint16_t)anim[i].order ||
        fabs(anim_c[i].along / 65535.0 - anim[i].along) > 1e-4 ||
        fabs(anim_c[i].phase / 65535.0 - anim[i].phase) > 1e-4) {
      CHECK(0, "animation %zu", i);
      break;
    }
  }
  free(anim_c);
  free(anim);
  /* An edit rewritten in place in the compact buffer equals a fresh compact write. */
  size_t nb = arbor_tree_branch_count(t);
  ArborCurve *curves = malloc(nb * sizeof *curves);
  CHECK_STATUS(arbor_tree_copy_curves(t, curves, nb), ARBOR_STATUS_OK);
  ArborCurve e = curves[nb - 1];
  e.p2[0] += 0.3f * (e.p3[1] - e.p0[1]);
  e.p3[2] += 0.2f * (e.p3[1] - e.p0[1]);
  CHECK_STATUS(arbor_tree_set_curve(t, nb - 1, &e), ARBOR_STATUS_OK);
  CHECK_STATUS(arbor_mesh_rewrite_branch_bytes(t, &o, nb - 1, c, nv * sizeof *c - 2, idx_c, ni),
               ARBOR_STATUS_INVALID_ARGUMENT);
  CHECK_STATUS(arbor_mesh_rewrite_branch_bytes(t, &o, nb - 1, c, nv * sizeof *c, idx_c, ni), ARBOR_STATUS_OK);
  ArborVertexCompact *fresh = malloc(nv * sizeof *fresh);
  CHECK_STATUS(arbor_mesh_write_bytes(t, &o, fresh, nv * sizeof *fresh, idx, ni), ARBOR_STATUS_OK);
  CHECK(memcmp(fresh, c, nv * sizeof *c) == 0, "a compact rewrite equals a fresh compact write");
  free(fresh);
  free(curves);
  CHECK(worst_v < 1.0 / 4096.0, "v error %g of the range", worst_v);
  free(c);
  free(idx_c);
  free(idx);
  free(vb);
  free(v);
  arbor_tree_free(t);
}

int main(int argc, char **argv) {
  const char *dir = argc > 1 ? argv[1] : ".";
  every_mesh_option();
  compact_vertices();
  branch_ranges();
  levels_of_detail();
  leaves(dir);
  obj_export(dir);
  return check_report("mesh_leaves");
}
