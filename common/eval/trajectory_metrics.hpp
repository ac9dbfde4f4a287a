#pragma once
/// Trajectory errors as the public benchmarks compute them:
///  - association of stamps as TUM's associate.py,
///  - ATE as TUM's evaluate_ate.py (positions aligned by Horn's method, no scale),
///  - RPE as TUM's evaluate_rpe.py with a fixed delta (seconds or frames),
///  - object trajectories as Co-Fusion's tools (aligned by their first pose).
/// Poses are world_T_camera (or world_T_object) in TUM's convention; see docs/evaluation.md.
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <optional>
#include <string>
#include <vector>

#include "core/status.hpp"
#include "eval/stats.hpp"
#include "io/tum/trajectory.hpp"

namespace df::eval {

using Trajectory = std::vector<io::StampedPose>;

struct LoadedTrajectory {
    std::string file;
    Trajectory poses;                   ///< sorted by stamp, stamps unique
    std::vector<std::string> warnings;  ///< e.g. a stamp given twice
};

/// Reads a TUM trajectory for scoring. Strict: any malformed line fails with "<file>:<line>: ...",
/// and so does a file without poses. Sorted by stamp; a stamp given twice keeps the later line
/// (TUM's tools read into a dict) and adds a warning.
Result<LoadedTrajectory> load_trajectory(const std::string& file);

/// Sorts by stamp (stable) and, of poses with equal stamps, keeps the last one. Returns how many
/// poses were dropped.
size_t sort_unique_by_stamp(Trajectory* trajectory);

std::vector<double> stamps_of(const Trajectory& trajectory);

struct AssociationConfig {
    double max_difference_s = 0.02;  ///< pairs need |t_gt - (t_est + offset)| < this
    double offset_s = 0.0;           ///< added to the estimate's stamps
};

/// A pair of indices into the ground truth and the estimate.
struct StampMatch {
    size_t gt = 0;
    size_t est = 0;
};

/// TUM's associate: every pair with |t_gt - (t_est + offset)| < max_difference is a candidate;
/// candidates are taken by increasing difference (ties by gt stamp, then est stamp), each stamp at
/// most once. Result sorted by gt stamp. Stamps must be sorted and unique.
std::vector<StampMatch> associate_stamps(const std::vector<double>& gt_stamps_s,
                                         const std::vector<double>& est_stamps_s,
                                         const AssociationConfig& config);

/// "ground truth has N poses in [a, b] s, estimate has M poses in [c, d] s".
std::string describe_ranges(const Trajectory& gt, const Trajectory& est);

/// "no common stamps: ground truth has N poses in [a, b] s, estimate M poses in [c, d] s, ...".
std::string describe_no_overlap(const Trajectory& gt, const Trajectory& est,
                                const AssociationConfig& config, size_t pairs_found);

/// The rigid transform gt_T_est (no scale) minimising sum |gt_i - gt_T_est est_i|^2:
/// centred points, W = sum gt_c est_c^T = U S V^T, R = U diag(1, 1, det(U V^T)) V^T,
/// t = mean(gt) - R mean(est). Both lists have the same length (>= 1).
Eigen::Isometry3d align_positions(const std::vector<Eigen::Vector3d>& gt_positions,
                                  const std::vector<Eigen::Vector3d>& est_positions);

enum class AlignmentKind {
    kHornPositions,  ///< TUM ATE: least squares over all associated positions
    kFirstPose,      ///< Co-Fusion objects: gt_T_est = T_gt(first) T_est(first)^-1
    kGivenWorld,     ///< objects: gt_T_est given (e.g. the camera ATE alignment), nothing solved
    /// objects: gt_T_est given (or identity) and the object frame offset solved from the first
    /// associated pair (see ObjectAlignment)
    kWorldAndObjectFirstPose,
};
const char* to_string(AlignmentKind kind);

struct AtePair {
    double gt_stamp_s = 0;
    double est_stamp_s = 0;
    Eigen::Vector3d gt_position = Eigen::Vector3d::Zero();           ///< world metres
    Eigen::Vector3d est_position_aligned = Eigen::Vector3d::Zero();  ///< gt_T_est * est
    double error_m = 0;
};

struct AteResult {
    ErrorStats translation_m;  ///< residual position errors after alignment
    Eigen::Isometry3d gt_T_est = Eigen::Isometry3d::Identity();  ///< the alignment applied
    AlignmentKind alignment = AlignmentKind::kHornPositions;
    std::vector<AtePair> pairs;  ///< sorted by gt stamp
    size_t gt_poses = 0;
    size_t est_poses = 0;
    AssociationConfig association;
};

/// ATE as TUM's evaluate_ate.py. Fails (kInvalidArgument, with both stamp ranges) when fewer than
/// two pairs associate.
Result<AteResult> compute_ate(const Trajectory& gt, const Trajectory& est,
                              const AssociationConfig& config = {});

enum class DeltaUnit { kSeconds, kFrames };
const char* to_string(DeltaUnit unit);  ///< "s" or "f"

/// Which relative error is measured. A = est_i^-1 est_j and B = gt_i^-1 gt_j are the relative
/// motions. Their rotation angles agree; their translations differ when the rotation is wrong.
enum class RpeForm {
    kTumScript,  ///< E = A B^-1, what evaluate_rpe.py computes (and published figures use)
    kPaper,      ///< E = B^-1 A, Sturm et al. 2012, eq. (1)
};
const char* to_string(RpeForm form);  ///< "tum" or "paper"

struct RpeConfig {
    double delta = 1.0;  ///< in `unit`
    DeltaUnit unit = DeltaUnit::kSeconds;
    double offset_s = 0.0;  ///< added to the estimate's stamps
    RpeForm form = RpeForm::kTumScript;
};

struct RpePair {
    double est_stamp_0_s = 0, est_stamp_1_s = 0;
    double gt_stamp_0_s = 0, gt_stamp_1_s = 0;
    double translation_m = 0;
    double rotation_deg = 0;
};

struct RpeResult {
    ErrorStats translation_m;
    ErrorStats rotation_deg;
    std::vector<RpePair> pairs;  ///< by est_stamp_0_s
    RpeConfig config;
};

/// RPE as TUM's evaluate_rpe.py with --fixed_delta: for each estimated pose i (sorted by stamp),
/// j is the pose whose index value (stamp, or frame number) is closest to index_i + delta (ties:
/// the earlier); pairs whose j is the last pose are dropped (as TUM does); each of the two est
/// stamps takes the closest gt stamp, and a pair is dropped if either is farther than twice the
/// median gt interval. All pairs are used (TUM samples 10000 at random if there are more).
/// Fails when fewer than two pairs remain.
Result<RpeResult> compute_rpe(const Trajectory& gt, const Trajectory& est,
                              const RpeConfig& config = {});

/// How an object's estimated poses are brought onto its ground truth: est'_i = W est_i X, with
/// W = gt_T_est (ground-truth world from estimated world) and X = est_object_T_gt_object (the
/// ground-truth object frame in the estimated object frame: a SLAM system picks its own origin
/// and axes for an object's model).
struct ObjectAlignment {
    /// W, e.g. the camera ATE alignment. Absent: W = T_gt(0) T_est(0)^-1 from the first
    /// associated pair (Co-Fusion), or the identity when `object_frame` is set.
    std::optional<Eigen::Isometry3d> world_gt_T_est;
    /// Also solve X from the first associated pair: X = (W T_est(0))^-1 T_gt(0), so that est'_0 =
    /// gt_0. Otherwise X = identity.
    bool object_frame = false;
};

struct ObjectTrajectoryResult {
    AteResult ate;  ///< alignment: kFirstPose, kGivenWorld or kWorldAndObjectFirstPose; W
    Eigen::Isometry3d est_object_T_gt_object = Eigen::Isometry3d::Identity();  ///< X
    ErrorStats rotation_deg;       ///< angle of gt^-1 (W est X) per associated pair
    std::optional<RpeResult> rpe;  ///< of W est X against gt; absent when too few pairs
    std::string rpe_error;
};

/// An object's estimated poses (est world_T_object) against its ground truth after aligning the
/// first associated pair: gt_T_est = T_gt(0) T_est(0)^-1 applied to every estimated pose.
/// The RPE uses association.offset_s (rpe.offset_s is ignored).
Result<ObjectTrajectoryResult> compute_object_errors(const Trajectory& gt, const Trajectory& est,
                                                     const AssociationConfig& association = {},
                                                     const RpeConfig& rpe = {});

/// As above with the alignment spelled out: est'_i = W est_i X (see ObjectAlignment); position
/// errors |t(est'_i) - t(gt_i)|, rotation errors angle(gt_i^-1 est'_i), RPE of est' against gt.
Result<ObjectTrajectoryResult> compute_object_errors(const Trajectory& gt, const Trajectory& est,
                                                     const ObjectAlignment& alignment,
                                                     const AssociationConfig& association = {},
                                                     const RpeConfig& rpe = {});

/// Every estimated pose moved as the result aligned them: W est_i X (for figures).
Trajectory aligned_object_poses(const ObjectTrajectoryResult& object, const Trajectory& est);

/// world_T_x as a 4x4 isometry.
Eigen::Isometry3d to_isometry(const io::StampedPose& pose);

}  // namespace df::eval
