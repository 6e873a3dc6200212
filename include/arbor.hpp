/*
 * arbor.hpp: a header-only C++17 wrapper over arbor.h (hand-written, not generated).
 *
 * - Trees and meshes are RAII objects that free themselves (move-only).
 * - Errors are exceptions: every call whose C function fails throws arbor::Error, which
 *   carries the ArborStatus and the library's message (what was wrong and where).
 * - Buffers are exposed as arbor::Span (pointer + size) over memory arbor owns, or written
 *   into spans the caller owns (a mapped GPU buffer, a TArray's data).
 */
#ifndef ARBOR_HPP
#define ARBOR_HPP

#if defined(_MSVC_LANG) ? _MSVC_LANG < 201703L : __cplusplus < 201703L
#error "arbor.hpp needs C++17 or later (-std=c++17, /std:c++17, or CMake's cxx_std_17; the arbor::arbor CMake targets ask for it)"
#endif

#include "arbor.h"

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace arbor {

/// Thrown by every wrapper call whose C function fails.
class Error : public std::runtime_error {
 public:
  Error(ArborStatus status, const std::string &message)
      : std::runtime_error(message), status_(status) {}
  /// The status the C function returned.
  ArborStatus status() const noexcept { return status_; }

 private:
  ArborStatus status_;
};

namespace detail {
inline std::string last_message() {
  std::size_t n = arbor_last_error_message(nullptr, 0);
  std::vector<char> buf(n + 1);
  arbor_last_error_message(buf.data(), buf.size());
  return std::string(buf.data(), n);
}

inline void check(ArborStatus s) {
  if (s != ARBOR_STATUS_OK) throw Error(s, last_message());
}
}  // namespace detail

/// A view of `size()` contiguous elements (std::span for C++17).
template <class T>
class Span {
 public:
  Span() noexcept = default;
  Span(T *data, std::size_t size) noexcept : data_(data), size_(size) {}
  template <class C>
  Span(C &container) noexcept : data_(container.data()), size_(container.size()) {}
  T *data() const noexcept { return data_; }
  std::size_t size() const noexcept { return size_; }
  bool empty() const noexcept { return size_ == 0; }
  T &operator[](std::size_t i) const noexcept { return data_[i]; }
  T *begin() const noexcept { return data_; }
  T *end() const noexcept { return data_ + size_; }

 private:
  T *data_ = nullptr;
  std::size_t size_ = 0;
};

/// A mesh arbor owns: vertices and indices readable in place.
class Mesh {
 public:
  explicit Mesh(ArborMesh *mesh) noexcept : mesh_(mesh) {}
  Mesh(Mesh &&other) noexcept : mesh_(std::exchange(other.mesh_, nullptr)) {}
  Mesh &operator=(Mesh &&other) noexcept {
    if (this != &other) {
      arbor_mesh_free(mesh_);
      mesh_ = std::exchange(other.mesh_, nullptr);
    }
    return *this;
  }
  Mesh(const Mesh &) = delete;
  Mesh &operator=(const Mesh &) = delete;
  ~Mesh() { arbor_mesh_free(mesh_); }

  Span<const ArborVertex> vertices() const noexcept {
    std::size_t n = 0;
    const ArborVertex *v = arbor_mesh_vertices(mesh_, &n);
    return {v, n};
  }
  Span<const uint32_t> indices() const noexcept {
    std::size_t n = 0;
    const uint32_t *i = arbor_mesh_indices(mesh_, &n);
    return {i, n};
  }
  ArborTopology topology() const noexcept {
    return static_cast<ArborTopology>(arbor_mesh_topology(mesh_));
  }
  const ArborMesh *get() const noexcept { return mesh_; }

 private:
  ArborMesh *mesh_;
};

/// Default options, to modify and pass on: each fills exactly sizeof the struct of this
/// header (the struct_size rule), so the host keeps working with a newer library.
inline ArborMeshOptions mesh_options() { return arbor_mesh_options_default(); }
inline ArborLeafOptions leaf_options() { return arbor_leaf_options_default(); }
inline ArborLsystemOptions lsystem_options() { return arbor_lsystem_options_default(); }
inline ArborWorldOptions world_options() { return arbor_world_options_default(); }
inline ArborGrowthParams growth_params() { return arbor_growth_params_default(); }
/// The parameters of a named species.
inline ArborGrowthParams species(ArborSpecies s) {
  ArborGrowthParams p;
  detail::check(arbor_growth_params_preset(static_cast<uint32_t>(s), &p, sizeof p));
  return p;
}

inline ArborLodOptions lod_options() { return arbor_lod_options_default(); }

/// An RGBA8 image arbor wrote into memory the host owns (rows from the top).
struct Image {
  uint32_t width = 0, height = 0;
  std::vector<uint8_t> rgba;
};

/// A mesh copied into memory the host owns (a triangle list, or strips as its options say).
struct MeshData {
  std::vector<ArborVertex> vertices;
  std::vector<uint32_t> indices;
};

struct Skin;

/// An octahedral impostor's atlases and frame (arbor_lods_impostor_create(); the layout is
/// docs/meshes.md's "Impostors"). Move-only.
class Impostor {
 public:
  Impostor(Impostor &&other) noexcept : imp_(std::exchange(other.imp_, nullptr)) {}
  Impostor &operator=(Impostor &&other) noexcept {
    std::swap(imp_, other.imp_);
    return *this;
  }
  Impostor(const Impostor &) = delete;
  Impostor &operator=(const Impostor &) = delete;
  ~Impostor() { arbor_impostor_free(imp_); }

  /// Pixels a side of each atlas.
  uint32_t atlas_size() const {
    uint32_t n = 0;
    detail::check(arbor_impostor_info(imp_, &n, nullptr, nullptr, nullptr));
    return n;
  }
  /// The bounding sphere the views frame: its centre (3 floats) and radius; the up axis.
  void frame(float centre[3], float *radius, float up[3]) const {
    detail::check(arbor_impostor_info(imp_, nullptr, centre, radius, up));
  }
  /// Atlas `which` (0: albedo and coverage, 1: normal and depth) into host memory.
  Image atlas(uint32_t which) const {
    std::size_t n = 0;
    detail::check(arbor_impostor_atlas_write(imp_, which, nullptr, 0, &n));
    Image out;
    out.width = out.height = atlas_size();
    out.rgba.resize(n);
    detail::check(arbor_impostor_atlas_write(imp_, which, out.rgba.data(), n, nullptr));
    return out;
  }
  /// Atlas `which` into a span the host owns (a mapped texture upload buffer): at least
  /// atlas_size()² × 4 bytes.
  void write_atlas(uint32_t which, Span<uint8_t> out) const {
    detail::check(arbor_impostor_atlas_write(imp_, which, out.data(), out.size(), nullptr));
  }
  const ArborImpostor *get() const noexcept { return imp_; }

 private:
  friend class Lods;
  explicit Impostor(ArborImpostor *imp) noexcept : imp_(imp) {}
  ArborImpostor *imp_;
};

/// Crossed quads with their atlas, for hosts without an impostor shader
/// (arbor_lods_billboard_create()). Move-only.
class Billboard {
 public:
  Billboard(Billboard &&other) noexcept : bb_(std::exchange(other.bb_, nullptr)) {}
  Billboard &operator=(Billboard &&other) noexcept {
    std::swap(bb_, other.bb_);
    return *this;
  }
  Billboard(const Billboard &) = delete;
  Billboard &operator=(const Billboard &) = delete;
  ~Billboard() { arbor_billboard_free(bb_); }

  /// The quads (a triangle list), each plane again the other way round with `two_sided`.
  MeshData mesh(bool two_sided = false) const {
    std::size_t nv = 0, ni = 0;
    detail::check(arbor_billboard_mesh_write(bb_, two_sided, nullptr, 0, nullptr, 0, &nv, &ni));
    MeshData out;
    out.vertices.resize(nv);
    out.indices.resize(ni);
    detail::check(arbor_billboard_mesh_write(bb_, two_sided, out.vertices.data(), nv,
                                             out.indices.data(), ni, nullptr, nullptr));
    return out;
  }
  /// Atlas `which` (0: albedo and coverage, 1: normal and depth), `planes` cells wide.
  Image atlas(uint32_t which) const {
    Image out;
    detail::check(arbor_billboard_atlas_write(bb_, which, nullptr, 0, &out.width, &out.height));
    out.rgba.resize(std::size_t(out.width) * out.height * 4);
    detail::check(arbor_billboard_atlas_write(bb_, which, out.rgba.data(), out.rgba.size(),
                                              nullptr, nullptr));
    return out;
  }
  const ArborBillboard *get() const noexcept { return bb_; }

 private:
  friend class Lods;
  explicit Billboard(ArborBillboard *bb) noexcept : bb_(bb) {}
  ArborBillboard *bb_;
};

/// A tree's levels of detail (Tree::lods(), arbor_tree_lods_create()): level 0 the full
/// tree, each level its bark (part 0) and baked leaves (part 1). Const member functions
/// may run on several threads at once. Move-only.
class Lods {
 public:
  /// What arbor_lods_level_info() says of a level.
  struct Level {
    float screen_coverage;  ///< drawn while the tree covers at least this share of the screen's height
    float silhouette;       ///< the IoU it keeps with the full tree where it is first drawn
    std::size_t triangles;
  };

  Lods(Lods &&other) noexcept : lods_(std::exchange(other.lods_, nullptr)) {}
  Lods &operator=(Lods &&other) noexcept {
    std::swap(lods_, other.lods_);
    return *this;
  }
  Lods(const Lods &) = delete;
  Lods &operator=(const Lods &) = delete;
  ~Lods() { arbor_lods_free(lods_); }

  std::size_t count() const noexcept { return arbor_lods_count(lods_); }
  Level level(std::size_t k) const {
    Level l{};
    detail::check(arbor_lods_level_info(lods_, k, &l.screen_coverage, &l.silhouette, &l.triangles));
    return l;
  }
  /// Sizes of part `part` (0 bark, 1 leaves) of level `k`: {vertices, indices}.
  std::pair<std::size_t, std::size_t> mesh_size(std::size_t k, uint32_t part) const {
    std::size_t nv = 0, ni = 0;
    detail::check(arbor_lods_mesh_write(lods_, k, part, nullptr, 0, nullptr, 0, &nv, &ni));
    return {nv, ni};
  }
  /// Part `part` of level `k` into spans the host owns (a mapped buffer), at least mesh_size().
  void write_mesh(std::size_t k, uint32_t part, Span<ArborVertex> vertices,
                  Span<uint32_t> indices) const {
    detail::check(arbor_lods_mesh_write(lods_, k, part, vertices.data(), vertices.size(),
                                        indices.data(), indices.size(), nullptr, nullptr));
  }
  MeshData mesh(std::size_t k, uint32_t part) const {
    auto size = mesh_size(k, part);
    MeshData out;
    out.vertices.resize(size.first);
    out.indices.resize(size.second);
    write_mesh(k, part, out.vertices, out.indices);
    return out;
  }
  /// The skin of part `part` of level `k` on the tree's bones(options, max_bones) for the
  /// options the chain was made with: four joints and weights a vertex of mesh(k, part).
  Skin skin(std::size_t k, uint32_t part, uint32_t max_bones = 32) const;
  /// The level an impostor of `cell`-pixel views is best baked from (the coarsest made
  /// for views at least that large; 0, the full tree, when none is).
  std::size_t impostor_level(uint32_t cell) const noexcept {
    return arbor_lods_impostor_level(lods_, cell);
  }
  /// The octahedral impostor of level `k`: `frames` × `frames` views of `cell` pixels,
  /// of the upper half of the sphere with `hemi`; the leaves sample `atlas` (the leaf
  /// atlas the levels were made with; empty: opaque cards).
  Impostor impostor(std::size_t k, uint32_t frames, uint32_t cell, bool hemi = true,
                    const Image *atlas = nullptr) const {
    ArborImpostor *i = nullptr;
    detail::check(arbor_lods_impostor_create(lods_, k, frames, cell, hemi,
                                             atlas ? atlas->rgba.data() : nullptr,
                                             atlas ? atlas->width : 0, atlas ? atlas->height : 0, &i));
    return Impostor(i);
  }
  /// The billboard of level `k`: `planes` (2..4) crossed quads, each a cell of `cell` pixels.
  Billboard billboard(std::size_t k, uint32_t planes, uint32_t cell,
                      const Image *atlas = nullptr) const {
    ArborBillboard *b = nullptr;
    detail::check(arbor_lods_billboard_create(lods_, k, planes, cell,
                                              atlas ? atlas->rgba.data() : nullptr,
                                              atlas ? atlas->width : 0, atlas ? atlas->height : 0, &b));
    return Billboard(b);
  }
  const ArborLods *get() const noexcept { return lods_; }

 private:
  friend class Tree;
  explicit Lods(ArborLods *lods) noexcept : lods_(lods) {}
  ArborLods *lods_;
};

/// A wind skin: four joints and four weights (summing to one) a vertex of a mesh, on the
/// bones of Tree::bones() (Tree::skin(), Lods::skin()).
struct Skin {
  std::vector<uint16_t> joints;
  std::vector<float> weights;
};

inline Skin Lods::skin(std::size_t k, uint32_t part, uint32_t max_bones) const {
  std::size_t n = 0;
  detail::check(arbor_lods_skin_write(lods_, k, part, max_bones, nullptr, nullptr, 0, &n));
  Skin out;
  out.joints.resize(4 * n);
  out.weights.resize(4 * n);
  detail::check(arbor_lods_skin_write(lods_, k, part, max_bones, out.joints.data(), out.weights.data(), n,
                                      nullptr));
  return out;
}

/// A looping wind clip (arbor_tree_wind_clip_write()): `times` a key each, `rotations` a
/// unit quaternion (x, y, z, w) per bone and key, bone `b`'s key `k` at 4 * (b * keys + k).
struct WindClip {
  std::size_t bones = 0;
  std::vector<float> times;
  std::vector<float> rotations;
};

class World;

/// A generated tree. Const member functions may run on several threads at once.
class Tree {
 public:
  /// One of the 1996 paper's trees 'a'..'i'.
  static Tree honda(char preset) {
    ArborHondaParams p;
    detail::check(arbor_honda_preset(static_cast<uint32_t>(preset), &p));
    return honda(p);
  }
  static Tree honda(const ArborHondaParams &params) {
    ArborTree *t = nullptr;
    detail::check(arbor_tree_from_honda(&params, &t));
    return Tree(t);
  }
  /// A tree from the host's own branches (parents before children), copied and checked.
  static Tree from_branches(Span<const ArborBranch> branches) {
    ArborTree *t = nullptr;
    detail::check(arbor_tree_from_branches(branches.data(), branches.size(), &t));
    return Tree(t);
  }
  /// A tree from L-system text in the cpfg language.
  static Tree lsystem(std::string_view source, const ArborLsystemOptions *options = nullptr) {
    ArborTree *t = nullptr;
    detail::check(arbor_tree_from_lsystem(source.data(), source.size(), options, &t));
    return Tree(t);
  }

  /// A cpfg file read as cpfg reads it: preprocessed, with its view file
  /// (options->view_path, else the .v beside it).
  static Tree lsystem_file(const std::string &path, const ArborLsystemOptions *options = nullptr) {
    ArborTree *t = nullptr;
    detail::check(arbor_tree_from_lsystem_file(path.c_str(), options, &t));
    return Tree(t);
  }

  Tree(Tree &&other) noexcept : tree_(std::exchange(other.tree_, nullptr)) {}
  Tree &operator=(Tree &&other) noexcept {
    if (this != &other) {
      arbor_tree_free(tree_);
      tree_ = std::exchange(other.tree_, nullptr);
    }
    return *this;
  }
  Tree(const Tree &) = delete;
  Tree &operator=(const Tree &) = delete;
  ~Tree() { arbor_tree_free(tree_); }

  std::size_t branch_count() const noexcept { return arbor_tree_branch_count(tree_); }

  std::vector<ArborBranch> branches() const {
    std::vector<ArborBranch> out(branch_count());
    detail::check(arbor_tree_copy_branches(tree_, out.data(), out.size()));
    return out;
  }

  /// Every branch's cubic Bezier curve (straight until smoothed or edited).
  std::vector<ArborCurve> curves() const {
    std::vector<ArborCurve> out(branch_count());
    detail::check(arbor_tree_copy_curves(tree_, out.data(), out.size()));
    return out;
  }
  /// Bends every axis into C1 curves; no joint moves.
  void smooth(float tension = 1.0f) { detail::check(arbor_tree_smooth(tree_, tension)); }
  /// Replaces one branch's curve; its subtree follows the end.
  void set_curve(std::size_t branch, const ArborCurve &curve) {
    detail::check(arbor_tree_set_curve(tree_, branch, &curve));
  }
  /// Rewrites, in buffers holding the whole mesh, what the edits since changed.
  void rewrite_branch(const ArborMeshOptions &options, std::size_t branch, Span<ArborVertex> vertices,
                      Span<uint32_t> indices) const {
    detail::check(arbor_mesh_rewrite_branch(tree_, &options, branch, vertices.data(), vertices.size(),
                                            indices.data(), indices.size()));
  }
  /// One std430 record per branch for shaders that ray-march curves.
  std::vector<ArborCurveRecord> curve_records() const {
    std::vector<ArborCurveRecord> out(branch_count());
    detail::check(arbor_tree_curve_records_write(tree_, out.data(), out.size()));
    return out;
  }

  /// The bark mesh, owned by the returned object.
  Mesh mesh(const ArborMeshOptions &options = mesh_options()) const {
    ArborMesh *m = nullptr;
    detail::check(arbor_mesh_create(tree_, &options, &m));
    return Mesh(m);
  }

  /// Exact buffer sizes for write_mesh(): {vertices, indices}.
  std::pair<std::size_t, std::size_t> mesh_size(
      const ArborMeshOptions &options = mesh_options()) const {
    std::size_t nv = 0, ni = 0;
    detail::check(arbor_mesh_size(tree_, &options, &nv, &ni));
    return {nv, ni};
  }

  /// Writes the bark mesh into caller memory (a mapped buffer, a TArray's data).
  void write_mesh(const ArborMeshOptions &options, Span<ArborVertex> vertices,
                  Span<uint32_t> indices) const {
    detail::check(arbor_mesh_write(tree_, &options, vertices.data(), vertices.size(),
                                   indices.data(), indices.size()));
  }

  /// Writes the bark mesh as compact vertices (ArborVertexCompact, 20 bytes each):
  /// `options.vertex_format` is set to ARBOR_VERTEX_FORMAT_COMPACT. Returns the v_scale
  /// a vertex's v is stored over (v = uv[1] / 65535 * v_scale).
  float write_mesh_compact(ArborMeshOptions options, Span<ArborVertexCompact> vertices,
                           Span<uint32_t> indices) const {
    options.vertex_format = ARBOR_VERTEX_FORMAT_COMPACT;
    detail::check(arbor_mesh_write_bytes(tree_, &options, vertices.data(),
                                         vertices.size() * sizeof(ArborVertexCompact),
                                         indices.data(), indices.size()));
    float v_scale = 1.0f;
    detail::check(arbor_mesh_v_scale(tree_, &options, &v_scale));
    return v_scale;
  }

  std::vector<ArborBranchRange> branch_ranges(
      const ArborMeshOptions &options = mesh_options()) const {
    std::vector<ArborBranchRange> out(branch_count());
    detail::check(arbor_mesh_branch_ranges(tree_, &options, out.data(), out.size()));
    return out;
  }

  std::vector<ArborLeafInstance> leaf_instances(
      const ArborLeafOptions &leaves, const ArborMeshOptions &options = mesh_options()) const {
    std::size_t n = 0;
    detail::check(arbor_leaf_instance_count(tree_, &leaves, &options, &n));
    std::vector<ArborLeafInstance> out(n);
    detail::check(arbor_leaf_instances_write(tree_, &leaves, &options, out.data(), n));
    return out;
  }

  Mesh leaf_mesh(const ArborLeafOptions &leaves,
                 const ArborMeshOptions &options = mesh_options()) const {
    ArborMesh *m = nullptr;
    detail::check(arbor_leaf_mesh_create(tree_, &leaves, &options, &m));
    return Mesh(m);
  }

  /// Bark (and leaves, if given) as a Wavefront OBJ file.
  void export_obj(const std::string &path, const ArborMeshOptions &options = mesh_options(),
                  const ArborLeafOptions *leaves = nullptr) const {
    detail::check(arbor_export_obj(tree_, &options, leaves, path.c_str()));
  }

  /// Levels of detail of the bark and, with `leaves`, its baked leaves alpha-tested
  /// against `atlas` (their leaf atlas; none: opaque cards) for the silhouettes the chain
  /// is fitted by (arbor_tree_lods_create()).
  Lods lods(const ArborMeshOptions &options = mesh_options(),
            const ArborLeafOptions *leaves = nullptr, const Image *atlas = nullptr,
            const ArborLodOptions &lod = lod_options()) const {
    ArborLods *l = nullptr;
    detail::check(arbor_tree_lods_create(tree_, &options, leaves, atlas ? atlas->rgba.data() : nullptr,
                                         atlas ? atlas->width : 0, atlas ? atlas->height : 0, &lod, &l));
    return Lods(l);
  }

  /// At most `max_capsules` collision capsules for the branches thicker than
  /// `min_radius` (0: a tenth of the trunk's), the trunk first (arbor_tree_capsules_write()).
  std::vector<ArborCapsule> capsules(const ArborMeshOptions &options = mesh_options(),
                                     uint32_t max_capsules = 32, float min_radius = 0.0f) const {
    std::size_t n = 0;
    detail::check(arbor_tree_capsules_write(tree_, &options, max_capsules, min_radius, nullptr, 0, &n));
    std::vector<ArborCapsule> out(n);
    detail::check(arbor_tree_capsules_write(tree_, &options, max_capsules, min_radius, out.data(), n, nullptr));
    return out;
  }

  /// The wind skin's bones (at most `max_bones`, parents first); with `inverse_bind`,
  /// 16 floats a bone, column-major (arbor_tree_bones_write()).
  std::vector<ArborBone> bones(const ArborMeshOptions &options = mesh_options(),
                               uint32_t max_bones = 32,
                               std::vector<float> *inverse_bind = nullptr) const {
    std::size_t n = 0;
    detail::check(arbor_tree_bones_write(tree_, &options, max_bones, nullptr, nullptr, 0, &n));
    std::vector<ArborBone> out(n);
    if (inverse_bind) inverse_bind->resize(16 * n);
    detail::check(arbor_tree_bones_write(tree_, &options, max_bones, out.data(),
                                         inverse_bind ? inverse_bind->data() : nullptr, n, nullptr));
    return out;
  }

  /// Each branch's pivot for a Pivot-Painter-style wind shader, 8 floats a branch: its
  /// start (x, y, z), length, unit axis (x, y, z) and parent (-1 for a root)
  /// (arbor_tree_pivots_write()).
  std::vector<float> pivots(const ArborMeshOptions &options = mesh_options()) const {
    std::size_t n = 0;
    detail::check(arbor_tree_pivots_write(tree_, &options, nullptr, 0, &n));
    std::vector<float> out(8 * n);
    detail::check(arbor_tree_pivots_write(tree_, &options, out.data(), n, nullptr));
    return out;
  }

  /// The skin of the bark mesh write_mesh() writes with `options`, on bones(options, max_bones).
  Skin skin(const ArborMeshOptions &options = mesh_options(), uint32_t max_bones = 32) const {
    std::size_t n = 0;
    detail::check(arbor_mesh_skin_write(tree_, &options, max_bones, nullptr, nullptr, 0, &n));
    Skin out;
    out.joints.resize(4 * n);
    out.weights.resize(4 * n);
    detail::check(arbor_mesh_skin_write(tree_, &options, max_bones, out.joints.data(),
                                        out.weights.data(), n, nullptr));
    return out;
  }

  /// The looping wind clip of bones(options, max_bones): `duration` seconds at
  /// `keys_per_second`, the wind along `wind` (3 floats, level; nullptr: +X) at `strength`
  /// (the defaults are the CLI's `--wind skin`).
  WindClip wind_clip(const ArborMeshOptions &options = mesh_options(), uint32_t max_bones = 32,
                     const float *wind = nullptr, float strength = 2.0f, float duration = 4.0f,
                     uint32_t keys_per_second = 30, uint64_t seed = 1) const {
    std::size_t keys = 0, bones = 0;
    detail::check(arbor_tree_wind_clip_write(tree_, &options, max_bones, wind, strength, duration,
                                             keys_per_second, seed, nullptr, 0, nullptr, 0, &keys,
                                             &bones));
    WindClip out;
    out.bones = bones;
    out.times.resize(keys);
    out.rotations.resize(4 * bones * keys);
    detail::check(arbor_tree_wind_clip_write(tree_, &options, max_bones, wind, strength, duration,
                                             keys_per_second, seed, out.times.data(), keys,
                                             out.rotations.data(), bones, nullptr, nullptr));
    return out;
  }

  /// This grown tree shaped as named species `s` shapes its own (trunk cleared, bare limbs
  /// shed, cone or dome, flare and roots, twigs): arbor_species_finish().
  Tree finished_as(ArborSpecies s) const {
    ArborTree *t = nullptr;
    detail::check(arbor_species_finish(static_cast<uint32_t>(s), tree_, &t));
    return Tree(t);
  }

  const ArborTree *get() const noexcept { return tree_; }

 private:
  friend class World;
  explicit Tree(ArborTree *tree) noexcept : tree_(tree) {}
  ArborTree *tree_;
};

/// Self-organizing trees growing together in one environment (move-only). Const member
/// functions may run on several threads at once; plant() and step() need it alone.
class World {
 public:
  explicit World(const ArborWorldOptions &options = world_options()) {
    detail::check(arbor_world_create(&options, &world_));
  }
  World(World &&other) noexcept : world_(std::exchange(other.world_, nullptr)) {}
  World &operator=(World &&other) noexcept {
    std::swap(world_, other.world_);
    return *this;
  }
  World(const World &) = delete;
  World &operator=(const World &) = delete;
  ~World() { arbor_world_free(world_); }

  /// Plants a tree; returns its index.
  uint32_t plant(const ArborGrowthParams &species, float x, float y, float z, uint64_t seed = 0) {
    const float at[3] = {x, y, z};
    uint32_t id = 0;
    detail::check(arbor_world_plant(world_, &species, at, seed, &id));
    return id;
  }
  void add_box(const float min[3], const float max[3]) {
    detail::check(arbor_world_add_box(world_, min, max));
  }
  void add_sphere(const float center[3], float radius) {
    detail::check(arbor_world_add_sphere(world_, center, radius));
  }
  void step(uint32_t cycles = 1) { detail::check(arbor_world_step(world_, cycles)); }
  /// A copy that grows on by itself (a preview to step ahead of this world).
  World clone() const {
    ArborWorld *w = nullptr;
    detail::check(arbor_world_clone(world_, &w));
    return World(w);
  }
  /// Lays a height field (columns x rows, x fastest) under the empty world.
  void set_ground(Span<const float> heights, uint32_t columns, uint32_t rows, float cell_size,
                  float origin_x, float origin_z) {
    if (heights.size() != std::size_t(columns) * rows)
      throw Error(ARBOR_STATUS_INVALID_ARGUMENT, "heights: expected columns * rows samples");
    detail::check(arbor_world_set_ground(world_, heights.data(), columns, rows, cell_size, origin_x,
                                         origin_z));
  }
  /// Lays a PNG height map (black at `base`, white at `base + height_scale`) under the world.
  void set_ground_png(Span<const uint8_t> png, float height_scale, float base, float cell_size,
                      float origin_x, float origin_z) {
    detail::check(arbor_world_set_ground_png(world_, png.data(), png.size(), height_scale, base,
                                             cell_size, origin_x, origin_z));
  }
  /// The ground's height at (x, z).
  float ground_height(float x, float z) const {
    float y = 0.0f;
    detail::check(arbor_world_ground_height(world_, x, z, &y));
    return y;
  }
  /// Plants a tree standing on the ground at (x, z) in species slot `slot`.
  uint32_t plant_on_ground(const ArborGrowthParams &species, float x, float z, uint32_t slot,
                           uint64_t seed = 0) {
    uint32_t id = 0;
    detail::check(arbor_world_plant_on_ground(world_, &species, x, z, slot, seed, &id));
    return id;
  }
  /// Plants from a species map (slots and densities a cell, x fastest); returns the trees
  /// planted.
  std::size_t plant_map(Span<const uint32_t> slots, Span<const float> density, uint32_t columns,
                        uint32_t rows, float cell_size, float origin_x, float origin_z,
                        const std::vector<ArborGrowthParams> &species, uint64_t seed) {
    if (slots.size() != std::size_t(columns) * rows || density.size() != slots.size())
      throw Error(ARBOR_STATUS_INVALID_ARGUMENT, "slots, density: expected columns * rows cells");
    std::vector<const ArborGrowthParams *> list;
    for (const auto &p : species) list.push_back(&p);
    std::size_t planted = 0;
    detail::check(arbor_world_plant_map(world_, slots.data(), density.data(), columns, rows,
                                        cell_size, origin_x, origin_z, list.data(), list.size(),
                                        seed, &planted));
    return planted;
  }
  /// The species slot tree `index` was planted in (a seedling: its parent's).
  uint32_t tree_slot(std::size_t index) const {
    uint32_t slot = 0;
    detail::check(arbor_world_tree_slot(world_, index, &slot));
    return slot;
  }
  /// Gives every tree of `slot` new parameters; returns how many changed.
  std::size_t set_species(uint32_t slot, const ArborGrowthParams &species) {
    std::size_t n = 0;
    detail::check(arbor_world_set_species(world_, slot, &species, &n));
    return n;
  }
  /// The trees as one glTF file, a node `NAME_k` a tree (`names` by slot).
  void export_gltf(const std::string &path, const std::vector<std::string> &names,
                   const ArborMeshOptions &options = mesh_options(),
                   const ArborLeafOptions *leaves = nullptr, uint32_t texture_size = 256,
                   bool ground = true) const {
    std::vector<const char *> list;
    for (const auto &n : names) list.push_back(n.c_str());
    detail::check(arbor_world_export_gltf(world_, list.data(), list.size(), &options, leaves,
                                          texture_size, ground ? 1u : 0u, path.c_str()));
  }
  std::size_t tree_count() const noexcept { return arbor_world_tree_count(world_); }
  std::size_t branch_count() const noexcept { return arbor_world_branch_count(world_); }
  /// A snapshot of tree `index` as an ordinary tree.
  Tree tree(std::size_t index) const {
    ArborTree *t = nullptr;
    detail::check(arbor_world_tree(world_, index, &t));
    return Tree(t);
  }
  const ArborWorld *get() const noexcept { return world_; }
  ArborWorld *get() noexcept { return world_; }

 private:
  explicit World(ArborWorld *world) noexcept : world_(world) {}
  ArborWorld *world_ = nullptr;
};

/// Points `options.progress` (ArborLsystemOptions or ArborWorldOptions) at `f`, called as
/// `f(stage, fraction)` on the calling thread; `f` returns false to cancel (the call then
/// throws arbor::Error with ARBOR_STATUS_CANCELLED). `f` must outlive the call and must not
/// throw.
template <class Options, class F> void set_progress(Options &options, F &f) {
  options.progress = [](void *user, uint32_t stage, float fraction) -> int32_t {
    return (*static_cast<F *>(user))(stage, fraction) ? 0 : 1;
  };
  options.progress_user_data = &f;
}

/// Serves every file of a model from the host (ARBOR_FILE_ACCESS_HOST) through `read`,
/// called as `read(path)` with the path as the model names it (resolved against the
/// model's folder) and returning `std::optional<std::string>` (std::nullopt: no such
/// file); arbor opens nothing. For ArborLsystemOptions and ArborLeafOptions. `read` must
/// outlive the call and must not throw.
template <class Options, class F> void set_file_reader(Options &options, F &read) {
  options.file_access = ARBOR_FILE_ACCESS_HOST;
  options.read_file = [](void *user, const char *path, uint8_t *buffer, size_t capacity,
                         size_t *size) -> int32_t {
    auto bytes = (*static_cast<F *>(user))(std::string_view(path));
    if (!bytes) return 1;
    *size = bytes->size();
    if (capacity > 0) std::memcpy(buffer, bytes->data(), std::min(capacity, bytes->size()));
    return 0;
  };
  options.read_file_user_data = &read;
}

}  // namespace arbor

#endif /* ARBOR_HPP */
