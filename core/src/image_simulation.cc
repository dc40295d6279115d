#include "cellmetry/image_simulation.h"

#include <tbb/parallel_for.h>

#include <filesystem>
#include <mutex>
#include <sstream>

#include "cellmetry/atomic_file.h"
#include "cellmetry/progress.h"

namespace cellmetry {
namespace {

RenderOptions ReadRender(const ConfigNode& node) {
  node.ExpectKeys({"supersampling", "blur_sigma_px", "noise_sigma", "background", "black",
                   "white", "illumination_gradient"});
  RenderOptions o;
  o.supersampling = node.GetInt("supersampling", o.supersampling);
  o.blur_sigma_px = node.GetDouble("blur_sigma_px", o.blur_sigma_px);
  o.noise_sigma = node.GetDouble("noise_sigma", o.noise_sigma);
  o.background = node.GetDouble("background", o.background);
  o.black = node.GetDouble("black", o.black);
  o.white = node.GetDouble("white", o.white);
  if (node.Has("illumination_gradient")) {
    const auto g = node["illumination_gradient"].AsDoubles(2);
    o.illumination_gradient = Eigen::Vector2d(g[0], g[1]);
  }
  if (o.supersampling < 1) throw node["supersampling"].Error("must be at least 1");
  return o;
}

std::string ImagePath(int sample, const std::string& view) {
  return "images/" + std::to_string(sample) + "_" + view + ".png";
}

}  // namespace

ImageRenderSpec ReadImageRenderSpec(const ConfigNode& images, Registry& registry) {
  images.ExpectKeys({"detector", "stereo", "mono", "render"});
  ImageRenderSpec spec;
  const ConfigNode detector = images["detector"];
  spec.detector_type = detector["type"].AsString();
  spec.detector_config = detector;
  registry.CreateDetector(spec.detector_type, detector);  // bad options fail now
  if (images.Has("stereo") && images.Has("mono")) {
    throw images.Error("give one of 'stereo:' or 'mono:'");
  }
  if (images.Has("mono")) {
    spec.mono = ReadCamera(images.ResolvePath(images["mono"].AsString()));
  } else {
    spec.rig = images.Has("stereo") ? ReadStereoRig(images.ResolvePath(images["stereo"].AsString()))
                                    : OakDLikeRig();
  }
  if (images.Has("render")) spec.render = ReadRender(images["render"]);
  return spec;
}

std::function<void(const std::string&)> PlanImages(const ImageRenderSpec& spec,
                                                   const std::string& camera,
                                                   const std::vector<SampleView>& views,
                                                   unsigned seed, Registry& registry,
                                                   Recording* recording) {
  const std::vector<std::string> names = spec.mono ? std::vector<std::string>{"mono"}
                                                   : std::vector<std::string>{"left", "right"};
  for (const auto& v : views) {
    for (const auto& view : names) recording->images.push_back({v.sample, camera, view, ImagePath(v.sample, view)});
  }
  return [spec, camera, views, seed, names, &registry](const std::string& folder) {
    std::filesystem::create_directories(folder + "/images");
    const auto detector = registry.CreateDetector(spec.detector_type, *spec.detector_config);
    const std::vector<MarkerFace> faces = detector->Faces(20.0);
    const std::vector<MarkerPoint> layout = detector->layout();
    std::vector<std::string> truth_rows(views.size());
    Progress progress("rendering samples", static_cast<int>(views.size()));
    std::mutex mutex;
    tbb::parallel_for(size_t(0), views.size(), [&](size_t i) {
      std::ostringstream rows;
      rows.precision(12);
      for (const auto& view : names) {
        const PinholeCamera& cam = spec.mono ? *spec.mono : view == "right" ? spec.rig->right : spec.rig->left;
        const Pose T_cam_target = view == "right" ? spec.rig->T_right_left * views[i].T_cam_target
                                                  : views[i].T_cam_target;
        // One seed per image: the same spec renders the same pixels whatever the thread order.
        std::mt19937 rng(seed * 1000003u + static_cast<unsigned>(views[i].sample) * 2u + (view == "right"));
        WriteGrayImage(RenderView(cam, {{T_cam_target, &faces}}, spec.render, rng),
                       folder + "/" + ImagePath(views[i].sample, view));
        for (const auto& k : ProjectLayout(cam, T_cam_target, layout)) {
          rows << views[i].sample << "," << camera << "," << view << "," << k.id << ","
               << k.pixel.x() << "," << k.pixel.y() << "\n";
        }
      }
      truth_rows[i] = rows.str();
      std::lock_guard<std::mutex> lock(mutex);
      progress.Advance();
    });
    std::string truth = "sample,camera,view,id,u,v\n";
    for (const auto& r : truth_rows) truth += r;
    AtomicWriteFile(folder + "/keypoints_truth.csv", truth);
  };
}

}  // namespace cellmetry
