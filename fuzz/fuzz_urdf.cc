// URDF robots (plugins/robots/urdf): the fuzzed bytes as the URDF file a `type: urdf` robot config
// names (configs/robots/staubli_tx2_90l_urdf.yaml, base_link to tool0), parsed by urdfdom and
// built into a chain by the plugin (plugins loaded). A model that loads must put its tool
// somewhere finite at zero joints, or say why the pose does not exist.
#include <filesystem>
#include <string>
#include <vector>

#include "cellmetry/formats/config_node.h"
#include "cellmetry/registry/registry.h"
#include "fuzz_support.h"

namespace {

std::string config_path;  // the robot config, written once
std::string urdf_path;    // the URDF it names, rewritten with every input

}  // namespace

extern "C" int LLVMFuzzerInitialize(int*, char***) {
  cellmetry::Registry::Global().LoadFolder(CELLMETRY_PLUGIN_DIR);
  const std::string folder = cellmetry::fuzz::TempDir() + "/urdf";
  std::filesystem::create_directories(folder);
  config_path = folder + "/robot.yaml";
  urdf_path = folder + "/robot.urdf";
  cellmetry::fuzz::WriteFile(config_path,
                             "type: urdf\nname: fuzzed\nfile: robot.urdf\nbase_link: base_link\n"
                             "tip_link: tool0\n");
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  cellmetry::fuzz::WriteFile(urdf_path, data, size);
  cellmetry::fuzz::CheckContract([&] {
    const cellmetry::ConfigNode config = cellmetry::ConfigNode::LoadFile(config_path);
    const auto model = cellmetry::Registry::Global().CreateRobotModel("urdf", config);
    std::vector<double> params;
    for (const auto& p : model->parameters()) params.push_back(p.nominal);
    const std::vector<double> q(static_cast<size_t>(model->num_joints()), 0.0);
    cellmetry::Transform<double> T;
    if (model->Forward(q.data(), params.data(), &T)) {
      if (!T.R.allFinite() || !T.t.allFinite()) {
        cellmetry::fuzz::Violation("urdf robot", "a model that loaded puts its tool nowhere");
      }
    } else {
      (void)model->ForwardFailure(q.data(), params.data());
    }
  });
  return 0;
}
