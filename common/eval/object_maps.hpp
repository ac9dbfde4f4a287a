#pragma once
/// Scoring a run's object maps (one surfel model and trajectory per object the SLAM system
/// tracked, numbered by the system) against a sequence's ground-truth instances: association by
/// mask overlap (object_association.hpp), then per matched pair the trajectory with both frames
/// aligned (est'_i = W est_i X) and the model in the ground-truth object frame.
#include <Eigen/Geometry>
#include <optional>
#include <string>
#include <vector>

#include "core/status.hpp"
#include "eval/object_association.hpp"
#include "eval/reconstruction.hpp"
#include "eval/trajectory_metrics.hpp"

namespace df::eval {

/// One entry of RUN_DIR/objects.json.
struct EstimatedObject {
    int id = 0;  ///< the value of its pixels in object_masks/<stamp>.png (1..65535)
    int class_id = -1;
    std::string class_name;
    int first_frame = -1, last_frame = -1;
    int frames_tracked = 0;
    long long surfels = 0;
    std::string state;       ///< "active" or "retired"
    std::string trajectory;  ///< relative to the run folder; default objects/<id>.txt
    std::string model;       ///< relative to the run folder; "" when null
};

/// Reads {"objects": [{"id", "class_id", "class_name", "first_frame", "last_frame",
/// "frames_tracked", "surfels", "state", "trajectory", "model"}...]}. Only "id" is required.
/// Errors name the file and the entry that is wrong (an id outside 1..65535 or listed twice).
Result<std::vector<EstimatedObject>> read_objects_json(const std::string& file);

struct ObjectMapsConfig {
    ObjectAssociationConfig association;
    AssociationConfig stamps;  ///< pairing an object's estimated and ground-truth poses
    /// The models: 1 cm, since objects are a few tens of cm and their ground truth is sampled
    /// every 4 mm (the map's 5 cm would hide most errors on a suitcase).
    ReconstructionConfig model{0.01};
    /// The model is also scored after a rigid registration onto the ground-truth model,
    /// starting from the first-pose alignment: its shape apart from that one pose's error.
    RegistrationConfig model_registration;
};

/// A ground-truth instance and the estimated object matched to it, scored.
struct ObjectMapScore {
    GtInstance instance;
    EstimatedObject estimated;
    ObjectPair masks;
    std::optional<ObjectTrajectoryResult> trajectory;  ///< absent: see errors
    std::optional<ReconstructionResult> model;         ///< absent: see model_note or errors
    std::string model_note;                            ///< why no model was scored
    /// The model after rigid registration onto the ground truth (absent: see
    /// model_registration_note), and the registration.
    std::optional<ReconstructionResult> model_registered;
    std::optional<RegistrationResult> model_registration;
    std::string model_registration_note;
    Trajectory gt_poses, est_poses;                    ///< as read, for figures
    std::string gt_trajectory_file, est_trajectory_file;
};

struct ObjectMapsResult {
    ObjectAssociation association;
    MaskFolderOverlap masks;  ///< counts and instances (overlap kept for the duplicates' figures)
    std::vector<EstimatedObject> estimated;  ///< objects.json
    bool world_aligned = false;              ///< W is the camera alignment; else identity ("none")
    double model_threshold_m = 0;            ///< config.model.threshold_m
    std::vector<ObjectMapScore> objects;     ///< one per match, by gt id
    /// Problems that left a part unscored, each naming its file; the rest is still scored.
    std::vector<std::string> errors;
    std::vector<std::string> warnings;

    /// The instance with this id (nullptr if none).
    const GtInstance* instance(int gt_id) const;
};

/// Scores RUN_DIR/objects.json, objects/<id>.txt, objects/<id>.ply and object_masks/ against
/// SEQ_DIR/instances.json, instances/, objects/<name>.txt and models/<name>.ply.
/// world_gt_T_est: W, the camera ATE alignment; absent: identity. Fails only when nothing can be
/// associated (objects.json, instances.json or a mask image malformed, a folder missing).
Result<ObjectMapsResult> score_object_maps(const std::string& sequence_dir,
                                           const std::string& run_dir,
                                           const std::optional<Eigen::Isometry3d>& world_gt_T_est,
                                           const ObjectMapsConfig& config = {});

}  // namespace df::eval
