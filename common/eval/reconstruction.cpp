#include "eval/reconstruction.hpp"

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

std::vector<Eigen::Vector3d> transform_points(const Eigen::Isometry3d& gt_T_est,
                                              const std::vector<Eigen::Vector3d>& points) {
    std::vector<Eigen::Vector3d> out;
    out.reserve(points.size());
    for (const auto& p : points) out.push_back(gt_T_est * p);
    return out;
}

}  // namespace df::eval
