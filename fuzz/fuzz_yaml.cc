// Any YAML file cellmetry reads (formats/config_node.h, ConfigNode::LoadString), then walked
// whole the way a reader walks it, aliases expanded. Anchors and aliases (&a, *a) let a few
// lines name one node a billion times: the load must refuse that with an InputError, and what
// loads must be walkable in bounded time. A second document, a key twice, a list as a key: an
// InputError at their line.
#include <string>

#include "cellmetry/formats/config_node.h"
#include "fuzz_support.h"

namespace {

// Every node, as readers reach them: keys of a map, elements of a list, scalars as text.
void Walk(const cellmetry::ConfigNode& node) {
  if (node.IsMap()) {
    for (const auto& key : node.Keys()) Walk(node[key]);
  } else if (node.IsSequence()) {
    for (const auto& element : node.Elements()) Walk(element);
  } else if (node.IsScalar()) {
    (void)node.AsString();
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  cellmetry::fuzz::CheckContract(
      [&] { Walk(cellmetry::ConfigNode::LoadString(text, "file.yaml")); });
  return 0;
}
