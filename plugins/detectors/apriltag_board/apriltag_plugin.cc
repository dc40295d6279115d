// Registers the `apriltag_board` detector: AprilTag 3 tags on a flat grid or on a cube.
//
//   detector: {type: apriltag_board, family: tag36h11, tags_x: 4, tags_y: 3, tag_size_mm: 30,
//              spacing_mm: 9, first_id: 0}                                   # a flat grid
//   detector: {type: apriltag_board, family: tag36h11, tags_x: 2, tags_y: 2, tag_size_mm: 20,
//              spacing_mm: 6, cube_mm: 60, cube_faces: {+x: 0, +y: 4, -x: 8, -y: 12, +z: 16}}
#include <algorithm>
#include <set>
#include <string>

#include "cellmetry/basics/text.h"
#include "cellmetry/registry/registry.h"
#include "apriltag_detector.h"

namespace cellmetry::apriltag_board {
namespace {

FamilyPtr ReadFamily(const ConfigNode& config, std::string* name) {
  *name = config.GetString("family", "tag36h11");
  FamilyPtr family = CreateFamily(*name);
  if (!family) {
    const std::string nearest = NearestWord(*name, FamilyNames());
    throw config["family"].Error("unknown AprilTag family '" + *name + "'",
                                 (nearest.empty() ? "" : "Did you mean '" + nearest + "'? ") +
                                     "Known families: " + Join(FamilyNames()));
  }
  return family;
}

// Ids first..first+count-1 must exist in the family.
void CheckIds(const ConfigNode& node, int first, int count, const apriltag_family_t& family,
              const std::string& family_name) {
  if (first < 0 || first + count > static_cast<int>(family.ncodes)) {
    throw node.Error("needs tag ids " + std::to_string(first) + ".." +
                         std::to_string(first + count - 1) + " but " + family_name +
                         " has ids 0.." + std::to_string(family.ncodes - 1),
                     "Use a lower first id, fewer tags or a larger family");
  }
}

void ReadGrid(const ConfigNode& config, const apriltag_family_t& family, TagBoard* b) {
  b->width_at_border = family.width_at_border;
  b->total_width = family.total_width;
  b->tags_x = config.GetInt("tags_x", 1);
  b->tags_y = config.GetInt("tags_y", 1);
  if (b->tags_x < 1) throw config["tags_x"].Error("must be at least 1");
  if (b->tags_y < 1) throw config["tags_y"].Error("must be at least 1");
  if (!config.Has("tag_size_mm")) {
    throw config.Error("missing key 'tag_size_mm'",
                       "Give the side of a tag's detection square in mm (the black border's "
                       "outer edge; the white ring's outer edge for tagStandard/tagCircle)");
  }
  b->tag_size_mm = config["tag_size_mm"].AsDouble();
  if (!(b->tag_size_mm > 0)) throw config["tag_size_mm"].Error("must be positive");
  const double min_spacing = 2 * b->outer_cells() * b->cell_mm();
  if (b->tags_x * b->tags_y > 1 && !config.Has("spacing_mm")) {
    throw config.Error("a grid of several tags needs spacing_mm",
                       "Give the gap between neighbouring tags' detection squares, at least " +
                           Mm(min_spacing, 4));
  }
  b->spacing_mm = config.GetDouble("spacing_mm", min_spacing);
  if (b->spacing_mm < min_spacing - 1e-9) {
    throw config["spacing_mm"].Error(
        "neighbouring " + std::string(family.name) + " tags would overlap",
        "A printed tag reaches " + std::to_string(b->outer_cells()) +
            " cell(s) beyond its detection square: spacing_mm must be at least " +
            Mm(min_spacing, 4));
  }
}

void ReadCube(const ConfigNode& config, const apriltag_family_t& family,
              const std::string& family_name, TagBoard* b) {
  if (config.Has("first_id")) {
    throw config["first_id"].Error("first_id is for a flat grid",
                                   "Give each cube face its first id in cube_faces");
  }
  if (!config.Has("cube_faces")) {
    throw config.Error("a cube needs cube_faces", "e.g. cube_faces: {+x: 0, +y: 4, -x: 8}");
  }
  b->cube_mm = config["cube_mm"].AsDouble();
  if (!(b->cube_mm > 0)) throw config["cube_mm"].Error("must be positive");
  const double printed_w = b->grid_width_mm() + 2 * b->outer_cells() * b->cell_mm();
  const double printed_h = b->grid_height_mm() + 2 * b->outer_cells() * b->cell_mm();
  if (printed_w > b->cube_mm + 1e-9 || printed_h > b->cube_mm + 1e-9) {
    throw config["cube_mm"].Error("a face's grid (" + Mm(printed_w, 4) + " x " + Mm(printed_h, 4) +
                                      " printed) does not fit on a " + Mm(b->cube_mm, 4) + " cube",
                                  "Use a larger cube, smaller tags or fewer tags per face");
  }
  const ConfigNode faces = config["cube_faces"];
  faces.ExpectMap();
  faces.ExpectKeys(CubeSideNames());
  const int per_face = b->tags_x * b->tags_y;
  std::set<int> used;
  for (const std::string& key : faces.Keys()) {
    const ConfigNode node = faces[key];
    CubeFace face;
    face.side = static_cast<CubeSide>(
        std::find(CubeSideNames().begin(), CubeSideNames().end(), key) - CubeSideNames().begin());
    face.first_id = node.AsInt();
    CheckIds(node, face.first_id, per_face, family, family_name);
    for (int id = face.first_id; id < face.first_id + per_face; ++id) {
      if (!used.insert(id).second) {
        throw node.Error("tag id " + std::to_string(id) + " is also on another face",
                         "Each face needs its own " + std::to_string(per_face) + " ids");
      }
    }
    b->cube_faces.push_back(face);
  }
  if (b->cube_faces.empty()) throw faces.Error("lists no face", "e.g. {+x: 0, +y: 4}");
}

std::unique_ptr<Detector> Create(const ConfigNode& config) {
  config.ExpectKeys({"type", "family", "tags_x", "tags_y", "tag_size_mm", "spacing_mm", "first_id",
                     "cube_mm", "cube_faces", "quad_decimate", "quad_sigma", "min_white_black_diff",
                     "refine_edges", "decode_sharpening", "nthreads", "max_hamming",
                     "edge_refinement", "redetect_unrefined", "sigma_px"});
  AprilTagOptions o;
  FamilyPtr family = ReadFamily(config, &o.family);
  ReadGrid(config, *family, &o.board);
  if (config.Has("cube_mm")) {
    ReadCube(config, *family, o.family, &o.board);
  } else {
    if (config.Has("cube_faces")) {
      throw config["cube_faces"].Error("cube_faces needs cube_mm", "Give the cube's side in mm");
    }
    o.board.first_id = config.GetInt("first_id", 0);
    CheckIds(config, o.board.first_id, o.board.tags_x * o.board.tags_y, *family, o.family);
  }
  o.quad_decimate = static_cast<float>(config.GetDouble("quad_decimate", o.quad_decimate));
  if (!(o.quad_decimate >= 1.0f)) {
    throw config["quad_decimate"].Error("must be at least 1", "1 finds quads at full resolution");
  }
  o.quad_sigma = static_cast<float>(config.GetDouble("quad_sigma", o.quad_sigma));
  o.min_white_black_diff = config.GetInt("min_white_black_diff", o.min_white_black_diff);
  if (o.min_white_black_diff < 0 || o.min_white_black_diff > 255) {
    throw config["min_white_black_diff"].Error("must be 0..255 gray levels");
  }
  o.refine_edges = config.GetBool("refine_edges", o.refine_edges);
  o.decode_sharpening = config.GetDouble("decode_sharpening", o.decode_sharpening);
  if (o.decode_sharpening < 0) throw config["decode_sharpening"].Error("must not be negative");
  o.nthreads = config.GetInt("nthreads", o.nthreads);
  if (o.nthreads < 1) throw config["nthreads"].Error("must be at least 1");
  o.max_hamming = config.GetInt("max_hamming", o.max_hamming);
  if (o.max_hamming < 0 || o.max_hamming > 2) {
    throw config["max_hamming"].Error(
        "must be 0, 1 or 2", "The library's decode table grows steeply: 3 takes gigabytes");
  }
  o.edge_refinement = config.GetBool("edge_refinement", o.edge_refinement);
  o.redetect_unrefined = config.GetBool("redetect_unrefined", o.redetect_unrefined);
  o.sigma_px = config.GetDouble("sigma_px", o.sigma_px);
  if (!(o.sigma_px > 0)) throw config["sigma_px"].Error("must be positive");
  return std::make_unique<AprilTagDetector>(std::move(o), std::move(family));
}

}  // namespace
}  // namespace cellmetry::apriltag_board

CELLMETRY_PLUGIN_ENTRY(registry) {
  cellmetry::PluginInfo info;
  info.kind = cellmetry::PluginKind::kDetector;
  info.name = "apriltag_board";
  info.description =
      "AprilTag 3 tags on a flat grid or on the faces of a cube; keypoint id = tag id * 4 + "
      "corner (top-left, top-right, bottom-right, bottom-left)";
  info.options = {
      {"family", "", "tag36h11",
       "tag16h5, tag25h9, tag36h10, tag36h11, tagCircle21h7, "
       "tagCircle49h12, tagCustom48h12, tagStandard41h12, tagStandard52h13"},
      {"tag_size_mm", "mm", "",
       "side of a tag's detection square (black border's outer edge; "
       "white ring's outer edge for reversed-border families)"},
      {"tags_x", "", "1", "tags per row of a grid"},
      {"tags_y", "", "1", "tags per column of a grid"},
      {"spacing_mm", "mm", "", "gap between neighbouring tags' detection squares"},
      {"first_id", "", "0",
       "flat grid: id of the top-left tag; row by row after it (origin at "
       "its top-left corner, x right, y down, z into the paper)"},
      {"cube_mm", "mm", "",
       "3D board: side of a cube with a grid on each listed face (target "
       "frame at the cube's centre)"},
      {"cube_faces", "", "",
       "3D board: face -> first id, e.g. {+x: 0, +y: 4, -x: 8, -y: 12, +z: "
       "16}; side faces read upright with +z up"},
      {"quad_decimate", "", "2.0",
       "find quads on an image decimated by this factor, decode and refine at full resolution "
       "(2: 4x faster than 1, same corners; 1: finds tags with cells under ~3 px, e.g. steep)"},
      {"quad_sigma", "px", "0.0", "Gaussian blur before finding quads (negative: sharpen)"},
      {"min_white_black_diff", "gray levels", "20",
       "a tile whose neighbourhood spans fewer levels has no edge (library default 5: with "
       "sensor noise of 2 levels blank paper breaks into clusters, 10x the time)"},
      {"refine_edges", "", "true",
       "library: snap the decimated quad's edges to the full-resolution gradient (0.1-0.2 ms "
       "a frame; its corners 1.3 -> 0.23 px worst at decimation 2; the edge lines need neither)"},
      {"decode_sharpening", "", "0.25", "sharpening of the sampled bits before decoding"},
      {"nthreads", "", "1", "library threads per detector (the core runs one detector per thread)"},
      {"max_hamming", "", "1",
       "bit errors corrected, 0..2 (each step multiplies the library's "
       "decode table per detector: 2 takes gigabytes for tagStandard52h13)"},
      {"edge_refinement", "", "true",
       "fit each side as a line through sub-pixel edge points; "
       "corners where they meet (the library's are 0.1-0.3 px off)"},
      {"redetect_unrefined", "", "true",
       "with quad_decimate > 1: a tag the edge lines cannot refine (cells too narrow for the "
       "blur) gets the library's full-resolution corners, from a window around it"},
      {"sigma_px", "px", "0.1",
       "corner standard deviation per image axis, covariance sigma^2 I (rendered views with "
       "noise 2 gray levels measure 0.01-0.02 px; 0.1 allows for real blur, print and focus)"},
  };
  registry->AddDetector(info, &cellmetry::apriltag_board::Create);
}
