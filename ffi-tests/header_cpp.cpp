// The header compiles as C++17 and its types work from C++.
#include "arbor.h"

#include <cstdio>
#include <memory>
#include <type_traits>
#include <vector>

static_assert(sizeof(ArborVertex) == 32, "ArborVertex is 32 bytes");
static_assert(sizeof(ArborBranch) == 48, "ArborBranch is 48 bytes");
static_assert(std::is_trivially_copyable<ArborVertex>::value, "ArborVertex is POD");

int main() {
  ArborHondaParams p{};
  if (arbor_honda_preset('g', &p) != ARBOR_STATUS_OK) return 1;
  ArborTree *raw = nullptr;
  if (arbor_tree_from_honda(&p, &raw) != ARBOR_STATUS_OK) return 1;
  std::unique_ptr<ArborTree, decltype(&arbor_tree_free)> tree(raw, &arbor_tree_free);
  ArborMeshOptions o = arbor_mesh_options_default();
  o.topology = ARBOR_TOPOLOGY_TRIANGLE_STRIP_RESTART;
  size_t nv = 0, ni = 0;
  if (arbor_mesh_size(tree.get(), &o, &nv, &ni) != ARBOR_STATUS_OK) return 1;
  std::vector<ArborVertex> v(nv);
  std::vector<uint32_t> i(ni);
  if (arbor_mesh_write(tree.get(), &o, v.data(), v.size(), i.data(), i.size()) != ARBOR_STATUS_OK)
    return 1;
  // One ring per branch plus one per axis start; an axis start's tube is two strips (its
  // first quad, then the rest), which takes 3 more indices.
  size_t axes = nv / 9 - 1023;
  int ok = nv > 1023 * 9 && ni == 1023 * 18 + 1022 + 3 * axes && i[4] == ARBOR_RESTART_INDEX;
  std::printf("header_cpp: %d passed, %d failed\n", ok, !ok);
  return ok ? 0 : 1;
}
