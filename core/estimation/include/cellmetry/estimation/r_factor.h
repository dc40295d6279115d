// The R factor of a sparse Jacobian: everything identifiability and the covariance need from J.
//
// For J (m x n, m >> n, each row touching a few columns), RFactor returns a small n x n matrix
// R with R^T R = J^T J, i.e. J = Q R for some Q with orthonormal columns. R has the singular
// values and right singular vectors of J, so the SVD of R (n x n) stands in for the SVD of J
// (m x n) exactly, and column scaling commutes: J D = Q (R D).
//
// How: rows that touch the same columns (a residual block's, and every block of one robot, tool
// and camera) are one group; each group's dense block (rows x its few columns) is reduced by a
// Householder QR to its small triangle (in pieces of 2,048 rows on every core, their triangles
// reduced once more on the group's columns), and the stacked triangles are reduced once more — a
// tall-skinny QR (Demmel, Grigori, Hoemmen, Langou 2012, "Communication-optimal parallel and
// sequential QR", SIAM J. Sci. Comput. 34(1), section on TSQR) whose tree follows the
// Jacobian's structure. Orthogonal transformations only: as accurate as a dense Householder QR
// of J (the normal equations J^T J would square the condition number). The cost is the rows
// times their own width squared, not m n^2, and the memory O(n^2) beyond J's nonzeros; against
// SuiteSparseQR's multifrontal QR and a dense QR: BM_RFactor in bench_scale (docs/benchmarks.md).
#pragma once

#include <Eigen/Core>
#include <Eigen/SparseCore>

namespace cellmetry {

// The whitened Jacobian with respect to a Problem's free parameters, one row per residual.
using SparseJacobian = Eigen::SparseMatrix<double, Eigen::RowMajor>;

// n x n, R^T R = J^T J (rows of zeros where J has fewer rows than columns); not necessarily
// triangular.
Eigen::MatrixXd RFactor(const SparseJacobian& J);

// Euclidean norm of each column of J.
Eigen::VectorXd ColumnNorms(const SparseJacobian& J);

}  // namespace cellmetry
