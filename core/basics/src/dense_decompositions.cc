// The one instantiation of the decompositions dense_decompositions.h declares extern (an explicit
// instantiation definition may follow its extern declaration).
#include "cellmetry/basics/dense_decompositions.h"

template class Eigen::BDCSVD<Eigen::MatrixXd>;
template class Eigen::JacobiSVD<Eigen::MatrixXd>;
template class Eigen::HouseholderQR<Eigen::MatrixXd>;
template class Eigen::ColPivHouseholderQR<Eigen::MatrixXd>;
