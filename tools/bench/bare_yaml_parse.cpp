// The baseline of tools/bench/check_vs_yaml.py: parse a file with bare yaml-cpp (YAML::LoadFile)
// and visit every scalar, as a program that used yaml-cpp's node tree would.
#include <yaml-cpp/yaml.h>

#include <cstdio>

static void visit(const YAML::Node& node, size_t& scalars, size_t& bytes) {
  switch (node.Type()) {
    case YAML::NodeType::Scalar:
      ++scalars;
      bytes += node.Scalar().size();
      break;
    case YAML::NodeType::Sequence:
      for (const auto& item : node) visit(item, scalars, bytes);
      break;
    case YAML::NodeType::Map:
      for (const auto& kv : node) {
        visit(kv.first, scalars, bytes);
        visit(kv.second, scalars, bytes);
      }
      break;
    default: break;
  }
}

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: bare_yaml_parse FILE\n");
    return 2;
  }
  YAML::Node root = YAML::LoadFile(argv[1]);
  size_t scalars = 0, bytes = 0;
  visit(root, scalars, bytes);
  std::printf("%zu scalars, %zu bytes\n", scalars, bytes);
  return 0;
}
