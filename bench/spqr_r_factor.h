// SuiteSparseQR's R factor of a sparse Jacobian: the library baseline bench_scale compares
// cellmetry's grouped QR (estimation/r_factor.h) with. Multifrontal Householder QR (Davis 2011,
// ACM TOMS 38(1)), COLAMD ordering, no rank tolerance, Q discarded; R^T R = J^T J.
#pragma once

#include <SuiteSparseQR.hpp>

#include <Eigen/Core>
#include <stdexcept>

#include "cellmetry/estimation/r_factor.h"

namespace cellmetry::bench {

inline Eigen::MatrixXd SuiteSparseRFactor(const SparseJacobian& J) {
  const Eigen::Index n = J.cols();
  Eigen::SparseMatrix<double, Eigen::ColMajor, SuiteSparse_long> column_major = J;
  column_major.makeCompressed();
  cholmod_sparse A{};
  A.nrow = static_cast<size_t>(column_major.rows());
  A.ncol = static_cast<size_t>(n);
  A.nzmax = static_cast<size_t>(column_major.nonZeros());
  A.p = column_major.outerIndexPtr();
  A.i = column_major.innerIndexPtr();
  A.x = column_major.valuePtr();
  A.itype = CHOLMOD_LONG;
  A.xtype = CHOLMOD_REAL;
  A.dtype = CHOLMOD_DOUBLE;
  A.sorted = 1;
  A.packed = 1;
  cholmod_common common;
  cholmod_l_start(&common);
  cholmod_sparse* sparse_R = nullptr;
  SuiteSparse_long* permutation = nullptr;
  const SuiteSparse_long rank =
      SuiteSparseQR<double>(SPQR_ORDERING_COLAMD, SPQR_NO_TOL, static_cast<SuiteSparse_long>(n), &A,
                            &sparse_R, &permutation, &common);
  if (rank < 0 || sparse_R == nullptr) throw std::runtime_error("SuiteSparseQR failed");
  Eigen::MatrixXd R = Eigen::MatrixXd::Zero(n, n);
  const auto* p = static_cast<const SuiteSparse_long*>(sparse_R->p);
  const auto* i = static_cast<const SuiteSparse_long*>(sparse_R->i);
  const auto* x = static_cast<const double*>(sparse_R->x);
  for (size_t k = 0; k < sparse_R->ncol; ++k) {
    const Eigen::Index column = permutation ? permutation[k] : static_cast<Eigen::Index>(k);
    for (SuiteSparse_long e = p[k]; e < p[k + 1]; ++e) R(i[e], column) = x[e];
  }
  cholmod_l_free_sparse(&sparse_R, &common);
  if (permutation) cholmod_l_free(n, sizeof(SuiteSparse_long), permutation, &common);
  cholmod_l_finish(&common);
  return R;
}

}  // namespace cellmetry::bench
