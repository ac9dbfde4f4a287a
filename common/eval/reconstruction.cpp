#include "eval/reconstruction.hpp"

#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <cmath>
#include <nanoflann.hpp>

namespace df::eval {

namespace {

/// nanoflann's view of a point list.
struct PointsAdaptor {
    const std::vector<Eigen::Vector3d>& points;
    size_t kdtree_get_point_count() const { return points.size(); }
    double kdtree_get_pt(size_t i, size_t dim) const { return points[i][static_cast<int>(dim)]; }
    template <class Box>
    bool kdtree_get_bbox(Box&) const {
        return false;  // let nanoflann compute it
    }
};

using KdTree =
    nanoflann::KDTreeSingleIndexAdaptor<nanoflann::L2_Simple_Adaptor<double, PointsAdaptor>,
                                        PointsAdaptor, 3, size_t>;

double fraction_within(const std::vector<double>& distances, double threshold) {
    size_t n = 0;
    for (double d : distances) n += d <= threshold;
    return distances.empty() ? 0.0 : static_cast<double>(n) / static_cast<double>(distances.size());
}

}  // namespace

std::vector<double> nearest_distances(const std::vector<Eigen::Vector3d>& from,
                                      const std::vector<Eigen::Vector3d>& to) {
    const PointsAdaptor adaptor{to};
    const KdTree tree(3, adaptor, nanoflann::KDTreeSingleIndexAdaptorParams(16));  // builds
    std::vector<double> distances(from.size());
    for (size_t i = 0; i < from.size(); ++i) {
        size_t index = 0;
        double dist_sq = 0;
        nanoflann::KNNResultSet<double, size_t> result(1);
        result.init(&index, &dist_sq);
        tree.findNeighbors(result, from[i].data(), nanoflann::SearchParams());
        distances[i] = std::sqrt(dist_sq);
    }
    return distances;
}

Result<ReconstructionResult> score_reconstruction(const std::vector<Eigen::Vector3d>& gt,
                                                  const std::vector<Eigen::Vector3d>& est,
                                                  const ReconstructionConfig& config) {
    if (gt.empty() || est.empty()) {
        return error(StatusCode::kInvalidArgument,
                     std::string("cannot score a reconstruction: the ") +
                         (gt.empty() ? "ground-truth model" : "reconstruction") + " has no points");
    }
    if (!(config.threshold_m > 0)) {
        return error(StatusCode::kInvalidArgument,
                     "reconstruction threshold must be positive, got " +
                         std::to_string(config.threshold_m) + " m");
    }
    const std::vector<double> est_to_gt = nearest_distances(est, gt);
    const std::vector<double> gt_to_est = nearest_distances(gt, est);
    ReconstructionResult r;
    r.threshold_m = config.threshold_m;
    r.accuracy = fraction_within(est_to_gt, config.threshold_m);
    r.completeness = fraction_within(gt_to_est, config.threshold_m);
    const double sum = r.accuracy + r.completeness;
    r.f_score = sum > 0 ? 2 * r.accuracy * r.completeness / sum : 0.0;
    r.est_to_gt_m = summarize_errors(est_to_gt);
    r.gt_to_est_m = summarize_errors(gt_to_est);
    r.est_points = est.size();
    r.gt_points = gt.size();
    return r;
}

namespace {

/// Unit normal of the ground truth at point i: the least-variance direction of its k nearest
/// neighbours (computed on first use; the ground truth is a point sample with no normals).
class GroundTruthNormals {
  public:
    GroundTruthNormals(const std::vector<Eigen::Vector3d>& points, const KdTree& tree)
        : points_(points), tree_(tree), normals_(points.size()), known_(points.size(), 0) {}

    const Eigen::Vector3d& at(size_t i) {
        if (known_[i]) return normals_[i];
        constexpr size_t kNeighbours = 12;
        std::array<size_t, kNeighbours> index{};
        std::array<double, kNeighbours> dist_sq{};
        nanoflann::KNNResultSet<double, size_t> result(kNeighbours);
        result.init(index.data(), dist_sq.data());
        tree_.findNeighbors(result, points_[i].data(), nanoflann::SearchParams());
        const size_t n = result.size();
        Eigen::Vector3d mean = Eigen::Vector3d::Zero();
        for (size_t k = 0; k < n; ++k) mean += points_[index[k]];
        mean /= static_cast<double>(std::max<size_t>(1, n));
        Eigen::Matrix3d cov = Eigen::Matrix3d::Zero();
        for (size_t k = 0; k < n; ++k) {
            const Eigen::Vector3d d = points_[index[k]] - mean;
            cov += d * d.transpose();
        }
        const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(cov);
        normals_[i] = eig.eigenvectors().col(0);  // smallest eigenvalue first
        known_[i] = 1;
        return normals_[i];
    }

  private:
    const std::vector<Eigen::Vector3d>& points_;
    const KdTree& tree_;
    std::vector<Eigen::Vector3d> normals_;
    std::vector<uint8_t> known_;
};

}  // namespace

Result<RegistrationResult> register_reconstruction(const std::vector<Eigen::Vector3d>& gt,
                                                   const std::vector<Eigen::Vector3d>& est,
                                                   const Eigen::Isometry3d& initial_gt_T_est,
                                                   const RegistrationConfig& config) {
    if (gt.empty() || est.empty()) {
        return error(StatusCode::kInvalidArgument,
                     std::string("cannot register a reconstruction: the ") +
                         (gt.empty() ? "ground-truth model" : "reconstruction") + " has no points");
    }
    if (!(config.max_distance_m > 0) || config.max_iterations < 1 || !(config.min_update_m >= 0)) {
        return error(StatusCode::kInvalidArgument,
                     "registration needs max_distance_m > 0, max_iterations >= 1 and "
                     "min_update_m >= 0, got " +
                         std::to_string(config.max_distance_m) + " m, " +
                         std::to_string(config.max_iterations) + ", " +
                         std::to_string(config.min_update_m) + " m");
    }
    const PointsAdaptor adaptor{gt};
    const KdTree tree(3, adaptor, nanoflann::KDTreeSingleIndexAdaptorParams(16));
    GroundTruthNormals normals(gt, tree);
    // The extent of the reconstruction, to turn a rotation update into a displacement.
    Eigen::Vector3d lo = est.front(), hi = est.front();
    for (const auto& p : est) {
        lo = lo.cwiseMin(p);
        hi = hi.cwiseMax(p);
    }
    const double extent = std::max(1e-3, 0.5 * (hi - lo).norm());
    const double max_sq = config.max_distance_m * config.max_distance_m;

    // Point-to-plane ICP (a point sample of a plane has no sliding force point-to-point: every
    // point sits in a well of its nearest sample), linearised about the current estimate.
    RegistrationResult r;
    r.gt_T_est = initial_gt_T_est;
    for (int it = 0; it < config.max_iterations; ++it) {
        Eigen::Matrix<double, 6, 6> a = Eigen::Matrix<double, 6, 6>::Zero();
        Eigen::Matrix<double, 6, 1> b = Eigen::Matrix<double, 6, 1>::Zero();
        size_t n = 0;
        double sum_sq = 0;
        for (const auto& point : est) {
            const Eigen::Vector3d p = r.gt_T_est * point;
            size_t index = 0;
            double dist_sq = 0;
            nanoflann::KNNResultSet<double, size_t> result(1);
            result.init(&index, &dist_sq);
            tree.findNeighbors(result, p.data(), nanoflann::SearchParams());
            if (dist_sq > max_sq) continue;
            const Eigen::Vector3d& normal = normals.at(index);
            Eigen::Matrix<double, 6, 1> j;
            j.head<3>() = p.cross(normal);
            j.tail<3>() = normal;
            const double residual = (p - gt[index]).dot(normal);
            a.noalias() += j * j.transpose();
            b.noalias() -= j * residual;
            sum_sq += dist_sq;
            ++n;
        }
        r.pairs = n;
        r.rmse_m = n > 0 ? std::sqrt(sum_sq / static_cast<double>(n)) : 0.0;
        if (n < 6) {
            return error(StatusCode::kInvalidArgument,
                         "cannot register: " + std::to_string(n) + " of " +
                             std::to_string(est.size()) + " reconstructed points lie within " +
                             std::to_string(config.max_distance_m) +
                             " m of the ground truth at the current alignment");
        }
        // A little damping keeps a degenerate shape (one plane) from sliding without bound.
        a.diagonal().array() += 1e-9 * a.trace() + 1e-12;
        const Eigen::Matrix<double, 6, 1> x = a.ldlt().solve(b);
        Eigen::Isometry3d step = Eigen::Isometry3d::Identity();
        const double angle = x.head<3>().norm();
        if (angle > 0) step.linear() = Eigen::AngleAxisd(angle, x.head<3>() / angle).toRotationMatrix();
        step.translation() = x.tail<3>();
        r.gt_T_est = step * r.gt_T_est;
        r.iterations = it + 1;
        if (x.tail<3>().norm() + angle * extent <= config.min_update_m) break;
    }
    const Eigen::Isometry3d correction = r.gt_T_est * initial_gt_T_est.inverse();
    // The correction's size at the reconstruction's centre, where it moves the model.
    const Eigen::Vector3d centre = initial_gt_T_est * (0.5 * (lo + hi));
    r.correction_translation_m = (correction * centre - centre).norm();
    r.correction_rotation_deg =
        Eigen::AngleAxisd(correction.linear()).angle() * 180.0 / 3.14159265358979323846;
    return r;
}

Result<RegisteredReconstruction> score_registered(const std::vector<Eigen::Vector3d>& gt,
                                                  const std::vector<Eigen::Vector3d>& est,
                                                  const Eigen::Isometry3d& initial_gt_T_est,
                                                  const ReconstructionConfig& score,
                                                  const RegistrationConfig& registration) {
    auto fit = register_reconstruction(gt, est, initial_gt_T_est, registration);
    if (!fit) return fit.status();
    auto scored = score_reconstruction(gt, transform_points(fit->gt_T_est, est), score);
    if (!scored) return scored.status();
    return RegisteredReconstruction{*fit, *scored};
}

std::vector<Eigen::Vector3d> transform_points(const Eigen::Isometry3d& gt_T_est,
                                              const std::vector<Eigen::Vector3d>& points) {
    std::vector<Eigen::Vector3d> out;
    out.reserve(points.size());
    for (const auto& p : points) out.push_back(gt_T_est * p);
    return out;
}

}  // namespace df::eval
