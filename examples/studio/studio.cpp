/*
 * arbor studio: grow a forest on a terrain with every growth parameter on a slider, paint
 * where each species grows, preview what a change does, and export the forest.
 *
 * Windows (Dear ImGui): Species (every ArborGrowthParams field of every species, as sliders
 * over its documented range; add, duplicate, reset to the preset), Map (paint species and
 * density on the terrain, then plant), Growth (step, run, reset, the preview), Stats (every
 * tree's species, age, branches and leaves; totals; the last growth step's and frame's
 * times), View (light, shadows, leaves, wireframe). The trees are meshes (bark with the
 * species' bark texture, baked leaves on its leaf atlas, alpha-tested), shadowed by the sun
 * through a shadow map, on a terrain from a PNG height map or seeded noise.
 *
 * The preview: every parameter change copies the original world (arbor_world_clone), gives
 * the copy the new parameters (arbor_world_set_species) and grows it `ahead` cycles; the
 * view shows the preview while it is on. The original follows on demand (F): it takes the
 * parameters and grows on with them.
 *
 * Keys: Space step one cycle, R run / pause, Backspace replant, M map editor, P preview on /
 * off, F the original follows the preview, L turn the light 15 degrees, E export
 * forest.glb, H hide / show the windows, G replay the growth (branches appear in the order they grew), Esc quit.
 * Right drag orbits, wheel zooms. The trees sway in the wind (View: its strength).
 *
 *   studio [--heightmap PNG [--height-scale H] [--cell C]] [--noise SEED]
 *          [--map PNG --legend RRGGBB=SPECIES,...] [--density D] [--seed S]
 *          [--steps N] [--export FILE.glb] [--screenshot FILE.png] [--size WxH]
 *          [--script FILE]
 *
 * With --screenshot (or --script) it runs headless: the session (options first, then the
 * script's lines), one frame drawn, the screenshot written, and exits. Script lines (one
 * command each, `#` comments):
 *   heightmap FILE [SCALE [CELL]]   the terrain from a PNG height map
 *   noise SEED                      the terrain from seeded noise
 *   species NAME                    add a species slot (oak, maple, birch, willow, poplar,
 *                                   pine, spruce, shrub) with its preset
 *   paint NAME X0 Z0 X1 Z1 [D]      paint a rectangle (world x, z) with a species (or
 *                                   `none`) at density D trees per 100 square metres
 *   plant [SEED]                    plant the world from the map
 *   step N                          grow the original N cycles (the preview follows)
 *   ahead N                         the preview grows N cycles ahead (0: preview off)
 *   set NAME FIELD VALUE            a growth parameter of a species (the preview regrows)
 *   follow                          the original takes the parameters
 *   pick K                          pick tree K (printed)
 *   export FILE.glb [picked]        the world (or the picked tree) as glTF
 *   stats FILE                      every tree of both worlds, one line each
 *   ui on|off                       show or hide the windows
 *   growth T                        draw what had grown by T (0..1 of each tree's growth)
 *   wind STRENGTH TIME              the wind's strength and the clock it sways by
 *   screenshot FILE.png             draw a frame and write it
 *   map-screenshot FILE.png         draw the map editor full-window and write it
 */
#define GLFW_INCLUDE_NONE
#ifndef _DEFAULT_SOURCE
#define _DEFAULT_SOURCE
#endif
#include <GLFW/glfw3.h>
#include <GL/glcorearb.h>

#include "arbor.hpp"
#include "../common/glapp.h"

#include <imgui.h>
#include <backends/imgui_impl_glfw.h>
#include <backends/imgui_impl_opengl3.h>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <map>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

namespace {

/* ---- species ---- */

/* The named species the studio grows (each has a bark texture and a leaf atlas). */
const ArborSpecies kNamed[] = {ARBOR_SPECIES_OAK,    ARBOR_SPECIES_MAPLE, ARBOR_SPECIES_BIRCH,
                               ARBOR_SPECIES_WILLOW, ARBOR_SPECIES_POPLAR, ARBOR_SPECIES_PINE,
                               ARBOR_SPECIES_SPRUCE, ARBOR_SPECIES_SHRUB};

bool species_by_name(const std::string &name, ArborSpecies *out) {
  for (ArborSpecies s : kNamed)
    if (name == arbor_species_name(s)) return *out = s, true;
  return false;
}

/* A growth parameter as a slider: its name, where it is, and its documented range. */
struct Field {
  const char *name;
  size_t offset;
  bool integer;
  float lo, hi;
};

#define FIELD_F(f, lo, hi) {#f, offsetof(ArborGrowthParams, f), false, lo, hi}
#define FIELD_U(f, lo, hi) {#f, offsetof(ArborGrowthParams, f), true, lo, hi}
const Field kFields[] = {
    FIELD_F(apical_control, 0, 1),        FIELD_F(vigor_multiplier, 0.1f, 6),
    FIELD_F(internode_length, 0.05f, 1),  FIELD_F(branch_angle, 0, 180),
    FIELD_F(phyllotaxis, 0, 360),         FIELD_F(tropism, -1, 1),
    FIELD_F(environment_weight, 0, 2),    FIELD_F(pipe_exponent, 1, 4),
    FIELD_F(tip_radius, 0.001f, 0.1f),    FIELD_F(shed_multiplier, 0, 0.5f),
    FIELD_F(shed_exponent, 0, 8),         FIELD_U(shed_delay, 0, 40),
    FIELD_U(seed_age, 0, 60),             FIELD_F(seed_spread, 0, 10),
    FIELD_F(perception_angle, 1, 180),    FIELD_F(perception_reach, 0.5f, 64),
    FIELD_F(occupancy_reach, 0, 64),      FIELD_U(max_shoot, 1, 64),
    FIELD_F(shed_light, 0, 1.5f),         FIELD_F(young_apical_control, 0, 1),
    FIELD_F(young_vigor_multiplier, 0.1f, 6), FIELD_U(maturity_age, 0, 200),
    FIELD_U(max_age, 0, 200),             FIELD_F(max_height, 0, 40),
    FIELD_F(droop, 0, 1),                 FIELD_F(germination_light, 0, 1.5f),
};

struct Slot {
  std::string name;
  ArborSpecies species;
  ArborGrowthParams params;
  float colour[3];
  GLuint bark_tex = 0, atlas_tex = 0;
};

const float kColours[][3] = {{0.85f, 0.25f, 0.2f}, {0.2f, 0.45f, 0.9f}, {0.95f, 0.8f, 0.2f},
                             {0.6f, 0.3f, 0.8f},   {0.2f, 0.8f, 0.7f},  {0.9f, 0.5f, 0.1f},
                             {0.5f, 0.8f, 0.2f},   {0.9f, 0.4f, 0.7f}};

/* ---- the session ---- */

/* A mesh on the GPU: ArborVertex, indices, and the animation stream (ArborAnimationVertex:
   growth time, branching order, place along the branch, phase) as attribute 3. */
struct Gpu {
  GLuint vao = 0, vbo = 0, ebo = 0, abo = 0;
  GLsizei count = 0;
  void upload(const std::vector<ArborVertex> &v, const std::vector<uint32_t> &ix,
              const std::vector<ArborAnimationVertex> &anim) {
    if (vao) {
      p_glDeleteVertexArrays(1, &vao);
      GLuint b[3] = {vbo, ebo, abo};
      p_glDeleteBuffers(3, b);
    }
    vao = vertex_array(v.data(), v.size(), ix.data(), ix.size(), &vbo, &ebo);
    p_glGenBuffers(1, &abo);
    p_glBindBuffer(GL_ARRAY_BUFFER, abo);
    p_glBufferData(GL_ARRAY_BUFFER, (GLsizeiptr)(anim.size() * sizeof(ArborAnimationVertex)), anim.data(),
                   GL_STATIC_DRAW);
    p_glVertexAttribPointer(3, 4, GL_FLOAT, GL_FALSE, sizeof(ArborAnimationVertex), nullptr);
    p_glEnableVertexAttribArray(3);
    p_glBindVertexArray(0);
    count = (GLsizei)ix.size();
  }
};

struct TreeStats {
  uint32_t slot = 0, age = 0;
  size_t branches = 0, leaves = 0;
  float root[3] = {0, 0, 0};
  uint64_t hash = 0;
};

struct Studio {
  int width = 1280, height = 800;
  /* Terrain: `terrain_n` samples a side, `cell` metres apart, from the origin (-half, -half). */
  std::vector<uint8_t> heightmap_png;
  float height_scale = 8.0f, cell = 1.0f;
  uint32_t noise_seed = 1, terrain_n = 97;
  std::vector<float> noise_heights;
  /* The map: `map_n` cells a side over the terrain. */
  uint32_t map_n = 48;
  std::vector<uint32_t> map_slots;
  std::vector<float> map_density; /* trees per square metre */
  float brush_density = 2.0f;     /* trees per 100 square metres */
  int brush_slot = 0, brush_radius = 3;
  uint64_t plant_seed = 1;
  std::vector<Slot> slots;
  std::unique_ptr<arbor::World> original, preview;
  uint32_t ahead = 0, cycle = 0;
  bool running = false, params_dirty = false, show_map = true, shadows = true, leaves = true;
  bool show_ui = true; /* the windows (H hides them) */
  /* Growth animation: the threshold on the vertices' growth times, and whether it plays. */
  float growth = 1.0f, wind = 0.5f;
  bool replaying = false;
  double time = 0;
  float sun_azimuth = 40.0f, sun_elevation = 50.0f;
  float yaw = 0.7f, pitch = 0.45f, zoom = 1.0f;
  double mouse_x = 0, mouse_y = 0;
  bool orbiting = false;
  int picked = -1;
  double step_ms = 0, frame_ms = 0, mesh_ms = 0;
  size_t gpu_bytes = 0;
  std::vector<TreeStats> stats;
  /* GPU */
  GLuint program = 0, shadow_program = 0, shadow_fbo = 0, shadow_tex = 0;
  Gpu terrain;
  std::vector<Gpu> bark, leaf; /* per slot */
  bool geometry_dirty = true;

  float half() const { return 0.5f * (float)(terrain_n - 1) * cell; }
  arbor::World *shown() { return preview && ahead > 0 ? preview.get() : original.get(); }
};

Studio S;

/* The growth cycle of the world on view. */
[[maybe_unused]] uint32_t shown_cycle() { return S.cycle + (S.shown() == S.preview.get() ? S.ahead : 0); }

/* ---- terrain ---- */

float noise_at(uint32_t seed, float x, float z) {
  /* A few octaves of sines with seeded phases: smooth hills. */
  float h = 0;
  uint32_t r = seed * 2654435761u + 12345u;
  float amp = 1.0f, freq = 0.04f;
  for (int o = 0; o < 4; o++) {
    r = r * 1664525u + 1013904223u;
    float a = (float)(r >> 8) / 16777216.0f * 6.2831853f;
    r = r * 1664525u + 1013904223u;
    float b = (float)(r >> 8) / 16777216.0f * 6.2831853f;
    h += amp * (std::sin(x * freq + a) * std::cos(z * freq * 1.3f + b));
    amp *= 0.5f;
    freq *= 2.1f;
  }
  return h;
}

bool read_file(const std::string &path, std::vector<uint8_t> *out) {
  std::ifstream f(path, std::ios::binary);
  if (!f) return false;
  out->assign(std::istreambuf_iterator<char>(f), std::istreambuf_iterator<char>());
  return true;
}

/* PNG width and height from its header (the studio sizes its terrain by it). */
bool png_size(const std::vector<uint8_t> &png, uint32_t *w, uint32_t *h) {
  if (png.size() < 24 || memcmp(png.data() + 12, "IHDR", 4) != 0) return false;
  auto be = [&](size_t k) {
    return (uint32_t)png[k] << 24 | (uint32_t)png[k + 1] << 16 | (uint32_t)png[k + 2] << 8 | png[k + 3];
  };
  *w = be(16);
  *h = be(20);
  return true;
}

ArborWorldOptions world_options() {
  ArborWorldOptions o = arbor::world_options();
  float h = S.half();
  o.min[0] = o.min[2] = -h;
  o.max[0] = o.max[2] = h;
  o.min[1] = -1.0f;
  o.max[1] = S.height_scale + 40.0f;
  o.cell_size = 0.25f;
  o.max_cells = (size_t)1 << 27; /* the box's cells are counted; the grid grows with the shade */
  o.seed = S.plant_seed;
  o.parallel = 1;
  return o;
}

/* A new, empty world on the terrain. */
std::unique_ptr<arbor::World> new_world() {
  auto w = std::make_unique<arbor::World>(world_options());
  float h = S.half();
  if (!S.heightmap_png.empty()) {
    w->set_ground_png(S.heightmap_png, S.height_scale, 0.0f, S.cell, -h, -h);
  } else {
    w->set_ground(S.noise_heights, S.terrain_n, S.terrain_n, S.cell, -h, -h);
  }
  return w;
}

void make_noise_terrain() {
  S.noise_heights.resize((size_t)S.terrain_n * S.terrain_n);
  float h = S.half();
  for (uint32_t j = 0; j < S.terrain_n; j++)
    for (uint32_t i = 0; i < S.terrain_n; i++) {
      float x = -h + (float)i * S.cell, z = -h + (float)j * S.cell;
      S.noise_heights[(size_t)j * S.terrain_n + i] = S.height_scale * 0.5f * (1.0f + 0.6f * noise_at(S.noise_seed, x, z));
    }
}

void load_heightmap(const std::string &path) {
  if (!read_file(path, &S.heightmap_png)) throw std::runtime_error("cannot read " + path);
  uint32_t w = 0, h = 0;
  if (!png_size(S.heightmap_png, &w, &h)) throw std::runtime_error(path + " is not a PNG");
  if (w != h) throw std::runtime_error(path + ": the studio takes a square height map");
  S.terrain_n = w;
}

/* ---- meshes ---- */

ArborMeshOptions mesh_options() {
  ArborMeshOptions o = arbor::mesh_options();
  o.radial_segments = 6;
  o.min_radial_segments = 3;
  o.texture_scale = 1.0f;
  /* Twigs thinner than 2.5 cm are left to the leaves: a forest of millions of internodes
     stays drawable on a software renderer. */
  o.cull_radius = 0.025f;
  return o;
}

/* The leaves a species puts on its trees (arbor_species_options: on its twigs' tips and
   young shoots, on its atlas' cells), kept in metres: those options size a tree to the
   species' adult height, and the studio's world is in metres already. */
ArborLeafOptions species_leaves(ArborSpecies species, const arbor::Tree &t, uint32_t seed) {
  ArborMeshOptions m = arbor::mesh_options();
  ArborLeafOptions l = arbor::leaf_options();
  arbor::detail::check(arbor_species_options(species, t.get(), &m, &l));
  l.size *= m.scale;
  l.wood_clearance *= m.scale;
  l.seed = seed;
  return l;
}

/* Tree `k` of `w` as its species shapes its own trees (twigs, cone, cleared trunk), or the
   snapshot as grown where it has no branches. */
arbor::Tree shaped(const arbor::World &w, size_t k, const Slot &slot) {
  arbor::Tree t = w.tree(k);
  if (t.branch_count() == 0) return t;
  return t.finished_as(slot.species);
}

uint64_t hash_branches(const std::vector<ArborBranch> &b) {
  uint64_t h = 1469598103934665603ull;
  const unsigned char *p = reinterpret_cast<const unsigned char *>(b.data());
  for (size_t k = 0; k < b.size() * sizeof(ArborBranch); k++) h = (h ^ p[k]) * 1099511628211ull;
  return h;
}

/* The mesh options leaves are placed with: no branch culled, so the twigs' leaves stay. */
ArborMeshOptions leaf_mesh_options() {
  ArborMeshOptions o = mesh_options();
  o.cull_radius = 0.0f;
  return o;
}

/* Every tree's slot, age, branches and root; the leaves are counted where the trees are
   shaped and meshed (rebuild_geometry), not shaped a second time here. */
std::vector<TreeStats> world_stats(const arbor::World &w, uint32_t cycle) {
  std::vector<TreeStats> out(w.tree_count());
  for (size_t k = 0; k < out.size(); k++) {
    arbor::Tree t = w.tree(k);
    TreeStats &s = out[k];
    s.slot = w.tree_slot(k);
    std::vector<ArborBranch> b = t.branches();
    s.branches = b.size();
    s.hash = hash_branches(b);
    if (!b.empty()) {
      memcpy(s.root, b[0].start, sizeof s.root);
      s.age = cycle >= b[0].depth ? cycle - b[0].depth : 0;
    }
  }
  return out;
}

/* Meshes every tree of the shown world into one bark and one leaf buffer a species. */
void rebuild_geometry() {
  double t0 = now_ms();
  arbor::World *w = S.shown();
  size_t n = S.slots.size();
  std::vector<std::vector<ArborVertex>> bv(n), lv(n);
  std::vector<std::vector<uint32_t>> bi(n), li(n);
  std::vector<std::vector<ArborAnimationVertex>> ba(n), la(n);
  ArborMeshOptions mo = mesh_options(), leaf_mo = leaf_mesh_options();
  if (w) {
    for (size_t k = 0; k < w->tree_count(); k++) {
      uint32_t slot = w->tree_slot(k);
      if (slot >= n) continue;
      arbor::Tree t = shaped(*w, k, S.slots[slot]);
      if (t.branch_count() == 0) continue;
      auto size = t.mesh_size(mo);
      size_t base = bv[slot].size();
      bv[slot].resize(base + size.first);
      std::vector<uint32_t> ix(size.second);
      t.write_mesh(mo, arbor::Span<ArborVertex>(bv[slot].data() + base, size.first), ix);
      for (uint32_t &i : ix) bi[slot].push_back(i + (uint32_t)base);
      /* The growth times and wind weights of the same vertices. */
      ba[slot].resize(base + size.first);
      arbor::detail::check(arbor_mesh_animation_write(t.get(), &mo, ba[slot].data() + base, size.first));
      ArborLeafOptions lo = species_leaves(S.slots[slot].species, t, (uint32_t)k);
      if (k < S.stats.size()) arbor_leaf_instance_count(t.get(), &lo, &leaf_mo, &S.stats[k].leaves);
      if (S.leaves) {
        arbor::Mesh m = t.leaf_mesh(lo, leaf_mo);
        size_t lb = lv[slot].size();
        for (const ArborVertex &v : m.vertices()) {
          lv[slot].push_back(v);
          /* Leaves come out at the end of the growth, flutter at the tips (phase by place). */
          float phase = std::fmod(std::fabs(v.position[0] * 0.37f + v.position[2] * 0.73f), 1.0f);
          la[slot].push_back(ArborAnimationVertex{1.0f, 3.0f, 1.0f, phase});
        }
        for (uint32_t i : m.indices()) li[slot].push_back(i + (uint32_t)lb);
      }
    }
  }
  S.bark.resize(n);
  S.leaf.resize(n);
  S.gpu_bytes = 0;
  for (size_t s = 0; s < n; s++) {
    S.bark[s].upload(bv[s], bi[s], ba[s]);
    S.leaf[s].upload(lv[s], li[s], la[s]);
    S.gpu_bytes += (bv[s].size() + lv[s].size()) * (sizeof(ArborVertex) + sizeof(ArborAnimationVertex)) +
                   (bi[s].size() + li[s].size()) * 4;
  }
  S.mesh_ms = now_ms() - t0;
  S.geometry_dirty = false;
}

void rebuild_terrain() {
  std::vector<ArborVertex> v((size_t)S.terrain_n * S.terrain_n);
  std::vector<uint32_t> ix;
  float h = S.half();
  arbor::World probe = std::move(*new_world());
  for (uint32_t j = 0; j < S.terrain_n; j++)
    for (uint32_t i = 0; i < S.terrain_n; i++) {
      ArborVertex &a = v[(size_t)j * S.terrain_n + i];
      float x = -h + (float)i * S.cell, z = -h + (float)j * S.cell;
      float e = 0.5f * S.cell;
      float dx = probe.ground_height(x + e, z) - probe.ground_height(x - e, z);
      float dz = probe.ground_height(x, z + e) - probe.ground_height(x, z - e);
      float len = std::sqrt(dx * dx + dz * dz + 4 * e * e);
      a.position[0] = x;
      a.position[1] = probe.ground_height(x, z);
      a.position[2] = z;
      a.normal[0] = -dx / len;
      a.normal[1] = 2 * e / len;
      a.normal[2] = -dz / len;
      a.uv[0] = x;
      a.uv[1] = z;
    }
  for (uint32_t j = 0; j + 1 < S.terrain_n; j++)
    for (uint32_t i = 0; i + 1 < S.terrain_n; i++) {
      uint32_t a = j * S.terrain_n + i, b = a + 1, c = a + S.terrain_n, d = c + 1;
      uint32_t q[6] = {a, c, b, b, c, d};
      ix.insert(ix.end(), q, q + 6);
    }
  S.terrain.upload(v, ix, std::vector<ArborAnimationVertex>(v.size(), ArborAnimationVertex{0, 0, 0, 0}));
}

/* ---- growth ---- */

void refresh_stats() {
  S.stats = S.shown() ? world_stats(*S.shown(), shown_cycle()) : std::vector<TreeStats>();
}

void regrow_preview() {
  S.preview.reset();
  if (S.original && S.ahead > 0) {
    S.preview = std::make_unique<arbor::World>(S.original->clone());
    for (size_t s = 0; s < S.slots.size(); s++) S.preview->set_species((uint32_t)s, S.slots[s].params);
    S.preview->step(S.ahead);
  }
  S.params_dirty = false;
  S.geometry_dirty = true;
  refresh_stats();
}

void plant() {
  S.original = new_world();
  std::vector<ArborGrowthParams> species;
  for (const Slot &s : S.slots) species.push_back(s.params);
  float h = S.half(), map_cell = 2 * h / (float)S.map_n;
  size_t planted = S.original->plant_map(S.map_slots, S.map_density, S.map_n, S.map_n, map_cell, -h, -h,
                                         species, S.plant_seed);
  S.cycle = 0;
  S.picked = -1;
  printf("studio: planted %zu trees\n", planted);
  regrow_preview();
}

void step(uint32_t n) {
  if (!S.original) plant();
  double t0 = now_ms();
  S.original->step(n);
  S.step_ms = now_ms() - t0;
  S.cycle += n;
  regrow_preview();
}

void follow() {
  if (!S.original) return;
  for (size_t s = 0; s < S.slots.size(); s++) S.original->set_species((uint32_t)s, S.slots[s].params);
  regrow_preview();
}

int add_slot(const std::string &name) {
  Slot s;
  if (!species_by_name(name, &s.species)) throw std::runtime_error("unknown species " + name);
  s.name = name;
  s.params = arbor::species(s.species);
  memcpy(s.colour, kColours[S.slots.size() % 8], sizeof s.colour);
  if (p_glGenTextures) {
    s.bark_tex = species_texture(s.species, ARBOR_TEXTURE_BARK_COLOR, 256, GL_TEXTURE1);
    s.atlas_tex = species_texture(s.species, ARBOR_TEXTURE_LEAF_ATLAS, 256, GL_TEXTURE2);
  }
  S.slots.push_back(s);
  return (int)S.slots.size() - 1;
}

int slot_by_name(const std::string &name) {
  for (size_t k = 0; k < S.slots.size(); k++)
    if (S.slots[k].name == name) return (int)k;
  return add_slot(name);
}

/* Paints the map cells whose centres lie in the world rectangle. */
void paint_rect(int slot, float x0, float z0, float x1, float z1, float per_100m2) {
  float h = S.half(), c = 2 * h / (float)S.map_n;
  for (uint32_t j = 0; j < S.map_n; j++)
    for (uint32_t i = 0; i < S.map_n; i++) {
      float x = -h + ((float)i + 0.5f) * c, z = -h + ((float)j + 0.5f) * c;
      if (x < std::min(x0, x1) || x > std::max(x0, x1) || z < std::min(z0, z1) || z > std::max(z0, z1)) continue;
      S.map_slots[(size_t)j * S.map_n + i] = slot < 0 ? UINT32_MAX : (uint32_t)slot;
      S.map_density[(size_t)j * S.map_n + i] = per_100m2 / 100.0f;
    }
}

void reset_map() {
  S.map_slots.assign((size_t)S.map_n * S.map_n, UINT32_MAX);
  S.map_density.assign((size_t)S.map_n * S.map_n, S.brush_density / 100.0f);
}

/* A species map from a PNG (8-bit RGB or RGBA; each pixel a cell) and its legend. */
void load_map(const std::string &path, const std::string &legend, float per_100m2) {
  FILE *f = fopen(path.c_str(), "rb");
  if (!f) throw std::runtime_error("cannot read " + path);
  png_structp png = png_create_read_struct(PNG_LIBPNG_VER_STRING, nullptr, nullptr, nullptr);
  png_infop info = png_create_info_struct(png);
  if (setjmp(png_jmpbuf(png))) {
    fclose(f);
    throw std::runtime_error(path + ": not a PNG the studio reads");
  }
  png_init_io(png, f);
  png_read_info(png, info);
  uint32_t w = png_get_image_width(png, info), h = png_get_image_height(png, info);
  if (w != h || w < 2 || w > 1024) {
    png_destroy_read_struct(&png, &info, nullptr);
    fclose(f);
    throw std::runtime_error(path + ": the map must be square, 2 to 1024 pixels");
  }
  png_set_expand(png);
  png_set_strip_16(png);
  png_set_gray_to_rgb(png);
  png_set_strip_alpha(png);
  png_read_update_info(png, info);
  std::vector<uint8_t> rgb((size_t)w * h * 3);
  std::vector<png_bytep> rows(h);
  for (uint32_t y = 0; y < h; y++) rows[y] = rgb.data() + (size_t)y * w * 3;
  png_read_image(png, rows.data());
  png_destroy_read_struct(&png, &info, nullptr);
  fclose(f);
  /* The legend: RRGGBB=SPECIES, comma separated. */
  std::map<uint32_t, int> colour_slot;
  std::stringstream ss(legend);
  std::string item;
  while (std::getline(ss, item, ',')) {
    size_t eq = item.find('=');
    if (eq != 6) throw std::runtime_error("legend item " + item + ": expected RRGGBB=SPECIES");
    colour_slot[(uint32_t)std::stoul(item.substr(0, 6), nullptr, 16)] = slot_by_name(item.substr(7));
  }
  S.map_n = w;
  reset_map();
  for (size_t k = 0; k < (size_t)w * h; k++) {
    uint32_t c = (uint32_t)rgb[3 * k] << 16 | (uint32_t)rgb[3 * k + 1] << 8 | rgb[3 * k + 2];
    auto it = colour_slot.find(c);
    S.map_slots[k] = it == colour_slot.end() ? UINT32_MAX : (uint32_t)it->second;
    S.map_density[k] = per_100m2 / 100.0f;
  }
}

bool set_param(Slot &s, const std::string &field, float value) {
  for (const Field &f : kFields)
    if (field == f.name) {
      char *p = reinterpret_cast<char *>(&s.params) + f.offset;
      if (f.integer) {
        uint32_t v = (uint32_t)value;
        memcpy(p, &v, 4);
      } else {
        memcpy(p, &value, 4);
      }
      return true;
    }
  return false;
}

/* ---- drawing ---- */

/* Wind: a branch sways with its place along it, less the lower its order, out of step by
   its phase; leaves flutter. */
#define WIND_GLSL                                                                          \
  "uniform float u_time, u_wind;\n"                                                        \
  "vec3 sway(vec3 p, vec4 a) {\n"                                                          \
  "  float s = sin(u_time * 1.3 + a.w * 6.2832) * a.z * a.z * (0.15 + 0.25 * a.y);\n"      \
  "  float f = a.y >= 3.0 ? 0.05 * sin(u_time * 7.0 + a.w * 40.0) : 0.0;\n"              \
  "  return p + u_wind * vec3(s + f, 0.0, 0.4 * s - f);\n"                                \
  "}\n"

const char *kVs =
    "#version 430 core\n"
    "layout(location = 0) in vec3 a_pos;\n"
    "layout(location = 1) in vec3 a_normal;\n"
    "layout(location = 2) in vec2 a_uv;\n"
    "layout(location = 3) in vec4 a_anim;\n" /* growth, order, along, phase */
    WIND_GLSL
    "uniform mat4 u_view_proj, u_light_vp;\n"
    "out vec3 v_normal, v_pos;\n"
    "out vec2 v_uv;\n"
    "out vec4 v_light;\n"
    "out float v_growth;\n"
    "void main() {\n"
    "  vec3 p = sway(a_pos, a_anim);\n"
    "  v_normal = a_normal; v_uv = a_uv; v_pos = p; v_growth = a_anim.x;\n"
    "  v_light = u_light_vp * vec4(p, 1.0);\n"
    "  gl_Position = u_view_proj * vec4(p, 1.0);\n"
    "}\n";

const char *kFs =
    "#version 430 core\n"
    "in vec3 v_normal, v_pos;\n"
    "in vec2 v_uv;\n"
    "in vec4 v_light;\n"
    "in float v_growth;\n"
    "uniform float u_growth;\n"
    "uniform int u_mode;\n" /* 0 terrain, 1 bark, 2 leaves */
    "uniform vec3 u_sun;\n"
    "uniform int u_shadows;\n"
    "uniform sampler2D u_bark, u_atlas_tex, u_shadow;\n"
    "out vec4 color;\n"
    "float lit() {\n"
    "  if (u_shadows == 0) return 1.0;\n"
    "  vec3 p = v_light.xyz / v_light.w * 0.5 + 0.5;\n"
    "  if (p.x < 0.0 || p.x > 1.0 || p.y < 0.0 || p.y > 1.0) return 1.0;\n"
    "  float s = 0.0; vec2 t = 1.0 / vec2(textureSize(u_shadow, 0));\n"
    "  for (int i = -1; i <= 1; i++) for (int j = -1; j <= 1; j++)\n"
    "    s += p.z - 0.002 > texture(u_shadow, p.xy + vec2(i, j) * t).r ? 0.0 : 1.0;\n"
    "  return s / 9.0;\n"
    "}\n"
    "void main() {\n"
    "  if (v_growth > u_growth) discard;\n"
    "  vec3 n = normalize(v_normal);\n"
    "  vec3 base;\n"
    "  if (u_mode == 0) {\n"
    "    float g = 0.5 + 0.5 * sin(v_uv.x * 0.7) * sin(v_uv.y * 0.9);\n"
    "    base = mix(vec3(0.24, 0.33, 0.14), vec3(0.34, 0.40, 0.18), g);\n"
    "    base = mix(vec3(0.42, 0.36, 0.28), base, smoothstep(0.7, 0.9, n.y));\n"
    "  } else if (u_mode == 1) {\n"
    "    base = texture(u_bark, v_uv).rgb;\n"
    "  } else {\n"
    /* Coverage from the full-size level: mipmapped alpha of thin needles falls below the
       cut at a distance and whole crowns would vanish. */
    "    vec4 a = texture(u_atlas_tex, v_uv);\n"
    "    if (textureLod(u_atlas_tex, v_uv, 0.0).a < 0.5) discard;\n"
    "    base = a.rgb;\n"
    "    if (!gl_FrontFacing) n = -n;\n"
    "  }\n"
    "  float d = max(dot(n, u_sun), 0.0);\n"
    "  if (u_mode == 2) d = 0.35 + 0.65 * abs(dot(n, u_sun));\n"
    "  vec3 sky = vec3(0.36, 0.42, 0.50) * (0.6 + 0.4 * n.y);\n"
    "  color = vec4(base * (sky + vec3(1.0, 0.95, 0.85) * d * lit()), 1.0);\n"
    "}\n";

const char *kShadowVs =
    "#version 430 core\n"
    "layout(location = 0) in vec3 a_pos;\n"
    "layout(location = 2) in vec2 a_uv;\n"
    "layout(location = 3) in vec4 a_anim;\n"
    WIND_GLSL
    "uniform mat4 u_light_vp;\n"
    "out vec2 v_uv;\n"
    "out float v_growth;\n"
    "void main() { v_uv = a_uv; v_growth = a_anim.x; gl_Position = u_light_vp * vec4(sway(a_pos, a_anim), 1.0); }\n";

const char *kShadowFs =
    "#version 430 core\n"
    "in vec2 v_uv;\n"
    "in float v_growth;\n"
    "uniform float u_growth;\n"
    "uniform int u_mode;\n"
    "uniform sampler2D u_atlas_tex;\n"
    "void main() {\n"
    "  if (v_growth > u_growth || (u_mode == 2 && textureLod(u_atlas_tex, v_uv, 0.0).a < 0.5)) discard;\n"
    "}\n";

const int kShadowSize = 2048;

void init_gl() {
  S.program = link_program(kVs, kFs);
  S.shadow_program = link_program(kShadowVs, kShadowFs);
  S.shadow_fbo = shadow_map(kShadowSize, &S.shadow_tex);
}

void sun_dir(float out[3]) {
  float az = S.sun_azimuth * 0.0174533f, el = S.sun_elevation * 0.0174533f;
  out[0] = std::cos(el) * std::cos(az);
  out[1] = std::sin(el);
  out[2] = std::cos(el) * std::sin(az);
}

Mat4 light_view_proj() {
  float d[3];
  sun_dir(d);
  float r = S.half() * 1.5f + 10.0f;
  float eye[3] = {d[0] * r * 2, d[1] * r * 2, d[2] * r * 2}, at[3] = {0, 0, 0};
  return mat_mul(orthographic(-r, r, -r, r, 0.1f, r * 4), look_at(eye, at));
}

void draw_scene(GLuint program, bool shadow_pass) {
  GLint mode = p_glGetUniformLocation(program, "u_mode");
  p_glUniform1i(mode, 0);
  if (!shadow_pass) {
    p_glBindVertexArray(S.terrain.vao);
    p_glDrawElements(GL_TRIANGLES, S.terrain.count, GL_UNSIGNED_INT, nullptr);
  }
  for (size_t s = 0; s < S.slots.size() && s < S.bark.size(); s++) {
    p_glActiveTexture(GL_TEXTURE1);
    p_glBindTexture(GL_TEXTURE_2D, S.slots[s].bark_tex);
    p_glActiveTexture(GL_TEXTURE2);
    p_glBindTexture(GL_TEXTURE_2D, S.slots[s].atlas_tex);
    p_glActiveTexture(GL_TEXTURE0);
    p_glUniform1i(mode, 1);
    p_glBindVertexArray(S.bark[s].vao);
    p_glDrawElements(GL_TRIANGLES, S.bark[s].count, GL_UNSIGNED_INT, nullptr);
    if (S.leaves && S.leaf[s].count > 0) {
      p_glUniform1i(mode, 2);
      p_glDisable(GL_CULL_FACE);
      p_glBindVertexArray(S.leaf[s].vao);
      p_glDrawElements(GL_TRIANGLES, S.leaf[s].count, GL_UNSIGNED_INT, nullptr);
      p_glEnable(GL_CULL_FACE);
    }
  }
}

/* The growth threshold (1: all grown) and the wind's time and strength. */
void set_motion(GLuint program) {
  p_glUniform1f(p_glGetUniformLocation(program, "u_growth"), S.growth);
  p_glUniform1f(p_glGetUniformLocation(program, "u_time"), (float)S.time);
  p_glUniform1f(p_glGetUniformLocation(program, "u_wind"), S.wind);
}

void draw_world(int w, int h) {
  if (S.geometry_dirty) rebuild_geometry();
  Mat4 lvp = light_view_proj();
  p_glEnable(GL_DEPTH_TEST);
  p_glEnable(GL_CULL_FACE);
  if (S.shadows) {
    p_glBindFramebuffer(GL_FRAMEBUFFER, S.shadow_fbo);
    p_glViewport(0, 0, kShadowSize, kShadowSize);
    p_glClear(GL_DEPTH_BUFFER_BIT);
    p_glUseProgram(S.shadow_program);
    p_glUniformMatrix4fv(p_glGetUniformLocation(S.shadow_program, "u_light_vp"), 1, GL_FALSE, lvp.m);
    p_glUniform1i(p_glGetUniformLocation(S.shadow_program, "u_atlas_tex"), 2);
    set_motion(S.shadow_program);
    draw_scene(S.shadow_program, true);
    p_glBindFramebuffer(GL_FRAMEBUFFER, 0);
  }
  p_glViewport(0, 0, w, h);
  p_glClearColor(0.62f, 0.74f, 0.86f, 1.0f);
  p_glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
  float r = S.half() * 1.9f / S.zoom + 8.0f;
  float eye[3] = {r * std::cos(S.pitch) * std::sin(S.yaw), S.height_scale * 0.5f + r * std::sin(S.pitch),
                  r * std::cos(S.pitch) * std::cos(S.yaw)};
  float at[3] = {0, S.height_scale * 0.5f, 0};
  Mat4 vp = mat_mul(perspective(0.8f, (float)w / (float)(h > 0 ? h : 1), 0.5f, r * 4), look_at(eye, at));
  p_glUseProgram(S.program);
  p_glUniformMatrix4fv(p_glGetUniformLocation(S.program, "u_view_proj"), 1, GL_FALSE, vp.m);
  p_glUniformMatrix4fv(p_glGetUniformLocation(S.program, "u_light_vp"), 1, GL_FALSE, lvp.m);
  float d[3];
  sun_dir(d);
  p_glUniform3f(p_glGetUniformLocation(S.program, "u_sun"), d[0], d[1], d[2]);
  p_glUniform1i(p_glGetUniformLocation(S.program, "u_shadows"), S.shadows ? 1 : 0);
  p_glUniform1i(p_glGetUniformLocation(S.program, "u_bark"), 1);
  p_glUniform1i(p_glGetUniformLocation(S.program, "u_atlas_tex"), 2);
  p_glUniform1i(p_glGetUniformLocation(S.program, "u_shadow"), 3);
  set_motion(S.program);
  p_glActiveTexture(GL_TEXTURE3);
  p_glBindTexture(GL_TEXTURE_2D, S.shadow_tex);
  p_glActiveTexture(GL_TEXTURE0);
  draw_scene(S.program, false);
  p_glBindVertexArray(0);
  p_glDisable(GL_CULL_FACE);
}

/* ---- the windows ---- */

void export_world(const std::string &path, bool picked_only) {
  arbor::World *w = S.shown();
  if (!w) throw std::runtime_error("nothing to export: plant first");
  ArborMeshOptions mo = mesh_options();
  ArborLeafOptions lo = arbor::leaf_options();
  if (picked_only) {
    if (S.picked < 0) throw std::runtime_error("nothing picked");
    uint32_t slot = w->tree_slot((size_t)S.picked);
    arbor::Tree t = shaped(*w, (size_t)S.picked, S.slots[slot]);
    ArborLeafOptions pl = species_leaves(S.slots[slot].species, t, (uint32_t)S.picked);
    arbor::detail::check(arbor_export_gltf(t.get(), &mo, &pl, path.c_str()));
  } else {
    std::vector<std::string> names;
    for (const Slot &s : S.slots) names.push_back(s.name);
    w->export_gltf(path, names, mo, &lo, 256, true);
  }
  printf("studio: wrote %s\n", path.c_str());
}

bool species_window() {
  bool changed = false;
  ImGui::SetNextWindowPos(ImVec2(10, 10), ImGuiCond_FirstUseEver);
  ImGui::SetNextWindowSize(ImVec2(330, 260), ImGuiCond_FirstUseEver);
  ImGui::Begin("Species");
  static int add = 0;
  const char *names[8];
  for (int k = 0; k < 8; k++) names[k] = arbor_species_name(kNamed[k]);
  ImGui::Combo("##add", &add, names, 8);
  ImGui::SameLine();
  if (ImGui::Button("Add")) add_slot(names[add]);
  for (size_t s = 0; s < S.slots.size(); s++) {
    Slot &sl = S.slots[s];
    ImGui::PushID((int)s);
    ImGui::ColorEdit3("##c", sl.colour, ImGuiColorEditFlags_NoInputs);
    ImGui::SameLine();
    if (ImGui::CollapsingHeader((sl.name + " (slot " + std::to_string(s) + ")").c_str())) {
      if (ImGui::Button("Reset to preset")) sl.params = arbor::species(sl.species), changed = true;
      ImGui::SameLine();
      if (ImGui::Button("Duplicate")) {
        Slot copy = sl;
        memcpy(copy.colour, kColours[S.slots.size() % 8], sizeof copy.colour);
        S.slots.push_back(copy);
        ImGui::PopID();
        break;
      }
      for (const Field &f : kFields) {
        char *p = reinterpret_cast<char *>(&sl.params) + f.offset;
        if (f.integer) {
          int v = (int)*reinterpret_cast<uint32_t *>(p);
          if (ImGui::SliderInt(f.name, &v, (int)f.lo, (int)f.hi)) {
            *reinterpret_cast<uint32_t *>(p) = (uint32_t)v;
            changed = true;
          }
        } else if (ImGui::SliderFloat(f.name, reinterpret_cast<float *>(p), f.lo, f.hi, "%.3f")) {
          changed = true;
        }
      }
    }
    ImGui::PopID();
  }
  ImGui::End();
  return changed;
}

/* The map: a cell a square, coloured by species, brighter with density; left drag paints. */
void map_window(bool full) {
  if (full) {
    ImGui::SetNextWindowPos(ImVec2(0, 0));
    ImGui::SetNextWindowSize(ImVec2((float)S.width, (float)S.height));
  } else {
    ImGui::SetNextWindowPos(ImVec2((float)S.width - 310, 10), ImGuiCond_FirstUseEver);
    ImGui::SetNextWindowSize(ImVec2(300, 400), ImGuiCond_FirstUseEver);
  }
  ImGui::Begin("Map");
  ImGui::RadioButton("none", &S.brush_slot, -1);
  for (size_t s = 0; s < S.slots.size(); s++) {
    ImGui::SameLine();
    ImGui::RadioButton(S.slots[s].name.c_str(), &S.brush_slot, (int)s);
  }
  ImGui::SliderInt("brush", &S.brush_radius, 0, 10);
  ImGui::SliderFloat("trees / 100 m2", &S.brush_density, 0.1f, 10.0f);
  if (ImGui::Button("Plant")) plant();
  ImGui::SameLine();
  if (ImGui::Button("Clear")) reset_map();
  ImVec2 avail = ImGui::GetContentRegionAvail();
  float side = std::min(avail.x, avail.y);
  float c = side / (float)S.map_n;
  ImVec2 o = ImGui::GetCursorScreenPos();
  ImDrawList *dl = ImGui::GetWindowDrawList();
  for (uint32_t j = 0; j < S.map_n; j++)
    for (uint32_t i = 0; i < S.map_n; i++) {
      size_t k = (size_t)j * S.map_n + i;
      uint32_t s = S.map_slots[k];
      ImVec4 col(0.15f, 0.17f, 0.12f, 1.0f);
      if (s < S.slots.size()) {
        float d = std::min(1.0f, 0.35f + S.map_density[k] * 100.0f / 8.0f);
        col = ImVec4(S.slots[s].colour[0] * d, S.slots[s].colour[1] * d, S.slots[s].colour[2] * d, 1.0f);
      }
      dl->AddRectFilled(ImVec2(o.x + i * c, o.y + j * c), ImVec2(o.x + (i + 1) * c, o.y + (j + 1) * c),
                        ImGui::ColorConvertFloat4ToU32(col));
    }
  /* Trees of the shown world as dots. */
  float h = S.half();
  for (const TreeStats &t : S.stats) {
    if (t.branches == 0) continue;
    float x = (t.root[0] + h) / (2 * h) * side, y = (t.root[2] + h) / (2 * h) * side;
    dl->AddCircleFilled(ImVec2(o.x + x, o.y + y), std::max(1.5f, c * 0.3f), IM_COL32(20, 20, 10, 255));
  }
  ImGui::InvisibleButton("map", ImVec2(side, side));
  if (ImGui::IsItemActive() && ImGui::IsMouseDown(ImGuiMouseButton_Left)) {
    ImVec2 m = ImGui::GetMousePos();
    int ci = (int)((m.x - o.x) / c), cj = (int)((m.y - o.y) / c);
    for (int dj = -S.brush_radius; dj <= S.brush_radius; dj++)
      for (int di = -S.brush_radius; di <= S.brush_radius; di++) {
        int i = ci + di, j = cj + dj;
        if (i < 0 || j < 0 || i >= (int)S.map_n || j >= (int)S.map_n || di * di + dj * dj > S.brush_radius * S.brush_radius)
          continue;
        size_t k = (size_t)j * S.map_n + i;
        S.map_slots[k] = S.brush_slot < 0 ? UINT32_MAX : (uint32_t)S.brush_slot;
        S.map_density[k] = S.brush_density / 100.0f;
      }
  }
  ImGui::End();
}

void growth_window() {
  ImGui::SetNextWindowPos(ImVec2(10, 280), ImGuiCond_FirstUseEver);
  ImGui::SetNextWindowSize(ImVec2(330, 150), ImGuiCond_FirstUseEver);
  ImGui::Begin("Growth");
  ImGui::Text("cycle %u%s", S.cycle, S.running ? " (running)" : "");
  if (ImGui::Button("Step")) step(1);
  ImGui::SameLine();
  if (ImGui::Button(S.running ? "Pause" : "Run")) S.running = !S.running;
  ImGui::SameLine();
  if (ImGui::Button("Replant")) plant();
  int ahead = (int)S.ahead;
  if (ImGui::SliderInt("preview ahead", &ahead, 0, 30)) {
    S.ahead = (uint32_t)ahead;
    regrow_preview();
  }
  if (ImGui::Button("Original follows")) follow();
  ImGui::SameLine();
  if (ImGui::Button("Export forest.glb")) export_world("forest.glb", false);
  ImGui::End();
}

void stats_window() {
  ImGui::SetNextWindowPos(ImVec2((float)S.width - 530, (float)S.height - 170), ImGuiCond_FirstUseEver);
  ImGui::SetNextWindowSize(ImVec2(520, 160), ImGuiCond_FirstUseEver);
  ImGui::Begin("Stats");
  size_t branches = 0, leaves = 0, alive = 0;
  for (const TreeStats &t : S.stats) branches += t.branches, leaves += t.leaves, alive += t.branches > 0;
  ImGui::Text("%s world: %zu trees (%zu alive), %zu branches, %zu leaves",
              S.shown() == S.preview.get() ? "preview" : "original", S.stats.size(), alive, branches, leaves);
  ImGui::Text("growth step %.1f ms, meshing %.1f ms, frame %.1f ms, %.1f MB on the GPU", S.step_ms, S.mesh_ms,
              S.frame_ms, (double)S.gpu_bytes / 1e6);
  if (ImGui::BeginTable("trees", 5, ImGuiTableFlags_ScrollY | ImGuiTableFlags_RowBg)) {
    ImGui::TableSetupColumn("tree");
    ImGui::TableSetupColumn("species");
    ImGui::TableSetupColumn("age");
    ImGui::TableSetupColumn("branches");
    ImGui::TableSetupColumn("leaves");
    ImGui::TableHeadersRow();
    for (size_t k = 0; k < S.stats.size(); k++) {
      const TreeStats &t = S.stats[k];
      ImGui::TableNextRow();
      ImGui::TableNextColumn();
      char label[32];
      snprintf(label, sizeof label, "%zu", k);
      if (ImGui::Selectable(label, S.picked == (int)k, ImGuiSelectableFlags_SpanAllColumns)) S.picked = (int)k;
      ImGui::TableNextColumn();
      ImGui::TextUnformatted(t.slot < S.slots.size() ? S.slots[t.slot].name.c_str() : "?");
      ImGui::TableNextColumn();
      ImGui::Text("%u", t.age);
      ImGui::TableNextColumn();
      ImGui::Text("%zu", t.branches);
      ImGui::TableNextColumn();
      ImGui::Text("%zu", t.leaves);
    }
    ImGui::EndTable();
  }
  ImGui::End();
}

void view_window() {
  ImGui::SetNextWindowPos(ImVec2(10, 440), ImGuiCond_FirstUseEver);
  ImGui::SetNextWindowSize(ImVec2(330, 170), ImGuiCond_FirstUseEver);
  ImGui::Begin("View");
  ImGui::SliderFloat("sun azimuth", &S.sun_azimuth, 0, 360);
  ImGui::SliderFloat("sun elevation", &S.sun_elevation, 5, 90);
  ImGui::Checkbox("shadows", &S.shadows);
  ImGui::SliderFloat("wind", &S.wind, 0, 3);
  if (ImGui::Button("Replay growth (G)")) S.growth = 0, S.replaying = true;
  ImGui::SameLine();
  ImGui::SliderFloat("growth", &S.growth, 0, 1);
  if (ImGui::Checkbox("leaves", &S.leaves)) S.geometry_dirty = true;
  ImGui::End();
}

void ui(bool map_full) {
  ImGui_ImplOpenGL3_NewFrame();
  ImGui_ImplGlfw_NewFrame();
  ImGui::NewFrame();
  if (map_full) {
    map_window(true);
  } else if (S.show_ui) {
    if (species_window()) S.params_dirty = true;
    if (S.show_map) map_window(false);
    growth_window();
    stats_window();
    view_window();
  }
  ImGui::Render();
}

void frame(GLFWwindow *win, bool map_full) {
  double t0 = now_ms();
  int w, h;
  glfwGetFramebufferSize(win, &w, &h);
  S.width = w;
  S.height = h;
  ui(map_full);
  if (S.params_dirty) regrow_preview();
  draw_world(w, h);
  ImGui_ImplOpenGL3_RenderDrawData(ImGui::GetDrawData());
  p_glFinish();
  S.frame_ms = now_ms() - t0;
}

/* ---- the script ---- */

void write_stats(const std::string &path) {
  std::ofstream f(path);
  if (!f) throw std::runtime_error("cannot write " + path);
  f << "# world tree species slot x y z branches hash\n";
  f.precision(9);
  for (int which = 0; which < 2; which++) {
    arbor::World *w = which == 0 ? S.original.get() : S.preview.get();
    if (!w) continue;
    std::vector<TreeStats> st = world_stats(*w, S.cycle);
    for (size_t k = 0; k < st.size(); k++) {
      const TreeStats &t = st[k];
      f << (which == 0 ? "original " : "preview ") << k << ' '
        << (t.slot < S.slots.size() ? S.slots[t.slot].name : "?") << ' ' << t.slot << ' ' << t.root[0] << ' '
        << t.root[1] << ' ' << t.root[2] << ' ' << t.branches << ' ' << t.hash << '\n';
    }
  }
  printf("studio: wrote %s\n", path.c_str());
}

void screenshot(GLFWwindow *win, const std::string &path, bool map_full) {
  /* Two frames: ImGui lays its windows out on the first. */
  frame(win, map_full);
  frame(win, map_full);
  if (!save_image(path.c_str(), S.width, S.height)) throw std::runtime_error("screenshot failed");
  size_t trees = S.shown() ? S.shown()->tree_count() : 0, branches = 0, leaves = 0;
  for (const TreeStats &t : S.stats) branches += t.branches, leaves += t.leaves;
  printf("studio: frame %.1f ms (meshing %.1f ms before it), %zu trees, %zu branches, %zu leaves, %.1f MB on the GPU\n",
         S.frame_ms, S.mesh_ms, trees, branches, leaves, (double)S.gpu_bytes / 1e6);
}

void run_line(GLFWwindow *win, const std::string &line) {
  std::istringstream in(line);
  std::string cmd;
  if (!(in >> cmd) || cmd[0] == '#') return;
  auto need = [&](bool ok) {
    if (!ok) throw std::runtime_error("script: bad line: " + line);
  };
  if (cmd == "heightmap") {
    std::string path;
    need(bool(in >> path));
    in >> S.height_scale >> S.cell;
    load_heightmap(path);
    rebuild_terrain();
    S.original.reset();
  } else if (cmd == "noise") {
    need(bool(in >> S.noise_seed));
    S.heightmap_png.clear();
    make_noise_terrain();
    rebuild_terrain();
  } else if (cmd == "species") {
    std::string name;
    need(bool(in >> name));
    slot_by_name(name);
  } else if (cmd == "paint") {
    std::string name;
    float x0, z0, x1, z1, d = S.brush_density;
    need(bool(in >> name >> x0 >> z0 >> x1 >> z1));
    in >> d;
    paint_rect(name == "none" ? -1 : slot_by_name(name), x0, z0, x1, z1, d);
  } else if (cmd == "plant") {
    in >> S.plant_seed;
    plant();
  } else if (cmd == "step") {
    uint32_t n = 0;
    need(bool(in >> n));
    step(n);
    printf("studio: cycle %u, %zu trees, step %.1f ms\n", S.cycle, S.original->tree_count(), S.step_ms);
  } else if (cmd == "ahead") {
    need(bool(in >> S.ahead));
    regrow_preview();
  } else if (cmd == "set") {
    std::string name, field;
    float v;
    need(bool(in >> name >> field >> v));
    need(set_param(S.slots[(size_t)slot_by_name(name)], field, v));
    regrow_preview();
  } else if (cmd == "ui") {
    std::string v;
    need(bool(in >> v) && (v == "on" || v == "off"));
    S.show_ui = v == "on";
  } else if (cmd == "growth") {
    need(bool(in >> S.growth));
  } else if (cmd == "wind") {
    need(bool(in >> S.wind >> S.time));
  } else if (cmd == "follow") {
    follow();
  } else if (cmd == "pick") {
    need(bool(in >> S.picked));
    need(S.picked >= 0 && (size_t)S.picked < S.stats.size());
    if (S.geometry_dirty) rebuild_geometry(); /* where the leaves are counted */
    const TreeStats &t = S.stats[(size_t)S.picked];
    printf("studio: tree %d: %s, age %u, %zu branches, %zu leaves\n", S.picked, S.slots[t.slot].name.c_str(), t.age,
           t.branches, t.leaves);
  } else if (cmd == "export") {
    std::string path, which;
    need(bool(in >> path));
    in >> which;
    export_world(path, which == "picked");
  } else if (cmd == "stats") {
    std::string path;
    need(bool(in >> path));
    write_stats(path);
  } else if (cmd == "screenshot" || cmd == "map-screenshot") {
    std::string path;
    need(bool(in >> path));
    screenshot(win, path, cmd == "map-screenshot");
  } else {
    need(false);
  }
}

/* ---- input ---- */

/* Installed before ImGui's GLFW backend, which calls them after its own. */
void on_key(GLFWwindow *win, int key, int, int action, int) {
  if (action != GLFW_PRESS || ImGui::GetIO().WantCaptureKeyboard) return;
  try {
    switch (key) {
      case GLFW_KEY_ESCAPE: glfwSetWindowShouldClose(win, 1); break;
      case GLFW_KEY_SPACE: step(1); break;
      case GLFW_KEY_R: S.running = !S.running; break;
      case GLFW_KEY_BACKSPACE: plant(); break;
      case GLFW_KEY_M: S.show_map = !S.show_map; break;
      case GLFW_KEY_P: S.ahead = S.ahead ? 0 : 10, regrow_preview(); break;
      case GLFW_KEY_F: follow(); break;
      case GLFW_KEY_L: S.sun_azimuth = std::fmod(S.sun_azimuth + 15.0f, 360.0f); break;
      case GLFW_KEY_E: export_world("forest.glb", false); break;
      case GLFW_KEY_G: S.growth = 0, S.replaying = true; break;
      case GLFW_KEY_H: S.show_ui = !S.show_ui; break;
      default: break;
    }
  } catch (const std::exception &e) {
    fprintf(stderr, "studio: %s\n", e.what());
  }
}

void on_button(GLFWwindow *win, int button, int action, int) {
  if (button == GLFW_MOUSE_BUTTON_RIGHT && !ImGui::GetIO().WantCaptureMouse) {
    S.orbiting = action == GLFW_PRESS;
    glfwGetCursorPos(win, &S.mouse_x, &S.mouse_y);
  }
}

void on_move(GLFWwindow *, double x, double y) {
  if (S.orbiting) orbit_drag(&S.yaw, &S.pitch, &S.mouse_x, &S.mouse_y, x, y, 0.05f, 1.45f);
}

void on_scroll(GLFWwindow *, double, double dy) {
  if (!ImGui::GetIO().WantCaptureMouse) S.zoom = orbit_zoom(S.zoom, dy);
}

}  // namespace

int main(int argc, char **argv) {
  glapp_name = "studio";
  std::string heightmap, map, legend, export_path, shot, script;
  uint32_t steps = 0;
  float density = 2.0f;
  bool noise = false;
  for (int i = 1; i < argc; i++) {
    std::string a = argv[i];
    auto next = [&]() -> std::string {
      if (i + 1 >= argc) {
        fprintf(stderr, "studio: %s needs a value\n", a.c_str());
        exit(2);
      }
      return argv[++i];
    };
    if (a == "--heightmap") heightmap = next();
    else if (a == "--height-scale") S.height_scale = std::stof(next());
    else if (a == "--cell") S.cell = std::stof(next());
    else if (a == "--noise") S.noise_seed = (uint32_t)std::stoul(next()), noise = true;
    else if (a == "--map") map = next();
    else if (a == "--legend") legend = next();
    else if (a == "--density") density = std::stof(next());
    else if (a == "--seed") S.plant_seed = std::stoull(next());
    else if (a == "--steps") steps = (uint32_t)std::stoul(next());
    else if (a == "--export") export_path = next();
    else if (a == "--screenshot") shot = next();
    else if (a == "--script") script = next();
    else if (a == "--size") sscanf(next().c_str(), "%dx%d", &S.width, &S.height);
    else {
      fprintf(stderr,
              "usage: studio [--heightmap PNG [--height-scale H] [--cell C]] [--noise SEED] [--map PNG --legend "
              "RRGGBB=SPECIES,...] [--density D] [--seed S] [--steps N] [--export FILE.glb] [--screenshot FILE.png] "
              "[--size WxH] [--script FILE]\n");
      return 2;
    }
  }
  bool headless = !shot.empty() || !script.empty();
  GLFWwindow *win = open_window("arbor studio", S.width, S.height, 4, 3, headless);
  if (!win || !load_gl()) return 1;
  IMGUI_CHECKVERSION();
  ImGui::CreateContext();
  ImGui::GetIO().IniFilename = nullptr;
  ImGui::StyleColorsDark();
  glfwSetKeyCallback(win, on_key);
  glfwSetMouseButtonCallback(win, on_button);
  glfwSetCursorPosCallback(win, on_move);
  glfwSetScrollCallback(win, on_scroll);
  ImGui_ImplGlfw_InitForOpenGL(win, true);
  ImGui_ImplOpenGL3_Init("#version 430");
  init_gl();
  int status = 0;
  try {
    if (!heightmap.empty()) load_heightmap(heightmap);
    if (heightmap.empty() || noise) make_noise_terrain();
    rebuild_terrain();
    reset_map();
    if (!map.empty()) {
      load_map(map, legend, density);
    } else if (script.empty()) {
      /* A default forest: oaks west, pines east. */
      float h = S.half();
      paint_rect(slot_by_name("oak"), -h, -h, -2, h, density);
      paint_rect(slot_by_name("pine"), 2, -h, h, h, density);
    }
    if (script.empty()) plant();
    if (steps > 0) step(steps);
    if (!script.empty()) {
      std::ifstream f(script);
      if (!f) throw std::runtime_error("cannot read " + script);
      std::string line;
      while (std::getline(f, line)) run_line(win, line);
    }
    if (!export_path.empty()) export_world(export_path, false);
    if (!shot.empty()) screenshot(win, shot, false);
    while (!headless && !glfwWindowShouldClose(win)) {
      glfwPollEvents();
      if (S.running) step(1);
      S.time = glfwGetTime();
      if (S.replaying) {
        S.growth = std::min(1.0f, S.growth + 0.004f);
        S.replaying = S.growth < 1.0f;
      }
      frame(win, false);
      glfwSwapBuffers(win);
    }
  } catch (const std::exception &e) {
    fprintf(stderr, "studio: %s\n", e.what());
    status = 1;
  }
  ImGui_ImplOpenGL3_Shutdown();
  ImGui_ImplGlfw_Shutdown();
  ImGui::DestroyContext();
  glfwDestroyWindow(win);
  glfwTerminate();
  return status;
}
