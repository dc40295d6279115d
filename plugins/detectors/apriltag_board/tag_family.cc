// AprilTag families by name (tag_family.h): each created and destroyed by the library's own
// matching pair of functions.
#include "tag_family.h"

#include <tag16h5.h>
#include <tag25h9.h>
#include <tag36h10.h>
#include <tag36h11.h>
#include <tagCircle21h7.h>
#include <tagCircle49h12.h>
#include <tagCustom48h12.h>
#include <tagStandard41h12.h>
#include <tagStandard52h13.h>

namespace cellmetry::apriltag_board {
namespace {

struct Entry {
  const char* name;
  apriltag_family_t* (*create)();
  void (*destroy)(apriltag_family_t*);
};

// Each name with its own create/destroy pair: a family is never freed by another's function.
constexpr Entry kFamilies[] = {
    {"tag16h5", tag16h5_create, tag16h5_destroy},
    {"tag25h9", tag25h9_create, tag25h9_destroy},
    {"tag36h10", tag36h10_create, tag36h10_destroy},
    {"tag36h11", tag36h11_create, tag36h11_destroy},
    {"tagCircle21h7", tagCircle21h7_create, tagCircle21h7_destroy},
    {"tagCircle49h12", tagCircle49h12_create, tagCircle49h12_destroy},
    {"tagCustom48h12", tagCustom48h12_create, tagCustom48h12_destroy},
    {"tagStandard41h12", tagStandard41h12_create, tagStandard41h12_destroy},
    {"tagStandard52h13", tagStandard52h13_create, tagStandard52h13_destroy},
};

}  // namespace

const std::vector<std::string>& FamilyNames() {
  static const std::vector<std::string> names = [] {
    std::vector<std::string> out;
    for (const Entry& e : kFamilies) out.push_back(e.name);
    return out;
  }();
  return names;
}

FamilyPtr CreateFamily(const std::string& name) {
  for (const Entry& e : kFamilies) {
    if (name == e.name) return FamilyPtr(e.create(), FamilyDeleter{e.destroy});
  }
  return FamilyPtr(nullptr, FamilyDeleter{nullptr});
}

}  // namespace cellmetry::apriltag_board
