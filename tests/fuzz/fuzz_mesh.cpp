// Fuzzes mesh import: the first byte picks the file's extension (the formats the docs name), the
// rest is the file, read through MeshCache as a type's or object's `mesh:` would be.
#include "fuzz_support.h"
#include "geometry/mesh_io.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  using namespace sscs;
  static const char* const kExtensions[] = {"stl", "obj", "ply", "glb", "gltf", "off", "dae"};
  if (size == 0) return 0;
  const char* ext = kExtensions[data[0] % (sizeof kExtensions / sizeof *kExtensions)];
  std::string path = fuzz::write_scratch(std::string("mesh.") + ext, data + 1, size - 1);
  Diagnostics diag;
  MeshCache cache;
  cache.load(path, SourceMark{}, diag);
  return 0;
}
