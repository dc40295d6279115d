// Tag families of the AprilTag 3 C library (libapriltag-dev 3.3.0) by name.
//
// Memory-safe family choice: each family is created and destroyed by the library's own pair
// (tag36h11_create / tag36h11_destroy, ...: the code tables are allocated per family and only
// the matching destroy frees them), held in a unique_ptr whose deleter is that destroy. One
// family instance serves one apriltag_detector_t only (apriltag.h: the detector keeps its decode
// table in the family), so every Detector creates its own.
#pragma once

#include <apriltag.h>

#include <memory>
#include <string>
#include <vector>

namespace cellmetry::apriltag_board {

struct FamilyDeleter {
  void (*destroy)(apriltag_family_t*) = nullptr;
  void operator()(apriltag_family_t* family) const {
    if (family != nullptr) destroy(family);
  }
};
using FamilyPtr = std::unique_ptr<apriltag_family_t, FamilyDeleter>;

// tag16h5, tag25h9, tag36h10, tag36h11, tagCircle21h7, tagCircle49h12, tagCustom48h12,
// tagStandard41h12, tagStandard52h13.
const std::vector<std::string>& FamilyNames();

// A new instance of the family; nullptr when `name` is not one of FamilyNames().
FamilyPtr CreateFamily(const std::string& name);

}  // namespace cellmetry::apriltag_board
