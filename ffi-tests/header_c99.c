/* The header alone compiles as strict C99 (-std=c99 -pedantic -Werror). */
#include "arbor.h"

int main(void) {
  ArborMeshOptions o = arbor_mesh_options_default();
  return (int)o.topology;
}
