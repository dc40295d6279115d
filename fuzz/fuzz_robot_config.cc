// Robot config reader: the fuzzed bytes as a robot config (configs/robots/*.yaml), parsed by the
// config reader and built by the robot model plugin its `type:` names (serial_mdh, delta), the
// way a job reads its robots. A model that loads must then evaluate its forward kinematics at
// zero joints without crashing (it may say the pose does not exist).
#include <string>
#include <vector>

#include "cellmetry/formats/config_node.h"
#include "cellmetry/registry/registry.h"
#include "fuzz_support.h"

extern "C" int LLVMFuzzerInitialize(int*, char***) {
  cellmetry::Registry::Global().LoadFolder(CELLMETRY_PLUGIN_DIR);
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  cellmetry::fuzz::CheckContract([&] {
    const cellmetry::ConfigNode config = cellmetry::ConfigNode::LoadString(text, "robot.yaml");
    const std::string type = config["type"].AsString();
    const auto model = cellmetry::Registry::Global().CreateRobotModel(type, config);
    std::vector<double> params;
    for (const auto& p : model->parameters()) params.push_back(p.nominal);
    const std::vector<double> q(static_cast<size_t>(model->num_joints()), 0.0);
    cellmetry::Transform<double> T;
    if (!model->Forward(q.data(), params.data(), &T))
      (void)model->ForwardFailure(q.data(), params.data());
  });
  return 0;
}
