#pragma once
// A raster image of one channel with a validity mask, as the image kernels exchange it
// (orthoimages, intensity patches). Pixel (row, column); rows and columns start at 0.
#include <Eigen/Core>

namespace tlsmon {

using ImageMask = Eigen::Array<bool, Eigen::Dynamic, Eigen::Dynamic>;

struct Image {
    Eigen::ArrayXXd value;  // rows × columns; meaningless where !valid
    ImageMask valid;        // same shape: false for an empty pixel

    Eigen::Index rows() const { return value.rows(); }
    Eigen::Index columns() const { return value.cols(); }
};

}  // namespace tlsmon
