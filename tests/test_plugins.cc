// Plugins: what the build ships, what `cellmetry plugins` shows, and a plugin built outside the
// tree against the core headers and loaded at run time.
#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>

#include "cellmetry/registry/registry.h"
#include "support/test_support.h"

namespace fs = std::filesystem;

namespace cellmetry {
namespace {

using ::testing::HasSubstr;
using ::testing::Not;

const std::vector<std::string> kBuiltSolvers = {"ceres_lm", "gradient_descent", "jacobian_pinv",
                                                "nlopt", "normal_lm"};
const std::vector<std::string> kBuiltRobotModels = {"delta", "serial_mdh", "urdf"};
const std::vector<std::string> kBuiltDetectors = {"apriltag_board", "aruco", "charuco",
                                                  "checkerboard",   "dot",   "dot_pattern"};

using testing::CatchInputError;

TEST(Registry, ListsTheBuiltPlugins) {
  const Registry& registry = testing::Plugins();
  EXPECT_EQ(registry.Names(PluginKind::kSolver), kBuiltSolvers);
  EXPECT_EQ(registry.Names(PluginKind::kRobotModel), kBuiltRobotModels);
  EXPECT_EQ(registry.Names(PluginKind::kDetector), kBuiltDetectors);
}

TEST(Registry, EveryPluginHasAOneLineDescriptionAndDocumentedOptions) {
  const auto infos = testing::Plugins().List();
  ASSERT_GE(infos.size(), 4u);
  for (const auto& info : infos) {
    SCOPED_TRACE(info.name);
    EXPECT_FALSE(info.description.empty());
    EXPECT_EQ(info.description.find('\n'), std::string::npos);
    EXPECT_FALSE(info.options.empty());
    for (const auto& option : info.options) {
      EXPECT_FALSE(option.name.empty());
      EXPECT_FALSE(option.description.empty()) << option.name;
    }
    EXPECT_THAT(info.library, HasSubstr(".so"));
  }
}

// A documented option the plugin then refuses as an unknown key would make the docs a lie.
TEST(Registry, DocumentedOptionsAreAcceptedKeysAndOthersAreNot) {
  Registry& registry = testing::Plugins();
  const auto ur3 = registry.CreateRobotModel(
      "serial_mdh", ConfigNode::LoadFile(testing::Source("configs/robots/ur3_vsb2020.yaml")));
  for (const auto& info : registry.List()) {
    SCOPED_TRACE(info.name);
    auto create = [&](const std::string& yaml) {
      const ConfigNode config = ConfigNode::LoadString("type: " + info.name + "\n" + yaml, "test");
      if (info.kind == PluginKind::kSolver) registry.CreateSolver(info.name, config);
      if (info.kind == PluginKind::kRobotModel) registry.CreateRobotModel(info.name, config);
      if (info.kind == PluginKind::kDetector) registry.CreateDetector(info.name, config);
      if (info.kind == PluginKind::kEffect) registry.CreateEffect(info.name, config, *ur3);
    };
    for (const auto& option : info.options) {
      try {
        create(option.name + ": 0\n");
      } catch (const InputError& e) {  // a bad value is fine here; an unknown key is not
        EXPECT_THAT(e.message(), Not(HasSubstr("unknown key"))) << option.name;
      }
    }
    const InputError e = CatchInputError([&] { create("no_such_option: 1\n"); });
    EXPECT_THAT(e.message(), HasSubstr("no_such_option: unknown key"));
  }
}

TEST(Registry, UnknownSolverTypeNamesTheKnownOnes) {
  const ConfigNode config = ConfigNode::LoadString("type: ceres_lmm\n", "job.yaml");
  const InputError e =
      CatchInputError([&] { testing::Plugins().CreateSolver("ceres_lmm", config); });
  EXPECT_THAT(e.hint(), HasSubstr("Did you mean 'ceres_lm'?"));
  EXPECT_THAT(e.hint(), HasSubstr("ceres_lm, gradient_descent, jacobian_pinv, nlopt"));
}

TEST(PluginsCommand, PrintsEveryBuiltPlugin) {
  const auto r = testing::RunCellmetry("plugins");
  EXPECT_EQ(r.exit_code, 0) << r.output;
  for (const auto& name : {"ceres_lm", "jacobian_pinv", "nlopt", "serial_mdh"}) {
    EXPECT_THAT(r.output, HasSubstr(name));
  }
  EXPECT_THAT(r.output, HasSubstr("max_iterations"));
}

TEST(LoadLibrary, AFileThatIsNotALibraryIsAnInputErrorNamingIt) {
  const std::string path = testing::TempDir("plugins/empty") + "/libempty.so";
  testing::WriteText(path, "");
  Registry registry;
  const InputError e = CatchInputError([&] { registry.LoadLibrary(path); });
  EXPECT_EQ(e.where().file, path);
  EXPECT_THAT(e.message(), HasSubstr("cannot load plugin"));
  EXPECT_FALSE(e.hint().empty());
}

TEST(LoadLibrary, ALibraryWithoutTheEntryPointIsAnInputErrorNamingIt) {
  // A core layer's library loads fine but registers nothing.
  const std::string path = std::string(CELLMETRY_BUILD_DIR) + "/lib/libcellmetry_basics.so";
  ASSERT_TRUE(fs::exists(path));
  Registry registry;
  const InputError e = CatchInputError([&] { registry.LoadLibrary(path); });
  EXPECT_EQ(e.where().file, path);
  EXPECT_THAT(e.message(), HasSubstr("not a cellmetry plugin"));
}

TEST(PluginsCommand, ABadFileInThePluginPathIsNamedWithExitCode2) {
  const std::string dir = testing::TempDir("plugins/bad_folder");
  testing::WriteText(dir + "/libbroken.so", "not a shared library\n");
  const auto r = testing::RunCellmetry("--plugin-path " + dir + " plugins");
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_THAT(r.output, HasSubstr(dir + "/libbroken.so: error: cannot load plugin"));
}

TEST(PluginsCommand, APluginFoundTwiceIsRefused) {
  const std::string dir = testing::TempDir("plugins/duplicate");
  const std::string copy = dir + "/libcellmetry_jacobian_pinv.so";
  fs::copy_file(std::string(CELLMETRY_PLUGIN_DIR) + "/libcellmetry_jacobian_pinv.so", copy);
  const auto r = testing::RunCellmetry("--plugin-path " + dir + " plugins");
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_THAT(r.output, HasSubstr("solver 'jacobian_pinv' is already registered"));
  EXPECT_THAT(r.output, HasSubstr(copy));
}

// tests/external_plugin, configured against this build tree's exported cellmetryConfig.cmake and
// built once for the suite. Its plugin lands in <build>/plugins.
class ExternalPlugin : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    // Per process: CTest runs each test in its own process, two at a time.
    build_ = testing::TempDir("plugins/external_build_" + std::to_string(::getpid()));
    const std::string log = build_ + "/build.log";
    const std::string command = "cmake -S " + testing::Source("tests/external_plugin") + " -B " +
                                build_ + " -G Ninja -Dcellmetry_DIR=" + CELLMETRY_BUILD_DIR +
                                " > " + log + " 2>&1 && " + "cmake --build " + build_ + " -j1 >> " +
                                log + " 2>&1";
    build_status_ = std::system(command.c_str());
  }

  static void TearDownTestSuite() {
    if (build_status_ == 0) fs::remove_all(build_);  // a failed build keeps its log
  }

  void SetUp() override {
    ASSERT_EQ(build_status_, 0) << "building tests/external_plugin failed; see " << build_
                                << "/build.log";
    ASSERT_TRUE(fs::exists(plugins() + "/libhello_solver.so"));
  }

  static std::string plugins() { return build_ + "/plugins"; }

  // The sim_b job in `dir` with this plugin folder and the given solver block (line 11).
  static std::string WriteSimBJob(const std::string& dir, const std::string& solver) {
    const std::string job = dir + "/job.yaml";
    testing::WriteText(job,
                       "job: workcell\n"
                       "recording: " +
                           testing::Source("tests/data/vsb/sim_b") +
                           "\n"
                           "output: " +
                           dir +
                           "/result\n"
                           "plugin_paths: [" +
                           plugins() +
                           "]\n"
                           "robots:\n"
                           "  ur3:\n"
                           "    model: " +
                           testing::Source("configs/robots/ur3_vsb2020.yaml") +
                           "\n"
                           "    base: {free: all}\n"
                           "    tools:\n"
                           "      tool: {xyz: [0, 0, 0], free: [x, y, z]}\n"
                           "solver: " +
                           solver + "\n");
    return job;
  }

  static std::string build_;
  static int build_status_;
};

std::string ExternalPlugin::build_;
int ExternalPlugin::build_status_ = -1;

TEST_F(ExternalPlugin, IsListedByThePluginsCommand) {
  const auto r = testing::RunCellmetry("--plugin-path " + plugins() + " plugins");
  EXPECT_EQ(r.exit_code, 0) << r.output;
  EXPECT_THAT(r.output, HasSubstr("hello_gradient"));
  EXPECT_THAT(r.output, HasSubstr(plugins() + "/libhello_solver.so"));
  // The built-in plugins are still there next to it.
  EXPECT_THAT(r.output, HasSubstr("ceres_lm"));
}

TEST_F(ExternalPlugin, IsNotThereWithoutThePluginPath) {
  const auto r = testing::RunCellmetry("plugins");
  EXPECT_EQ(r.exit_code, 0) << r.output;
  EXPECT_THAT(r.output, Not(HasSubstr("hello_gradient")));
}

TEST_F(ExternalPlugin, AJobNamingItsSolverRuns) {
  const std::string dir = testing::TempDir("plugins/external_job");
  const std::string job = WriteSimBJob(dir, "{type: hello_gradient, max_iterations: 50}");
  const auto r = testing::RunCellmetry("run " + job);
  EXPECT_EQ(r.exit_code, 0) << r.output;
  EXPECT_THAT(r.output, HasSubstr("hello_gradient"));
  EXPECT_TRUE(fs::exists(dir + "/result/result.yaml"));
}

TEST_F(ExternalPlugin, RejectsAnUnknownOptionLikeABuiltInPlugin) {
  const std::string dir = testing::TempDir("plugins/external_bad_option");
  const std::string job = WriteSimBJob(dir, "{type: hello_gradient, max_iteration: 50}");
  const auto r = testing::RunCellmetry("run " + job);
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_THAT(r.output, HasSubstr("job.yaml:11:"));
  EXPECT_THAT(r.output, HasSubstr("Did you mean 'max_iterations'?"));
}

}  // namespace
}  // namespace cellmetry
