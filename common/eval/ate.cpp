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

/// est'_i = W est_i X.
io::StampedPose move_pose(const Eigen::Isometry3d& W, const io::StampedPose& est,
                          const Eigen::Isometry3d& X) {
    io::StampedPose out = est;
    out.t = W * (est.q * X.translation() + est.t);  // exactly W est.t when X is the identity
    out.q = Eigen::Quaterniond(W.linear() * est.q.toRotationMatrix() * X.linear()).normalized();
    return out;
}

/// Fills the pairs and their statistics of `result` for the alignment result->gt_T_est, with the
/// estimated object frame moved by X (identity for camera trajectories).
void score_aligned(const Associated& a, const Eigen::Isometry3d& X, AteResult* result) {
    std::vector<double> errors;
    for (const StampMatch& m : a.matches) {
        AtePair p;
        p.gt_stamp_s = a.gt[m.gt].stamp_s;
        p.est_stamp_s = a.est[m.est].stamp_s;
        p.gt_position = a.gt[m.gt].t;
        p.est_position_aligned = move_pose(result->gt_T_est, a.est[m.est], X).t;
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
    score_aligned(*a, Eigen::Isometry3d::Identity(), &result);
    return result;
}

Result<ObjectTrajectoryResult> compute_object_errors(const Trajectory& gt, const Trajectory& est,
                                                     const AssociationConfig& association,
                                                     const RpeConfig& rpe) {
    return compute_object_errors(gt, est, ObjectAlignment{}, association, rpe);
}

Result<ObjectTrajectoryResult> compute_object_errors(const Trajectory& gt, const Trajectory& est,
                                                     const ObjectAlignment& alignment,
                                                     const AssociationConfig& association,
                                                     const RpeConfig& rpe) {
    auto a = sort_and_associate(gt, est, association);
    if (!a) return a.status();
    ObjectTrajectoryResult result;
    AteResult& ate = result.ate;
    ate.association = association;
    const StampMatch& first = a->matches.front();
    const Eigen::Isometry3d gt_0 = to_isometry(a->gt[first.gt]);
    const Eigen::Isometry3d est_0 = to_isometry(a->est[first.est]);
    Eigen::Isometry3d& W = ate.gt_T_est;
    Eigen::Isometry3d& X = result.est_object_T_gt_object;
    if (alignment.world_gt_T_est) {
        W = *alignment.world_gt_T_est;
    } else if (!alignment.object_frame) {
        W = gt_0 * est_0.inverse();
    }
    if (alignment.object_frame) X = (W * est_0).inverse() * gt_0;
    ate.alignment = alignment.object_frame     ? AlignmentKind::kWorldAndObjectFirstPose
                    : alignment.world_gt_T_est ? AlignmentKind::kGivenWorld
                                               : AlignmentKind::kFirstPose;
    score_aligned(*a, X, &ate);
    std::vector<double> angles_deg;
    for (const StampMatch& m : a->matches) {
        const Eigen::Quaterniond est_aligned = move_pose(W, a->est[m.est], X).q;
        angles_deg.push_back(a->gt[m.gt].q.angularDistance(est_aligned) * kDegPerRad);
    }
    result.rotation_deg = summarize_errors(angles_deg);
    RpeConfig rpe_config = rpe;
    rpe_config.offset_s = association.offset_s;  // one clock offset for both figures
    // A constant W does not change relative motions, X does: only then is est' scored.
    auto relative = compute_rpe(
        a->gt, alignment.object_frame ? aligned_object_poses(result, a->est) : a->est, rpe_config);
    if (relative) {
        result.rpe = std::move(*relative);
    } else {
        result.rpe_error = relative.status().message();
    }
    return result;
}

Trajectory aligned_object_poses(const ObjectTrajectoryResult& object, const Trajectory& est) {
    Trajectory out;
    out.reserve(est.size());
    for (const auto& p : est) {
        out.push_back(move_pose(object.ate.gt_T_est, p, object.est_object_T_gt_object));
    }
    return out;
}

}  // namespace df::eval
