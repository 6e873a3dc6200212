/*
 * arbor gallery: the nine trees of Prusinkiewicz, Hammel, Hanan & Mech (1996) in a 3 x 3
 * grid, grown and meshed by arbor through include/arbor.h and uploaded straight into
 * mapped OpenGL buffers.
 *
 *   gallery [--tree a..i] [--size WxH] [--list] [--leaves] [--depth K] [--forest]
 *           [--smooth] [--compact] [--world CYCLES [--world-env 0|1] [--world-species -1|N|NAME]]
 *           [--lsystem FILE.l|FOLDER [--next K]] [--species oak|maple|birch|willow|poplar|pine|spruce|shrub]
 *           [--screenshot FILE.png|FILE.ppm --frames N] [--species NAME --lod-check [--screenshot F]]
 *           [--species NAME --impostors]
 *
 * Keys: mouse drag orbits, wheel zooms; 1-9 one tree, 0 the grid; + / - derivation steps;
 * [ / ] radial segments; T / Shift+T thickness; L / Shift+L length; V leaves; G growth
 * animation (a moving threshold on arbor's per-vertex growth times); N wind (sway from
 * arbor's per-vertex order, position along the branch and phase); W wireframe; S strips
 * <-> triangle list; C smooth (C1 curves swept with 3 inner rings) (editing branches:
 * examples/editor; tree bodies without triangles: examples/raymarch);
 * F forest (one merged mesh of 25 varied trees); I with --species, its impostor on a
 * field of 400 quads (the reference shader); O a self-organized
 * world of seven trees sharing light (Space: one more growth cycle, R reset, E shadow /
 * space colonization, K species: a mix, then each preset); P screenshot; Esc.
 */
#define GLFW_INCLUDE_NONE
/* scandir, alphasort, strdup (POSIX) under -std=c11. */
#define _DEFAULT_SOURCE
#include <GLFW/glfw3.h>
#include <GL/glcorearb.h>
#include <png.h>

#include "arbor.h"

#include <dirent.h>
#include <errno.h>
#include <sys/stat.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "../common/glapp.h"
#include "lodcheck.h"

/* ---- shaders ---- */
static const char *vs_src =
    "#version 330 core\n"
    "layout(location = 0) in vec3 a_pos;\n"
    "layout(location = 1) in vec3 a_normal;\n"
    "layout(location = 2) in vec2 a_uv;\n"
    "layout(location = 3) in vec3 i_pos;\n"
    "layout(location = 4) in vec4 i_rot;\n"
    "layout(location = 5) in float i_scale;\n"
    "layout(location = 6) in vec4 a_anim;\n" /* growth, order, along, phase (arbor) */
    "layout(location = 7) in vec2 a_oct;\n"  /* compact vertices: octahedral normal */
    "layout(location = 8) in float i_cell;\n" /* a leaf's atlas cell (arbor_leaf_cell) */
    "flat out float v_cell;\n"
    "uniform mat4 u_view_proj;\n"
    "uniform float u_time;\n"
    "uniform float u_wind;\n"
    "out float v_growth;\n"
    "uniform mat4 u_model;\n"
    "uniform int u_mode;\n"
    "uniform float u_v_scale;\n" /* > 0: compact vertices, v stored over it */
    "out vec3 v_normal;\n"
    "out vec2 v_uv;\n"
    "vec3 rotate(vec4 q, vec3 v) { return v + 2.0 * cross(q.xyz, cross(q.xyz, v) + q.w * v); }\n"
    "vec3 octahedral(vec2 e) {\n"
    "  vec3 n = vec3(e, 1.0 - abs(e.x) - abs(e.y));\n"
    "  if (n.z < 0.0) n.xy = (1.0 - abs(n.yx)) * vec2(n.x >= 0.0 ? 1.0 : -1.0, n.y >= 0.0 ? 1.0 : -1.0);\n"
    "  return normalize(n);\n"
    "}\n"
    "void main() {\n"
    "  vec3 p = a_pos; vec3 n = a_normal; vec2 uv = a_uv;\n"
    "  vec4 anim = a_anim;\n"
    "  if (u_mode == 0 && u_v_scale > 0.0) { n = octahedral(a_oct); uv.y *= u_v_scale; anim.y *= 65535.0; }\n"
    "  if (u_mode == 2) { p = i_pos + rotate(i_rot, a_pos * i_scale); n = rotate(i_rot, a_normal); }\n"
    "  if (u_mode == 0 && u_wind > 0.0) {\n"
    "    float sway = sin(u_time * 1.7 + anim.w * 6.2832) * anim.z * (0.4 + 0.6 * anim.y);\n"
    "    p += vec3(sway, 0.0, 0.5 * sway) * u_wind;\n"
    "  }\n"
    "  v_growth = u_mode == 0 ? anim.x : 0.0;\n"
    "  vec4 world = u_model * vec4(p, 1.0);\n"
    "  v_normal = mat3(u_model) * n;\n"
    "  v_uv = uv;\n"
    "  v_cell = i_cell;\n"
    "  gl_Position = u_view_proj * world;\n"
    "}\n";

static const char *fs_src =
    "#version 330 core\n"
    "in vec3 v_normal;\n"
    "in vec2 v_uv;\n"
    "in float v_growth;\n"
    "flat in float v_cell;\n"
    ATLAS_GLSL
    "uniform sampler2D u_bark;\n"
    "uniform int u_bark_textured;\n" /* a named species: its bark texture, one tile a unit of uv */
    "uniform int u_mode;\n"
    "uniform float u_growth;\n"
    "uniform vec3 u_light;\n"
    "out vec4 color;\n"
    "void main() {\n"
    "  if (v_growth > u_growth) discard;\n"
    "  vec3 n = normalize(v_normal);\n"
    "  if (u_mode >= 2 && !gl_FrontFacing) n = -n;\n"
    "  float diffuse = max(dot(n, u_light), 0.0);\n"
    "  vec3 base;\n"
    "  if (u_mode == 0 && u_bark_textured == 1) {\n"
    "    base = texture(u_bark, v_uv).rgb * 1.25;\n"
    "  } else if (u_mode == 0) {\n"
    "    float grain = 0.5 + 0.5 * sin(v_uv.x * 37.7 + sin(v_uv.y * 3.1) * 2.0);\n"
    "    float rings = 0.5 + 0.5 * sin(v_uv.y * 1.7);\n"
    "    base = mix(vec3(0.30, 0.19, 0.11), vec3(0.52, 0.36, 0.22), 0.6 * grain + 0.4 * rings);\n"
    "  } else if (u_mode == 1) {\n"
    "    base = vec3(0.36, 0.47, 0.28);\n"
    "  } else if (u_mode == 3) {\n"
    "    base = vec3(0.78, 0.30, 0.42);\n"
    "  } else {\n"
    "    vec4 leaf = atlas(v_cell, v_uv);\n" /* the oak's sprays, alpha-cut */
    "    if (leaf.a < 0.5) discard;\n"
    "    base = leaf.rgb * 1.3;\n"
    "  }\n"
    "  color = vec4(base * (0.35 + 0.65 * diffuse), 1.0);\n"
    "}\n";

/* ---- trees ---- */
typedef struct {
  char name;
  ArborHondaParams params;
  GLuint vao, vbo, ebo, anim_vbo;
  size_t vertices, indices, triangles;
  GLuint leaf_vao, leaf_instances_vbo, leaf_cells_vbo;
  size_t leaves;
  float lo[3], hi[3];
  double grow_ms, upload_ms;
  /* Compact vertices (--compact): the v_scale of the uploaded mesh; 0 for f32 vertices. */
  float v_scale;
} Tree;

typedef struct {
  int width, height, single; /* single: -1 grid, else tree index */
  int strips, leaves, wireframe, forest, growth, growth_step;
  unsigned radial_segments;
  float thickness, length;
  int steps_delta;
  float yaw, pitch, zoom;
  double drag_x, drag_y;
  int dragging, dirty, screenshot_requested, wind, threshold_growth;
  double growth_clock;
  /* Self-organized world mode: environment (0 shadow, 1 colonization), species (-1: a mix),
     cycles grown so far. */
  int world_mode, world_env, world_species, world_cycles, world_trees, world_forest;
  /* Smooth mode: every tree's branches bent into C1 curves and swept with inner rings. */
  int smooth;
  /* Compact vertices: bark uploaded as ArborVertexCompact (20 bytes) through
     arbor_mesh_write_bytes, decoded in the vertex shader. */
  int compact;
  /* Headless screenshots: the wind's clock stands still at 1 s. */
  int fixed_time;
  /* With --species: the species' impostor on a field of 400 quads (the reference shader,
     examples/common/impostor.glsl), baked when first shown from the level
     arbor_lods_impostor_level() names. */
  int impostors;
  /* L-system mode: a cpfg file read as cpfg reads it (preprocessor, view file), drawn with
     its polygons, spheres, discs and leaves; Tab / Shift+Tab step through the .l files of
     its folder (or of the folder given, searched recursively). */
  int lsys_mode, lsys_index, lsys_count;
  char **lsys_files;
  /* --species NAME: a named species (ARBOR_SPECIES_OAK ...) grown alone, its bark and
     leaves textured by arbor; -1: the nine 1996 trees. */
  int species;
} State;

static Tree trees[9];
static State st;
static GLuint program, ground_vao, leaf_quad_vao, leaf_quad_vbo, leaf_quad_ebo;
static GLint u_view_proj, u_model, u_mode, u_light, u_time, u_wind, u_growth, u_v_scale;
static GLuint forest_vao, forest_vbo, forest_ebo;
static size_t forest_indices;
static ArborWorld *world;
static GLuint world_vao, world_vbo, world_ebo;
static size_t world_indices;
static GLuint lsys_vao, lsys_vbo, lsys_ebo, organ_vao, organ_vbo, organ_ebo;
static size_t lsys_indices, organ_indices;
/* The model matrix that frames the L-system's geometry: translate, then uniform scale. */
static float lsys_center[3], lsys_scale = 1;

static ArborMeshOptions mesh_options(void) {
  ArborMeshOptions o = arbor_mesh_options_default();
  o.radial_segments = st.radial_segments;
  o.topology = st.strips ? ARBOR_TOPOLOGY_TRIANGLE_STRIP_RESTART : ARBOR_TOPOLOGY_TRIANGLE_LIST;
  o.smooth_taper = 1;
  o.tip = ARBOR_TIP_POINT;
  o.texture_scale = 6.0f;
  o.curve_rings = st.smooth ? 3u : 0u;
  return o;
}

/* Uploads `tree`'s leaf instances (with `lo`, in the conventions of `o`) to t's leaf VAO:
 * the leaf quad, one ArborLeafInstance and one atlas cell per instance. */
static void upload_leaves(Tree *t, ArborTree *tree, const ArborLeafOptions *lop, const ArborMeshOptions *o) {
  ArborLeafOptions lo = *lop;
  size_t nl = 0;
  if (arbor_leaf_instance_count(tree, &lo, o, &nl) != ARBOR_STATUS_OK) fail("leaves");
  ArborLeafInstance *leaves = malloc((nl ? nl : 1) * sizeof *leaves);
  if (arbor_leaf_instances_write(tree, &lo, o, leaves, nl) != ARBOR_STATUS_OK) fail("leaves");
  if (!t->leaf_vao) {
    p_glGenVertexArrays(1, &t->leaf_vao);
    p_glGenBuffers(1, &t->leaf_instances_vbo);
  }
  p_glBindVertexArray(t->leaf_vao);
  p_glBindBuffer(GL_ARRAY_BUFFER, leaf_quad_vbo);
  p_glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, leaf_quad_ebo);
  vertex_layout();
  p_glBindBuffer(GL_ARRAY_BUFFER, t->leaf_instances_vbo);
  p_glBufferData(GL_ARRAY_BUFFER, (GLsizeiptr)(nl * sizeof *leaves), leaves, GL_STATIC_DRAW);
  p_glVertexAttribPointer(3, 3, GL_FLOAT, GL_FALSE, sizeof *leaves, (void *)offsetof(ArborLeafInstance, position));
  p_glVertexAttribPointer(4, 4, GL_FLOAT, GL_FALSE, sizeof *leaves, (void *)offsetof(ArborLeafInstance, rotation));
  p_glVertexAttribPointer(5, 1, GL_FLOAT, GL_FALSE, sizeof *leaves, (void *)offsetof(ArborLeafInstance, scale));
  for (GLuint k = 3; k < 6; k++) {
    p_glEnableVertexAttribArray(k);
    p_glVertexAttribDivisor(k, 1);
  }
  /* Each leaf's atlas cell, as arbor's baked leaves pick it. */
  if (!t->leaf_cells_vbo) p_glGenBuffers(1, &t->leaf_cells_vbo);
  float *cells = leaf_cells(&lo, nl);
  p_glBindBuffer(GL_ARRAY_BUFFER, t->leaf_cells_vbo);
  p_glBufferData(GL_ARRAY_BUFFER, (GLsizeiptr)((nl ? nl : 1) * sizeof *cells), cells, GL_STATIC_DRAW);
  p_glVertexAttribPointer(8, 1, GL_FLOAT, GL_FALSE, sizeof *cells, (void *)0);
  p_glEnableVertexAttribArray(8);
  p_glVertexAttribDivisor(8, 1);
  free(cells);
  t->leaves = nl;
  free(leaves);
  p_glBindVertexArray(0);
}

/* Grows tree t with the current settings and uploads it: size, map, write, unmap. */
static void build_tree(Tree *t) {
  double t0 = now_ms();
  ArborHondaParams p = t->params;
  p.trunk_width *= st.thickness;
  p.trunk_length *= st.length;
  p.min_length *= st.length; /* scale min with the trunk, or the shape changes */
  int steps = (int)p.steps + st.steps_delta;
  if (st.growth) steps = st.growth_step;
  p.steps = (uint32_t)(steps < 0 ? 0 : steps);
  ArborTree *tree = NULL;
  if (arbor_tree_from_honda(&p, &tree) != ARBOR_STATUS_OK) fail("arbor_tree_from_honda");
  if (st.smooth && arbor_tree_smooth(tree, 1.0f) != ARBOR_STATUS_OK) fail("arbor_tree_smooth");
  double t1 = now_ms();

  /* Frame the grown tree, so the growth animation does not zoom. */
  ArborTree *framed = tree;
  if (st.growth) {
    ArborHondaParams full = p;
    int full_steps = (int)t->params.steps + st.steps_delta;
    full.steps = (uint32_t)(full_steps < 0 ? 0 : full_steps);
    if (arbor_tree_from_honda(&full, &framed) != ARBOR_STATUS_OK) fail("arbor_tree_from_honda");
  }
  size_t nb = arbor_tree_branch_count(framed);
  ArborBranch *b = malloc((nb ? nb : 1) * sizeof *b);
  arbor_tree_copy_branches(framed, b, nb);
  if (framed != tree) arbor_tree_free(framed);
  for (int k = 0; k < 3; k++) {
    t->lo[k] = 1e30f;
    t->hi[k] = -1e30f;
  }
  for (size_t i = 0; i < nb; i++)
    for (int k = 0; k < 3; k++) {
      float a = b[i].start[k], e = b[i].end[k];
      t->lo[k] = fminf(t->lo[k], fminf(a, e));
      t->hi[k] = fmaxf(t->hi[k], fmaxf(a, e));
    }
  if (nb == 0)
    for (int k = 0; k < 3; k++) t->lo[k] = t->hi[k] = 0;
  free(b);

  ArborMeshOptions o = mesh_options();
  size_t nv = 0, ni = 0;
  if (arbor_mesh_size(tree, &o, &nv, &ni) != ARBOR_STATUS_OK) fail("arbor_mesh_size");
  if (!t->vao) {
    p_glGenVertexArrays(1, &t->vao);
    p_glGenBuffers(1, &t->vbo);
    p_glGenBuffers(1, &t->ebo);
  }
  p_glBindVertexArray(t->vao);
  p_glBindBuffer(GL_ARRAY_BUFFER, t->vbo);
  p_glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, t->ebo);
  ArborMeshOptions upload = o;
  if (st.compact) upload.vertex_format = ARBOR_VERTEX_FORMAT_COMPACT;
  size_t stride = st.compact ? sizeof(ArborVertexCompact) : sizeof(ArborVertex);
  p_glBufferData(GL_ARRAY_BUFFER, (GLsizeiptr)(nv * stride), NULL, GL_STATIC_DRAW);
  p_glBufferData(GL_ELEMENT_ARRAY_BUFFER, (GLsizeiptr)(ni * sizeof(uint32_t)), NULL, GL_STATIC_DRAW);
  if (nv > 0 && ni > 0) {
    /* arbor writes straight into the GPU buffers. */
    GLbitfield access = GL_MAP_WRITE_BIT | GL_MAP_INVALIDATE_BUFFER_BIT;
    void *vmem = p_glMapBufferRange(GL_ARRAY_BUFFER, 0, (GLsizeiptr)(nv * stride), access);
    void *imem = p_glMapBufferRange(GL_ELEMENT_ARRAY_BUFFER, 0, (GLsizeiptr)(ni * sizeof(uint32_t)), access);
    if (!vmem || !imem) {
      fprintf(stderr, "gallery: glMapBufferRange failed\n");
      exit(1);
    }
    if (arbor_mesh_write_bytes(tree, &upload, vmem, nv * stride, imem, ni) != ARBOR_STATUS_OK)
      fail("arbor_mesh_write_bytes");
    p_glUnmapBuffer(GL_ELEMENT_ARRAY_BUFFER);
    p_glUnmapBuffer(GL_ARRAY_BUFFER);
  }
  t->v_scale = 0.0f;
  if (st.compact) {
    if (arbor_mesh_v_scale(tree, &upload, &t->v_scale) != ARBOR_STATUS_OK) fail("arbor_mesh_v_scale");
    GLsizei s20 = (GLsizei)sizeof(ArborVertexCompact);
    p_glVertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, s20, (void *)offsetof(ArborVertexCompact, position));
    p_glVertexAttribPointer(7, 2, GL_SHORT, GL_TRUE, s20, (void *)offsetof(ArborVertexCompact, normal));
    p_glVertexAttribPointer(2, 2, GL_UNSIGNED_SHORT, GL_TRUE, s20, (void *)offsetof(ArborVertexCompact, uv));
    p_glEnableVertexAttribArray(0);
    p_glDisableVertexAttribArray(1);
    p_glEnableVertexAttribArray(2);
    p_glEnableVertexAttribArray(7);
  } else {
    vertex_layout();
  }
  /* The animation stream (growth, order, along, phase) as a second vertex buffer. */
  if (!t->anim_vbo) p_glGenBuffers(1, &t->anim_vbo);
  /* Compact: 8-byte records (growth, order, along, phase as uint16), read normalised; the
     shader scales order back. */
  size_t anim_size = st.compact ? sizeof(ArborAnimationVertexCompact) : sizeof(ArborAnimationVertex);
  void *anim = malloc((nv ? nv : 1) * anim_size);
  if (arbor_mesh_animation_write_bytes(tree, &upload, anim, nv * anim_size) != ARBOR_STATUS_OK)
    fail("arbor_mesh_animation_write_bytes");
  p_glBindBuffer(GL_ARRAY_BUFFER, t->anim_vbo);
  p_glBufferData(GL_ARRAY_BUFFER, (GLsizeiptr)(nv * anim_size), anim, GL_STATIC_DRAW);
  if (st.compact)
    p_glVertexAttribPointer(6, 4, GL_UNSIGNED_SHORT, GL_TRUE, (GLsizei)anim_size, (void *)0);
  else
    p_glVertexAttribPointer(6, 4, GL_FLOAT, GL_FALSE, (GLsizei)anim_size, (void *)0);
  p_glEnableVertexAttribArray(6);
  free(anim);
  t->vertices = nv;
  t->indices = ni;
  t->triangles = st.strips ? 0 : ni / 3;
  if (st.strips) {
    ArborMeshOptions list = o;
    list.topology = ARBOR_TOPOLOGY_TRIANGLE_LIST;
    size_t lv, li;
    arbor_mesh_size(tree, &list, &lv, &li);
    t->triangles = li / 3;
  }

  /* Leaf instances for glDrawElementsInstanced. */
  ArborLeafOptions lo = arbor_leaf_options_default();
  lo.tips = 1;
  lo.min_depth = p.steps > 3 ? p.steps - 2 : 0;
  lo.density = 2.0f;
  lo.size = 9.0f * st.length;
  lo.atlas_columns = 4; /* the species atlas' grid (arbor_leaf_atlas_rect) */
  lo.atlas_rows = 2;
  upload_leaves(t, tree, &lo, &o);
  p_glBindVertexArray(0);
  arbor_tree_free(tree);
  double t2 = now_ms();
  t->grow_ms = t1 - t0;
  t->upload_ms = t2 - t1;
}

/* --species: a named species grown by arbor (its twigs baked in), drawn as its own
 * options say (metres, even bark texels), bark and leaf instances textured by arbor's
 * images; into trees[0]. */
static void build_species(void) {
  Tree *t = &trees[0];
  double t0 = now_ms();
  ArborTree *tree = NULL;
  if (arbor_tree_from_species((uint32_t)st.species, 1, &tree) != ARBOR_STATUS_OK) fail("arbor_tree_from_species");
  double t1 = now_ms();
  ArborMeshOptions o = arbor_mesh_options_default();
  o.topology = ARBOR_TOPOLOGY_TRIANGLE_LIST;
  ArborLeafOptions lo = arbor_leaf_options_default();
  if (arbor_species_options((uint32_t)st.species, tree, &o, &lo) != ARBOR_STATUS_OK) fail("arbor_species_options");
  size_t nv = 0, ni = 0;
  if (arbor_mesh_size(tree, &o, &nv, &ni) != ARBOR_STATUS_OK) fail("arbor_mesh_size");
  ArborVertex *v = malloc((nv ? nv : 1) * sizeof *v);
  uint32_t *ix = malloc((ni ? ni : 1) * sizeof *ix);
  if (arbor_mesh_write(tree, &o, v, nv, ix, ni) != ARBOR_STATUS_OK) fail("arbor_mesh_write");
  for (int k = 0; k < 3; k++) {
    t->lo[k] = 1e30f;
    t->hi[k] = -1e30f;
  }
  for (size_t i = 0; i < nv; i++)
    for (int k = 0; k < 3; k++) {
      t->lo[k] = fminf(t->lo[k], v[i].position[k]);
      t->hi[k] = fmaxf(t->hi[k], v[i].position[k]);
    }
  t->vao = vertex_array(v, nv, ix, ni, NULL, NULL);
  t->vertices = nv;
  t->indices = ni;
  t->triangles = ni / 3;
  free(v);
  free(ix);
  upload_leaves(t, tree, &lo, &o);
  arbor_tree_free(tree);
  t->grow_ms = t1 - t0;
  t->upload_ms = now_ms() - t1;
  printf("species %d: %zu vertices, %zu triangles, %zu leaf cards; %.1f ms to grow, %.1f ms to mesh and upload\n",
         st.species, t->vertices, t->triangles, t->leaves, t->grow_ms, t->upload_ms);
}

/* The forest: 25 trees of the nine models with seeded variation, placed on a jittered
 * grid and merged into one mesh by arbor_forest_mesh_create. */
static void build_forest(float spacing) {
  ArborForestTree trees[25];
  memset(trees, 0, sizeof trees);
  unsigned seed = 12345u;
  for (int k = 0; k < 25; k++) {
    seed = seed * 1103515245u + 12345u;
    float jx = (float)((seed >> 16) & 1023) / 1023.0f - 0.5f;
    seed = seed * 1103515245u + 12345u;
    float jz = (float)((seed >> 16) & 1023) / 1023.0f - 0.5f;
    arbor_honda_preset((uint32_t)('a' + (k * 7 + 3) % 9), &trees[k].params);
    trees[k].seed = (uint64_t)k + 1;
    trees[k].position[0] = ((float)(k % 5) - 2 + jx * 0.6f) * spacing;
    trees[k].position[2] = ((float)(k / 5) - 2 + jz * 0.6f) * spacing;
    trees[k].rotation = (float)((seed >> 8) % 360);
    trees[k].scale = 0.45f + 0.3f * (float)((seed >> 4) & 255) / 255.0f;
  }
  ArborMeshOptions o = mesh_options();
  ArborMesh *m = NULL;
  double t0 = now_ms();
  if (arbor_forest_mesh_create(trees, 25, &o, &m) != ARBOR_STATUS_OK) fail("arbor_forest_mesh_create");
  size_t nv = 0, ni = 0;
  const ArborVertex *v = arbor_mesh_vertices(m, &nv);
  const uint32_t *i = arbor_mesh_indices(m, &ni);
  if (!forest_vao) {
    p_glGenVertexArrays(1, &forest_vao);
    p_glGenBuffers(1, &forest_vbo);
    p_glGenBuffers(1, &forest_ebo);
  }
  p_glBindVertexArray(forest_vao);
  p_glBindBuffer(GL_ARRAY_BUFFER, forest_vbo);
  p_glBufferData(GL_ARRAY_BUFFER, (GLsizeiptr)(nv * sizeof *v), v, GL_STATIC_DRAW);
  p_glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, forest_ebo);
  p_glBufferData(GL_ELEMENT_ARRAY_BUFFER, (GLsizeiptr)(ni * sizeof *i), i, GL_STATIC_DRAW);
  vertex_layout();
  p_glBindVertexArray(0);
  forest_indices = ni;
  printf("forest: 25 trees, %zu vertices, %zu indices, %.2f ms to grow, place and merge\n", nv, ni,
         now_ms() - t0);
  arbor_mesh_free(m);
}

/* The self-organized world: seven trees planted in a 12 x 10 x 12 box, sharing one
 * environment; st.world_cycles cycles are grown (stepping on from the current world when
 * it has fewer), every tree snapshotted and meshed, and the meshes concatenated into one
 * triangle list for one draw call. */
/* How many species arbor names (arbor_species_name() is NULL past the last). */
static uint32_t species_count(void) {
  uint32_t n = 0;
  while (arbor_species_name(n) != NULL) n++;
  return n;
}

/* The 100-tree forest of the growth benchmark: decurrent trees 5 apart in a 60 x 20 x 60
 * box, dropping seeds from 20 cycles on. */
static void plant_forest(void) {
  ArborWorldOptions o = arbor_world_options_default();
  o.min[0] = -30; o.min[1] = 0; o.min[2] = -30;
  o.max[0] = 30; o.max[1] = 20; o.max[2] = 30;
  if (arbor_world_create(&o, &world) != ARBOR_STATUS_OK) fail("arbor_world_create");
  ArborGrowthParams p;
  if (arbor_growth_params_preset(ARBOR_SPECIES_DECURRENT, &p, sizeof p) != ARBOR_STATUS_OK) fail("preset");
  p.seed_age = 20;
  for (int i = 0; i < 10; i++)
    for (int j = 0; j < 10; j++) {
      float pos[3] = {i * 5.0f - 22.5f, 0, j * 5.0f - 22.5f};
      if (arbor_world_plant(world, &p, pos, (uint64_t)(i * 10 + j), NULL) != ARBOR_STATUS_OK) fail("plant");
    }
}

static void reset_world(void) {
  arbor_world_free(world);
  world = NULL;
  if (st.world_forest) {
    plant_forest();
    return;
  }
  ArborWorldOptions o = arbor_world_options_default();
  o.environment = (uint32_t)st.world_env;
  o.min[0] = -6; o.min[1] = 0; o.min[2] = -6;
  o.max[0] = 6; o.max[1] = 10; o.max[2] = 6;
  o.seed = 7;
  if (arbor_world_create(&o, &world) != ARBOR_STATUS_OK) fail("arbor_world_create");
  static const float at[7][2] = {{0, 0}, {2.6f, 0.4f}, {-2.4f, 1.1f}, {0.9f, 2.5f},
                                 {-1.1f, -2.6f}, {2.2f, -2.2f}, {-2.7f, -1.4f}};
  for (int k = 0; k < st.world_trees; k++) {
    ArborGrowthParams p;
    uint32_t species = st.world_species >= 0 ? (uint32_t)st.world_species : (uint32_t)k % species_count();
    if (arbor_growth_params_preset(species, &p, sizeof p) != ARBOR_STATUS_OK) fail("preset");
    float pos[3] = {at[k][0], 0, at[k][1]};
    if (arbor_world_plant(world, &p, pos, (uint64_t)k + 1, NULL) != ARBOR_STATUS_OK) fail("plant");
  }
}

static int world_grown;
/* The world's meshes' bounds, to frame them. */
static float world_lo[3], world_hi[3];

static void build_world(void) {
  double t0 = now_ms();
  if (!world || st.world_cycles < world_grown) {
    reset_world();
    world_grown = 0;
  }
  if (st.world_cycles > world_grown) {
    if (arbor_world_step(world, (uint32_t)(st.world_cycles - world_grown)) != ARBOR_STATUS_OK)
      fail("arbor_world_step");
    world_grown = st.world_cycles;
  }
  double grow_ms = now_ms() - t0;
  ArborMeshOptions o = mesh_options();
  o.topology = ARBOR_TOPOLOGY_TRIANGLE_LIST;
  o.radial_segments = 6;
  size_t trees_n = arbor_world_tree_count(world), nv = 0, ni = 0;
  ArborMesh **meshes = calloc(trees_n, sizeof *meshes);
  for (size_t k = 0; k < trees_n; k++) {
    ArborTree *t = NULL;
    size_t a = 0, b = 0;
    if (arbor_world_tree(world, k, &t) != ARBOR_STATUS_OK) fail("arbor_world_tree");
    if (arbor_mesh_create(t, &o, &meshes[k]) != ARBOR_STATUS_OK) fail("arbor_mesh_create");
    arbor_mesh_vertices(meshes[k], &a);
    arbor_mesh_indices(meshes[k], &b);
    nv += a;
    ni += b;
    arbor_tree_free(t);
  }
  if (!world_vao) {
    p_glGenVertexArrays(1, &world_vao);
    p_glGenBuffers(1, &world_vbo);
    p_glGenBuffers(1, &world_ebo);
  }
  p_glBindVertexArray(world_vao);
  p_glBindBuffer(GL_ARRAY_BUFFER, world_vbo);
  p_glBufferData(GL_ARRAY_BUFFER, (GLsizeiptr)(nv * sizeof(ArborVertex)), NULL, GL_STATIC_DRAW);
  p_glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, world_ebo);
  p_glBufferData(GL_ELEMENT_ARRAY_BUFFER, (GLsizeiptr)(ni * sizeof(uint32_t)), NULL, GL_STATIC_DRAW);
  size_t vat = 0, iat = 0;
  for (int c = 0; c < 3; c++) {
    world_lo[c] = 0;
    world_hi[c] = c == 1 ? 1.0f : 0;
  }
  for (size_t k = 0; k < trees_n; k++) {
    size_t a = 0, b = 0;
    const ArborVertex *v = arbor_mesh_vertices(meshes[k], &a);
    for (size_t j = 0; j < a; j++)
      for (int c = 0; c < 3; c++) {
        world_lo[c] = fminf(world_lo[c], v[j].position[c]);
        world_hi[c] = fmaxf(world_hi[c], v[j].position[c]);
      }
    const uint32_t *ix = arbor_mesh_indices(meshes[k], &b);
    uint32_t *shifted = malloc((b ? b : 1) * sizeof *shifted);
    for (size_t j = 0; j < b; j++) shifted[j] = ix[j] + (uint32_t)vat;
    p_glBufferSubData(GL_ARRAY_BUFFER, (GLintptr)(vat * sizeof *v), (GLsizeiptr)(a * sizeof *v), v);
    p_glBufferSubData(GL_ELEMENT_ARRAY_BUFFER, (GLintptr)(iat * 4), (GLsizeiptr)(b * 4), shifted);
    free(shifted);
    vat += a;
    iat += b;
    arbor_mesh_free(meshes[k]);
  }
  free(meshes);
  vertex_layout();
  p_glBindVertexArray(0);
  world_indices = ni;
  printf("world (%s, %s): %zu trees, %zu branches after %d cycles, %zu vertices; %.2f ms to grow, "
         "%.2f ms to mesh + upload\n",
         st.world_env ? "space colonization" : "shadow",
         st.world_species >= 0 ? arbor_species_name((uint32_t)st.world_species) : "mixed species", trees_n,
         arbor_world_branch_count(world), st.world_cycles, nv, grow_ms, now_ms() - t0 - grow_ms);
}

/* ---- L-system mode ---- */
static int has_suffix(const char *s, const char *suffix) {
  size_t n = strlen(s), k = strlen(suffix);
  return n >= k && !strcmp(s + n - k, suffix);
}

static void add_file(const char *path) {
  st.lsys_files = realloc(st.lsys_files, (size_t)(st.lsys_count + 1) * sizeof *st.lsys_files);
  st.lsys_files[st.lsys_count++] = strdup(path);
}

/* Every .l file under dir (recursively when deep), in name order. */
static void list_folder(const char *dir, int deep) {
  struct dirent **names = NULL;
  int n = scandir(dir, &names, NULL, alphasort);
  for (int i = 0; i < n; i++) {
    char path[4096];
    snprintf(path, sizeof path, "%s/%s", dir, names[i]->d_name);
    if (names[i]->d_name[0] != '.') {
      DIR *sub = deep ? opendir(path) : NULL;
      if (sub) {
        closedir(sub);
        list_folder(path, deep);
      } else if (has_suffix(names[i]->d_name, ".l")) {
        add_file(path);
      }
    }
    free(names[i]);
  }
  free(names);
}

/* --lsystem PATH: a file (and its neighbours) or a folder. A path that is neither, or a
   folder without .l files, is an error: the gallery says so and exits 1. */
static void open_lsystems(const char *path) {
  struct stat info;
  if (stat(path, &info) != 0) {
    fprintf(stderr, "gallery: --lsystem %s: %s (expected a .l file or a folder of them)\n", path,
            strerror(errno));
    exit(1);
  }
  if (S_ISDIR(info.st_mode)) {
    list_folder(path, 1);
    if (st.lsys_count == 0) {
      fprintf(stderr, "gallery: --lsystem %s: the folder has no .l files\n", path);
      exit(1);
    }
  } else {
    char dir[4096];
    snprintf(dir, sizeof dir, "%s", path);
    char *slash = strrchr(dir, '/');
    if (slash) *slash = 0;
    else snprintf(dir, sizeof dir, ".");
    const char *base = strrchr(path, '/') ? strrchr(path, '/') + 1 : path;
    list_folder(dir, 0);
    st.lsys_index = -1;
    for (int i = 0; i < st.lsys_count; i++) {
      const char *name = strrchr(st.lsys_files[i], '/') + 1;
      if (!strcmp(name, base)) st.lsys_index = i;
    }
    /* Not among its folder's .l files (another extension): that file alone. */
    if (st.lsys_index < 0) {
      for (int i = 0; i < st.lsys_count; i++) free(st.lsys_files[i]);
      st.lsys_count = 0;
      add_file(path);
      st.lsys_index = 0;
    }
  }
  st.lsys_mode = 1;
}

static void upload(GLuint *vao, GLuint *vbo, GLuint *ebo, const ArborVertex *v, size_t nv, const uint32_t *ix,
                   size_t ni) {
  if (!*vao) {
    p_glGenVertexArrays(1, vao);
    p_glGenBuffers(1, vbo);
    p_glGenBuffers(1, ebo);
  }
  p_glBindVertexArray(*vao);
  p_glBindBuffer(GL_ARRAY_BUFFER, *vbo);
  p_glBufferData(GL_ARRAY_BUFFER, (GLsizeiptr)(nv * sizeof *v), v, GL_STATIC_DRAW);
  p_glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, *ebo);
  p_glBufferData(GL_ELEMENT_ARRAY_BUFFER, (GLsizeiptr)(ni * sizeof *ix), ix, GL_STATIC_DRAW);
  vertex_layout();
  p_glBindVertexArray(0);
}

/* Grows the current file: bark as strips, organs (polygons, spheres, discs, baked leaf
   quads) as a second mesh; frames both. A file that does not run is reported and shown
   empty, so stepping on still works. */
static void build_lsystem(void) {
  lsys_indices = organ_indices = 0;
  if (st.lsys_count == 0) return;
  const char *path = st.lsys_files[st.lsys_index];
  double t0 = now_ms();
  ArborTree *t = NULL;
  if (arbor_tree_from_lsystem_file(path, NULL, &t) != ARBOR_STATUS_OK) {
    char msg[512];
    arbor_last_error_message(msg, sizeof msg);
    printf("%d/%d %s: does not run: %s\n", st.lsys_index + 1, st.lsys_count, path, msg);
    return;
  }
  double grown = now_ms() - t0;
  ArborMeshOptions o = mesh_options();
  o.tip = ARBOR_TIP_CAP;
  ArborMesh *bark = NULL, *organs = NULL;
  if (arbor_mesh_create(t, &o, &bark) != ARBOR_STATUS_OK) fail("arbor_mesh_create");
  /* Leaves in proportion to the plant: 4% of the extent of its branches and sites. */
  float ext_lo[3] = {1e30f, 1e30f, 1e30f}, ext_hi[3] = {-1e30f, -1e30f, -1e30f};
  size_t nb = arbor_tree_branch_count(t), ns = arbor_tree_leaf_site_count(t);
  ArborBranch *br = malloc((nb ? nb : 1) * sizeof *br);
  ArborLeafSite *sites = malloc((ns ? ns : 1) * sizeof *sites);
  arbor_tree_copy_branches(t, br, nb);
  arbor_tree_copy_leaf_sites(t, sites, ns);
  for (size_t k = 0; k < nb + ns; k++)
    for (int c = 0; c < 3; c++) {
      float q = k < nb ? br[k].end[c] : sites[k - nb].position[c];
      ext_lo[c] = fminf(ext_lo[c], q);
      ext_hi[c] = fmaxf(ext_hi[c], q);
    }
  float extent = 0;
  for (int c = 0; c < 3 && nb + ns > 0; c++) extent = fmaxf(extent, ext_hi[c] - ext_lo[c]);
  free(br);
  free(sites);
  ArborLeafOptions lo = arbor_leaf_options_default();
  lo.size = extent > 0 ? 0.04f * extent : 1.0f;
  if (arbor_leaf_mesh_create(t, &lo, &o, &organs) != ARBOR_STATUS_OK) fail("arbor_leaf_mesh_create");
  size_t nv = 0, ni = 0, mv = 0, mi = 0;
  const ArborVertex *v = arbor_mesh_vertices(bark, &nv);
  const uint32_t *ix = arbor_mesh_indices(bark, &ni);
  const ArborVertex *w = arbor_mesh_vertices(organs, &mv);
  const uint32_t *jx = arbor_mesh_indices(organs, &mi);
  float lo3[3] = {1e30f, 1e30f, 1e30f}, hi3[3] = {-1e30f, -1e30f, -1e30f};
  for (size_t k = 0; k < nv + mv; k++) {
    const float *q = k < nv ? v[k].position : w[k - nv].position;
    for (int c = 0; c < 3; c++) {
      lo3[c] = fminf(lo3[c], q[c]);
      hi3[c] = fmaxf(hi3[c], q[c]);
    }
  }
  float size = 0;
  for (int c = 0; c < 3; c++) size = fmaxf(size, hi3[c] - lo3[c]);
  if (nv + mv == 0 || !(size > 0)) size = 1;
  lsys_scale = 11.0f / size;
  for (int c = 0; c < 3; c++) lsys_center[c] = 0.5f * (lo3[c] + hi3[c]);
  if (nv + mv == 0) lsys_center[0] = lsys_center[1] = lsys_center[2] = 0;
  upload(&lsys_vao, &lsys_vbo, &lsys_ebo, v, nv, ix, ni);
  upload(&organ_vao, &organ_vbo, &organ_ebo, w, mv, jx, mi);
  lsys_indices = ni;
  organ_indices = mi;
  printf("%d/%d %s: %zu branches, %zu organs, %zu leaf sites; %zu + %zu vertices; %.2f ms to grow\n",
         st.lsys_index + 1, st.lsys_count, path, arbor_tree_branch_count(t), arbor_tree_organ_count(t),
         arbor_tree_leaf_site_count(t), nv, mv, grown);
  arbor_mesh_free(bark);
  arbor_mesh_free(organs);
  arbor_tree_free(t);
}

static void build_all(int verbose) {
  for (int i = 0; i < 9; i++) build_tree(&trees[i]);
  if (verbose) {
    printf("tree  steps  vertices  triangles  leaves  grow ms  mesh+upload ms\n");
    for (int i = 0; i < 9; i++)
      printf("%c     %5u  %8zu  %9zu  %6zu  %7.2f  %14.2f\n", trees[i].name,
             trees[i].params.steps + (unsigned)st.steps_delta, trees[i].vertices,
             trees[i].triangles, trees[i].leaves, trees[i].grow_ms, trees[i].upload_ms);
  }
}

static void make_static_geometry(void) {
  /* Ground: a large square at y = 0. */
  ArborVertex g[4];
  uint32_t gi[6];
  ground_square(0, 0, 5000, g, gi);
  ground_vao = vertex_array(g, 4, gi, 6, NULL, NULL);
  /* Leaf quad: the leaf space of ArborLeafInstance. */
  ArborVertex q[4];
  uint32_t qi[6];
  leaf_quad(q, qi);
  leaf_quad_vao = vertex_array(q, 4, qi, 6, &leaf_quad_vbo, &leaf_quad_ebo);
  p_glBindVertexArray(0);
}

static void draw_tree(const Tree *t, Mat4 model) {
  p_glUniformMatrix4fv(u_model, 1, GL_FALSE, model.m);
  p_glUniform1i(u_mode, 0);
  p_glBindVertexArray(t->vao);
  GLenum mode = st.strips ? GL_TRIANGLE_STRIP : GL_TRIANGLES;
  p_glUniform1f(u_v_scale, t->v_scale);
  if (t->indices) p_glDrawElements(mode, (GLsizei)t->indices, GL_UNSIGNED_INT, 0);
  p_glUniform1f(u_v_scale, 0.0f);
  if (st.leaves && t->leaves) {
    p_glUniform1i(u_mode, 2);
    p_glBindVertexArray(t->leaf_vao);
    p_glDisable(GL_CULL_FACE);
    p_glDrawElementsInstanced(GL_TRIANGLES, 6, GL_UNSIGNED_INT, 0, (GLsizei)t->leaves);
    p_glEnable(GL_CULL_FACE);
  }
}

/* The species' impostor field (lodcheck.h), made when first drawn: its chain of levels,
 * the level arbor_lods_impostor_level() names for 128-pixel views baked into 12 x 12. */
static ImpostorField impostor_field;
static int impostor_field_ready;

static void draw_impostor_field(const Mat4 *vp, const float eye[3]) {
  if (!impostor_field_ready) {
    double t0 = now_ms();
    unsigned char *atlas = NULL;
    ArborLods *lods = species_lods((uint32_t)st.species, 256, &atlas);
    size_t level = arbor_lods_impostor_level(lods, 128);
    impostor_field_build(&impostor_field, lods, level, atlas, 256);
    free(atlas);
    arbor_lods_free(lods);
    impostor_field_ready = 1;
    printf("impostors: %s, %d on a field, baked from level %zu in %.0f ms\n", arbor_species_name((uint32_t)st.species),
           FIELD * FIELD, level, now_ms() - t0);
  }
  float l[3] = {0.45f, 0.75f, 0.5f};
  impostor_field_draw(&impostor_field, vp, eye, l, FIELD * FIELD);
}

/* Renders one view of tree index i (or the forest) into the viewport x, y, w, h. */
static void draw_view(int i, int x, int y, int w, int h) {
  p_glViewport(x, y, w, h);
  p_glScissor(x, y, w, h);
  p_glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
  const Tree *t = &trees[i];
  /* Frame the tree about its trunk axis x = z = 0, so symmetric trees stay centred. */
  float rx = fmaxf(fabsf(t->lo[0]), fabsf(t->hi[0]));
  float rz = fmaxf(fabsf(t->lo[2]), fabsf(t->hi[2]));
  float height = t->hi[1] > 1 ? t->hi[1] : 1;
  float radius = 0.5f * sqrtf(height * height + 4 * (rx * rx + rz * rz)) * 1.08f;
  if (st.forest) radius *= 3.2f;
  if (st.impostors && st.species >= 0) radius *= 4.0f;
  if (st.lsys_mode) {
    height = 10;
    radius = 8.5f;
  }
  if (st.world_mode) {
    /* Frame the grown world about x = z = 0. */
    if (!world_vao) build_world();
    /* The frame of the gallery's 12 x 10 x 12 world box. */
    height = 10;
    radius = 8.5f;
    if (st.world_trees == 1 || st.world_forest) {
      /* A lone tree or the forest: fitted to its bounds. */
      rx = fmaxf(fabsf(world_lo[0]), fabsf(world_hi[0]));
      rz = fmaxf(fabsf(world_lo[2]), fabsf(world_hi[2]));
      height = world_hi[1] > 1 ? world_hi[1] : 1;
      radius = 0.5f * sqrtf(height * height + 4 * (rx * rx + rz * rz)) * 1.02f;
    }
  }
  float fov = 0.6f;
  float dist = radius / sinf(fov / 2) * st.zoom;
  float at[3] = {0, height * 0.5f, 0};
  float eye[3] = {at[0] + dist * cosf(st.pitch) * sinf(st.yaw), at[1] + dist * sinf(st.pitch),
                  at[2] + dist * cosf(st.pitch) * cosf(st.yaw)};
  Mat4 vp = mat_mul(perspective(fov, (float)w / (float)h, dist * 0.05f, dist * 4 + radius * 4),
                    look_at(eye, at));
  p_glUniformMatrix4fv(u_view_proj, 1, GL_FALSE, vp.m);
  Mat4 identity = model_matrix(0, 0, 0, 1);
  p_glUniformMatrix4fv(u_model, 1, GL_FALSE, identity.m);
  p_glUniform1i(u_mode, 1);
  p_glBindVertexArray(ground_vao);
  if (!st.lsys_mode) p_glDrawElements(GL_TRIANGLES, 6, GL_UNSIGNED_INT, 0);
  if (st.lsys_mode) {
    /* Scale the geometry into the frame, its centre at the middle of the view. */
    Mat4 m = model_matrix(0, 0, 0, lsys_scale);
    for (int c = 0; c < 3; c++) m.m[12 + c] = -lsys_center[c] * lsys_scale;
    m.m[13] += height * 0.5f;
    p_glUniformMatrix4fv(u_model, 1, GL_FALSE, m.m);
    p_glUniform1i(u_mode, 0);
    if (lsys_indices) {
      p_glBindVertexArray(lsys_vao);
      p_glDrawElements(st.strips ? GL_TRIANGLE_STRIP : GL_TRIANGLES, (GLsizei)lsys_indices, GL_UNSIGNED_INT, 0);
    }
    if (organ_indices) {
      p_glUniform1i(u_mode, 3);
      p_glDisable(GL_CULL_FACE);
      p_glBindVertexArray(organ_vao);
      p_glDrawElements(st.strips ? GL_TRIANGLE_STRIP : GL_TRIANGLES, (GLsizei)organ_indices, GL_UNSIGNED_INT, 0);
      p_glEnable(GL_CULL_FACE);
    }
    return;
  }
  if (st.impostors && st.species >= 0) {
    draw_impostor_field(&vp, eye);
    p_glUseProgram(program);
    p_glEnable(GL_CULL_FACE);
    return;
  }
  if (st.world_mode) {
    if (!world_vao) build_world();
    p_glUniform1i(u_mode, 0);
    p_glBindVertexArray(world_vao);
    p_glDrawElements(GL_TRIANGLES, (GLsizei)world_indices, GL_UNSIGNED_INT, 0);
    return;
  }
  if (!st.forest) {
    draw_tree(t, identity);
    return;
  }
  /* Forest: one merged mesh of 25 varied trees. */
  if (!forest_vao) build_forest(radius * 0.45f / 0.55f);
  p_glUniformMatrix4fv(u_model, 1, GL_FALSE, identity.m);
  p_glUniform1i(u_mode, 0);
  p_glBindVertexArray(forest_vao);
  p_glDrawElements(st.strips ? GL_TRIANGLE_STRIP : GL_TRIANGLES, (GLsizei)forest_indices, GL_UNSIGNED_INT, 0);
}

static void render(void) {
  p_glDisable(GL_SCISSOR_TEST);
  p_glClearColor(0.78f, 0.86f, 0.95f, 1);
  p_glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
  p_glEnable(GL_SCISSOR_TEST);
  p_glPolygonMode(GL_FRONT_AND_BACK, st.wireframe ? GL_LINE : GL_FILL);
  p_glUseProgram(program);
  float l[3] = {0.45f, 0.75f, 0.5f};
  float ll = sqrtf(l[0] * l[0] + l[1] * l[1] + l[2] * l[2]);
  p_glUniform3f(u_light, l[0] / ll, l[1] / ll, l[2] / ll);
  /* A screenshot sways at a fixed moment, so two runs draw the same picture. */
  p_glUniform1f(u_time, st.fixed_time ? 1.0f : (float)glfwGetTime());
  p_glUniform1f(u_wind, st.wind ? 1.0f : 0.0f);
  float growth = 1.0f;
  if (st.threshold_growth) {
    growth = (float)((glfwGetTime() - st.growth_clock) / 6.0);
    if (growth > 1.0f) growth = 1.0f;
  }
  p_glUniform1f(u_growth, growth);
  if (st.single >= 0 || st.forest || st.world_mode || st.lsys_mode) {
    draw_view(st.single >= 0 ? st.single : 0, 0, 0, st.width, st.height);
  } else {
    int cw = st.width / 3, ch = st.height / 3;
    for (int i = 0; i < 9; i++) {
      int col = i % 3, row = i / 3;
      draw_view(i, col * cw, (2 - row) * ch, cw, ch);
    }
  }
  p_glDisable(GL_SCISSOR_TEST);
}

static int save_shot(const char *path) { return save_image(path, st.width, st.height); }

static void key(GLFWwindow *win, int k, int scancode, int action, int mods) {
  (void)scancode;
  if (action != GLFW_PRESS && action != GLFW_REPEAT) return;
  int shift = (mods & GLFW_MOD_SHIFT) != 0;
  if (k == GLFW_KEY_ESCAPE) glfwSetWindowShouldClose(win, 1);
  /* L-system mode: Tab the next file of the folder, Shift+Tab the one before. */
  else if (k == GLFW_KEY_TAB && st.lsys_mode && st.lsys_count > 0) {
    st.lsys_index = (st.lsys_index + (shift ? st.lsys_count - 1 : 1)) % st.lsys_count;
    st.dirty = 1;
  }
  else if (k >= GLFW_KEY_1 && k <= GLFW_KEY_9) { st.single = k - GLFW_KEY_1; st.forest = 0; }
  else if (k == GLFW_KEY_0) { st.single = -1; st.forest = 0; }
  else if (k == GLFW_KEY_EQUAL || k == GLFW_KEY_KP_ADD) { st.steps_delta++; st.dirty = 1; }
  else if (k == GLFW_KEY_MINUS || k == GLFW_KEY_KP_SUBTRACT) { st.steps_delta--; st.dirty = 1; }
  else if (k == GLFW_KEY_LEFT_BRACKET && st.radial_segments > 3) { st.radial_segments--; st.dirty = 1; }
  else if (k == GLFW_KEY_RIGHT_BRACKET && st.radial_segments < 64) { st.radial_segments++; st.dirty = 1; }
  else if (k == GLFW_KEY_T) { st.thickness *= shift ? 1 / 1.15f : 1.15f; st.dirty = 1; }
  else if (k == GLFW_KEY_L) { st.length *= shift ? 1 / 1.1f : 1.1f; st.dirty = 1; }
  else if (k == GLFW_KEY_V) st.leaves = !st.leaves;
  else if (k == GLFW_KEY_W) st.wireframe = !st.wireframe;
  else if (k == GLFW_KEY_S) { st.strips = !st.strips; st.dirty = 1; }
  else if (k == GLFW_KEY_F) st.forest = !st.forest;
  else if (k == GLFW_KEY_I && st.species >= 0) st.impostors = !st.impostors;
  else if (k == GLFW_KEY_P) st.screenshot_requested = 1;
  else if (k == GLFW_KEY_G) {
    /* Growth from the animation stream: one upload, a moving threshold. */
    st.threshold_growth = !st.threshold_growth;
    st.growth_clock = glfwGetTime();
  }
  else if (k == GLFW_KEY_N) st.wind = !st.wind;
  else if (k == GLFW_KEY_C) { st.smooth = !st.smooth; st.dirty = 1; }
  /* The self-organized world: O on/off, Space one more cycle, R reset, E environment,
     K species (a mix, then each preset). */
  else if (k == GLFW_KEY_O) { st.world_mode = !st.world_mode; st.forest = 0; st.dirty = 1; }
  else if (k == GLFW_KEY_SPACE && st.world_mode) { st.world_cycles++; st.dirty = 1; }
  else if (k == GLFW_KEY_R && st.world_mode) { st.world_cycles = 0; arbor_world_free(world); world = NULL; st.dirty = 1; }
  else if (k == GLFW_KEY_E && st.world_mode) { st.world_env = !st.world_env; arbor_world_free(world); world = NULL; st.dirty = 1; }
  else if (k == GLFW_KEY_K && st.world_mode) {
    st.world_species = st.world_species + 1 >= (int)species_count() ? -1 : st.world_species + 1;
    arbor_world_free(world);
    world = NULL;
    st.dirty = 1;
  }
}

static void mouse_button(GLFWwindow *win, int button, int action, int mods) {
  (void)mods;
  if (button == GLFW_MOUSE_BUTTON_LEFT) {
    st.dragging = action == GLFW_PRESS;
    glfwGetCursorPos(win, &st.drag_x, &st.drag_y);
  }
}

static void cursor(GLFWwindow *win, double x, double y) {
  (void)win;
  if (!st.dragging) return;
  orbit_drag(&st.yaw, &st.pitch, &st.drag_x, &st.drag_y, x, y, -0.2f, 1.4f);
}

static void scroll(GLFWwindow *win, double dx, double dy) {
  (void)win;
  (void)dx;
  st.zoom *= dy > 0 ? 0.9f : 1.1f;
}

static void resize(GLFWwindow *win, int w, int h) {
  (void)win;
  st.width = w;
  st.height = h;
}

int main(int argc, char **argv) {
  glapp_name = "gallery";
  const char *shot = NULL;
  int frames = 3, headless = 0, depth = -1, next_files = 0, check_lods = 0;
  st.width = 1080;
  st.height = 1080;
  st.single = -1;
  st.species = -1;
  st.strips = 1;
  st.radial_segments = 8;
  st.thickness = 1;
  st.length = 1;
  st.zoom = 1;
  st.pitch = 0.12f;
  st.world_species = -1;
  st.world_trees = 7;
  for (int i = 1; i < argc; i++) {
    if (!strcmp(argv[i], "--screenshot") && i + 1 < argc) { shot = argv[++i]; headless = 1; st.fixed_time = 1; }
    else if (!strcmp(argv[i], "--frames") && i + 1 < argc) frames = atoi(argv[++i]);
    else if (!strcmp(argv[i], "--tree") && i + 1 < argc) st.single = argv[++i][0] - 'a';
    else if (!strcmp(argv[i], "--size") && i + 1 < argc) sscanf(argv[++i], "%dx%d", &st.width, &st.height);
    else if (!strcmp(argv[i], "--list")) st.strips = 0;
    else if (!strcmp(argv[i], "--leaves")) st.leaves = 1;
    else if (!strcmp(argv[i], "--species") && i + 1 < argc) {
      static const char *names[] = {"oak", "maple", "birch", "willow", "poplar", "pine", "spruce", "shrub"};
      const char *name = argv[++i];
      st.species = -2;
      for (int k = 0; k < 8; k++)
        if (!strcmp(name, names[k])) st.species = ARBOR_SPECIES_OAK + k;
      st.single = 0;
      st.leaves = 1;
    }
    else if (!strcmp(argv[i], "--lod-check")) { check_lods = 1; headless = 1; }
    else if (!strcmp(argv[i], "--impostors")) st.impostors = 1;
    else if (!strcmp(argv[i], "--forest")) st.forest = 1;
    else if (!strcmp(argv[i], "--smooth")) st.smooth = 1;
    else if (!strcmp(argv[i], "--compact")) st.compact = 1;
    else if (!strcmp(argv[i], "--world") && i + 1 < argc) { st.world_mode = 1; st.world_cycles = atoi(argv[++i]); }
    else if (!strcmp(argv[i], "--world-env") && i + 1 < argc) st.world_env = atoi(argv[++i]) != 0;
    else if (!strcmp(argv[i], "--world-trees") && i + 1 < argc) st.world_trees = atoi(argv[++i]);
    else if (!strcmp(argv[i], "--world-forest")) { st.world_mode = 1; st.world_forest = 1; }
    else if (!strcmp(argv[i], "--pitch") && i + 1 < argc) st.pitch = (float)atof(argv[++i]) * 3.14159265f / 180.0f;
    else if (!strcmp(argv[i], "--zoom") && i + 1 < argc) st.zoom = (float)atof(argv[++i]);
    else if (!strcmp(argv[i], "--world-species") && i + 1 < argc) {
      /* A species' number or name (arbor_species_name); -1 a mix. */
      const char *a = argv[++i];
      st.world_species = atoi(a);
      for (uint32_t n = 0; arbor_species_name(n) != NULL; n++)
        if (!strcmp(a, arbor_species_name(n))) st.world_species = (int)n;
      if (st.world_species < -1 || st.world_species >= (int)species_count()) {
        fprintf(stderr, "--world-species %s: expected -1 (a mix), 0..%u or a species name\n", a,
                species_count() - 1);
        return 2;
      }
    }
    else if (!strcmp(argv[i], "--depth") && i + 1 < argc) depth = atoi(argv[++i]);
    else if (!strcmp(argv[i], "--wind")) st.wind = 1;
    else if (!strcmp(argv[i], "--lsystem") && i + 1 < argc) open_lsystems(argv[++i]);
    else if (!strcmp(argv[i], "--next") && i + 1 < argc) next_files = atoi(argv[++i]);
    else {
      fprintf(stderr, "usage: gallery [--tree a..i] [--size WxH] [--list] [--leaves] [--forest] [--depth K] "
                      "[--smooth] [--compact] [--lsystem FILE.l|FOLDER] [--world CYCLES [--world-species NAME] [--world-trees 1..7] "
                      "[--world-forest] [--world-env 0|1]] [--pitch DEGREES] "
                      "[--screenshot FILE.png|FILE.ppm --frames N] [--species NAME --lod-check]\n"
                      "       [--species NAME --impostors]\n");
      return 2;
    }
  }
  if (st.single < -1 || st.single > 8 || st.width < 64 || st.height < 64 || frames < 1 ||
      st.world_trees < 1 || st.world_trees > 7 || st.pitch < -0.2f || st.pitch > 1.56f) {
    fprintf(stderr, "gallery: bad --tree, --size or --frames\n");
    return 2;
  }
  if (st.species == -2) {
    fprintf(stderr, "gallery: --species takes oak, maple, birch, willow, poplar, pine, spruce or shrub\n");
    return 2;
  }
  GLFWwindow *win = open_window("arbor gallery", st.width, st.height, 3, 3, headless);
  if (!load_gl()) return 1;
  glfwGetFramebufferSize(win, &st.width, &st.height);
  printf("gallery: arbor %s, OpenGL %s\n", arbor_version(), (const char *)p_glGetString(GL_VERSION));
  if (check_lods) {
    /* examples/gallery/lodcheck.h: the levels' silhouettes by OpenGL, the baker's speed. */
    if (st.species < 0) {
      fprintf(stderr, "gallery: --lod-check needs --species NAME\n");
      return 2;
    }
    int r = lod_check((uint32_t)st.species, shot);
    glfwDestroyWindow(win);
    glfwTerminate();
    return r;
  }

  program = link_program(vs_src, fs_src);
  u_view_proj = p_glGetUniformLocation(program, "u_view_proj");
  u_model = p_glGetUniformLocation(program, "u_model");
  u_mode = p_glGetUniformLocation(program, "u_mode");
  u_light = p_glGetUniformLocation(program, "u_light");
  u_time = p_glGetUniformLocation(program, "u_time");
  u_wind = p_glGetUniformLocation(program, "u_wind");
  u_growth = p_glGetUniformLocation(program, "u_growth");
  u_v_scale = p_glGetUniformLocation(program, "u_v_scale");
  /* The leaves: the oak's leaf atlas, drawn by arbor, on texture unit 1. */
  uint32_t textured = st.species >= 0 ? (uint32_t)st.species : ARBOR_SPECIES_OAK;
  if (!species_texture(textured, ARBOR_TEXTURE_LEAF_ATLAS, 512, GL_TEXTURE1)) return 1;
  if (st.species >= 0 && !species_texture(textured, ARBOR_TEXTURE_BARK_COLOR, 512, GL_TEXTURE2)) return 1;
  p_glUseProgram(program);
  p_glUniform1i(p_glGetUniformLocation(program, "u_atlas"), 1);
  p_glUniform1i(p_glGetUniformLocation(program, "u_bark"), 2);
  p_glUniform1i(p_glGetUniformLocation(program, "u_bark_textured"), st.species >= 0);
  p_glEnable(GL_DEPTH_TEST);
  p_glEnable(GL_CULL_FACE);
  p_glEnable(GL_PRIMITIVE_RESTART_FIXED_INDEX);
  make_static_geometry();

  for (int i = 0; i < 9; i++) {
    trees[i].name = (char)('a' + i);
    if (arbor_honda_preset((uint32_t)trees[i].name, &trees[i].params) != ARBOR_STATUS_OK) fail("preset");
  }
  if (depth >= 0) {
    st.growth = 1;
    st.growth_step = depth;
  }
  /* --next K: as if Tab were pressed K times (to check the stepping headless). */
  if (st.lsys_mode && st.lsys_count > 0) st.lsys_index = (st.lsys_index + next_files) % st.lsys_count;
  if (st.lsys_mode) build_lsystem();
  else if (st.species >= 0) build_species();
  else build_all(1);
  if (!headless)
    printf("keys: drag orbit, wheel zoom, 1-9 one tree, 0 grid, +/- steps, [ ] sides, T/L thickness/length "
           "(Shift: smaller), V leaves, G growth, N wind, W wireframe, S strips/list, F forest, "
           "C smooth, O self-organized world (Space cycle, R reset, E environment, K species), "
           "Tab / Shift+Tab next / previous L-system file (--lsystem), P screenshot\n");

  glfwSetKeyCallback(win, key);
  glfwSetMouseButtonCallback(win, mouse_button);
  glfwSetCursorPosCallback(win, cursor);
  glfwSetScrollCallback(win, scroll);
  glfwSetFramebufferSizeCallback(win, resize);

  int frame = 0;
  while (!glfwWindowShouldClose(win)) {
    if (st.growth && depth < 0) {
      int step = (int)((glfwGetTime() - st.growth_clock) * 2.0);
      if (step != st.growth_step && step <= 16) {
        st.growth_step = step;
        st.dirty = 1;
      }
    }
    if (st.dirty) {
      if (st.lsys_mode) build_lsystem();
      else if (st.world_mode) build_world();
      else build_all(!st.growth);
      st.dirty = 0;
    }
    render();
    frame++;
    if (headless && frame >= frames) {
      int ok = save_shot(shot);
      arbor_world_free(world);
      glfwDestroyWindow(win);
      glfwTerminate();
      return ok ? 0 : 1;
    }
    if (st.screenshot_requested) {
      save_shot("arbor_gallery.png");
      st.screenshot_requested = 0;
    }
    glfwSwapBuffers(win);
    glfwPollEvents();
    char title[160];
    size_t verts = 0, tris = 0;
    double ms = 0;
    for (int i = 0; i < 9; i++) {
      verts += trees[i].vertices;
      tris += trees[i].triangles;
      ms += trees[i].grow_ms + trees[i].upload_ms;
    }
    snprintf(title, sizeof title, "arbor gallery: %zu vertices, %zu triangles, %.1f ms to grow and upload (%s)",
             verts, tris, ms, st.strips ? "strips" : "list");
    glfwSetWindowTitle(win, title);
  }
  glfwDestroyWindow(win);
  glfwTerminate();
  return 0;
}
