// Rows grouped by the columns they touch (column_patterns.h).
#include "column_patterns.h"

namespace cellmetry {
namespace {

bool Same(const std::vector<int>& group, const int* columns, int count) {
  return static_cast<int>(group.size()) == count &&
         std::equal(columns, columns + count, group.begin());
}

// FNV-1a over the column indices.
std::uint64_t PatternHash(const int* columns, int count) {
  std::uint64_t hash = 1469598103934665603ull;
  for (int k = 0; k < count; ++k) {
    hash = (hash ^ static_cast<std::uint32_t>(columns[k])) * 1099511628211ull;
  }
  return hash;
}

}  // namespace

int ColumnPatterns::Find(const int* columns, int count) {
  std::vector<int>& candidates = by_hash_[PatternHash(columns, count)];
  for (int g : candidates) {
    if (Same(groups_[static_cast<size_t>(g)], columns, count)) return g;
  }
  candidates.push_back(static_cast<int>(groups_.size()));
  groups_.emplace_back(columns, columns + count);
  return candidates.back();
}

}  // namespace cellmetry
