// The one instantiation of the decompositions dense_decompositions.h declares extern.
#include <Eigen/Core>
#include <Eigen/QR>
#include <Eigen/SVD>

template class Eigen::BDCSVD<Eigen::MatrixXd>;
template class Eigen::JacobiSVD<Eigen::MatrixXd>;
template class Eigen::HouseholderQR<Eigen::MatrixXd>;
template class Eigen::ColPivHouseholderQR<Eigen::MatrixXd>;
