#pragma once
/// Instance segmentation quality: predicted label images against ground-truth instance images.
/// Per frame, predicted segments are matched one-to-one to ground-truth instances by IoU
/// (greedy, largest IoU first, a match needs IoU >= match_iou; with match_iou >= 0.5 a match is
/// unique anyway, since the segments of a label image are disjoint). See docs/evaluation.md.
#include <functional>
#include <opencv2/core.hpp>
#include <string>
#include <vector>

#include "core/status.hpp"

namespace df::eval {

enum class InstanceKind { kRigid, kNonRigid, kUnknown };
const char* to_string(InstanceKind kind);  ///< "rigid", "non_rigid", "unknown"

/// One entry of a sequence's instances.json.
struct GtInstance {
    int id = 0;  ///< value in instances/<stamp>.png (1..65535)
    std::string name;
    int class_id = -1;
    std::string class_name;
    InstanceKind kind = InstanceKind::kUnknown;
    /// Relative to the sequence folder. model: "" when null (a person); both default to
    /// models/<name>.ply and objects/<name>.txt when the entry does not say.
    std::string model;
    std::string trajectory;
};

/// Reads instances.json ({"instances": [{"id", "name", "class_id", "class_name", "kind", "model",
/// "trajectory"}...]}). Errors name the file and the entry that is wrong.
Result<std::vector<GtInstance>> read_instances_json(const std::string& file);

/// A label image as stored (any depth, e.g. CV_16UC1). kIoError naming the file if unreadable.
Result<cv::Mat> read_label_png(const std::string& file);

struct SegmentationConfig {
    double match_iou = 0.5;  ///< a predicted segment matches an instance when IoU >= this
    /// false: a ground-truth frame without a prediction counts as an empty prediction (every
    /// visible instance missed); true: such frames are left out.
    bool skip_missing = false;
    double max_stamp_difference_s = 1e-4;  ///< pairing prediction and GT files by stamp
    /// > 0: an instance is scored in a frame only when it moved at least this far (metres)
    /// since the previous ground-truth frame, by its trajectory (instances.json "trajectory",
    /// objects/<name>.txt); in the other frames, and for instances without a trajectory, it is
    /// left out of the ground truth (a segment on it then counts as a false positive).
    /// 0: every frame where it is visible.
    double moving_min_m = 0;
    /// Called after each ground-truth frame of score_segmentation_folders (done, total); may be
    /// empty.
    std::function<void(int, int)> progress;
};

/// One ground-truth instance in one frame and the predicted segment matched to it.
struct InstanceMatch {
    int gt_id = 0;
    int pred_label = 0;  ///< 0: not matched
    double iou = 0;      ///< 0 when not matched
    size_t intersection_px = 0, gt_px = 0, pred_px = 0;
};

struct FrameMatches {
    std::vector<InstanceMatch> instances;  ///< every GT instance visible in the frame, by id
    size_t predicted_segments = 0;         ///< non-zero labels in the prediction
    size_t unmatched_segments = 0;         ///< false positives
};

/// Matches one frame. gt: CV_16UC1 instance ids (0 = static/none); pred: CV_16UC1 or CV_8UC1
/// labels (0 = background) of the same size, or empty (nothing predicted).
Result<FrameMatches> match_frame(const cv::Mat& gt, const cv::Mat& pred, double match_iou);

struct InstanceScore {
    GtInstance instance;
    size_t frames_visible = 0;
    size_t frames_matched = 0;
    double mean_iou = 0;          ///< over visible frames; a missed frame counts 0
    double mean_precision = 0;    ///< |P and G| / |P| over matched frames
    double mean_recall = 0;       ///< |P and G| / |G| over visible frames; a missed frame counts 0
    double detection_recall = 0;  ///< frames_matched / frames_visible
};

/// Summary over the instances of one kind ("rigid", "non_rigid", "unknown") or "all": figures
/// over all (instance, frame) pairs where the instance is visible.
struct KindSummary {
    std::string kind;
    size_t instances = 0;  ///< instances of this kind visible in at least one frame
    size_t visible = 0;    ///< (instance, frame) pairs
    size_t matched = 0;
    double mean_iou = 0;
    double mean_precision = 0;
    double mean_recall = 0;
    double detection_recall = 0;
};

struct SegmentationResult {
    double match_iou = 0.5;
    size_t frames = 0;                     ///< GT frames scored
    size_t frames_without_prediction = 0;  ///< scored as empty (or skipped with skip_missing)
    size_t predictions_without_gt = 0;     ///< prediction files no GT frame pairs with
    size_t predicted_segments = 0;
    size_t false_positive_segments = 0;
    double detection_precision = 0;  ///< matched segments / predicted segments
    double detection_recall = 0;     ///< matched (instance, frame) / visible (instance, frame)
    std::vector<InstanceScore> instances;  ///< by id, instances visible at least once
    std::vector<KindSummary> kinds;        ///< rigid, non_rigid, unknown, all
};

/// Accumulates frames; ids in the GT images must be listed in `instances`.
class SegmentationScorer {
  public:
    SegmentationScorer(std::vector<GtInstance> instances, SegmentationConfig config);
    /// `frame` names the frame in messages (e.g. the GT file).
    Status add_frame(const cv::Mat& gt, const cv::Mat& pred, const std::string& frame);
    void add_missing_frame() { ++missing_; }
    void add_unpaired_prediction() { ++unpaired_; }
    SegmentationResult result() const;

  private:
    struct Sums {
        size_t visible = 0, matched = 0;
        double iou = 0, precision = 0, recall = 0;
    };
    std::vector<GtInstance> instances_;
    SegmentationConfig config_;
    std::vector<Sums> sums_;  ///< parallel to instances_
    size_t frames_ = 0, missing_ = 0, unpaired_ = 0, segments_ = 0, false_positives_ = 0;
};

/// Scores PRED_DIR/<stamp>.png against GT_SEQ_DIR/instances/<stamp>.png with
/// GT_SEQ_DIR/instances.json; files pair by stamp (within max_stamp_difference_s).
Result<SegmentationResult> score_segmentation_folders(const std::string& gt_sequence_dir,
                                                      const std::string& pred_dir,
                                                      const SegmentationConfig& config = {});

/// A binary mask folder against another (a mover's ground-truth masks, e.g. 7-Scenes-dyn's
/// masks/, against a run's invalid/): per ground-truth PNG, the prediction of the same name
/// (resized by nearest neighbour to its size; missing = empty), non-zero = in the mask.
struct MaskScore {
    int frames = 0;          ///< ground-truth PNGs
    int frames_with_gt = 0;  ///< of those, with a non-empty mask
    int missing = 0;         ///< ground-truth PNGs without a prediction
    double mean_iou = 0;     ///< mean IoU over the frames with a non-empty ground truth
    double pooled_iou = 0;   ///< sum of intersections / sum of unions over those frames
    double mean_precision = 0, mean_recall = 0;  ///< over the same frames (precision 0 when empty)
};

/// kNotFound / kIoError naming the folder or file that could not be read.
Result<MaskScore> score_mask_folders(const std::string& gt_dir, const std::string& pred_dir);

}  // namespace df::eval
