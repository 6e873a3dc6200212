// The C++ wrapper: RAII, exceptions, spans, and an Unreal-style fill of
// CreateMeshSection arrays (Z up, centimetres, clockwise) from the triangle list.
#include "arbor.hpp"

#include <algorithm>

#include <cmath>
#include <cstdio>
#include <cstring>
#include <string>
#include <vector>

static int passed = 0, failed = 0;
#define EXPECT(cond, ...)                                        \
  do {                                                           \
    if (cond) {                                                  \
      passed++;                                                  \
    } else {                                                     \
      failed++;                                                  \
      std::fprintf(stderr, "%s:%d: %s: ", __FILE__, __LINE__, #cond); \
      std::fprintf(stderr, __VA_ARGS__);                         \
      std::fprintf(stderr, "\n");                                \
    }                                                            \
  } while (0)

// Stand-ins for Unreal's FVector / FVector2D / TArray, to show the fill.
struct FVector { double X, Y, Z; };
struct FVector2D { double X, Y; };

int main(int argc, char **argv) {
  const std::string dir = argc > 1 ? argv[1] : ".";
  for (char name = 'a'; name <= 'i'; name++) {
    arbor::Tree tree = arbor::Tree::honda(name);
    EXPECT(tree.branch_count() == tree.branches().size(), "tree %c", name);
    arbor::Mesh mesh = tree.mesh();
    auto size = tree.mesh_size();
    EXPECT(mesh.vertices().size() == size.first && mesh.indices().size() == size.second,
           "tree %c owned mesh sizes", name);
    // Caller-owned buffers through spans.
    std::vector<ArborVertex> v(size.first);
    std::vector<uint32_t> i(size.second);
    tree.write_mesh(arbor::mesh_options(), v, i);
    EXPECT(std::memcmp(v.data(), mesh.vertices().data(), v.size() * sizeof v[0]) == 0,
           "tree %c vertices", name);
    EXPECT(std::equal(i.begin(), i.end(), mesh.indices().begin()), "tree %c indices", name);
    // Compact vertices: the same positions and indices, v within its scale.
    std::vector<ArborVertexCompact> c(size.first);
    std::vector<uint32_t> ci(size.second);
    float v_scale = tree.write_mesh_compact(arbor::mesh_options(), c, ci);
    EXPECT(ci == i && v_scale >= 1.0f, "tree %c compact indices", name);
    bool same = true;
    for (std::size_t k = 0; k < c.size(); k++)
      same = same && std::memcmp(c[k].position, v[k].position, sizeof c[k].position) == 0 &&
             std::fabs(c[k].uv[1] / 65535.0 * v_scale - v[k].uv[1]) <= v_scale / 65535.0;
    EXPECT(same, "tree %c compact vertices", name);
  }

  // The host's own skeleton: the branches of tree c, copied back in, mesh the same.
  {
    arbor::Tree c = arbor::Tree::honda('c');
    std::vector<ArborBranch> b = c.branches();
    arbor::Tree own = arbor::Tree::from_branches(arbor::Span<const ArborBranch>(b.data(), b.size()));
    EXPECT(own.branch_count() == b.size(), "own tree count");
    EXPECT(own.mesh_size() == c.mesh_size(), "own tree mesh size");
    b[1].parent = 5;
    try {
      arbor::Tree::from_branches(arbor::Span<const ArborBranch>(b.data(), b.size()));
      EXPECT(false, "no exception for a parent after its child");
    } catch (const arbor::Error &e) {
      EXPECT(e.status() == ARBOR_STATUS_INVALID_ARGUMENT, "status %d", (int)e.status());
      EXPECT(std::string(e.what()).find("branch 1") != std::string::npos, "%s", e.what());
    }
  }

  // Curves: smooth, edit one branch, rewrite in place; equal to a full write.
  {
    arbor::Tree t = arbor::Tree::honda('b');
    t.smooth(1.0f);
    ArborMeshOptions o = arbor::mesh_options();
    o.curve_rings = 2;
    auto size = t.mesh_size(o);
    std::vector<ArborVertex> v(size.first), fresh(size.first);
    std::vector<uint32_t> ix(size.second), fresh_i(size.second);
    t.write_mesh(o, v, ix);
    std::vector<ArborCurve> curves = t.curves();
    ArborCurve e = curves.back();
    e.p3[1] += 0.5f;
    t.set_curve(curves.size() - 1, e);
    t.rewrite_branch(o, curves.size() - 1, v, ix);
    t.write_mesh(o, fresh, fresh_i);
    EXPECT(std::memcmp(v.data(), fresh.data(), v.size() * sizeof v[0]) == 0, "rewrite = full write");
    EXPECT(t.curve_records().size() == t.branch_count(), "one record per branch");
  }

  // A self-organized forest: a snapshot is an ordinary tree that meshes.
  {
    arbor::World world;
    world.plant(arbor::species(ARBOR_SPECIES_EXCURRENT), 0, 0, 0, 1);
    world.plant(arbor::species(ARBOR_SPECIES_DECURRENT), 3, 0, 0, 2);
    world.step(8);
    EXPECT(world.tree_count() == 2, "two trees");
    arbor::Tree t = world.tree(1);
    EXPECT(t.branch_count() > 50, "grown: %zu", t.branch_count());
    EXPECT(t.mesh().indices().size() > 0, "the snapshot meshes");
    try {
      world.plant(arbor::growth_params(), 500, 0, 0);
      EXPECT(false, "no exception for a plant outside the box");
    } catch (const arbor::Error &e) {
      EXPECT(e.status() == ARBOR_STATUS_INVALID_ARGUMENT, "status %d", (int)e.status());
    }
  }

  // Game assets: levels of detail with their leaves, an impostor and a billboard, the
  // collision capsules, the wind skin and its clip, through the wrapper's RAII objects.
  {
    arbor::Tree t = arbor::Tree::honda('b');
    ArborMeshOptions mo = arbor::mesh_options();
    mo.threads = 1;  // on the calling thread (the test runs under valgrind)
    ArborLeafOptions lo = arbor::leaf_options();
    lo.sites = 0;
    lo.tips = 1;
    lo.density = 3.0f;
    lo.size = 8.0f;
    arbor::Lods lods = t.lods(mo, &lo);
    EXPECT(lods.count() == 4, "%zu levels", lods.count());
    const std::size_t full = lods.level(0).triangles;
    float previous = 2.0f;
    for (std::size_t k = 0; k < lods.count(); k++) {
      arbor::Lods::Level l = lods.level(k);
      EXPECT(l.screen_coverage <= previous && l.screen_coverage > 0.0f, "level %zu coverage", k);
      previous = l.screen_coverage;
      EXPECT(k == 0 || (double)l.triangles <= 0.4 * (double)full * 1.0001, "level %zu: %zu of %zu", k,
             l.triangles, full);
      std::size_t sum = 0;
      for (uint32_t part = 0; part < 2; part++) {
        arbor::MeshData m = lods.mesh(k, part);
        EXPECT(lods.mesh_size(k, part) == std::make_pair(m.vertices.size(), m.indices.size()),
               "level %zu part %u sizes", k, part);
        EXPECT(std::all_of(m.indices.begin(), m.indices.end(),
                           [&](uint32_t i) { return i < m.vertices.size(); }),
               "level %zu part %u indices", k, part);
        sum += m.indices.size() / 3;
      }
      EXPECT(sum == l.triangles, "level %zu: %zu indexed vs %zu", k, sum, l.triangles);
    }
    // The impostor's level: every level is first drawn at least 8 pixels across, none
    // at UINT32_MAX.
    EXPECT(lods.impostor_level(8) == lods.count() - 1, "%zu", lods.impostor_level(8));
    EXPECT(lods.impostor_level(UINT32_MAX) == 0, "%zu", lods.impostor_level(UINT32_MAX));
    arbor::Impostor imp = lods.impostor(lods.impostor_level(32), 4, 32);
    EXPECT(imp.atlas_size() == 128, "atlas %u", imp.atlas_size());
    float centre[3], up[3], radius = 0.0f;
    imp.frame(centre, &radius, up);
    EXPECT(radius > 0.0f && up[1] == 1.0f, "frame: radius %f", (double)radius);
    arbor::Image albedo = imp.atlas(0);
    EXPECT(albedo.width == 128 && albedo.rgba.size() == 128u * 128u * 4u, "albedo %zu bytes",
           albedo.rgba.size());
    for (uint32_t cell = 0; cell < 16; cell++) {
      uint32_t covered = 0, x0 = (cell % 4) * 32, y0 = (cell / 4) * 32;
      for (uint32_t y = 0; y < 32; y++)
        for (uint32_t x = 0; x < 32; x++) covered += albedo.rgba[((y0 + y) * 128 + x0 + x) * 4 + 3] > 0;
      EXPECT(covered > 20, "view %u: %u pixels", cell, covered);
    }
    std::vector<uint8_t> small(128 * 128 * 4 - 1, 7);
    try {
      imp.write_atlas(1, small);
      EXPECT(false, "no exception for an atlas buffer one byte short");
    } catch (const arbor::Error &e) {
      EXPECT(e.status() == ARBOR_STATUS_BUFFER_TOO_SMALL && small[0] == 7, "status %d", (int)e.status());
    }
    arbor::Billboard bb = lods.billboard(lods.count() - 1, 3, 32);
    arbor::MeshData quads = bb.mesh(true);
    EXPECT(quads.vertices.size() == 24 && quads.indices.size() == 36, "two-sided quads: %zu, %zu",
           quads.vertices.size(), quads.indices.size());
    arbor::Image card = bb.atlas(0);
    EXPECT(card.width == 96 && card.height == 32 && card.rgba.size() == 96u * 32u * 4u, "card %u x %u",
           card.width, card.height);
    try {
      lods.level(lods.count());
      EXPECT(false, "no exception for a level past the chain");
    } catch (const arbor::Error &e) {
      EXPECT(e.status() == ARBOR_STATUS_INVALID_ARGUMENT, "status %d", (int)e.status());
      EXPECT(std::string(e.what()).find("level") != std::string::npos, "%s", e.what());
    }

    // Collision: the trunk first, then the limbs, thickest first.
    std::vector<ArborCapsule> caps = t.capsules(mo, 8);
    EXPECT(!caps.empty() && caps.size() <= 8, "%zu capsules", caps.size());
    bool thickest_first = true;
    for (std::size_t k = 2; k < caps.size(); k++) thickest_first = thickest_first && caps[k].radius <= caps[k - 1].radius;
    EXPECT(thickest_first && caps[0].radius > 0.0f, "capsule radii");

    // Wind: bones parents first, every vertex's weights summing to one on them, and a
    // clip whose last key is its first.
    std::vector<float> inverse_bind;
    std::vector<ArborBone> bones = t.bones(mo, 16, &inverse_bind);
    EXPECT(!bones.empty() && bones.size() <= 16 && inverse_bind.size() == 16 * bones.size(), "%zu bones",
           bones.size());
    EXPECT(bones[0].parent == ARBOR_NO_PARENT, "the root");
    for (std::size_t k = 1; k < bones.size(); k++) EXPECT(bones[k].parent < k, "bone %zu's parent", k);
    arbor::Skin skin = t.skin(mo, 16);
    const std::size_t vertices = t.mesh_size(mo).first;
    EXPECT(skin.weights.size() == 4 * vertices && skin.joints.size() == 4 * vertices, "%zu weights",
           skin.weights.size());
    bool summed = true, joined = true;
    for (std::size_t v = 0; v < vertices; v++) {
      float w = skin.weights[4 * v] + skin.weights[4 * v + 1] + skin.weights[4 * v + 2] + skin.weights[4 * v + 3];
      summed = summed && std::fabs(w - 1.0f) < 1e-4f;
      for (int j = 0; j < 4; j++) joined = joined && skin.joints[4 * v + j] < bones.size();
    }
    EXPECT(summed && joined, "skin weights and joints");
    // Every level's bark and leaves on the same bones, level 0's bark as the tree's own.
    for (std::size_t k = 0; k < lods.count(); k++)
      for (uint32_t part = 0; part < 2; part++) {
        arbor::Skin s = lods.skin(k, part, 16);
        EXPECT(s.weights.size() == 4 * lods.mesh_size(k, part).first && !s.weights.empty(),
               "level %zu part %u skin", k, part);
        EXPECT(std::all_of(s.joints.begin(), s.joints.end(), [&](uint16_t j) { return j < bones.size(); }),
               "level %zu part %u joints", k, part);
      }
    EXPECT(lods.skin(0, 0, 16).weights == skin.weights && lods.skin(0, 0, 16).joints == skin.joints,
           "level 0's bark skin is the tree's");
    std::vector<float> pivots = t.pivots(mo);
    EXPECT(pivots.size() == 8 * t.branch_count() && pivots[7] == -1.0f, "%zu pivot floats", pivots.size());
    arbor::WindClip clip = t.wind_clip(mo, 16);
    const std::size_t keys = clip.times.size();
    EXPECT(clip.bones == bones.size() && keys >= 2 && clip.rotations.size() == 4 * clip.bones * keys,
           "%zu bones, %zu keys", clip.bones, keys);
    EXPECT(clip.times[0] == 0.0f && std::fabs(clip.times[keys - 1] - 4.0f) < 1e-4f, "times");
    bool loops = true, unit = true;
    for (std::size_t b = 0; b < clip.bones; b++) {
      const float *first = &clip.rotations[4 * (b * keys)], *last = &clip.rotations[4 * (b * keys + keys - 1)];
      for (int c = 0; c < 4; c++) loops = loops && std::fabs(first[c] - last[c]) < 1e-5f;
      for (std::size_t k = 0; k < keys; k++) {
        const float *q = &clip.rotations[4 * (b * keys + k)];
        unit = unit && std::fabs(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3] - 1.0f) < 1e-4f;
      }
    }
    EXPECT(loops && unit, "the clip loops with unit rotations");
  }

  // Errors are exceptions with the status and message.
  try {
    arbor::Tree::honda('z');
    EXPECT(false, "no exception for a bad preset");
  } catch (const arbor::Error &e) {
    EXPECT(e.status() == ARBOR_STATUS_INVALID_ARGUMENT, "status %d", (int)e.status());
    EXPECT(std::string(e.what()).find("preset") != std::string::npos, "%s", e.what());
  }
  try {
    arbor::Tree::lsystem("Axiom: F\nF --> F(y +)\n");
    EXPECT(false, "no exception for a parse error");
  } catch (const arbor::Error &e) {
    EXPECT(e.status() == ARBOR_STATUS_PARSE_ERROR, "status %d", (int)e.status());
    EXPECT(std::string(e.what()).find("line 2") != std::string::npos, "%s", e.what());
  }

  try {
    arbor::Tree::lsystem_file("no/such/grammar.l");
    EXPECT(false, "no exception for a missing file");
  } catch (const arbor::Error &e) {
    EXPECT(e.status() == ARBOR_STATUS_INVALID_ARGUMENT, "status %d", (int)e.status());
    EXPECT(std::string(e.what()).find("grammar.l") != std::string::npos, "%s", e.what());
  }

  // Progress and cancellation through a lambda.
  {
    int calls = 0;
    auto stop_at_three = [&calls](uint32_t, float) noexcept { return ++calls < 3; };
    ArborLsystemOptions o = arbor_lsystem_options_default();
    arbor::set_progress(o, stop_at_three);
    try {
      arbor::Tree::lsystem("derivation length: 8\nAxiom: F\nF --> F[+F]F\n", &o);
      EXPECT(false, "no exception for a cancelled derivation");
    } catch (const arbor::Error &e) {
      EXPECT(e.status() == ARBOR_STATUS_CANCELLED && calls == 3, "status %d after %d calls", (int)e.status(),
             calls);
    }
  }

  // Moves transfer ownership; the moved-from object frees nothing.
  arbor::Tree g = arbor::Tree::lsystem("angle increment: 30\nAxiom: F[+F~]F[-F~]F~\n");
  arbor::Tree h = std::move(g);
  EXPECT(h.branch_count() == 5 && g.get() == nullptr, "moved tree");
  arbor::Mesh m1 = h.mesh();
  arbor::Mesh m2 = std::move(m1);
  EXPECT(m1.get() == nullptr && m2.vertices().size() > 0, "moved mesh");

  // Leaves and OBJ.
  ArborLeafOptions leaves = arbor::leaf_options();
  EXPECT(h.leaf_instances(leaves).size() == 3, "three ~ sites");
  EXPECT(h.leaf_mesh(leaves).vertices().size() == 12, "three quads");
  h.export_obj(dir + "/wrapper.obj", arbor::mesh_options(), &leaves);
  try {
    h.export_obj("/nonexistent/dir/x.obj");
    EXPECT(false, "no exception for an unwritable path");
  } catch (const arbor::Error &e) {
    EXPECT(e.status() == ARBOR_STATUS_IO_ERROR, "status %d", (int)e.status());
  }

  // Unreal: CreateMeshSection(0, Vertices, Triangles, Normals, UV0, ...) wants a triangle
  // list in Unreal's left-handed, Z-up centimetres, faces as Unreal culls them: the
  // Unreal preset (a mirror, so tree g spirals as it does in arbor).
  ArborMeshOptions ue = arbor::mesh_options();
  ue.topology = ARBOR_TOPOLOGY_TRIANGLE_LIST;
  ue.axes = ARBOR_AXES_UNREAL;
  ue.scale = 0.1f;  // the 1996 trees are 100 units tall: as 10 m, 1,000 cm
  arbor::Tree tree = arbor::Tree::honda('g');
  arbor::Mesh section = tree.mesh(ue);
  std::vector<FVector> Vertices, Normals;
  std::vector<FVector2D> UV0;
  std::vector<int> Triangles;
  for (const ArborVertex &vx : section.vertices()) {
    Vertices.push_back({vx.position[0], vx.position[1], vx.position[2]});
    Normals.push_back({vx.normal[0], vx.normal[1], vx.normal[2]});
    UV0.push_back({vx.uv[0], vx.uv[1]});
  }
  for (uint32_t ix : section.indices()) Triangles.push_back(static_cast<int>(ix));
  EXPECT(Triangles.size() % 3 == 0 && Vertices.size() == section.vertices().size(), "arrays");
  double top = 0;
  for (const FVector &p : Vertices) top = p.Z > top ? p.Z : top;
  EXPECT(top > 1000.0 * 0.999, "Z is up in cm: the trunk alone reaches 1,000 (top %f)", top);
  // A mesh write reports progress through the same options and can be cancelled.
  int reports = 0;
  auto count = [&reports](uint32_t stage, float) { reports += stage == ARBOR_STAGE_MESH; return true; };
  arbor::set_progress(ue, count);
  EXPECT(tree.mesh(ue).vertices().size() == section.vertices().size() && reports == 1, "mesh progress: %d reports", reports);
  auto stop = [](uint32_t, float) { return false; };
  arbor::set_progress(ue, stop);
  try {
    tree.mesh(ue);
    EXPECT(false, "no exception for a cancelled mesh");
  } catch (const arbor::Error &e) {
    EXPECT(e.status() == ARBOR_STATUS_CANCELLED, "status %d", (int)e.status());
  }

  // A model read through the host's asset system: arbor opens no file, and a model that
  // names a file outside its folder is refused without the host being asked.
  {
    std::vector<std::string> asked;
    auto read = [&asked](std::string_view path) -> std::optional<std::string> {
      asked.emplace_back(path);
      if (path == "m/tree.l") return std::string("#include \"defs.h\"\nderivation length: N\nAxiom: A\nA --> F[+A][-A]\n");
      if (path == "m/defs.h") return std::string("#define N 3\n");
      if (path == "m/esc.l") return std::string("#include \"../secret.h\"\nAxiom: F\n");
      if (path == "secret.h") return std::string("#define S hunter2\n");
      return std::nullopt;
    };
    ArborLsystemOptions fo = arbor::lsystem_options();
    arbor::set_file_reader(fo, read);
    arbor::Tree hosted = arbor::Tree::lsystem_file("m/tree.l", &fo);
    EXPECT(hosted.branch_count() == 7, "host-read model: %zu branches", hosted.branch_count());
    EXPECT(std::find(asked.begin(), asked.end(), "m/defs.h") != asked.end(), "include asked of the host");
    try {
      arbor::Tree::lsystem_file("m/esc.l", &fo);
      EXPECT(false, "no exception for an include leaving the model's folder");
    } catch (const arbor::Error &e) {
      EXPECT(e.status() == ARBOR_STATUS_IO_ERROR && std::string(e.what()).find("hunter2") == std::string::npos,
             "status %d: %s", (int)e.status(), e.what());
    }
    EXPECT(std::find(asked.begin(), asked.end(), "secret.h") == asked.end(), "the secret was never asked for");
  }

  std::printf("wrapper: %d passed, %d failed\n", passed, failed);
  return failed == 0 ? 0 : 1;
}
