#pragma once
/// Reconstruction quality: accuracy and completeness of a reconstructed point set against a
/// ground-truth surface sampled as points, by nearest neighbours (nanoflann k-d trees).
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <vector>

#include "core/status.hpp"
#include "eval/stats.hpp"

namespace df::eval {

struct ReconstructionConfig {
    /// A point counts as matched when its nearest neighbour on the other set is at most this far.
    /// 5 cm: the "completion ratio" threshold of room-scale RGB-D SLAM papers (NICE-SLAM,
    /// Co-SLAM), and safely above the distances that sampling alone causes against a ground truth
    /// sampled every 2 cm (up to ~2 cm for a perfect surface; see docs/evaluation.md).
    double threshold_m = 0.05;
};

struct ReconstructionResult {
    double threshold_m = 0;
    double accuracy = 0;      ///< fraction of reconstructed points within threshold of the GT
    double completeness = 0;  ///< fraction of GT points within threshold of the reconstruction
    double f_score = 0;       ///< harmonic mean of accuracy and completeness (0 if both are 0)
    ErrorStats est_to_gt_m;   ///< nearest-GT distance of every reconstructed point
    ErrorStats gt_to_est_m;   ///< nearest-reconstruction distance of every GT point
    size_t est_points = 0;
    size_t gt_points = 0;
};

/// Distance from every point of `from` to its nearest neighbour in `to` (metres). `to` non-empty.
std::vector<double> nearest_distances(const std::vector<Eigen::Vector3d>& from,
                                      const std::vector<Eigen::Vector3d>& to);

/// Scores `est` (already in the GT frame) against `gt`. kInvalidArgument if either is empty or
/// the threshold is not positive.
Result<ReconstructionResult> score_reconstruction(const std::vector<Eigen::Vector3d>& gt,
                                                  const std::vector<Eigen::Vector3d>& est,
                                                  const ReconstructionConfig& config = {});

/// Rigid registration of a reconstruction onto its ground truth (trimmed point-to-plane ICP, the
/// ground truth's normals from its points' neighbourhoods):
/// separates the model's shape from the pose error that placed it. An object model is moved
/// into the ground-truth object frame by its first pose pair, so a 1 cm error of that one pose
/// shifts every point by 1 cm and a 1 cm accuracy figure then measures the pose, not the model.
struct RegistrationConfig {
    int max_iterations = 50;
    /// Pairs farther apart than this are left out (the part of a reconstruction the ground
    /// truth lacks, e.g. floor fused into an object's model, does not pull the fit).
    double max_distance_m = 0.03;
    /// Iterations stop when the update moves no point of the reconstruction's bounding box by
    /// more than this.
    double min_update_m = 1e-6;
};

struct RegistrationResult {
    Eigen::Isometry3d gt_T_est = Eigen::Isometry3d::Identity();  ///< refined
    /// The correction applied on top of the initial gt_T_est (in the ground-truth frame): how far
    /// the initial alignment was from the best fit.
    double correction_translation_m = 0;
    double correction_rotation_deg = 0;
    int iterations = 0;
    size_t pairs = 0;  ///< pairs within max_distance_m at the end
    double rmse_m = 0;  ///< their RMS distance
};

/// Refines `initial` gt_T_est so that `est` fits `gt` best. kInvalidArgument if either set is
/// empty, the configuration is invalid, or fewer than 6 points of
/// `est` lie within max_distance_m of `gt` at an iteration (nothing to fit).
Result<RegistrationResult> register_reconstruction(const std::vector<Eigen::Vector3d>& gt,
                                                   const std::vector<Eigen::Vector3d>& est,
                                                   const Eigen::Isometry3d& initial_gt_T_est,
                                                   const RegistrationConfig& config = {});

/// A reconstruction registered onto its ground truth from `initial_gt_T_est`, and its score there.
struct RegisteredReconstruction {
    RegistrationResult registration;
    ReconstructionResult score;
};
/// register_reconstruction() then score_reconstruction() at the fitted pose; their errors.
Result<RegisteredReconstruction> score_registered(const std::vector<Eigen::Vector3d>& gt,
                                                  const std::vector<Eigen::Vector3d>& est,
                                                  const Eigen::Isometry3d& initial_gt_T_est,
                                                  const ReconstructionConfig& score = {},
                                                  const RegistrationConfig& registration = {});

/// Applies gt_T_est to every point.
std::vector<Eigen::Vector3d> transform_points(const Eigen::Isometry3d& gt_T_est,
                                              const std::vector<Eigen::Vector3d>& points);

}  // namespace df::eval
