// Absolute trajectory error: TUM's evaluate_ate.py (Horn alignment of positions) and Co-Fusion's
// object trajectories (alignment of the first pose).
#include <Eigen/SVD>
#include <cmath>

#include "eval/trajectory_metrics.hpp"

namespace df::eval {

Eigen::Isometry3d align_positions(const std::vector<Eigen::Vector3d>& gt_positions,
                                  const std::vector<Eigen::Vector3d>& est_positions) {
    const size_t n = std::min(gt_positions.size(), est_positions.size());
    Eigen::Vector3d gt_mean = Eigen::Vector3d::Zero(), est_mean = Eigen::Vector3d::Zero();
    for (size_t i = 0; i < n; ++i) {
        gt_mean += gt_positions[i];
        est_mean += est_positions[i];
    }
    gt_mean /= static_cast<double>(n);
    est_mean /= static_cast<double>(n);
    Eigen::Matrix3d W = Eigen::Matrix3d::Zero();
    for (size_t i = 0; i < n; ++i) {
        W += (gt_positions[i] - gt_mean) * (est_positions[i] - est_mean).transpose();
    }
    const Eigen::JacobiSVD<Eigen::Matrix3d> svd(W, Eigen::ComputeFullU | Eigen::ComputeFullV);
    const Eigen::Matrix3d& U = svd.matrixU();
    const Eigen::Matrix3d& V = svd.matrixV();
    Eigen::Matrix3d S = Eigen::Matrix3d::Identity();
    if (U.determinant() * V.determinant() < 0) S(2, 2) = -1;  // a rotation, not a reflection
    Eigen::Isometry3d gt_T_est = Eigen::Isometry3d::Identity();
    gt_T_est.linear() = U * S * V.transpose();
    gt_T_est.translation() = gt_mean - gt_T_est.linear() * est_mean;
    return gt_T_est;
}

namespace {

struct Associated {
    Trajectory gt, est;
    std::vector<StampMatch> matches;
};

Result<Associated> sort_and_associate(const Trajectory& gt, const Trajectory& est,
                                      const AssociationConfig& config) {
    Associated a{gt, est, {}};
    sort_unique_by_stamp(&a.gt);
    sort_unique_by_stamp(&a.est);
    a.matches = associate_stamps(stamps_of(a.gt), stamps_of(a.est), config);
    if (a.matches.size() < 2) {
        return error(StatusCode::kInvalidArgument,
                     describe_no_overlap(a.gt, a.est, config, a.matches.size()));
    }
    return a;
}

/// Fills the pairs and their statistics of `result` for the alignment result->gt_T_est.
void score_aligned(const Associated& a, AteResult* result) {
    std::vector<double> errors;
    for (const StampMatch& m : a.matches) {
        AtePair p;
        p.gt_stamp_s = a.gt[m.gt].stamp_s;
        p.est_stamp_s = a.est[m.est].stamp_s;
        p.gt_position = a.gt[m.gt].t;
        p.est_position_aligned = result->gt_T_est * a.est[m.est].t;
        p.error_m = (p.est_position_aligned - p.gt_position).norm();
        errors.push_back(p.error_m);
        result->pairs.push_back(p);
    }
    result->translation_m = summarize_errors(errors);
    result->gt_poses = a.gt.size();
    result->est_poses = a.est.size();
}

}  // namespace

Result<AteResult> compute_ate(const Trajectory& gt, const Trajectory& est,
                              const AssociationConfig& config) {
    auto a = sort_and_associate(gt, est, config);
    if (!a) return a.status();
    std::vector<Eigen::Vector3d> gt_xyz, est_xyz;
    for (const StampMatch& m : a->matches) {
        gt_xyz.push_back(a->gt[m.gt].t);
        est_xyz.push_back(a->est[m.est].t);
    }
    AteResult result;
    result.association = config;
    result.alignment = AlignmentKind::kHornPositions;
    result.gt_T_est = align_positions(gt_xyz, est_xyz);
    score_aligned(*a, &result);
    return result;
}

Result<ObjectTrajectoryResult> compute_object_errors(const Trajectory& gt, const Trajectory& est,
                                                     const AssociationConfig& association,
                                                     const RpeConfig& rpe) {
    auto a = sort_and_associate(gt, est, association);
    if (!a) return a.status();
    ObjectTrajectoryResult result;
    AteResult& ate = result.ate;
    ate.association = association;
    ate.alignment = AlignmentKind::kFirstPose;
    const StampMatch& first = a->matches.front();
    ate.gt_T_est = to_isometry(a->gt[first.gt]) * to_isometry(a->est[first.est]).inverse();
    score_aligned(*a, &ate);
    std::vector<double> angles_deg;
    for (const StampMatch& m : a->matches) {
        const Eigen::Quaterniond est_aligned(ate.gt_T_est.linear() *
                                             a->est[m.est].q.toRotationMatrix());
        angles_deg.push_back(a->gt[m.gt].q.angularDistance(est_aligned) * kDegPerRad);
    }
    result.rotation_deg = summarize_errors(angles_deg);
    RpeConfig rpe_config = rpe;
    rpe_config.offset_s = association.offset_s;  // one clock offset for both figures
    auto relative = compute_rpe(a->gt, a->est, rpe_config);
    if (relative) {
        result.rpe = std::move(*relative);
    } else {
        result.rpe_error = relative.status().message();
    }
    return result;
}

}  // namespace df::eval
