// Rendered images for `cellmetry simulate` (image_simulation.h): the `images:` section read, each
// view listed in images.csv and rendered in parallel (one seed per image), exact keypoints kept.
#include "cellmetry/imaging/image_simulation.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <filesystem>
#include <mutex>
#include <sstream>

#include "cellmetry/basics/progress.h"
#include "cellmetry/basics/text.h"
#include "cellmetry/formats/atomic_file.h"

namespace cellmetry {
namespace {

RenderOptions ReadRender(const ConfigNode& node) {
  node.ExpectKeys({"supersampling", "blur_sigma_px", "noise_sigma", "background", "black", "white",
                   "illumination_gradient"});
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

std::string ImagePath(int sample, const std::string& camera, const std::string& view) {
  return "images/" + std::to_string(sample) + "_" + camera + "_" + view + ".png";
}

bool Contains(const std::vector<std::string>& names, const std::string& name) {
  return std::find(names.begin(), names.end(), name) != names.end();
}

std::vector<TargetMarker> ReadMarkers(const ConfigNode& images,
                                      const std::vector<std::string>& targets, Registry& registry) {
  if (images.Has("detector") == images.Has("targets")) {
    throw images.Error("give exactly one of 'detector:' (the one target's marker) or 'targets:'",
                       "e.g. targets: {tool: {type: <detector>, ...}}, a detector of " +
                           Join(registry.Names(PluginKind::kDetector)));
  }
  if (images.Has("detector")) {
    if (targets.size() != 1) {
      throw images["detector"].Error("this simulation has targets " + Join(targets),
                                     "Say which marker each carries under 'targets:'");
    }
    return {ReadTargetMarker(targets[0], images["detector"], registry)};
  }
  std::vector<TargetMarker> markers;
  const ConfigNode node = images["targets"];
  for (const auto& target : node.Keys()) {
    if (!Contains(targets, target)) {
      throw node[target].Error("no target '" + target + "' in this simulation",
                               "Its targets are: " + Join(targets));
    }
    markers.push_back(ReadTargetMarker(target, node[target], registry));
  }
  return markers;
}

std::map<std::string, ImagingCamera> ReadCameras(const ConfigNode& images,
                                                 const std::vector<std::string>& cameras) {
  std::map<std::string, ImagingCamera> out;
  if (images.Has("cameras")) {
    if (images.Has("stereo") || images.Has("mono")) {
      throw images.Error("give 'cameras:' or one 'stereo:'/'mono:' for all, not both");
    }
    const ConfigNode node = images["cameras"];
    for (const auto& name : node.Keys()) {
      if (!Contains(cameras, name)) {
        throw node[name].Error("no camera '" + name + "' in this simulation",
                               "Its cameras are: " + Join(cameras));
      }
      node[name].ExpectKeys({"stereo", "mono"});
      out[name] = ReadImagingCamera(node[name]);
    }
    for (const auto& name : cameras) {
      if (!out.count(name)) {
        throw node.Error("camera '" + name + "' has no calibration", "Add it under 'cameras:'");
      }
    }
    return out;
  }
  ImagingCamera shared;
  if (images.Has("stereo") || images.Has("mono")) {
    shared = ReadImagingCamera(images);
  } else {
    shared.rig = OakDLikeRig();
  }
  for (const auto& name : cameras) out[name] = shared;
  return out;
}

}  // namespace

ImageRenderSpec ReadImageRenderSpec(const ConfigNode& images,
                                    const std::vector<std::string>& cameras,
                                    const std::vector<std::string>& targets, Registry& registry) {
  images.ExpectKeys({"detector", "targets", "stereo", "mono", "cameras", "render"});
  ImageRenderSpec spec;
  spec.markers = ReadMarkers(images, targets, registry);
  spec.cameras = ReadCameras(images, cameras);
  if (images.Has("render")) spec.render = ReadRender(images["render"]);
  return spec;
}

std::function<void(const std::string&)> PlanImages(const ImageRenderSpec& spec,
                                                   const std::vector<SampleView>& views,
                                                   unsigned seed, Registry& registry,
                                                   Recording* recording) {
  for (const auto& v : views) {
    for (const auto& view : spec.cameras.at(v.camera).Views()) {
      recording->images.push_back({v.sample, v.camera, view, ImagePath(v.sample, v.camera, view)});
    }
  }
  std::map<std::string, unsigned> camera_index;
  for (const auto& [name, camera] : spec.cameras) camera_index.emplace(name, camera_index.size());
  return [spec, views, seed, camera_index, &registry](const std::string& folder) {
    std::filesystem::create_directories(folder + "/images");
    struct Printed {
      std::vector<MarkerFace> faces;
      std::vector<MarkerPoint> layout;
    };
    std::map<std::string, Printed> printed;
    for (const auto& marker : spec.markers) {
      const auto detector = registry.CreateDetector(marker.detector_type, *marker.detector_config);
      printed[marker.target] = {detector->Faces(20.0), detector->layout()};
    }
    std::vector<std::string> truth_rows(views.size());
    Progress progress("rendering views", static_cast<int>(views.size()));
    std::mutex mutex;
    tbb::parallel_for(size_t(0), views.size(), [&](size_t i) {
      const SampleView& sample_view = views[i];
      const ImagingCamera& camera = spec.cameras.at(sample_view.camera);
      std::ostringstream rows;
      rows.precision(12);
      for (const auto& view : camera.Views()) {
        const Pose T_view_camera = camera.T_view_camera(view);
        std::vector<PlacedTarget> placed;
        for (const auto& [target, T_cam_target] : sample_view.T_cam_target) {
          const auto it = printed.find(target);
          if (it != printed.end())
            placed.push_back({T_view_camera * T_cam_target, &it->second.faces});
        }
        // One seed per image: the same spec renders the same pixels whatever the thread order.
        std::mt19937 rng(seed * 1000003u + static_cast<unsigned>(sample_view.sample) * 64u +
                         camera_index.at(sample_view.camera) * 2u + (view == "right"));
        WriteGrayImage(RenderView(camera.View(view), placed, spec.render, rng),
                       folder + "/" + ImagePath(sample_view.sample, sample_view.camera, view));
        for (const auto& [target, T_cam_target] : sample_view.T_cam_target) {
          const auto it = printed.find(target);
          if (it == printed.end()) continue;
          for (const auto& k :
               ProjectLayout(camera.View(view), T_view_camera * T_cam_target, it->second.layout)) {
            rows << sample_view.sample << "," << sample_view.camera << "," << view << "," << target
                 << "," << k.id << "," << k.pixel.x() << "," << k.pixel.y() << "\n";
          }
        }
      }
      truth_rows[i] = rows.str();
      std::lock_guard<std::mutex> lock(mutex);
      progress.Advance();
    });
    std::string truth = "sample,camera,view,target,id,u,v\n";
    for (const auto& r : truth_rows) truth += r;
    AtomicWriteFile(folder + "/keypoints_truth.csv", truth);
  };
}

}  // namespace cellmetry
