#pragma once
/// Rigid-pose hygiene. Eigen::Isometry3d::inverse() transposes the rotation, which is the
/// inverse only while the matrix is orthonormal. Chained tracking (estimate = reference *
/// reference^-1 * ...) turns a rotation with scale 1 + e into one with scale 1 + 3e each frame,
/// so rounding noise of 1e-16 becomes a visible depth scale after about 25 frames unless every
/// pose that is kept is projected back onto SO(3).
#include <Eigen/Geometry>
#include <Eigen/SVD>

namespace df::slam {

/// The nearest rigid transform: the rotation part replaced by its closest rotation matrix
/// (polar decomposition U V^T, determinant +1), the translation kept.
inline Eigen::Isometry3d orthonormalized(const Eigen::Isometry3d& pose) {
    const Eigen::JacobiSVD<Eigen::Matrix3d> svd(pose.linear(),
                                                Eigen::ComputeFullU | Eigen::ComputeFullV);
    Eigen::Matrix3d u = svd.matrixU();
    const Eigen::Matrix3d v = svd.matrixV();
    if ((u * v.transpose()).determinant() < 0.0) u.col(2) = -u.col(2);
    Eigen::Isometry3d out = Eigen::Isometry3d::Identity();
    out.linear() = u * v.transpose();
    out.translation() = pose.translation();
    return out;
}

}  // namespace df::slam
