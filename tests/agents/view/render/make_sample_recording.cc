// Writes the renderer tests' sample recording (sample_world.h) to the path given, and the
// sample world as a world file beside it when a second path is given. For tools/render_cli_test.sh.
#include <cstdio>
#include <fstream>

#include "quiver/graph/world_file.h"
#include "sample_world.h"

int main(int argc, char** argv) {
  if (argc < 2) {
    std::fprintf(stderr, "usage: make_sample_recording OUT.qrec [WORLD.json]\n");
    return 2;
  }
  const auto bytes = quiver::render_test::sample_recording_bytes();
  std::ofstream out(argv[1], std::ios::binary);
  out.write(reinterpret_cast<const char*>(bytes.data()),
            static_cast<std::streamsize>(bytes.size()));
  if (!out) return 1;
  if (argc > 2) {
    quiver::graph::Graph g(quiver::graph::ReplicaId{1, 1});
    quiver::render_test::build_sample_world(g);
    if (!quiver::graph::save_world_file(g, argv[2]).ok()) return 1;
  }
  return 0;
}
