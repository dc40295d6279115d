// Eigen's dense decompositions of a dynamic-size double matrix, compiled once for the library.
//
// Instantiating Eigen::BDCSVD<MatrixXd>, JacobiSVD or a QR costs seconds of compiler time in every
// translation unit that uses one (BDCSVD the most, tens of seconds with GCC at -O2). Include this
// header instead of <Eigen/SVD> or <Eigen/QR>: its extern declarations keep the user from
// instantiating them again, and dense_decompositions.cc instantiates them for everyone. Use the
// classes exactly as Eigen documents them; only these four matrix types are covered.
#pragma once

#include <Eigen/Core>
#include <Eigen/QR>
#include <Eigen/SVD>

extern template class Eigen::BDCSVD<Eigen::MatrixXd>;
extern template class Eigen::JacobiSVD<Eigen::MatrixXd>;
extern template class Eigen::HouseholderQR<Eigen::MatrixXd>;
extern template class Eigen::ColPivHouseholderQR<Eigen::MatrixXd>;
