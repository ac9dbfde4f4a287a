#pragma once
/// The subcommands of df_eval: each loads its inputs, calls the df_eval library, prints a table
/// and writes the JSON / PNG asked for. They return the process exit code (0 ok, 1 failed).
#include <optional>
#include <string>
#include <vector>

#include "eval/object_association.hpp"
#include "eval/reconstruction.hpp"
#include "eval/segmentation.hpp"
#include "eval/trajectory_metrics.hpp"

namespace df::eval_cli {

struct Outputs {
    std::string json_file;  ///< empty: none
    std::string plot_file;  ///< empty: none
};

int cmd_ate(const std::string& gt, const std::string& est, const eval::AssociationConfig& config,
            const Outputs& out);
int cmd_rpe(const std::string& gt, const std::string& est, const eval::RpeConfig& config,
            const Outputs& out);
/// How `object` aligns the estimate (see eval::ObjectAlignment).
struct ObjectOptions {
    std::string world;        ///< empty, or "tx ty tz qx qy qz qw": gt_T_est of the worlds (W)
    bool body_align = false;  ///< also solve the object frame offset X from the first pair
};
int cmd_object(const std::string& gt, const std::string& est,
               const eval::AssociationConfig& association, const eval::RpeConfig& rpe,
               const ObjectOptions& object, const Outputs& out);
/// `transform`: empty, or "tx ty tz qx qy qz qw" (gt_T_est) applied to the estimate first.
/// `registration`: when set, the estimate is also registered onto the ground truth from there
/// and scored again.
int cmd_recon(const std::string& gt_ply, const std::string& est_ply,
              const eval::ReconstructionConfig& config, const std::string& transform,
              const std::optional<eval::RegistrationConfig>& registration, const Outputs& out);
int cmd_seg(const std::string& gt_sequence, const std::string& pred_dir,
            const eval::SegmentationConfig& config, const Outputs& out);
/// Binary masks (non-zero = in) of `pred_dir` against those of `gt_dir`, by file name.
int cmd_mask(const std::string& gt_dir, const std::string& pred_dir, const Outputs& out);
int cmd_timing(const std::vector<std::string>& logs, const Outputs& out);

struct RunOptions {
    eval::AssociationConfig association;
    eval::ReconstructionConfig reconstruction;
    eval::SegmentationConfig segmentation;
    bool plots = true;
    bool align_map = true;  ///< move map.ply into the GT frame with the camera ATE alignment
    /// Object maps (RUN_DIR/objects.json): association by masks and the models' threshold.
    eval::ObjectAssociationConfig object_association;
    eval::ReconstructionConfig object_model{0.01};
};
/// Scores whatever RUN_DIR holds against SEQ_DIR; writes RUN_DIR/eval.json and eval_*.png.
int cmd_run(const std::string& sequence_dir, const std::string& run_dir, const RunOptions& options);

}  // namespace df::eval_cli
