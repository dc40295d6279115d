// Rows (or residual blocks) grouped by the list of columns they touch (internal to the
// estimation layer). A Jacobian's rows come in few patterns -- every observation of one tool by
// one camera touches the same base, tool and camera columns -- and both the R factor
// (r_factor.cc) and the normal equations (normal_equations_evaluator.h, through the column
// groups of evaluation_layout.h) work on each pattern's rows densely.
#pragma once

#include <algorithm>
#include <cstdint>
#include <unordered_map>
#include <vector>

namespace cellmetry {

class ColumnPatterns {
 public:
  // The group of the ascending column list columns[0 .. count): the same list, the same group,
  // numbered 0, 1, ... in the order first seen. The previous call's list is tried first (a
  // residual block's rows come together), then a hash of the list.
  int GroupOf(const int* columns, int count) {
    if (last_ >= 0) {  // inline: most calls end here
      const std::vector<int>& last = groups_[static_cast<size_t>(last_)];
      if (static_cast<int>(last.size()) == count &&
          std::equal(columns, columns + count, last.begin())) {
        return last_;
      }
    }
    return last_ = Find(columns, count);
  }

  // Each group's columns, ascending.
  const std::vector<std::vector<int>>& groups() const { return groups_; }

 private:
  int Find(const int* columns, int count);  // by hash; adds a group when new

  std::unordered_map<std::uint64_t, std::vector<int>> by_hash_;  // hash -> groups with it
  std::vector<std::vector<int>> groups_;
  int last_ = -1;
};

}  // namespace cellmetry
